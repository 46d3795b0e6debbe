//! The exact (rational) polynomial path: the reference the f64 solver is
//! tested against, the certificate every `sturmray roots` answer passes
//! ([`Isolation`]: the exact count, and each f64 root alone within the
//! tolerance of one exact root), and the answer when it does not.
//!
//! Why exact: every finite f64 is a dyadic rational, so the polynomial an f64
//! caller means is known exactly. Floating-point Sturm sequences blur multiple
//! roots (a double root has no sign change, and remainders that should vanish
//! come out as rounding noise), so they miss exactly the cases tests care
//! about most, like (x−1)³. Here the square-free part p / gcd(p, p′) is
//! computed exactly, its Sturm chain is exact, and so are the counts.
//!
//! How the numbers stay small:
//! - Inside, every polynomial is an *integer* polynomial (the input scaled by
//!   a power of two and divided by its content), never a vector of reduced
//!   fractions: no gcd per arithmetic operation.
//! - gcds and the Sturm chain come from the subresultant pseudo-remainder
//!   sequence, whose exact divisions bound coefficient growth without taking
//!   any integer gcd (a primitive PRS needs one per member, and with
//!   coefficients spanning 1e±144 those took seconds). Each member's sign is
//!   tracked so it is a *positive* multiple of the true Sturm remainder
//!   (ARCHITECTURE.md: never normalise by a factor that may be negative). For a
//!   square-free input, the sequence that proves gcd(p, p′) = 1 is itself
//!   the Sturm chain, so it is built once.
//! - Evaluation points are dyadic, m·2^e: midpoints of dyadic endpoints stay
//!   dyadic, and the sign of p(m/2^k) is the sign of the homogeneous integer
//!   sum Σ cᵢ·mⁱ·2^(k(n−i)), so isolating and refining never take a gcd.
//! - Wide brackets are cut at powers of two (a bisection of the exponent)
//!   before they are cut at midpoints, so a root bound of 2^1000 or a root
//!   near 1e-300 costs tens of steps, and numerators carry only the bits the
//!   root needs.
//! - Work is capped by f64 resolution: once every point of a bracket rounds to
//!   the same f64 the bracket is finished, so clusters of roots closer than an
//!   ulp end as one f64 value repeated (once per distinct root) instead of
//!   thousands of bisections.
//!
//! This file is the API the crate calls; `isolate` isolates and refines,
//! `dyadic` holds the evaluation points, and `ipoly` the integer polynomials
//! with the subresultant sequence.

mod certificate;
mod dyadic;
mod ipoly;
mod isolate;

pub use certificate::{Certificate, CertifiedRoot};

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Zero};

use certificate::{Found, Span};
use dyadic::Dyadic;
use ipoly::{
    IPoly, count_variations, count_variations_dyadic, gcd_int, ipoly_gcd, primitive, sign_dyadic,
    sign_rational, square_free_and_chain, square_free_ipoly,
};
use isolate::{Input, Point, Solved};

/// The highest degree `sturmray roots` answers. Everything here is
/// heap-allocated, so the limit is one of cost, not of storage: the exact
/// Sturm chain of a degree-n input with 53-bit coefficients holds about n²/2
/// integers of up to about 2·53·n bits (measured in docs/accuracy.md).
pub const MAX_EXACT_DEGREE: usize = 128;

/// A polynomial with exact rational coefficients, lowest degree first.
///
/// Kept trimmed (no zero leading coefficient), so `PartialEq` compares
/// polynomials, not representations.
#[derive(Clone, Debug, PartialEq)]
pub struct ExactPoly {
    coeffs: Vec<BigRational>,
}

impl ExactPoly {
    /// Exact conversion of finite f64 coefficients (every finite f64 is a
    /// dyadic rational). Returns None if any coefficient is NaN or infinite.
    pub fn from_f64(coeffs: &[f64]) -> Option<ExactPoly> {
        let coeffs = coeffs
            .iter()
            .map(|&c| BigRational::from_float(c))
            .collect::<Option<Vec<_>>>()?;
        Some(ExactPoly::from_rationals(coeffs))
    }

    /// A polynomial from rational coefficients, lowest degree first (trailing
    /// zeros are dropped).
    pub fn from_rationals(mut coeffs: Vec<BigRational>) -> ExactPoly {
        while coeffs.last().is_some_and(Zero::is_zero) {
            coeffs.pop();
        }
        ExactPoly { coeffs }
    }

    /// The coefficients, lowest degree first, without trailing zeros (empty
    /// for the zero polynomial).
    pub fn coefficients(&self) -> &[BigRational] {
        &self.coeffs
    }

