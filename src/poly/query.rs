//! One `roots` query: a polynomial, an interval, a method and a tolerance,
//! checked and answered with its certificate. The CLI's `roots` (JSON lines)
//! and the Python module's `sturmray.roots` both answer through here, so
//! they give the same roots and the same messages.

use super::MAX_DEGREE;
use super::exact::{Certificate, Isolation, MAX_EXACT_DEGREE, Relative};
use super::solve::{Method, Solver, Source};
use super::univariate::nonzero;

/// The method name of the exact rational path (not a renderer method: it allocates).
pub const EXACT: &str = "exact";

/// The interval when none is given: every root an f64 can hold (a root
/// beyond ±MAX has no f64 to print).
pub const DEFAULT_INTERVAL: [f64; 2] = [-f64::MAX, f64::MAX];

/// A query as asked; `None` takes the default.
#[derive(Clone, Debug, Default)]
pub struct Query {
    /// Lowest degree first.
    pub coeffs: Vec<f64>,
    pub interval: Option<[f64; 2]>,
    pub method: Option<String>,
    pub tolerance: Option<f64>,
}

/// The answer: the certificate (its `values()` are the roots) and which
/// path found the roots, as `--explain` names it.
pub struct Answer {
    pub certificate: Certificate,
    pub found_by: String,
}

impl Query {
    /// The interval asked for, or the default.
    pub fn interval(&self) -> [f64; 2] {
        self.interval.unwrap_or(DEFAULT_INTERVAL)
    }

    /// Checks the query and solves it; Err is the message for the user.
    pub fn answer(&self) -> Result<Answer, String> {
        let coeffs = &self.coeffs;
        if coeffs.is_empty() || coeffs.len() > MAX_EXACT_DEGREE + 1 {
            return Err(format!(
                "coeffs: expected 1 to {} numbers (degree <= {MAX_EXACT_DEGREE}), found {}",
                MAX_EXACT_DEGREE + 1,
                coeffs.len()
            ));
        }
        let not_finite = "coeffs: every coefficient must be finite";
        if coeffs.iter().any(|c| !c.is_finite()) {
            return Err(not_finite.into());
        }
        // From the bits: this thread reads subnormals as zero, and a subnormal
        // coefficient is an ordinary nonzero number here.
        match coeffs.iter().rposition(|&c| nonzero(c)) {
            None => {
                return Err("the polynomial is identically zero (every coefficient is 0)".into());
            }
            Some(0) => return Err("the polynomial is a nonzero constant: it has no roots".into()),
            Some(_) => {}
        }
        let [a, b] = self.interval();
        if !(a.is_finite() && b.is_finite() && a < b) {
            return Err(format!("interval: expected finite a < b, found [{a}, {b}]"));
        }
        let mut solver = Solver::default();
        if let Some(t) = self.tolerance {
            if !(t > 0.0 && t < 1.0) {
                return Err(format!("tolerance: expected a number in (0, 1), found {t}"));
            }
            solver.tolerance = t;
        }
        // Both answers carry the same proof: the exact path's brackets, or the
        // windows around the f64 roots that `Solver::certified` proved.
        let (certificate, found_by) = match self.method.as_deref() {
            Some(EXACT) => Isolation::new(coeffs, a, b)
                .and_then(|isolation| isolation.solve(solver.tolerance, Relative::Magnitude))
                .map(|c| (c, EXACT.to_string()))
                .ok_or(not_finite)?,
            name => {
                if let Some(name) = name {
                    solver.method = name
                        .parse::<Method>()
                        .map_err(|e| format!("{e}, {EXACT}"))?;
                }
                let (c, source) = solver.certified(coeffs, a, b).ok_or(not_finite)?;
                let by = match source {
                    Source::F64 => solver.method.name().to_string(),
                    Source::Exact if coeffs.len() > MAX_DEGREE + 1 => {
                        format!("{EXACT} (degree above {MAX_DEGREE}: no f64 path)")
                    }
                    Source::Exact => {
                        format!("{EXACT} (the {} answer failed)", solver.method.name())
                    }
                };
                (c, by)
            }
        };
        Ok(Answer {
            certificate,
            found_by,
        })
    }
}
