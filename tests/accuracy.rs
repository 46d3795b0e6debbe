//! The renderer's default root finder against the exact rational reference
//! on the hard cases of the accuracy study: thin tori, degree 6–10 surfaces
//! (the very polynomials their camera rays solve) and polynomials with
//! clustered and repeated roots. A correctness test, not a timing one.

use std::path::Path;

use sturmray::poly::solve::Solver;
use sturmray::report::accuracy::cases::hard_cases;
use sturmray::report::accuracy::measure::{Errors, Finder, reference};

#[test]
fn default_method_misses_no_hit_on_the_hard_cases() {
    let default = Solver::default();
    let finder = Finder::Cold(default.method);
    let sets = hard_cases(Path::new(env!("CARGO_MANIFEST_DIR")), 24, 150).unwrap();
    let mut hits = 0;
    for set in &sets {
        assert!(!set.cases.is_empty(), "{}", set.name);
        let exact = reference(&set.cases);
        hits += exact.iter().flatten().count();
        let found = finder.solve(default.tolerance, &set.cases);
        let e = Errors::compare(&found, &exact);
        assert_eq!(
            e.missed, 0,
            "{}: the exact reference hits, the default does not",
            set.name
        );
    }
    assert!(hits > 300, "only {hits} hits: the sets test too little");
}