    /// True for the zero polynomial (which has every number as a root, so
    /// the root finders report none).
    pub fn is_zero(&self) -> bool {
        self.coeffs.is_empty()
    }

    /// The degree; 0 for constants and for the zero polynomial.
    pub fn degree(&self) -> usize {
        self.coeffs.len().saturating_sub(1)
    }

    /// The derivative, exactly.
    pub fn derivative(&self) -> ExactPoly {
        let coeffs = self
            .coeffs
            .iter()
            .enumerate()
            .skip(1)
            .map(|(i, c)| c * BigRational::from_integer(BigInt::from(i)))
            .collect();
        ExactPoly::from_rationals(coeffs)
    }

    /// The greatest common divisor, monic (leading coefficient 1) so it is
    /// unique; zero only if both are zero. Computed on primitive integer
    /// polynomials (a primitive PRS), which keeps the numbers small.
    pub fn gcd(&self, other: &ExactPoly) -> ExactPoly {
        let g = ipoly_gcd(&self.to_ipoly(), &other.to_ipoly());
        let Some(lead) = g.last() else {
            return ExactPoly::from_rationals(Vec::new());
        };
        let coeffs = g
            .iter()
            .map(|c| BigRational::new(c.clone(), lead.clone()))
            .collect();
        ExactPoly::from_rationals(coeffs)
    }

    /// p / gcd(p, p′) with the monic gcd: the same distinct roots, all simple,
    /// and the same leading coefficient as p. The zero polynomial stays zero.
    pub fn square_free(&self) -> ExactPoly {
        let Some(lead) = self.coeffs.last() else {
            return self.clone();
        };
        let q = square_free_ipoly(&self.to_ipoly());
        // q is a positive or negative integer multiple of the answer; rescale
        // so the leading coefficients agree.
        let scale = lead / BigRational::from_integer(q[q.len() - 1].clone());
        let coeffs = q
            .into_iter()
            .map(|c| BigRational::from_integer(c) * &scale)
            .collect();
        ExactPoly::from_rationals(coeffs)
    }

    /// The sign of p(x): -1, 0 or 1 (0 everywhere for the zero polynomial).
    pub fn sign_at(&self, x: &BigRational) -> i32 {
        sign_rational(&self.to_ipoly(), x)
    }

    /// The primitive integer polynomial that is a positive multiple of this
    /// one (multiply by the lcm of the denominators, divide by the content).
    fn to_ipoly(&self) -> IPoly {
        let mut lcm = BigInt::one();
        for c in &self.coeffs {
            let d = c.denom();
            lcm = &lcm / gcd_int(&lcm, d) * d;
        }
        let p = self
            .coeffs
            .iter()
            .map(|c| c.numer() * (&lcm / c.denom()))
            .collect();
        primitive(p)
    }
}

/// The exact Sturm chain of a polynomial's square-free part, for exact counts
/// of distinct real roots.
///
/// Members are primitive integer polynomials, each a positive multiple of the
/// classical member (p, p′, −rem, …), so sign variations are exact.
#[derive(Clone, Debug)]
pub struct ExactSturm {
    chain: Vec<IPoly>,
}

impl ExactSturm {
    /// The chain of the square-free part of p (empty for the zero polynomial,
    /// which then counts no roots).
    pub fn new(p: &ExactPoly) -> ExactSturm {
        let p = p.to_ipoly();
        if p.is_empty() {
            return ExactSturm { chain: Vec::new() };
        }
        ExactSturm {
            chain: square_free_and_chain(&p).1,
        }
    }

    /// Distinct real roots in (a, b], exactly; 0 if a >= b.
    ///
    /// (a, b] rather than [a, b]: at a root of a square-free p the variation
    /// count equals its value just right of the root, so V(a) − V(b) counts
    /// a root at b and not one at a, even when a or b is a root.
    pub fn count(&self, a: &BigRational, b: &BigRational) -> usize {
        if a >= b {
            return 0;
        }
        self.variations(a).saturating_sub(self.variations(b))
    }

    /// The number of sign variations of the chain at x (zeros skipped).
    pub fn variations(&self, x: &BigRational) -> usize {
        count_variations(self.chain.iter().map(|p| sign_rational(p, x)))
    }

    /// The number of members in the chain (degree of the square-free part
    /// plus one, or 0 for the zero polynomial).
    pub fn len(&self) -> usize {
        self.chain.len()
    }

    /// True only for the chain of the zero polynomial.
    pub fn is_empty(&self) -> bool {
        self.chain.is_empty()
    }
}

