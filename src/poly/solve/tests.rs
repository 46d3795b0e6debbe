//! Tests of the f64 root finders: every method against polynomials built
//! from known roots, the cases fuzzing and review found, the exact path as
//! the reference.

use super::condition::{DEGENERATE_TRIM, above, below, strictly_inside, without_negligible_terms};
use super::*;
use crate::poly::exact::{exact_count, exact_roots};
use crate::poly::sturm::SturmSequence;
use crate::poly::univariate::from_roots;
use proptest::prelude::*;

const STURM: [Method; 3] = [
    Method::SturmBisect,
    Method::SturmNewton,
    Method::SturmIllinois,
];

fn solver(method: Method) -> Solver {
    Solver {
        method,
        ..Solver::default()
    }
}

fn roots_of(s: &Solver, p: &Poly, a: f64, b: f64) -> Vec<f64> {
    let mut out = [0.0; MAX_DEGREE];
    let n = s.roots(p, a, b, &mut out);
    out[..n].to_vec()
}

/// Asserts `got` matches the constructed roots `want` one for one, each
/// within `tol * max(1, |root|)`.
#[track_caller]
fn assert_near(got: &[f64], want: &[f64], tol: f64) {
    assert_eq!(got.len(), want.len(), "got {got:?}, want {want:?}");
    for (g, w) in got.iter().zip(want) {
        assert!(
            (g - w).abs() <= tol * w.abs().max(1.0),
            "got {got:?}, want {want:?}"
        );
    }
}

#[test]
fn worked_examples_roots() {
    for m in Method::ALL {
        let s = solver(*m);
        assert_near(
            &roots_of(&s, &Poly::new(&[-1.0, 0.0, 1.0]), -2.0, 2.0),
            &[-1.0, 1.0],
            1e-12,
        );
        assert_near(
            &roots_of(&s, &Poly::new(&[0.0, -1.0, 0.0, 1.0]), -2.0, 2.0),
            &[-1.0, 0.0, 1.0],
            1e-12,
        );
    }
    for m in STURM {
        let t4_t2 = Poly::new(&[0.0, 0.0, -1.0, 0.0, 1.0]);
        assert_near(
            &roots_of(&solver(m), &t4_t2, -2.0, 2.0),
            &[-1.0, 0.0, 1.0],
            1e-12,
        );
    }
}

#[test]
fn repeated_roots_are_found_once_to_tolerance() {
    let cases: [(&[f64], &[f64]); 6] = [
        (&[1.0, 1.0], &[1.0]),
        (&[1.0, 1.0, 1.0], &[1.0]),
        (&[1.0, 1.0, 2.0], &[1.0, 2.0]),
        (&[-1.0, 0.0, 0.0, 1.0], &[-1.0, 0.0, 1.0]),
        (&[0.5, 0.5, 0.5, 0.5, -1.25], &[-1.25, 0.5]),
        (&[3.0, 3.0, -0.75, -0.75, -0.75], &[-0.75, 3.0]),
    ];
    for m in STURM {
        for (built, distinct) in cases {
            let p = from_roots(1.0, built);
            let got = roots_of(&solver(m), &p, -2.0, 4.0);
            assert_near(&got, distinct, 1e-12);
            let seq = SturmSequence::new(&p);
            assert_eq!(seq.count(-2.0, 4.0), distinct.len(), "{built:?}");
        }
    }
}

#[test]
fn repeated_roots_with_rounded_coefficients() {
    // Not exactly representable: the f64 polynomial's own roots moved by
    // up to eps^(1/k) for multiplicity k, a double root split into two
    // simple ones or none. The f64 chain cannot tell, so `roots` reports
    // the exact path's answer for the f64 polynomial.
    let cases: [(&[f64], &[f64]); 3] = [
        (&[0.1, 0.1, 0.3], &[0.1, 0.3]),
        (&[0.7, 0.7, 0.7], &[0.7]),
        (&[-1.3, -1.3, 0.2, 2.9, 2.9], &[-1.3, 0.2, 2.9]),
    ];
    for m in STURM {
        for (built, distinct) in cases {
            let p = from_roots(1.0, built);
            let got = roots_of(&solver(m), &p, -2.0, 4.0);
            let exact = exact_roots(p.coeffs(), -2.0, 4.0, 0.0).unwrap();
            assert_near(&got, &exact, 1e-12);
            for g in got {
                assert!(distinct.iter().any(|d| (g - d).abs() < 1e-5), "{g}");
            }
        }
    }
}

#[test]
fn nearest_and_any_see_double_roots() {
    // A tangent ray: (t - 2)^2, no sign change anywhere.
    let p = from_roots(3.0, &[2.0, 2.0]);
    for m in STURM {
        let s = solver(m);
        let near = s.nearest(&p, 0.0, 5.0).unwrap();
        assert!((near - 2.0).abs() <= 2e-12, "{m}: {near}");
        assert!(s.any(&p, 0.0, 5.0));
        assert!(!s.any(&p, 0.0, 2.0));
        assert_eq!(s.nearest(&p, 2.0, 5.0), None);
    }
}

#[test]
fn clustered_roots() {
    let ten: Vec<f64> = (1..=10).map(f64::from).collect();
    let p = from_roots(1.0, &ten);
    let pair = from_roots(1.0, &[1.0 - 1e-6, 1.0 + 1e-6]);
    let triple = from_roots(-2.0, &[1.0 - 1e-6, 1.0 + 1e-6, 3.0]);
    for m in STURM {
        let s = solver(m);
        assert_near(&roots_of(&s, &p, 0.0, 11.0), &ten, 1e-8);
        assert_near(
            &roots_of(&s, &pair, 0.0, 2.0),
            &[1.0 - 1e-6, 1.0 + 1e-6],
            1e-9,
        );
        assert_near(
            &roots_of(&s, &triple, 0.0, 4.0),
            &[1.0 - 1e-6, 1.0 + 1e-6, 3.0],
            1e-9,
        );
        let near = s.nearest(&pair, 0.0, 2.0).unwrap();
        assert!((near - (1.0 - 1e-6)).abs() < 1e-9, "{m}: {near}");
        let near = s.nearest(&p, 4.5, 20.0).unwrap();
        assert!((near - 5.0).abs() < 1e-8, "{m}: {near}");
    }
}

