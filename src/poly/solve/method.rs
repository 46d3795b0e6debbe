//! The root finder's settings: the refinement [`Method`] with its stable
//! names (parsed from the CLI and scene files), and the [`Solver`] that
//! pairs it with a tolerance and a step cap.

use std::fmt;
use std::str::FromStr;

/// How an isolated root is refined. Names are stable: the CLI, `accuracy`
/// and `bench` use them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Method {
    /// Interval halving: one bit per step, never fails.
    SturmBisect,
    /// Newton's method kept inside the bracket, halving when a step leaves
    /// it or does not shrink fast enough.
    SturmNewton,
    /// Regula falsi with the Illinois modification (halve the stale end's
    /// value), so both ends of the bracket move.
    SturmIllinois,
    /// The closed forms of [`crate::poly::closed`] for degree <= 4 (a
    /// comparison method: they decide double roots by a discriminant's sign);
    /// sturm-newton above degree 4.
    Closed,
    /// Yuksel's derivative intervals ("High-Performance Polynomial Root
    /// Finding for Graphics", HPG 2022), no Sturm chain: the roots of p'
    /// cut the interval into pieces where p is monotonic, so each holds at
    /// most one root, refined by bracketed Newton where p changes sign; the
    /// roots of p' come the same way from p'', down to a quadratic solved
    /// in closed form. A root of even multiplicity (no sign change, as at a
    /// tangent) is found only where p evaluates to exactly 0.
    Yuksel,
}

impl Method {
    pub const ALL: &'static [Method] = &[
        Method::SturmBisect,
        Method::SturmNewton,
        Method::SturmIllinois,
        Method::Closed,
        Method::Yuksel,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Method::SturmBisect => "sturm-bisect",
            Method::SturmNewton => "sturm-newton",
            Method::SturmIllinois => "sturm-illinois",
            Method::Closed => "closed",
            Method::Yuksel => "yuksel",
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Method {
    type Err = String;

    fn from_str(s: &str) -> Result<Method, String> {
        Method::ALL
            .iter()
            .copied()
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
                format!(
                    "unknown root-finding method {s:?}: expected one of {}",
                    names.join(", ")
                )
            })
    }
}

/// A root finder: the refinement method, the tolerance (see the
/// [`crate::poly::solve`] docs) and a cap on refinement steps per root,
/// which bounds the time per ray whatever the input.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Solver {
    pub method: Method,
    pub tolerance: f64,
    pub max_iterations: u32,
}

impl Default for Solver {
    /// Sturm + Newton at 1e-12; 100 steps is more than bisection needs to
    /// shrink any bracket within the root bound to 1e-12 relative.
    fn default() -> Self {
        Solver {
            method: Method::SturmNewton,
            tolerance: 1e-12,
            max_iterations: 100,
        }
    }
}
