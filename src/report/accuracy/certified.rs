//! How often the f64 path's answer fails its certificate, per degree 17 to
//! 35 (issue 17): for each polynomial, `Solver::certified` on (0, 4] either
//! keeps the f64 answer (the exact isolation proves it) or answers from the
//! exact path. The renderer's rays take the f64 answer unproven, so this is
//! how often a ray's root list at that degree would be wrong somewhere.

use std::fmt::Write as _;

use serde::Serialize;

use super::cases::by_degree;
use crate::poly::solve::{Solver, Source};

/// The degrees of the study: above the Bernstein pass's 16, up to the
/// renderer's limit.
pub const DEGREES: std::ops::RangeInclusive<usize> = 17..=35;

/// One degree's count.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Disagreement {
    pub degree: usize,
    pub polynomials: usize,
    /// The f64 answer failed the certificate (the exact path answered).
    pub f64_disagrees: usize,
}

/// Runs the default solver on `per_degree` polynomials of each degree.
pub fn run(per_degree: usize) -> Vec<Disagreement> {
    let solver = Solver::default();
    by_degree(DEGREES, per_degree)
        .into_iter()
        .map(|(degree, set)| {
            let f64_disagrees = set
                .cases
                .iter()
                .filter(|c| {
                    let answer = solver.certified(c.q.coeffs(), 0.0, c.hi);
                    !matches!(answer, Some((_, Source::F64)))
                })
                .count();
            Disagreement {
                degree,
                polynomials: set.cases.len(),
                f64_disagrees,
            }
        })
        .collect()
}

/// The table `sturmray accuracy` prints after the main one.
pub fn table(rows: &[Disagreement]) -> String {
    let mut out = String::from(
        "\nf64 answers that fail their certificate (default solver, (0, 4]):\n\
         degree  polynomials  f64 disagrees\n",
    );
    for r in rows {
        let share = 100.0 * r.f64_disagrees as f64 / r.polynomials.max(1) as f64;
        let _ = writeln!(
            out,
            "{:>6}  {:>11}  {:>6} ({share:.0}%)",
            r.degree, r.polynomials, r.f64_disagrees
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_row_per_degree_and_counts_within_the_set() {
        let rows = run(1);
        assert_eq!(rows.len(), DEGREES.count());
        assert_eq!(rows[0].degree, 17);
        assert!(
            rows.iter()
                .all(|r| r.polynomials == 1 && r.f64_disagrees <= 1)
        );
        let text = table(&rows);
        assert!(text.contains("\n    35            1"), "{text}");
    }
}