#[test]
fn root_at_an_interval_end() {
    let p = from_roots(1.0, &[1.0, 2.0]);
    for m in Method::ALL {
        let s = solver(*m);
        assert_eq!(
            roots_of(&s, &p, 1.0, 2.0),
            vec![2.0],
            "{m}: (a, b] holds b, not a"
        );
        assert_eq!(roots_of(&s, &p, 0.0, 1.0), vec![1.0], "{m}");
        assert_eq!(
            s.nearest(&p, 1.0, 2.0),
            None,
            "{m}: (a, b) holds neither end"
        );
        // To the tolerance: a root is refined within its bracket to 1e-12,
        // and only some brackets' midpoints (bisecting (0, 2] at 1, say)
        // land on it exactly.
        let near = |a: f64, b: f64, want: f64| {
            s.nearest(&p, a, b)
                .is_some_and(|t| (t - want).abs() <= s.tolerance * want)
        };
        assert!(near(1.0, 3.0, 2.0), "{m}");
        assert!(near(0.0, 2.0, 1.0), "{m}");
        assert!(!s.any(&p, 1.0, 2.0), "{m}");
        assert!(!s.any(&p, 0.0, 1.0), "{m}");
        assert!(s.any(&p, 0.0, 1.5), "{m}");
        assert!(s.any(&p, 1.0, 2.5), "{m}");
    }
}

#[test]
fn ray_starting_on_the_surface_skips_its_own_root() {
    // Roots 0 (the ray's origin) and 3: t^2 - 3t.
    let p = Poly::new(&[0.0, -3.0, 1.0]);
    for m in Method::ALL {
        let s = solver(*m);
        let near = s.nearest(&p, 0.0, 10.0).unwrap();
        assert!((near - 3.0).abs() < 1e-12, "{m}: {near}");
        assert!(!s.any(&p, 0.0, 2.0), "{m}");
        let near = s.nearest_from(&p, 0.0, 10.0, 1e-3).unwrap();
        assert!((near - 3.0).abs() < 1e-12, "{m}: {near}");
    }
}

#[test]
fn no_roots_in_the_interval() {
    let none = [
        (Poly::new(&[1.0, 0.0, 1.0]), -10.0, 10.0),
        (from_roots(1.0, &[5.0, 6.0]), 0.0, 4.0),
        (from_roots(1.0, &[-1.0, 1.0, 2.0, 3.0]), 1.1, 1.9),
        (Poly::new(&[4.0]), -1.0, 1.0),
        (Poly::ZERO, -1.0, 1.0),
    ];
    for m in Method::ALL {
        let s = solver(*m);
        for (p, a, b) in &none {
            assert!(roots_of(&s, p, *a, *b).is_empty(), "{m}: {p:?}");
            assert_eq!(s.nearest(p, *a, *b), None, "{m}: {p:?}");
            assert_eq!(s.nearest_from(p, *a, *b, 0.5 * (a + b)), None, "{m}: {p:?}");
            assert!(!s.any(p, *a, *b), "{m}: {p:?}");
        }
        let p = from_roots(1.0, &[1.0]);
        assert!(roots_of(&s, &p, 2.0, 1.0).is_empty(), "{m}: empty interval");
        assert!(roots_of(&s, &p, f64::NAN, 3.0).is_empty(), "{m}: NaN end");
    }
}

#[test]
fn roots_answer_the_exact_count_where_the_chain_miscounts() {
    // Found by `make fuzz`: the f64 chain counts no root in (-0.5, 1.5],
    // and p > 0 at both ends, so parity cannot tell either.
    let c = [
        -1.0,
        -674.7134819353886,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        649.9810629293474,
        -8.985278822260234e-10,
        0.0,
        1.0,
    ];
    let (a, b) = (-0.5, 1.5);
    let p = Poly::new(&c);
    assert_eq!(exact_count(&c, a, b), Some(2));
    assert_ne!(
        SturmSequence::new(&p).count(a, b),
        2,
        "the f64 chain counts this one right now: pick a harder case"
    );
    for m in STURM {
        let s = solver(m);
        let want = exact_roots(&c, a, b, s.tolerance).unwrap();
        assert_near(&roots_of(&s, &p, a, b), &want, 1e-12);
    }
}

#[test]
fn roots_of_a_trimmed_chain_are_refined_on_the_input() {
    // t^3 (588.3 + 3t^2 - 3t^3 - 2.7e-10 t^4): the tiny leading term
    // degenerates the chain, which then counts the trimmed polynomial
    // (with the triple root at 0); its root near 6.163 is 1.3e-9 from
    // the input's.
    let c = [
        0.0,
        0.0,
        0.0,
        588.3205658607934,
        0.0,
        3.0,
        -3.0,
        -2.6695779584047033e-10,
    ];
    let p = Poly::new(&c);
    let want = exact_roots(&c, 3.5, 6.5, 0.0).unwrap();
    assert_eq!(want.len(), 1);
    for m in STURM {
        let s = solver(m);
        let near = s.nearest(&p, 3.5, 6.5).unwrap();
        assert!(
            (near - want[0]).abs() < 1e-11,
            "{m}: {near} for {}",
            want[0]
        );
        assert_near(&roots_of(&s, &p, 3.5, 6.5), &want, 1e-11);
    }
}