/// All distinct real roots in (a, b] of the polynomial with these f64
/// coefficients (lowest degree first), increasing.
///
/// Each is the correctly rounded f64 of the root, or the f64 of the midpoint
/// of a bracket of width ≤ `tolerance`·max(1, |root|) (exact comparison),
/// whichever is reached first; pass 0 for correctly rounded roots. A
/// tolerance looser than 2^-30 (≈ 9.3e-10) is tightened to 2^-30: refining is
/// cheap here, and it makes the exactness below hold for any tolerance. A
/// root that is a rational number (like 1 in (x−1)³, or 1/3) is found
/// exactly when it is the simplest rational in its bracket — always for
/// denominators up to 2^15 in [−1, 1] and integers up to 2^30 — and is then
/// returned as its correctly rounded f64.
///
/// Endpoints may be infinite (clipped to an exact root bound). Distinct roots
/// closer together than f64 resolution come out as one f64 repeated once per
/// root, so the length always equals [`exact_count`]. The zero polynomial and
/// constants have no roots here. None if a coefficient is NaN or infinite or
/// an endpoint or the tolerance is NaN; a negative tolerance acts as 0.
pub fn exact_roots(coeffs: &[f64], a: f64, b: f64, tolerance: f64) -> Option<Vec<f64>> {
    Isolation::new(coeffs, a, b)?.roots(tolerance, Relative::MagnitudeOrOne)
}

/// The exact count of distinct real roots in (a, b] (0 if a >= b, and for the
/// zero polynomial). Endpoints may be infinite. None if a coefficient is NaN
/// or infinite or an endpoint is NaN.
pub fn exact_count(coeffs: &[f64], a: f64, b: f64) -> Option<usize> {
    Some(Isolation::new(coeffs, a, b)?.count())
}

/// The exact isolation of the distinct real roots in (a, b] of the
/// polynomial with these f64 coefficients: the one source of truth for how
/// many roots there are and where, which f64 answers are checked against
/// ([`Isolation::certifies`]) and which answers itself when they fail
/// ([`Isolation::roots`]). Built once (the exact Sturm chain is the costly
/// part), then each check costs a few exact evaluations of the chain.
pub struct Isolation {
    input: Input,
    /// Sign variations of the chain at the clipped ends (lo, hi].
    variations: [usize; 2],
    count: usize,
}

impl Isolation {
    /// None if a coefficient is NaN or infinite or an endpoint is NaN;
    /// endpoints may be infinite. Subnormal coefficients are ordinary
    /// nonzero numbers here; only the all-zero polynomial is zero.
    pub fn new(coeffs: &[f64], a: f64, b: f64) -> Option<Isolation> {
        let input = Input::new(coeffs, a, b)?;
        let variations = input.interval.as_ref().map_or([0, 0], |(lo, hi)| {
            [
                count_variations_dyadic(&input.chain, lo),
                count_variations_dyadic(&input.chain, hi),
            ]
        });
        let count = variations[0].saturating_sub(variations[1]);
        Some(Isolation {
            input,
            variations,
            count,
        })
    }

    /// The exact number of distinct real roots in (a, b].
    pub fn count(&self) -> usize {
        self.count
    }

    /// Whether `roots` is a right answer to within `tolerance`, proven
    /// exactly: they are as many as [`Isolation::count`], increasing, in
    /// (a, b], and each r is alone with one exact root in its own interval
    /// (r − w, r + w], w = tolerance·scale(r) (see [`Relative`]), these
    /// intervals disjoint. Disjoint intervals holding one root each, as many
    /// as there are roots, pair every root with exactly one listed value
    /// within w of it. Where w is 0 (r = 0 with [`Relative::Magnitude`]) r
    /// must be a root itself. A tolerance that is not positive and finite
    /// proves nothing but an empty answer.
    pub fn certifies(&self, roots: &[f64], tolerance: f64, relative: Relative) -> bool {
        self.windows(roots, tolerance, relative).is_some()
    }

    /// [`Isolation::certifies`] with its proof: the certificate of `roots`
    /// (each window, the root's multiplicity and error bound), or None.
    pub fn certify(
        &self,
        roots: &[f64],
        tolerance: f64,
        relative: Relative,
    ) -> Option<Certificate> {
        let found = self.windows(roots, tolerance, relative)?;
        let interval = self.input.interval.as_ref();
        Some(certificate::certify(
            &self.input,
            interval,
            self.variations,
            found,
        ))
    }

