//! Polynomials: univariate ones in f64 with Sturm sequences, root isolation
//! and refinement, closed forms, an exact rational path for ill-conditioned
//! inputs; trivariate ones parsed from expressions, with a ray substituted.

/// The highest degree sturmray handles anywhere: it sizes the fixed Sturm
/// storage (no allocation per ray) and bounds the expression parser. 35 is
/// POV-Ray's limit for `poly`, so its scenes fit; polynomials of degree 16
/// or less are solved in smaller storage (`univariate::SMALL_SLOTS`, and
/// `QUARTIC_SLOTS` for degree 4 or less).
pub const MAX_DEGREE: usize = 35;

pub mod closed;
pub mod exact;
pub mod expr;
pub mod query;
pub mod solve;
pub mod sturm;
pub mod trivariate;
pub mod univariate;