#[test]
fn a_tiny_coefficient_inside_does_not_hide_a_root() {
    // The 5.3e-10 t^4 term leaves a remainder with a leading coefficient
    // of 7e-13 relative, and the chain counted no root in (-2.5, -0.5]
    // for the one at -0.9948. Found by a sweep of random polynomials
    // against the exact count.
    let c = [
        -144.20804782892182,
        0.0,
        735.1777929034166,
        -5.0,
        -5.318248212515959e-10,
        0.0,
        -606.9473473192332,
    ];
    let p = Poly::new(&c);
    let want = exact_roots(&c, -2.5, -0.5, 0.0).unwrap();
    assert_eq!(want.len(), 1);
    for m in STURM {
        let near = solver(m).nearest(&p, -2.5, -0.5).unwrap();
        assert!(
            (near - want[0]).abs() < 1e-12,
            "{m}: {near} for {}",
            want[0]
        );
        assert!(solver(m).any(&p, -2.5, -0.5), "{m}");
    }
}

#[test]
fn a_term_that_overflows_at_the_bound_does_not_hide_the_others() {
    // 1e-20 t^16 overflows to infinity at t = 1e21; compared with it,
    // every lower term looked negligible and the chain became a
    // constant (found in review).
    let cases: [(&[f64], f64, f64); 2] = [
        (&[-0.5, 1.0, 0.0, 0.0, 1e-100], 0.0, f64::INFINITY),
        (
            &[
                -0.5, 1.0, 0., 0., 0., 0., 0., 0., 0., 0., 0., 0., 0., 0., 0., 0., 1e-20,
            ],
            -1e21,
            1e21,
        ),
    ];
    for (c, a, b) in cases {
        let p = Poly::new(c);
        let want = exact_roots(c, a, b, 0.0).unwrap();
        for m in STURM {
            let near = solver(m).nearest(&p, a, b).unwrap();
            assert!((near - want[0]).abs() < 1e-9, "{m}: {near} for {want:?}");
            assert!(solver(m).any(&p, a, b), "{m}");
        }
    }
}

#[test]
fn inner_terms_are_judged_without_underflow() {
    // The t term of 1e-200 + t + 1e200 t^3 dominates near t = 1e-100,
    // where the other two are equal; (1e-200 / 1e200)^(1/3) underflowed
    // to 0 and the term was dropped (found in review).
    let p = Poly::new(&[1e-200, 1.0, 0.0, 1e200]);
    assert_eq!(without_negligible_terms(&p, 1.0, DEGENERATE_TRIM), p);
    // A term that is dominated everywhere still goes: 1e-12 t against
    // 1 + t^2, which are at least 2|t| on any interval.
    let q = Poly::new(&[1.0, 1e-12, 1.0]);
    let dropped = without_negligible_terms(&q, 10.0, DEGENERATE_TRIM);
    assert_eq!(dropped, Poly::new(&[1.0, 0.0, 1.0]));
}

#[test]
fn leading_coefficient_near_zero() {
    // 1e-20 t^2 + t - 0.5: the quadratic term is noise; one root at
    // 0.5 (to 1e-20), the other near -1e20, out of the interval.
    let p = Poly::new(&[-0.5, 1.0, 1e-20]);
    // A cylinder seen along its axis: round-off of either sign on top.
    let q = from_roots(1.0, &[0.25, 1.75]);
    let mut qc = q.coeffs().to_vec();
    qc.push(-3e-17);
    let q_noisy = Poly::new(&qc);
    for m in Method::ALL {
        let s = solver(*m);
        let cases: [(Poly, &[f64]); 3] = [
            (p, &[0.5]),
            (p.trimmed(1e-14, 1.0), &[0.5]),
            (q_noisy.trimmed(1e-14, 1.0), &[0.25, 1.75]),
        ];
        for (poly, want) in cases {
            assert_near(&roots_of(&s, &poly, -2.0, 2.0), want, 1e-12);
            let near = s.nearest(&poly, 0.0, 10.0).unwrap();
            assert!((near - want[0]).abs() < 1e-12, "{m}");
        }
    }
}

#[test]
fn small_leading_coefficients_without_trimming() {
    // eps t^(n+1) + Q(t): a ray close to an asymptotic direction. The
    // extra root sits near -1/eps, outside; the others move by about
    // eps r^(n+1) / Q'(r). The Sturm path needs no trimming by the
    // caller for any eps (the closed forms do: they divide by eps).
    let bases: [&[f64]; 3] = [&[0.25, 1.75], &[-0.5, 0.25, 1.75], &[-0.7, 0.3, 0.9, 1.2]];
    for base in bases {
        let q = from_roots(1.0, base);
        for k in 6..=20 {
            for eps in [10f64.powi(-k), -(10f64.powi(-k))] {
                let mut c = q.coeffs().to_vec();
                c.push(eps);
                let p = Poly::new(&c);
                for t_max in [2.0, 10.0, 1e3] {
                    for m in STURM {
                        let got = roots_of(&solver(m), &p, -1.0, t_max);
                        let ctx = format!("{m} {base:?} eps {eps:e} t_max {t_max}: {got:?}");
                        assert_eq!(got.len(), base.len(), "{ctx}");
                        for (g, r) in got.iter().zip(base) {
                            let slope = q.derivative().eval(*r).abs();
                            let moved = eps.abs() * r.abs().powi(c.len() as i32 - 1) / slope;
                            assert!((g - r).abs() <= 2.0 * moved + 1e-10, "{ctx}");
                        }
                        let near = solver(m).nearest(&p, -1.0, t_max).unwrap();
                        assert!((near - got[0]).abs() <= 1e-10, "{ctx}");
                    }
                }
            }
        }
    }
}

#[test]
fn coefficient_scale_does_not_matter() {
    let want = [-1.25, 0.5, 0.75, 3.0];
    let p = from_roots(1.0, &want);
    for m in Method::ALL {
        let s = solver(*m);
        for scale in [1e-100, 1e-30, -1.0, 1e30, -1e100, 1e300, 1e-300] {
            let scaled = p.scaled(scale);
            assert_near(&roots_of(&s, &scaled, -2.0, 4.0), &want, 1e-12);
            assert!(
                !s.any(&scaled, 0.6, 0.7) && s.any(&scaled, 0.6, 0.8),
                "{m} {scale}"
            );
            let near = s.nearest(&scaled, 0.6, 10.0).unwrap();
            assert!((near - 0.75).abs() < 1e-12, "{m} {scale}");
        }
    }
}

