//! How often the f64 path's answer fails its certificate, per degree 17 to
//! 35 (issue 17): the default solver's unproven f64 roots on (0, 4], checked
//! by the exact isolation at its tolerance in two senses. At the renderer's
//! (within tolerance·max(1, |t|) of its own root, the count right) a
//! failure is a ray's root list wrong somewhere; at the `roots` tool's
//! (tolerance·|t|, relative even below 1) a failure sends `roots` to the
//! exact path. Then the ray's own question, the nearest root, against the
//! exact one.

use std::fmt::Write as _;

use serde::Serialize;

use super::cases::by_degree;
use crate::poly::MAX_DEGREE;
use crate::poly::exact::{Isolation, Relative, exact_roots};
use crate::poly::solve::Solver;

/// The degrees of the study: above the Bernstein pass's 16, up to the
/// renderer's limit.
pub const DEGREES: std::ops::RangeInclusive<usize> = 17..=35;

/// One degree's counts.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Disagreement {
    pub degree: usize,
    pub polynomials: usize,
    /// Failed at the renderer's tolerance: a wrong count, or a root
    /// farther than tolerance·max(1, |t|) from its own.
    pub ray: usize,
    /// Failed at the `roots` tool's relative tolerance (these include `ray`).
    pub relative: usize,
    /// The ray's own query, `nearest` on (0, 4), missed the nearest root,
    /// invented one, or returned one farther than tolerance·max(1, |t|)
    /// from it.
    pub nearest: usize,
}

/// Runs the default solver on `per_degree` polynomials of each degree.
pub fn run(per_degree: usize) -> Vec<Disagreement> {
    let solver = Solver::default();
    let mut out = [0.0; MAX_DEGREE];
    by_degree(DEGREES, per_degree)
        .into_iter()
        .map(|(degree, set)| {
            let (mut ray, mut relative, mut nearest) = (0, 0, 0);
            for c in &set.cases {
                let first = exact_roots(c.q.coeffs(), 0.0, c.hi, 0.0)
                    .and_then(|roots| roots.into_iter().find(|&t| t < c.hi));
                let got = solver.nearest(&c.q, 0.0, c.hi);
                let right = match (got, first) {
                    (None, None) => true,
                    (Some(t), Some(want)) => {
                        (t - want).abs() <= solver.tolerance * want.abs().max(1.0) * (1.0 + 1e-9)
                    }
                    _ => false,
                };
                nearest += usize::from(!right);
                let n = solver.unproven_roots(&c.q, 0.0, c.hi, &mut out);
                let Some(isolation) = Isolation::new(c.q.coeffs(), 0.0, c.hi) else {
                    continue;
                };
                let fails = |r| !isolation.certifies(&out[..n], solver.tolerance, r);
                ray += usize::from(fails(Relative::MagnitudeOrOne));
                relative += usize::from(fails(Relative::Magnitude));
            }
            Disagreement {
                degree,
                polynomials: set.cases.len(),
                ray,
                relative,
                nearest,
            }
        })
        .collect()
}

/// The table `sturmray accuracy` prints after the main one.
pub fn table(rows: &[Disagreement]) -> String {
    let mut out = String::from(
        "\nf64 answers that fail their exact certificate (default solver, (0, 4]):\n\
         degree  polynomials  at max(1,|t|)·tol  at |t|·tol (roots)  nearest (rays)\n",
    );
    for r in rows {
        let share = |k: usize| 100.0 * k as f64 / r.polynomials.max(1) as f64;
        let _ = writeln!(
            out,
            "{:>6}  {:>11}  {:>10} ({:>3.0}%)  {:>11} ({:>3.0}%)  {:>7} ({:>3.0}%)",
            r.degree,
            r.polynomials,
            r.ray,
            share(r.ray),
            r.relative,
            share(r.relative),
            r.nearest,
            share(r.nearest)
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
        assert!(rows.iter().all(|r| r.polynomials == 1
            && r.ray <= r.relative
            && r.relative <= 1
            && r.nearest <= 1));
        let text = table(&rows);
        assert!(text.contains("\n    35            1"), "{text}");
    }
}