    /// The windows that prove `roots`, or None: see [`Isolation::certifies`].
    fn windows(&self, roots: &[f64], tolerance: f64, relative: Relative) -> Option<Vec<Found>> {
        if roots.len() != self.count {
            return None;
        }
        let Some((lo, hi)) = &self.input.interval else {
            return roots.is_empty().then(Vec::new);
        };
        if !(tolerance > 0.0 && tolerance.is_finite()) {
            return roots.is_empty().then(Vec::new);
        }
        let tol = Dyadic::from_f64(tolerance);
        let mut previous_end = lo.clone();
        let mut found = Vec::with_capacity(roots.len());
        for &r in roots {
            if !(r.is_finite() && self.input.a < r && r <= self.input.b) {
                return None;
            }
            let x = Dyadic::from_f64(r);
            let w = tol.mul(&relative.scale(x.abs()));
            let (start, end) = (x.sub(&w).max(lo.clone()), x.add(&w).min(hi.clone()));
            let span = if w.is_zero() {
                let alone =
                    previous_end < x && x <= *hi && sign_dyadic(&self.input.square_free, &x) == 0;
                alone.then(|| Span::At(x.clone()))
            } else {
                let alone = start >= previous_end
                    && start < end
                    && count_variations_dyadic(&self.input.chain, &start)
                        .saturating_sub(count_variations_dyadic(&self.input.chain, &end))
                        == 1;
                alone.then(|| Span::Interval {
                    lo: start,
                    hi: Point::Dyadic(end.clone()),
                    distinct: 1,
                })
            };
            found.push(Found {
                value: r,
                span: span?,
            });
            previous_end = if w.is_zero() { x } else { end };
        }
        Some(found)
    }

    /// The exact path's answer with its certificate: every distinct root
    /// in (a, b] as [`Isolation::roots`] gives it, each with the bracket it
    /// was refined in. None if the tolerance is NaN.
    pub fn solve(self, tolerance: f64, relative: Relative) -> Option<Certificate> {
        let variations = self.variations;
        let interval = self.input.interval.clone();
        let Solved { input, groups } = Solved::new(self.input, tolerance, relative)?;
        let found = groups
            .into_iter()
            .map(|g| Found {
                value: g.value,
                span: Span::Interval {
                    lo: g.lo,
                    hi: g.hi,
                    distinct: g.count,
                },
            })
            .collect();
        Some(certificate::certify(
            &input,
            interval.as_ref(),
            variations,
            found,
        ))
    }

    /// Every distinct real root in (a, b], increasing, as many as
    /// [`Isolation::count`]: see [`exact_roots`] for what each value is
    /// (there with [`Relative::MagnitudeOrOne`]). None if the tolerance is
    /// NaN.
    pub fn roots(self, tolerance: f64, relative: Relative) -> Option<Vec<f64>> {
        let solved = Solved::new(self.input, tolerance, relative)?;
        let roots: Vec<f64> = solved
            .groups
            .iter()
            .flat_map(|g| std::iter::repeat_n(g.value, g.count))
            .collect();
        debug_assert_eq!(roots.len(), self.count, "one value per isolated root");
        Some(roots)
    }
}

/// What a tolerance is relative to, at a root x.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Relative {
    /// max(1, |x|): relative above 1, absolute below, so a root at 0 costs
    /// finite work in f64 (the renderer's and [`crate::poly::solve::Solver`]'s
    /// tolerance).
    MagnitudeOrOne,
    /// |x|: relative everywhere (the `roots` tool's promise, so 1e-14 is
    /// not answered with 1.4e-14); a root at 0 is then found exactly.
    Magnitude,
}

impl Relative {
    fn scale(self, magnitude: Dyadic) -> Dyadic {
        match self {
            Relative::MagnitudeOrOne => magnitude.max(Dyadic::pow2(0)),
            Relative::Magnitude => magnitude,
        }
    }
}

/// Each distinct real root in (a, b] with its multiplicity, increasing, for
/// reports. Roots are as in [`exact_roots`] (same values, same order); the
/// multiplicities come from the square-free factorisation p = ∏ fₖᵏ (repeated
/// gcds, exact), each root's factor found by exact Sturm counts of the fₖ on
/// its final bracket.
pub fn exact_roots_with_multiplicity(
    coeffs: &[f64],
    a: f64,
    b: f64,
    tolerance: f64,
) -> Option<Vec<(f64, u32)>> {
    let certificate = Isolation::new(coeffs, a, b)?.solve(tolerance, Relative::MagnitudeOrOne)?;
    Some(
        certificate
            .roots
            .iter()
            .map(|r| (r.value, r.multiplicity))
            .collect(),
    )
}

#[cfg(test)]
mod tests;