#[test]
fn infinite_intervals_use_the_root_bound() {
    let want = [-300.0, -0.5, 2.0, 1e4];
    let p = from_roots(0.5, &want);
    for m in Method::ALL {
        let s = solver(*m);
        assert_near(
            &roots_of(&s, &p, f64::NEG_INFINITY, f64::INFINITY),
            &want,
            1e-12,
        );
        let near = s.nearest(&p, 0.0, f64::INFINITY).unwrap();
        assert!((near - 2.0).abs() < 1e-12, "{m}");
        assert!(s.any(&p, 3.0, f64::INFINITY), "{m}");
        assert!(!s.any(&p, 1e4, f64::INFINITY), "{m}");
    }
}

#[test]
fn nearest_never_skips_a_nearer_root() {
    // A ray through both tubes of a torus: two close pairs.
    let want = [1.0, 1.001, 3.0, 3.001];
    let p = from_roots(1.0, &want);
    for m in Method::ALL {
        let s = solver(*m);
        // The f64 polynomial's own roots are within ~1e-11 of these.
        for (a, nearest) in [
            (0.0, 1.0),
            (0.9999, 1.0),
            (1.0005, 1.001),
            (1.002, 3.0),
            (2.0, 3.0),
        ] {
            let got = s.nearest(&p, a, 10.0).unwrap();
            assert!((got - nearest).abs() < 1e-10, "{m}: from {a} got {got}");
        }
        assert_eq!(s.nearest(&p, 3.002, 10.0), None);
    }
}

#[test]
fn nearest_from_validates_the_warm_start() {
    let p = from_roots(1.0, &[1.0, 1.001, 3.0, 3.001]);
    for m in Method::ALL {
        let s = solver(*m);
        // A guess beside the far pair converges there; the count check
        // must reject it.
        for guess in [0.9, 1.0004, 2.9, 3.0004, 9.0, -5.0, f64::NAN] {
            let got = s.nearest_from(&p, 0.0, 10.0, guess).unwrap();
            assert!((got - 1.0).abs() < 1e-10, "{m}: guess {guess} gave {got}");
        }
        let got = s.nearest_from(&p, 2.0, 10.0, 3.0004).unwrap();
        assert!((got - 3.0).abs() < 1e-10, "{m}: {got}");
        assert_eq!(s.nearest_from(&p, 2.0, 3.0, 2.99), None, "{m}");
    }
    // A double root, where Newton on p itself would crawl.
    let q = from_roots(1.0, &[0.5, 0.5, 2.0]);
    let got = Solver::default().nearest_from(&q, 0.0, 3.0, 0.6).unwrap();
    assert!((got - 0.5).abs() < 1e-12, "{got}");
}

#[test]
fn tolerance_is_a_bracket_width() {
    let p = Poly::new(&[-2.0, 0.0, 1.0]);
    for m in STURM {
        for tol in [1e-2, 1e-6, 1e-10, 1e-14] {
            let s = Solver {
                method: m,
                tolerance: tol,
                max_iterations: 200,
            };
            let got = s.nearest(&p, 0.0, 10.0).unwrap();
            assert!(
                (got - std::f64::consts::SQRT_2).abs() <= tol * 1.5,
                "{m} {tol}: {got}"
            );
        }
    }
    // Relative for large roots.
    let big = from_roots(1.0, &[1e6, 3e6]);
    for m in STURM {
        let got = solver(m).nearest(&big, 0.0, 1e7).unwrap();
        assert!((got - 1e6).abs() <= 1e-12 * 1e6, "{m}: {got}");
    }
    // Tolerances below f64 resolution stop at adjacent floats.
    let s = Solver {
        tolerance: 0.0,
        ..Solver::default()
    };
    let got = s.nearest(&p, 0.0, 10.0).unwrap();
    assert!(
        (got - std::f64::consts::SQRT_2).abs() <= 2.0 * f64::EPSILON,
        "{got}"
    );
}

#[test]
fn closed_method_matches_and_falls_back() {
    let s = solver(Method::Closed);
    let quartic = from_roots(2.0, &[-3.0, -1.0, 0.5, 2.5]);
    assert_near(
        &roots_of(&s, &quartic, -5.0, 5.0),
        &[-3.0, -1.0, 0.5, 2.5],
        1e-13,
    );
    assert_eq!(
        s.nearest(&quartic, -1.0, 5.0)
            .map(|t| (t - 0.5).abs() < 1e-13),
        Some(true)
    );
    let cubic = from_roots(1.0, &[-2.0, 0.0, 3.0]);
    assert_near(&roots_of(&s, &cubic, -5.0, 5.0), &[-2.0, 0.0, 3.0], 1e-13);
    let linear = Poly::new(&[1.0, 4.0]);
    assert_near(&roots_of(&s, &linear, -5.0, 5.0), &[-0.25], 0.0);
    // Degree 6: sturm-newton.
    let sextic = from_roots(1.0, &[-2.0, -1.0, 0.0, 1.0, 2.0, 3.0]);
    assert_near(
        &roots_of(&s, &sextic, -5.0, 5.0),
        &[-2.0, -1.0, 0.0, 1.0, 2.0, 3.0],
        1e-12,
    );
}

#[test]
fn yuksel_finds_every_root_of_high_degree_polynomials() {
    let s = solver(Method::Yuksel);
    // Roots 1..10, and ten roots of a Chebyshev-like spread in (-1, 1).
    let integers: Vec<f64> = (1..=10).map(f64::from).collect();
    let cheb: Vec<f64> = (0..10)
        .map(|k| (std::f64::consts::PI * (f64::from(k) + 0.5) / 10.0).cos())
        .rev()
        .collect();
    for want in [integers, cheb] {
        let p = from_roots(1.0, &want);
        let got = roots_of(&s, &p, -2.0, 11.0);
        assert_near(&got, &want, 1e-9);
        let near = s.nearest(&p, want[3], 11.0).unwrap();
        assert!((near - want[4]).abs() < 1e-9, "{near}");
        assert!(s.any(&p, want[3] + 1e-3, want[4] + 1e-3));
        assert!(!s.any(&p, want[3] + 1e-3, want[4] - 1e-3));
    }
}

#[test]
fn yuksel_tolerance_and_odd_multiplicity() {
    let p = Poly::new(&[-2.0, 0.0, 1.0]);
    for tol in [1e-2, 1e-6, 1e-10, 1e-14] {
        let s = Solver {
            method: Method::Yuksel,
            tolerance: tol,
            max_iterations: 200,
        };
        let got = s.nearest(&p, 0.0, 10.0).unwrap();
        assert!(
            (got - std::f64::consts::SQRT_2).abs() <= tol * 1.5,
            "{tol}: {got}"
        );
    }
    // A triple root changes sign: found, to the cube root of rounding.
    let triple = from_roots(1.0, &[0.3, 0.3, 0.3, 2.0]);
    let got = solver(Method::Yuksel).nearest(&triple, 0.0, 3.0).unwrap();
    assert!((got - 0.3).abs() < 1e-4, "{got}");
    // A tangent with no crossing: (t - 1)^2 + 1e-12 has no real root.
    let touch = Poly::new(&[1.0 + 1e-12, -2.0, 1.0]);
    assert_eq!(solver(Method::Yuksel).nearest(&touch, 0.0, 3.0), None);
}

#[test]
fn every_root_is_a_crossing_or_comes_from_the_exact_path() {
    // Found by tests/fuzz_poly.rs: roots on the open end a reported,
    // a multiple root on b lost or reported twice, a quadruple root
    // reported twice (the chain took noise for a remainder and counted
    // two roots near it), a phantom root from a chain that divided by
    // noise, and a root near -3.85e-5 reported as 0 (a remainder
    // 60 times its error estimate taken for a gcd).
    let cases: [(&[f64], f64, f64, &[f64]); 8] = [
        // t^2 (t + 3)^2 (t - 3)
        (&[0.0, 0.0, -27.0, -9.0, 3.0, 1.0], -3.0, -2.5, &[]),
        // (t - 2)^3 (t - 2.5)^2
        (&[-50.0, 115.0, -105.5, 48.25, -11.0, 1.0], 2.0, 2.5, &[2.5]),
        (
            &[-1728.0, -432.0, 396.0, 71.0, -33.0, -3.0, 1.0],
            -5.0,
            4.0,
            &[-3.0, 4.0],
        ),
        // (t + 2.5)^2 (t - 0.5)^2
        (&[1.5625, -5.0, 1.5, 4.0, 1.0], -5.0, -2.5, &[-2.5]),
        (
            &[576.0, -384.0, -1256.0, -580.0, 6.25, 60.25, 14.0, 1.0],
            -4.5,
            -4.0,
            &[-4.0],
        ),
        // Roots 2 and 3.5 (of multiplicity 4) in the interval.
        (
            &[
                -750.3125, 182.21875, 629.34375, -367.9375, -3.25, 48.0, -12.5, 1.0,
            ],
            0.0,
            9.517386142912624,
            &[2.0, 3.5],
        ),
        (
            &[
                -1.0,
                0.0,
                8.663053858603911e-11,
                0.0,
                -114.78162187541942,
                152.92263966434385,
            ],
            0.0,
            1.0,
            &[0.7692601072953948],
        ),
        (
            &[
                1.4842386762401313e-12,
                -1.3329307065093328e-10,
                0.0,
                25.94724897905935,
            ],
            -0.5,
            0.0,
            &[-0.000038574896734644426],
        ),
    ];
    for m in STURM {
        for (c, a, b, want) in cases {
            let got = roots_of(&solver(m), &Poly::new(c), a, b);
            assert_near(&got, want, 1e-12);
        }
    }
}

#[test]
fn a_root_the_chain_lost_between_ends_of_opposite_signs() {
    // Found by tests/fuzz_poly.rs: the tiny t^4 coefficient left the
    // chain counting 0 roots in (-1, 0].
    let p = Poly::new(&[
        74.0708084071424,
        3.0,
        0.0,
        907.9238821826626,
        6.027905747477918e-10,
        0.0,
        -170.1871154478272,
    ]);
    for m in STURM {
        let got = roots_of(&solver(m), &p, -1.0, 0.0);
        assert_near(&got, &[-0.4290752462521165], 1e-12);
    }
}

#[test]
fn simple_root_beside_a_double_root_on_the_open_end() {
    // t^2 (-1 + 834.7t + t^4 + 2t^6) on (0, 0.5]: found by
    // tests/fuzz_poly.rs with no root at all for 0.0011980.
    let p = Poly::new(&[0.0, 0.0, -1.0, 834.699808367765, 0.0, 0.0, 1.0, 0.0, 2.0]);
    for m in STURM {
        let got = roots_of(&solver(m), &p, 0.0, 0.5);
        assert_near(&got, &[0.0011980354970546614], 1e-12);
    }
}

#[test]
fn illinois_falls_back_to_bisection_when_its_steps_run_out() {
    // Found by tests/fuzz_poly.rs: Illinois returned -2.7199 for the
    // root -2.7329 on the root bound's wide bracket after 100 steps.
    let p = Poly::new(&[
        -2.0, -3.0, 5.0, 0.0, 2.0, 1.0, -7.0, 302.2, 0.0, 0.0, 4.0, -4.0,
    ]);
    let want = [-2.732864725128479, 0.49532316282557076, 3.2290574698979526];
    let got = roots_of(
        &solver(Method::SturmIllinois),
        &p,
        f64::NEG_INFINITY,
        f64::INFINITY,
    );
    assert_near(&got, &want, 1e-11);
}

#[test]
fn nudges_inside_skip_subnormals() {
    assert_eq!(above(0.0), f64::MIN_POSITIVE);
    assert_eq!(above(-f64::MIN_POSITIVE), 0.0);
    assert_eq!(above(1.0), 1.0 + f64::EPSILON);
    assert_eq!(below(0.0), -f64::MIN_POSITIVE);
    assert_eq!(strictly_inside(0.0, 0.0, 1.0), f64::MIN_POSITIVE);
    assert_eq!(strictly_inside(1.0, 0.0, 1.0), 1.0 - f64::EPSILON / 2.0);
    assert_eq!(strictly_inside(0.5, 0.0, 1.0), 0.5);
}

#[test]
fn method_names_round_trip() {
    for m in Method::ALL {
        assert_eq!(m.name().parse::<Method>(), Ok(*m));
        assert_eq!(m.to_string(), m.name());
    }
    let err = "newton".parse::<Method>().unwrap_err();
    for m in Method::ALL {
        assert!(err.contains(m.name()), "{err}");
    }
    assert_eq!(Solver::default().method, Method::SturmNewton);
    assert_eq!(Solver::default().tolerance, 1e-12);
}

/// Sorted roots in [-4, 4], pairwise more than 0.1 apart.
fn separated_roots() -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(-4.0f64..4.0, 1..=7).prop_filter_map("roots too close", |mut r| {
        r.sort_by(f64::total_cmp);
        r.windows(2).all(|w| w[1] - w[0] > 0.1).then_some(r)
    })
}

fn leading() -> impl Strategy<Value = f64> {
    (-3i32..=3, any::<bool>())
        .prop_map(|(e, neg)| if neg { -(10f64.powi(e)) } else { 10f64.powi(e) })
}

/// Distinct quarter-integer roots in [-3, 3] with multiplicities 1 to
/// 3, at most degree 8: with a power-of-two leading coefficient the
/// expanded coefficients need under 40 bits, so the f64 polynomial has
/// exactly these multiple roots.
fn exact_multiple_roots() -> impl Strategy<Value = (Vec<f64>, Vec<f64>)> {
    prop::collection::btree_map(-12i32..=12, 1usize..=3, 1..=4).prop_filter_map(
        "degree above 8",
        |m| {
            let distinct: Vec<f64> = m.keys().map(|&k| f64::from(k) / 4.0).collect();
            let all: Vec<f64> = m
                .iter()
                .flat_map(|(&k, &n)| std::iter::repeat_n(f64::from(k) / 4.0, n))
                .collect();
            (all.len() <= 8).then_some((all, distinct))
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn roots_finds_constructed_roots(
        roots in separated_roots(), lead in leading(), m in 0usize..Method::ALL.len(),
    ) {
        let p = from_roots(lead, &roots);
        let s = solver(Method::ALL[m]);
        let got = roots_of(&s, &p, -5.0, 5.0);
        prop_assert_eq!(got.len(), SturmSequence::new(&p).count(-5.0, 5.0));
        prop_assert_eq!(got.len(), roots.len());
        for (g, w) in got.iter().zip(&roots) {
            prop_assert!(
                (g - w).abs() <= 1e-7 * w.abs().max(1.0), "got {:?}, want {:?}", got, roots
            );
        }
    }

    #[test]
    fn multiple_roots_are_found_once(
        (all, distinct) in exact_multiple_roots(), e in -40i32..40, m in 0usize..3,
    ) {
        let p = from_roots(2f64.powi(e), &all);
        let s = solver(STURM[m]);
        let got = roots_of(&s, &p, -4.0, 4.0);
        prop_assert_eq!(SturmSequence::new(&p).count(-4.0, 4.0), distinct.len());
        prop_assert_eq!(got.len(), distinct.len(), "got {:?}, want {:?}", got, distinct);
        // Not to 1e-12: the roots are those of the square-free part,
        // whose coefficients carry the round-off of the chain that found
        // gcd(p, p') (the exact path is the reference for these).
        for (g, w) in got.iter().zip(&distinct) {
            prop_assert!((g - w).abs() <= 1e-7 * w.abs().max(1.0), "got {:?}", got);
        }
        // The ray path (`nearest`) does not reduce p to its square-free
        // part, so a root of multiplicity m is known only to within its
        // f64 conditioning, (noise / |a_m|)^(1/m) with a_m = p^(m)(r)/m!
        // (a triple root 0.25 from another triple root: 1.2e-7 off).
        let near = s.nearest(&p, -4.0, 4.0);
        let r = distinct[0];
        let m = all.iter().filter(|&&x| x == r).count();
        let others = all.iter().filter(|&&x| x != r);
        let a_m = 2f64.powi(e) * others.map(|&x| r - x).product::<f64>();
        let noise = f64::EPSILON
            * p.coeffs().iter().rev().fold(0.0, |acc, c| acc * r.abs() + c.abs());
        let within = (noise / a_m.abs()).powf(1.0 / m as f64).max(1e-7);
        prop_assert!(
            near.is_some_and(|t| (t - r).abs() <= within),
            "nearest {:?}, want {} within {}", near, r, within
        );
        prop_assert!(s.any(&p, -4.0, 4.0));
    }

    #[test]
    fn nearest_and_any_agree_with_the_construction(
        roots in separated_roots(),
        lead in leading(),
        m in 0usize..Method::ALL.len(),
        a in -4.5f64..4.5,
        len in 0.01f64..9.0,
    ) {
        let b = a + len;
        prop_assume!(roots.iter().all(|r| (r - a).abs() > 1e-6 && (r - b).abs() > 1e-6));
        let p = from_roots(lead, &roots);
        let s = solver(Method::ALL[m]);
        let want = roots.iter().copied().find(|&r| r > a && r < b);
        let got = s.nearest(&p, a, b);
        prop_assert_eq!(got.is_some(), want.is_some(), "got {:?}, want {:?}", got, want);
        if let (Some(g), Some(w)) = (got, want) {
            prop_assert!((g - w).abs() <= 1e-7 * w.abs().max(1.0), "got {}, want {}", g, w);
        }
        prop_assert_eq!(s.any(&p, a, b), want.is_some());
        let warm = s.nearest_from(&p, a, b, roots[roots.len() - 1] + 0.01);
        prop_assert_eq!(warm.is_some(), want.is_some());
        if let (Some(g), Some(w)) = (warm, want) {
            prop_assert!(
                (g - w).abs() <= 1e-7 * w.abs().max(1.0), "warm got {}, want {}", g, w
            );
        }
    }
}

/// (t − 1e-13)(t − 3e-13): two simple roots 2e-13 apart near 0, where the
/// tolerance is 1e-12 absolute. The chain counts two, and bisection
/// reaches a bracket narrower than the tolerance before it splits them:
/// one unseparated query, on this thread, answered within the tolerance of
/// both. Well separated roots count none.
#[test]
fn unseparated_roots_are_counted() {
    let solver = Solver::default();
    let before = unseparated_count();
    let far = from_roots(1.0, &[0.5, 2.0, 3.0]);
    let t = solver.nearest(&far, 0.0, 10.0).expect("a root");
    assert!((t - 0.5).abs() <= 1e-12, "{t}");
    assert_eq!(unseparated_count(), before);
    let pair = from_roots(1.0, &[1e-13, 3e-13]);
    let t = solver.nearest(&pair, -1.0, 1.0).expect("a root");
    assert!(
        (t - 1e-13).abs() <= 1e-12 && (t - 3e-13).abs() <= 1e-12,
        "{t}"
    );
    assert_eq!(unseparated_count(), before + 1);
    let mut out = [0.0; MAX_DEGREE];
    let n = solver.roots(&pair, -1.0, 1.0, &mut out);
    assert!(n >= 1, "the exact path answers: {:?}", &out[..n]);
    assert_eq!(unseparated_count(), before + 2, "its f64 try counted");
}

/// Wilkinson-like: 26 equally spaced roots 4k/27 in f64. The rounded
/// coefficients leave the f64 chain degenerate, so its counts are no proof
/// (in the accuracy study they skip the first roots): the query counts as
/// unseparated whatever it answers.
#[test]
fn degenerate_chains_count_as_unseparated() {
    let roots: Vec<f64> = (1..=26).map(|k| 4.0 * f64::from(k) / 27.0).collect();
    let p = from_roots(1.0, &roots);
    assert!(SturmSequence::new(&p).is_degenerate());
    let before = unseparated_count();
    let _ = Solver::default().nearest(&p, 0.0, 4.0);
    assert_eq!(unseparated_count(), before + 1);
}

/// One query in the quartic (5-slot) and the small (17-slot) instantiation:
/// nearest root, any root, all roots, as bits.
fn quartic_and_small(s: &Solver, p: &Poly, a: f64, b: f64) -> [(Option<u64>, bool, Vec<u64>); 2] {
    fn run<const S: usize>(
        s: &Solver,
        p: &PolyN<S>,
        a: f64,
        b: f64,
    ) -> (Option<u64>, bool, Vec<u64>) {
        let mut out = [0.0; MAX_DEGREE];
        let n = s.unproven_roots_in(p, a, b, &mut out);
        (
            s.nearest_of(p, a, b).map(f64::to_bits),
            s.any_of(p, a, b),
            out[..n].iter().map(|t| t.to_bits()).collect(),
        )
    }
    let quartic = p.resized::<QUARTIC_SLOTS>().expect("degree 4 or less");
    let small = p.resized::<SMALL_SLOTS>().expect("degree 16 or less");
    [run(s, &quartic, a, b), run(s, &small, a, b)]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Degree 4 or less runs in 5 slots (`by_degree!`) with the operations
    /// of the 17-slot instantiation, so images stay the same bits: random
    /// coefficients, and products of integer roots (double, triple and
    /// quadruple roots take the reduced chain).
    #[test]
    fn quartic_slots_answer_as_small_slots(
        coeffs in proptest::collection::vec(-10.0f64..10.0, 2..=5),
        roots in proptest::collection::vec(-3i32..=3, 1..=4),
        m in 0usize..Method::ALL.len(),
    ) {
        let s = solver(Method::ALL[m]);
        let roots: Vec<f64> = roots.into_iter().map(f64::from).collect();
        for p in [Poly::new(&coeffs), from_roots(1.5, &roots)] {
            let [quartic, small] = quartic_and_small(&s, &p, -4.0, 4.0);
            prop_assert_eq!(quartic, small, "{:?}", p);
        }
    }
}

/// Q(t) of the ray o + t d against the torus about z with radii (major,
/// minor), substituted as the renderer does for an algebraic surface.
fn torus_ray(major: f64, minor: f64, o: [f64; 3], d: [f64; 3]) -> Poly {
    let torus = crate::poly::expr::parse(
        "(x^2 + y^2 + z^2 + R^2 - r^2)^2 - 4*R^2*(x^2 + y^2)",
        &[("R", major), ("r", minor)],
    )
    .expect("a torus");
    let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let mut q = [0.0; 5];
    let n = torus.substitute_ray(o, d.map(|x| x / len), &mut q);
    Poly::new(&q[..n])
}

/// The nearest root by the Sturm chain alone, without a first pass.
fn sturm_nearest(s: &Solver, p: &Poly, a: f64, b: f64) -> Option<f64> {
    let q = p.resized::<QUARTIC_SLOTS>().expect("a quartic");
    let mut search = Search::EMPTY;
    if !search.prepare(&q, a, b) {
        return None;
    }
    s.nearest_in(&search, a, b)
}

/// The default `nearest` and `any` against the Sturm chain alone: the same
/// hit or miss; and the root within the tolerance of the exact nearest
/// root, plus what the f64 evaluation's rounding allows near a double
/// root (2 (n + 1) ε Σ |c_i| |t|^i over |p'(t)|: two grazing roots are that
/// ill-conditioned, and the chain's answer is off by as much).
#[track_caller]
fn agrees_with_the_chain(p: &Poly, a: f64, b: f64) {
    let s = Solver::default();
    let (got, want) = (s.nearest(p, a, b), sturm_nearest(&s, p, a, b));
    assert_eq!(
        got.is_some(),
        want.is_some(),
        "{p:?}: nearest {got:?}, the chain {want:?}"
    );
    assert_eq!(s.any(p, a, b), want.is_some(), "{p:?}: any");
    let Some(t) = got else { return };
    let exact = exact_roots(p.coeffs(), a, b, 1e-15).unwrap();
    let Some(&root) = exact.iter().find(|&&r| r > a && r < b) else {
        panic!("{p:?}: nearest {t}, no exact root in ({a}, {b})");
    };
    let rounding: f64 = p
        .coeffs()
        .iter()
        .rev()
        .fold(0.0, |m, c| m * t.abs() + c.abs());
    let slope = p.eval_with_derivative(t).1.abs();
    let allowed = 2.0 * s.width_tol(t, root) + 10.0 * f64::EPSILON * rounding / slope;
    assert!(
        (t - root).abs() <= allowed,
        "{p:?}: nearest {t}, exact {root}, the chain {want:?}"
    );
}

#[test]
fn grazing_a_torus_hits_as_the_chain_says() {
    // R = 1, r = 0.3; rays along x past the outer equator (y = R + r),
    // the inner one (y = R - r) and over the top of the tube (z = r), each
    // by 1e-9 to 1e-3 of r inside and outside, and tilted a little.
    let (major, minor) = (1.0, 0.3);
    for rel in [1e-9, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4, 1e-3] {
        for side in [-1.0, 1.0] {
            let off = side * rel * minor;
            for tilt in [0.0, 1e-3, 0.1] {
                for o in [
                    [-4.0, major + minor + off, 0.0],
                    [-4.0, major - minor - off, 0.0],
                    [-4.0, 0.0, minor + off],
                    [-4.0, major, minor + off],
                ] {
                    let p = torus_ray(major, minor, o, [1.0, tilt * 1e-3, tilt]);
                    agrees_with_the_chain(&p, 0.0, 10.0);
                    agrees_with_the_chain(&p, 1e-6, 1e3);
                }
            }
        }
    }
    // A double root of the f64 quartic itself: x^2 + (y - 1.3)^2 touching
    // at t = 4 along y = R + r exactly, as the chain sees it.
    let p = torus_ray(major, minor, [-4.0, major + minor, 0.0], [1.0, 0.0, 0.0]);
    agrees_with_the_chain(&p, 0.0, 10.0);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    /// Random rays at a torus (near its surface more often than not, thin
    /// tori included), from inside and outside: the default nearest
    /// agrees with the Sturm chain's.
    #[test]
    fn torus_rays_hit_as_the_chain_says(
        minor in prop_oneof![0.05..0.5f64, 1e-3..0.05f64],
        o in prop::array::uniform3(-4.0..4.0f64),
        target in prop::array::uniform3(-1.5..1.5f64),
        a in prop_oneof![Just(0.0), 1e-6..1.0f64],
    ) {
        let d = [target[0] - o[0], target[1] - o[1], target[2] - o[2]];
        prop_assume!(d.iter().any(|x| x.abs() > 1e-3));
        let p = torus_ray(1.0, minor, o, d);
        agrees_with_the_chain(&p, a, 20.0);
    }
}

/// Two rays' Q (degree 12) through a product of four ellipsoids and a torus
/// less 1e-3, formed where each enters its clipping ball, from
/// `make povray-fuzz` (tools/povray/fuzz_poly.py, seed 253). Their roots
/// are simple and apart, but their values sink to 1e-9 among terms of
/// 1e5: the first pass's bound over the whole interval proves nothing
/// there, and the f64 Sturm chain degenerates and counts none. Both lost
/// every root before the pass restarted on parts (`restarted`); the second
/// has one 1e-4 of the way from the interval's middle.
#[test]
fn degree_12_roots_under_the_whole_intervals_rounding() {
    let cases: [(&[f64], f64); 2] = [
        (
            &[
                58.36661220903557,
                -318.9963533800405,
                804.3107760368359,
                -1237.918632717931,
                1296.2158223684976,
                -973.4608401024244,
                538.019041959981,
                -220.62417088864586,
                66.65107200379778,
                -14.470851628920462,
                2.1434229444498394,
                -0.19443785394601304,
                0.008165575120843507,
            ],
            3.692477113445599,
        ),
        (
            &[
                55.31748880699925,
                -307.46580806092317,
                786.8416322838352,
                -1226.7192903219454,
                1298.4944302808046,
                -983.7361766489461,
                547.2642791726731,
                -225.3603639264815,
                68.1993479350245,
                -14.793723601986322,
                2.1832726768135093,
                -0.19677126434799247,
                0.008186314842824442,
            ],
            3.72212037932539,
        ),
    ];
    // p's f64 values there carry some 3e-10 of rounding (2 (n + 1) ε
    // Σ|c_k| s^k) where its slope is 5e-6, so f64 knows the roots to about
    // 1e-4: the width they are checked to (a render polishes a root on Q
    // formed again at it).
    let known = 1e-4;
    for (c, hi) in cases {
        let p = Poly::new(c);
        let want = exact_roots(c, 0.0, hi, 0.0).unwrap();
        assert!(want.len() >= 2, "{want:?}");
        for method in STURM {
            let s = solver(method);
            assert!(s.any(&p, 0.0, hi), "{method:?}");
            // From the start, and from midway to each next root. (From
            // just past a root the start's sign is noise to the pass, and
            // the chain here cannot count what follows: not yet solved.)
            let froms = std::iter::once(0.0).chain(want.windows(2).map(|w| 0.5 * (w[0] + w[1])));
            let got: Vec<f64> = froms
                .map(|from| s.nearest(&p, from, hi).expect("a root"))
                .collect();
            assert_near(&got, &want, known);
        }
    }
}
