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

use std::cmp::Ordering;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{Float, One, Signed, ToPrimitive, Zero};

/// An integer polynomial, lowest degree first, with no trailing zeros (the
/// zero polynomial is empty). Only used inside this module.
type IPoly = Vec<BigInt>;

// ---------------------------------------------------------------------------
// Public API
// ---------------------------------------------------------------------------

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
    count: usize,
}

impl Isolation {
    /// None if a coefficient is NaN or infinite or an endpoint is NaN;
    /// endpoints may be infinite. Subnormal coefficients are ordinary
    /// nonzero numbers here; only the all-zero polynomial is zero.
    pub fn new(coeffs: &[f64], a: f64, b: f64) -> Option<Isolation> {
        let input = Input::new(coeffs, a, b)?;
        let count = input.interval.as_ref().map_or(0, |(lo, hi)| {
            count_variations_dyadic(&input.chain, lo)
                .saturating_sub(count_variations_dyadic(&input.chain, hi))
        });
        Some(Isolation { input, count })
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
        if roots.len() != self.count {
            return false;
        }
        let Some((lo, hi)) = &self.input.interval else {
            return roots.is_empty();
        };
        if !(tolerance > 0.0 && tolerance.is_finite()) {
            return roots.is_empty();
        }
        let tol = Dyadic::from_f64(tolerance);
        let mut previous_end = lo.clone();
        for &r in roots {
            if !(r.is_finite() && self.input.a < r && r <= self.input.b) {
                return false;
            }
            let x = Dyadic::from_f64(r);
            let w = tol.mul(&relative.scale(x.abs()));
            let (start, end) = (x.sub(&w).max(lo.clone()), x.add(&w).min(hi.clone()));
            let alone = if w.is_zero() {
                previous_end < x && x <= *hi && sign_dyadic(&self.input.square_free, &x) == 0
            } else {
                start >= previous_end
                    && start < end
                    && count_variations_dyadic(&self.input.chain, &start)
                        .saturating_sub(count_variations_dyadic(&self.input.chain, &end))
                        == 1
            };
            if !alone {
                return false;
            }
            previous_end = end;
        }
        true
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
    let Solved { input, groups } = Solved::new(
        Input::new(coeffs, a, b)?,
        tolerance,
        Relative::MagnitudeOrOne,
    )?;
    if groups.is_empty() {
        return Some(Vec::new());
    }
    let factors: Vec<(Vec<IPoly>, u32)> = if input.square_free.len() == input.poly.len() {
        // Already square-free: one factor, whose chain is at hand.
        vec![(input.chain, 1)]
    } else {
        square_free_factors(&input.poly)
            .into_iter()
            .map(|(f, k)| (sturm_chain(f), k))
            .collect()
    };
    let mut out = Vec::new();
    for g in &groups {
        let mut found = 0;
        for (chain, k) in &factors {
            let v_lo = count_variations_dyadic(chain, &g.lo);
            let v_hi = match &g.hi {
                Point::Dyadic(d) => count_variations_dyadic(chain, d),
                Point::Rational(r) => count_variations(chain.iter().map(|p| sign_rational(p, r))),
            };
            let n = v_lo.saturating_sub(v_hi);
            found += n;
            out.extend(std::iter::repeat_n((g.value, *k), n));
        }
        debug_assert_eq!(
            found, g.count,
            "factor counts must add up to the group's count"
        );
    }
    Some(out)
}

// ---------------------------------------------------------------------------
// Solving
// ---------------------------------------------------------------------------

/// The shared front end: the input as a primitive integer polynomial, its
/// square-free part with that part's Sturm chain, and the interval clipped to
/// an exact root bound.
struct Input {
    poly: IPoly,
    square_free: IPoly,
    chain: Vec<IPoly>,
    /// (lo, hi] with lo < hi, or None when no root can lie in the interval.
    interval: Option<(Dyadic, Dyadic)>,
    /// The interval (a, b] as asked.
    a: f64,
    b: f64,
}

impl Input {
    fn new(coeffs: &[f64], a: f64, b: f64) -> Option<Input> {
        if a.is_nan() || b.is_nan() {
            return None;
        }
        let poly = ipoly_from_f64(coeffs)?;
        if poly.len() <= 1 {
            // Zero or a nonzero constant: no isolated roots.
            return Some(Input {
                chain: sturm_chain(poly.clone()),
                poly: poly.clone(),
                square_free: poly,
                interval: None,
                a,
                b,
            });
        }
        let (square_free, chain) = square_free_and_chain(&poly);
        // Every root lies strictly inside (−B, B), so (a, b] ∩ (−B, B] has the
        // same roots and finite, dyadic ends.
        let bound = Dyadic::pow2(upper_root_exp(&square_free));
        let lo = if a == f64::NEG_INFINITY {
            bound.neg()
        } else {
            Dyadic::from_f64(a).max(bound.neg())
        };
        let hi = if b == f64::INFINITY {
            bound
        } else {
            Dyadic::from_f64(b).min(bound)
        };
        let interval =
            (a != f64::INFINITY && b != f64::NEG_INFINITY && lo < hi).then_some((lo, hi));
        Some(Input {
            poly,
            square_free,
            chain,
            interval,
            a,
            b,
        })
    }
}

/// One finished bracket (lo, hi] holding `count` distinct roots, all with the
/// f64 value `value` (count > 1 only when they are closer than f64 resolution).
struct Group {
    lo: Dyadic,
    hi: Point,
    count: usize,
    value: f64,
}

/// A bracket end: dyadic from bisection, or a rational root found exactly.
enum Point {
    Dyadic(Dyadic),
    Rational(BigRational),
}

struct Solved {
    input: Input,
    groups: Vec<Group>,
}

impl Solved {
    fn new(mut input: Input, tolerance: f64, relative: Relative) -> Option<Solved> {
        if tolerance.is_nan() {
            return None;
        }
        let groups = match input.interval.take() {
            None => Vec::new(),
            Some((lo, hi)) => {
                let loosest = Dyadic::pow2(LOOSEST_TOLERANCE_EXP);
                let tol = Tolerance {
                    tol: Dyadic::from_f64(tolerance.max(0.0)).min(loosest),
                    relative,
                };
                isolate(&input.square_free, &input.chain, lo, hi, &tol)
            }
        };
        Some(Solved { input, groups })
    }
}

/// Tolerances looser than 2^-30 are tightened to it. Refinement is cheap
/// here (one evaluation of q per halving), and a bracket of width ≤ 2^-30
/// around a root in [−1, 1] holds at most one rational with denominator
/// ≤ 2^15 (two such differ by ≥ 2^-30), so the simplest-rational test then
/// finds every such rational root exactly (integers up to |x| < 2^30). A
/// loose tolerance like 0.1 would otherwise stop with a bracket holding
/// both 11 and 12 and return its midpoint instead of the root 12.
const LOOSEST_TOLERANCE_EXP: i64 = -30;

/// Stop refining when width <= tol · scale(x) for every x in the bracket
/// (0: never, refine to f64 resolution).
struct Tolerance {
    tol: Dyadic,
    relative: Relative,
}

impl Tolerance {
    fn met(&self, lo: &Dyadic, hi: &Dyadic) -> bool {
        if self.tol.is_zero() {
            return false;
        }
        let width = hi.sub(lo);
        // The smallest |x| over the bracket (0 if it straddles 0).
        let straddles = lo.signum() < 0 && hi.signum() > 0;
        let smallest = if straddles {
            Dyadic::zero()
        } else {
            lo.abs().min(hi.abs())
        };
        width <= self.tol.mul(&self.relative.scale(smallest))
    }
}

/// Safety net on refinement steps; the f64-resolution stop is reached far
/// sooner (exponent bisection, then ≤ ~60 halvings, then a boundary cut).
const MAX_REFINE_STEPS: usize = 4096;

/// How often refinement tries the simplest rational in the bracket as an
/// exact root (one extra evaluation every so many steps).
const RATIONAL_TRY_EVERY: usize = 8;

/// Isolates the roots of the square-free q (Sturm chain `chain`) in (lo, hi]
/// by exact Sturm counts and refines each; groups come out in increasing
/// order.
fn isolate(q: &IPoly, chain: &[IPoly], lo: Dyadic, hi: Dyadic, tol: &Tolerance) -> Vec<Group> {
    let min_exp = lower_root_exp(q);
    let v_lo = count_variations_dyadic(chain, &lo);
    let v_hi = count_variations_dyadic(chain, &hi);
    let mut out = Vec::new();
    // Depth-first, left half first, so groups come out sorted.
    let mut stack = vec![(lo, hi, v_lo, v_hi)];
    while let Some((lo, hi, v_lo, v_hi)) = stack.pop() {
        let count = v_lo.saturating_sub(v_hi);
        match count {
            0 => {}
            1 => out.push(refine(q, lo, hi, min_exp, tol)),
            _ => match next_cut(&lo, &hi, min_exp, false) {
                Cut::Covered(value) => out.push(Group {
                    lo,
                    hi: Point::Dyadic(hi),
                    count,
                    value,
                }),
                Cut::At { at, .. } => {
                    let v_at = count_variations_dyadic(chain, &at);
                    stack.push((at.clone(), hi, v_at, v_hi));
                    stack.push((lo, at, v_lo, v_at));
                }
            },
        }
    }
    out
}

/// Refines the single root of the square-free q in (lo, hi] by bisection on
/// q's sign (the root is simple, so q changes sign there). Only the sign at
/// hi is used: lo may itself be the previous root, where q is zero.
fn refine(q: &IPoly, lo: Dyadic, hi: Dyadic, min_exp: i64, tol: &Tolerance) -> Group {
    let s_hi = sign_dyadic(q, &hi);
    if s_hi == 0 {
        let value = hi.to_f64();
        return Group {
            lo,
            hi: Point::Dyadic(hi),
            count: 1,
            value,
        };
    }
    let (mut lo, mut hi) = (lo, hi);
    let mut last_value = lo.mid(&hi).to_f64();
    for step in 0..MAX_REFINE_STEPS {
        if step % RATIONAL_TRY_EVERY == 0
            && let Some(g) = try_rational(q, &lo, &hi)
        {
            return g;
        }
        match next_cut(&lo, &hi, min_exp, true) {
            Cut::Covered(value) => {
                return Group {
                    lo,
                    hi: Point::Dyadic(hi),
                    count: 1,
                    value,
                };
            }
            Cut::At { at, mid_value } => {
                if tol.met(&lo, &hi) {
                    return try_rational(q, &lo, &hi).unwrap_or(Group {
                        lo,
                        hi: Point::Dyadic(hi),
                        count: 1,
                        value: mid_value,
                    });
                }
                last_value = mid_value;
                match sign_dyadic(q, &at) {
                    0 => {
                        let value = at.to_f64();
                        return Group {
                            lo,
                            hi: Point::Dyadic(at),
                            count: 1,
                            value,
                        };
                    }
                    s if s == s_hi => hi = at,
                    _ => lo = at,
                }
            }
        }
    }
    Group {
        lo,
        hi: Point::Dyadic(hi),
        count: 1,
        value: last_value,
    }
}

/// If the simplest rational strictly inside (lo, hi) is a root of q, the
/// group for it. Bisection alone never lands on a root like 1 when the
/// bracket started as (0, 3]; but a rational root p/s is the simplest
/// rational in any bracket around it narrower than about 1/s².
fn try_rational(q: &IPoly, lo: &Dyadic, hi: &Dyadic) -> Option<Group> {
    let c = simplest_between(&lo.to_rational(), &hi.to_rational());
    if sign_rational(q, &c) != 0 {
        return None;
    }
    let value = c.to_f64().unwrap_or(f64::NAN);
    Some(Group {
        lo: lo.clone(),
        hi: Point::Rational(c),
        count: 1,
        value,
    })
}

/// The next step for a bracket (lo, hi].
enum Cut {
    /// Every candidate root in the bracket rounds to this f64: finished.
    Covered(f64),
    /// Cut at `at` (strictly inside); `mid_value` is the midpoint's f64.
    At { at: Dyadic, mid_value: f64 },
}

/// Decides whether (lo, hi] is finished at f64 resolution and otherwise where
/// to cut it: at a rounding boundary once the bracket is narrower than an
/// ulp's region (so a root near a half-way point is settled in one cut
/// instead of bisecting towards it forever), else at a power of two or the
/// midpoint ([`split_point`]). `hi_excluded` says hi is known not to be a
/// root, so hi itself need not round to the same f64.
fn next_cut(lo: &Dyadic, hi: &Dyadic, min_exp: i64, hi_excluded: bool) -> Cut {
    let mid = lo.mid(hi);
    let f = mid.to_f64();
    let (l, u) = rounding_region(f);
    let lo_in = l.as_ref().is_none_or(|l| l <= lo);
    let hi_in = u.as_ref().is_none_or(|u| hi <= u) && (hi_excluded || hi.to_f64() == f);
    if lo_in && hi_in {
        return Cut::Covered(f);
    }
    if let (Some(l), Some(u)) = (&l, &u)
        && hi.sub(lo) < u.sub(l)
    {
        for boundary in [l, u] {
            if lo < boundary && boundary < hi {
                return Cut::At {
                    at: boundary.clone(),
                    mid_value: f,
                };
            }
        }
    }
    Cut::At {
        at: split_point(lo, hi, min_exp),
        mid_value: f,
    }
}

/// A cut strictly inside (lo, hi): 0 if the bracket straddles it; a power of
/// two near the geometric mean if the ends differ by more than a factor 16
/// (no root of q has magnitude ≤ 2^min_exp except 0, so an end at 0 counts
/// as 2^min_exp); otherwise the midpoint.
fn split_point(lo: &Dyadic, hi: &Dyadic, min_exp: i64) -> Dyadic {
    if lo.signum() < 0 && hi.signum() > 0 {
        return Dyadic::zero();
    }
    if lo.signum() >= 0 {
        geometric_or_mid(lo, hi, min_exp)
    } else {
        geometric_or_mid(&hi.neg(), &lo.neg(), min_exp).neg()
    }
}

/// For 0 <= lo < hi: with e_lo = ⌊log2 max(lo, 2^min_exp)⌋ and e_hi =
/// ⌊log2 hi⌋ at least 4 apart, 2^⌊(e_lo+e_hi)/2⌋ lies in [2^(e_lo+2),
/// 2^(e_hi−2)], strictly inside; else the midpoint.
fn geometric_or_mid(lo: &Dyadic, hi: &Dyadic, min_exp: i64) -> Dyadic {
    let e_lo = if lo.is_zero() {
        min_exp
    } else {
        lo.log2_floor().max(min_exp)
    };
    let e_hi = hi.log2_floor();
    if e_hi - e_lo >= 4 {
        Dyadic::pow2((e_lo + e_hi).div_euclid(2))
    } else {
        lo.mid(hi)
    }
}

/// The half-way points (l, u) around the f64 f: every real strictly between
/// them rounds to f (None: unbounded, for ±∞). Exact dyadics.
fn rounding_region(f: f64) -> (Option<Dyadic>, Option<Dyadic>) {
    // Reals at or past MAX + ulp/2 round to infinity.
    let past_max = Dyadic::from_f64(f64::MAX).mid(&Dyadic::pow2(1024));
    if f == f64::INFINITY {
        return (Some(past_max), None);
    }
    if f == f64::NEG_INFINITY {
        return (None, Some(past_max.neg()));
    }
    let x = Dyadic::from_f64(f);
    let below = if f == -f64::MAX {
        Dyadic::pow2(1024).neg()
    } else {
        Dyadic::from_f64(f.next_down())
    };
    let above = if f == f64::MAX {
        Dyadic::pow2(1024)
    } else {
        Dyadic::from_f64(f.next_up())
    };
    (Some(x.mid(&below)), Some(x.mid(&above)))
}

/// The rational with the smallest denominator strictly inside (x, y), x < y,
/// by continued fractions (the Stern–Brocot descent).
fn simplest_between(x: &BigRational, y: &BigRational) -> BigRational {
    if x.is_negative() && y.is_positive() {
        return BigRational::zero();
    }
    if !y.is_positive() {
        return -simplest_between(&-y, &-x);
    }
    // 0 <= x < y. Work on numerator/denominator pairs; y may become ∞
    // (denominator 0).
    let (mut xn, mut xd) = (x.numer().clone(), x.denom().clone());
    let (mut yn, mut yd) = (y.numer().clone(), y.denom().clone());
    let mut terms = Vec::new();
    loop {
        let fl = &xn / &xd; // floor, as x >= 0
        let next = &fl + 1;
        if yd.is_zero() || &next * &yd < yn {
            // The smallest integer above x is below y.
            terms.push(next);
            break;
        }
        // fl <= x < y <= fl + 1: take off fl, recurse on (1/y', 1/x').
        let x_rem = &xn - &fl * &xd;
        let y_rem = &yn - &fl * &yd;
        terms.push(fl);
        (xn, xd, yn, yd) = (yd, y_rem, xd, x_rem);
    }
    let mut num = terms.pop().unwrap_or_default();
    let mut den = BigInt::one();
    while let Some(t) = terms.pop() {
        let next = t * &num + den;
        den = num;
        num = next;
    }
    BigRational::new(num, den)
}

// ---------------------------------------------------------------------------
// Dyadic numbers
// ---------------------------------------------------------------------------

/// m·2^e, normalised (m odd, or m = 0 and e = 0), so equal values are equal
/// representations and midpoints never need a gcd.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Dyadic {
    m: BigInt,
    e: i64,
}

impl Dyadic {
    fn new(m: BigInt, e: i64) -> Dyadic {
        match m.trailing_zeros() {
            None => Dyadic::zero(),
            Some(tz) => Dyadic {
                m: m >> tz,
                e: e + tz as i64,
            },
        }
    }

    fn zero() -> Dyadic {
        Dyadic {
            m: BigInt::zero(),
            e: 0,
        }
    }

    fn pow2(e: i64) -> Dyadic {
        Dyadic {
            m: BigInt::one(),
            e,
        }
    }

    /// Exact, for finite x.
    fn from_f64(x: f64) -> Dyadic {
        let (mantissa, exponent, sign) = Float::integer_decode(x);
        Dyadic::new(
            BigInt::from(mantissa) * BigInt::from(sign),
            i64::from(exponent),
        )
    }

    fn is_zero(&self) -> bool {
        self.m.is_zero()
    }

    fn signum(&self) -> i32 {
        sign_of(&self.m)
    }

    fn neg(&self) -> Dyadic {
        Dyadic {
            m: -&self.m,
            e: self.e,
        }
    }

    fn abs(&self) -> Dyadic {
        Dyadic {
            m: self.m.abs(),
            e: self.e,
        }
    }

    /// ⌊log2 |x|⌋ for x ≠ 0.
    fn log2_floor(&self) -> i64 {
        self.m.bits() as i64 - 1 + self.e
    }

    /// Both mantissas over the common exponent min(e₁, e₂).
    fn aligned(&self, other: &Dyadic) -> (BigInt, BigInt, i64) {
        let e = self.e.min(other.e);
        (
            &self.m << (self.e - e) as u64,
            &other.m << (other.e - e) as u64,
            e,
        )
    }

    fn sub(&self, other: &Dyadic) -> Dyadic {
        let (a, b, e) = self.aligned(other);
        Dyadic::new(a - b, e)
    }

    fn add(&self, other: &Dyadic) -> Dyadic {
        let (a, b, e) = self.aligned(other);
        Dyadic::new(a + b, e)
    }

    fn mid(&self, other: &Dyadic) -> Dyadic {
        let sum = self.add(other);
        Dyadic::new(sum.m, sum.e - 1)
    }

    fn mul(&self, other: &Dyadic) -> Dyadic {
        Dyadic::new(&self.m * &other.m, self.e + other.e)
    }

    fn to_rational(&self) -> BigRational {
        if self.e >= 0 {
            BigRational::from_integer(&self.m << self.e as u64)
        } else {
            // m is odd, so m / 2^k is already in lowest terms.
            BigRational::new_raw(self.m.clone(), BigInt::one() << (-self.e) as u64)
        }
    }

    /// Correctly rounded (num-rational's conversion rounds to nearest, ties
    /// to even), ±∞ beyond the f64 range.
    fn to_f64(&self) -> f64 {
        self.to_rational().to_f64().unwrap_or(f64::NAN)
    }
}

impl Ord for Dyadic {
    fn cmp(&self, other: &Dyadic) -> Ordering {
        let (a, b, _) = self.aligned(other);
        a.cmp(&b)
    }
}

impl PartialOrd for Dyadic {
    fn partial_cmp(&self, other: &Dyadic) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

// ---------------------------------------------------------------------------
// Integer polynomials
// ---------------------------------------------------------------------------

fn sign_of(x: &BigInt) -> i32 {
    if x.is_zero() {
        0
    } else if x.is_negative() {
        -1
    } else {
        1
    }
}

/// gcd of |a| and |b| (Euclid with remainders: a small operand is reduced in
/// one division, unlike binary gcd).
fn gcd_int(a: &BigInt, b: &BigInt) -> BigInt {
    let mut a = a.abs();
    let mut b = b.abs();
    while !b.is_zero() {
        let r = &a % &b;
        a = b;
        b = r;
    }
    a
}

fn trim(p: &mut IPoly) {
    while p.last().is_some_and(Zero::is_zero) {
        p.pop();
    }
}

/// The exact integer polynomial of f64 coefficients: each is mᵢ·2^eᵢ, so
/// shifting by the smallest exponent makes all integers; then primitive.
fn ipoly_from_f64(coeffs: &[f64]) -> Option<IPoly> {
    if coeffs.iter().any(|c| !c.is_finite()) {
        return None;
    }
    let parts: Vec<Dyadic> = coeffs.iter().map(|&c| Dyadic::from_f64(c)).collect();
    let e_min = parts
        .iter()
        .filter(|d| !d.is_zero())
        .map(|d| d.e)
        .min()
        .unwrap_or(0);
    let p = parts
        .into_iter()
        .map(|d| {
            if d.is_zero() {
                d.m
            } else {
                d.m << (d.e - e_min) as u64
            }
        })
        .collect();
    Some(primitive(p))
}

/// The positive gcd of the coefficients (0 for the zero polynomial). Smallest
/// coefficients first, stopping at 1, so it is usually a few cheap steps.
fn content(p: &[BigInt]) -> BigInt {
    let mut nonzero: Vec<&BigInt> = p.iter().filter(|c| !c.is_zero()).collect();
    nonzero.sort_by_key(|c| c.bits());
    let mut g = BigInt::zero();
    for c in nonzero {
        g = gcd_int(&g, c);
        if g.is_one() {
            break;
        }
    }
    g
}

/// Trimmed and divided by its positive content: sign preserved, so Sturm
/// members keep their meaning.
fn primitive(mut p: IPoly) -> IPoly {
    trim(&mut p);
    let g = content(&p);
    if !g.is_zero() && !g.is_one() {
        for c in &mut p {
            *c /= &g;
        }
    }
    p
}

fn derivative_int(p: &[BigInt]) -> IPoly {
    let mut d: IPoly = p
        .iter()
        .enumerate()
        .skip(1)
        .map(|(i, c)| c * BigInt::from(i))
        .collect();
    trim(&mut d);
    d
}

/// Pseudo-remainder: (r, e) with lc(b)^e · a = Q·b + r and deg r < deg b, b ≠ 0.
/// e counts the reduction steps actually taken, so the sign of lc(b)^e — and
/// with it the sign of the true remainder r / lc(b)^e — is known.
fn prem(a: &[BigInt], b: &[BigInt]) -> (IPoly, u32) {
    let db = b.len() - 1;
    let lcb = &b[db];
    let mut r = a.to_vec();
    let mut e = 0;
    while r.len() > db {
        let k = r.len() - 1 - db;
        let Some(lr) = r.pop() else { break };
        // r ← lc(b)·r − lc(r)·x^k·b; the leading terms cancel (popped).
        for c in r.iter_mut() {
            *c *= lcb;
        }
        for (j, bj) in b[..db].iter().enumerate() {
            r[j + k] -= &lr * bj;
        }
        trim(&mut r);
        e += 1;
    }
    (r, e)
}

/// The gcd as a primitive polynomial with positive leading coefficient (empty
/// if both are zero): the last member of the subresultant sequence, made
/// primitive once at the end.
fn ipoly_gcd(a: &[BigInt], b: &[BigInt]) -> IPoly {
    let mut a = primitive(a.to_vec());
    let mut b = primitive(b.to_vec());
    if a.len() < b.len() {
        std::mem::swap(&mut a, &mut b);
    }
    let mut g = if b.is_empty() {
        a
    } else {
        let (mut members, _) = subresultant_prs(a, b);
        members.pop().unwrap_or_default()
    };
    if g.len() == 1 {
        return vec![BigInt::one()];
    }
    g = primitive(g);
    if g.last().is_some_and(Signed::is_negative) {
        for c in &mut g {
            *c = -&*c;
        }
    }
    g
}

/// The subresultant pseudo-remainder sequence of a, b (deg a >= deg b, b ≠ 0),
/// a and b included, up to the last nonzero member, with the Sturm signs εᵢ:
/// εᵢ·Bᵢ is a positive multiple of the classical Sturm member (a, b, −rem, …).
///
/// Why subresultants: the members' sizes stay bounded by determinants of the
/// inputs (the division by g·h^δ is exact) without taking any gcd. A
/// primitive PRS needs a content gcd per member, and with f64 coefficients of
/// wildly different exponents (thousand-bit integers) those gcds took
/// seconds; this takes milliseconds.
///
/// Signs: with R = prem(Bᵢ₋₁, Bᵢ) = lc(Bᵢ)^(δ+1)·rem(Bᵢ₋₁, Bᵢ) and Bᵢ₊₁ = R/D,
/// the Sturm member −rem(εᵢ₋₁Bᵢ₋₁, εᵢBᵢ) = −εᵢ₋₁·D/lc(Bᵢ)^(δ+1)·Bᵢ₊₁, so
/// εᵢ₊₁ = −εᵢ₋₁·sign(D)·sign(lc(Bᵢ))^(δ+1).
fn subresultant_prs(a: IPoly, b: IPoly) -> (Vec<IPoly>, Vec<i32>) {
    let mut members = vec![a, b];
    let mut eps = vec![1, 1];
    let mut g = BigInt::one();
    let mut h = BigInt::one();
    loop {
        let n = members.len();
        let (a, b) = (&members[n - 2], &members[n - 1]);
        let delta = (a.len() - b.len()) as u32;
        let (mut r, steps) = prem(a, b);
        if r.is_empty() {
            break;
        }
        let lc_b = b[b.len() - 1].clone();
        // Make it the full pseudo-remainder, lc(b)^(δ+1)·a mod b.
        if steps < delta + 1 {
            let f = lc_b.pow(delta + 1 - steps);
            for c in &mut r {
                *c *= &f;
            }
        }
        let d = &g * h.pow(delta);
        // Exact (checked on the leading coefficient only: a full check would
        // double the cost of the dominant step in debug builds).
        debug_assert!(
            (&r[r.len() - 1] % &d).is_zero(),
            "subresultant division is exact"
        );
        for c in &mut r {
            *c /= &d;
        }
        let lc_negative = lc_b.is_negative() && delta.is_multiple_of(2); // sign(lc)^(δ+1) < 0
        let flip = (d.is_negative() != lc_negative) as i32; // sign(D)·sign(lc)^(δ+1) < 0
        let e = -eps[n - 2] * (1 - 2 * flip);
        // Next g, h: g = lc(new a) = lc(b), h = g^δ / h^(δ−1).
        g = lc_b;
        h = if delta == 0 {
            h
        } else {
            g.pow(delta) / h.pow(delta - 1)
        };
        members.push(r);
        eps.push(e);
    }
    (members, eps)
}

/// a / b for b dividing a exactly. With b primitive and a integer, the
/// quotient is an integer polynomial (Gauss's lemma), so every step's
/// leading-coefficient division is exact.
fn div_exact(a: &[BigInt], b: &[BigInt]) -> IPoly {
    let db = b.len() - 1;
    if a.len() < b.len() {
        debug_assert!(a.is_empty(), "div_exact: inexact division");
        return Vec::new();
    }
    let mut r = a.to_vec();
    let mut q = vec![BigInt::zero(); a.len() - db];
    for k in (0..q.len()).rev() {
        let qk = &r[k + db] / &b[db];
        debug_assert!(&qk * &b[db] == r[k + db], "div_exact: inexact division");
        for (j, bj) in b.iter().enumerate() {
            r[j + k] -= &qk * bj;
        }
        q[k] = qk;
    }
    debug_assert!(r.iter().all(Zero::is_zero), "div_exact: nonzero remainder");
    trim(&mut q);
    q
}

/// p / gcd(p, p′) as a primitive integer polynomial (sign of p's leading
/// coefficient kept).
fn square_free_ipoly(p: &[BigInt]) -> IPoly {
    if p.len() <= 2 {
        return primitive(p.to_vec());
    }
    let g = ipoly_gcd(p, &derivative_int(p));
    if g.len() <= 1 {
        return primitive(p.to_vec());
    }
    primitive(div_exact(p, &g))
}

/// The square-free part of a primitive p (deg >= 1) and its Sturm chain.
/// When p is already square-free (the usual case) the subresultant sequence
/// of (p, p′) that proves it is also p's Sturm chain, so it is computed once.
fn square_free_and_chain(p: &IPoly) -> (IPoly, Vec<IPoly>) {
    if p.len() <= 2 {
        let q = primitive(p.clone());
        return (q.clone(), sturm_chain(q));
    }
    let d = primitive(derivative_int(p));
    let (members, eps) = subresultant_prs(p.clone(), d);
    if members.last().is_some_and(|g| g.len() == 1) {
        return (p.clone(), chain_from_prs(members, eps));
    }
    let mut g = primitive(members.into_iter().last().unwrap_or_default());
    if g.last().is_some_and(Signed::is_negative) {
        for c in &mut g {
            *c = -&*c;
        }
    }
    let q = primitive(div_exact(p, &g));
    (q.clone(), sturm_chain(q))
}

/// The square-free factorisation p = c·∏ fₖᵏ as (fₖ, k) for non-constant fₖ,
/// by repeated gcds: gₖ = gcd(gₖ₋₁, gₖ₋₁′) = ∏ fⱼ^max(j−k, 0), hₖ = gₖ₋₁/gₖ =
/// ∏_{j≥k} fⱼ and fₖ = hₖ / hₖ₊₁. Every division is exact.
fn square_free_factors(p: &[BigInt]) -> Vec<(IPoly, u32)> {
    if p.len() <= 1 {
        return Vec::new();
    }
    let mut g = vec![primitive(p.to_vec())];
    while g[g.len() - 1].len() > 1 {
        let last = &g[g.len() - 1];
        g.push(ipoly_gcd(last, &derivative_int(last)));
    }
    let h: Vec<IPoly> = g.windows(2).map(|w| div_exact(&w[0], &w[1])).collect();
    let mut out = Vec::new();
    for k in 0..h.len() {
        let f = match h.get(k + 1) {
            Some(next) => div_exact(&h[k], next),
            None => h[k].clone(),
        };
        if f.len() > 1 {
            out.push((primitive(f), k as u32 + 1));
        }
    }
    out
}

/// The Sturm chain of a square-free q: q, q′, then −rem(sᵢ₋₁, sᵢ) up to a
/// positive factor, until the remainder vanishes (at a nonzero constant, as
/// q is square-free). Built from the subresultant sequence with its Sturm
/// signs, then each member is shrunk by a positive factor ([`shrink`]).
fn sturm_chain(q: IPoly) -> Vec<IPoly> {
    if q.is_empty() {
        return Vec::new();
    }
    if q.len() == 1 {
        return vec![q];
    }
    let d = primitive(derivative_int(&q));
    let (members, eps) = subresultant_prs(q, d);
    chain_from_prs(members, eps)
}

/// Applies the Sturm signs to a subresultant sequence and shrinks each member.
fn chain_from_prs(members: Vec<IPoly>, eps: Vec<i32>) -> Vec<IPoly> {
    members
        .into_iter()
        .zip(eps)
        .map(|(mut p, e)| {
            if e < 0 {
                for c in &mut p {
                    *c = -&*c;
                }
            }
            shrink(p)
        })
        .collect()
}

/// Coefficients beyond this many bits skip the content gcd in [`shrink`].
const CONTENT_GCD_MAX_BITS: u64 = 4096;

/// Divides by a positive common factor to make evaluation cheaper: always the
/// common power of two (free), and the full content when the coefficients
/// are small enough for the gcd to be cheap. Only positive factors, so the
/// signs Sturm counts rely on are kept.
fn shrink(mut p: IPoly) -> IPoly {
    if p.iter().all(|c| c.bits() <= CONTENT_GCD_MAX_BITS) {
        return primitive(p);
    }
    if let Some(tz) = p.iter().filter_map(BigInt::trailing_zeros).min()
        && tz > 0
    {
        for c in &mut p {
            *c >>= tz;
        }
    }
    p
}

/// Sign changes in a sequence of signs, zeros skipped.
fn count_variations(signs: impl Iterator<Item = i32>) -> usize {
    let mut last = 0;
    let mut count = 0;
    for s in signs.filter(|&s| s != 0) {
        if last != 0 && s != last {
            count += 1;
        }
        last = s;
    }
    count
}

fn count_variations_dyadic(chain: &[IPoly], x: &Dyadic) -> usize {
    count_variations(chain.iter().map(|p| sign_dyadic(p, x)))
}

/// The sign of p(m·2^e) without fractions: for e = −k < 0 it is the sign of
/// Σ cᵢ·mⁱ·2^(k(n−i)) (p(x) times the positive 2^(kn)), by Horner with
/// shifts.
fn sign_dyadic(p: &[BigInt], x: &Dyadic) -> i32 {
    let Some(lead) = p.last() else { return 0 };
    if x.is_zero() {
        return sign_of(&p[0]);
    }
    let n = p.len() - 1;
    let mut acc = lead.clone();
    if x.e >= 0 {
        let xi = &x.m << x.e as u64;
        for c in p[..n].iter().rev() {
            acc = acc * &xi + c;
        }
    } else {
        let k = x.e.unsigned_abs();
        for (i, c) in p[..n].iter().enumerate().rev() {
            acc *= &x.m;
            if !c.is_zero() {
                acc += c << (k * (n - i) as u64);
            }
        }
    }
    sign_of(&acc)
}

/// The sign of p(num/den) as the sign of Σ cᵢ·numⁱ·den^(n−i) with den > 0.
fn sign_rational(p: &[BigInt], x: &BigRational) -> i32 {
    let Some(lead) = p.last() else { return 0 };
    let (num, den) = if x.denom().is_negative() {
        (-x.numer(), -x.denom())
    } else {
        (x.numer().clone(), x.denom().clone())
    };
    let mut acc = lead.clone();
    let mut den_pow = BigInt::one();
    for c in p[..p.len() - 1].iter().rev() {
        den_pow *= &den;
        acc = acc * &num + c * &den_pow;
    }
    sign_of(&acc)
}

/// β with every root |z| < 2^β (deg p ≥ 1): Fujiwara's bound
/// 2·maxᵢ |cᵢ/cₙ|^(1/(n−i)), with |cᵢ/cₙ| < 2^(bits(cᵢ) − bits(cₙ) + 1).
fn upper_root_exp(p: &[BigInt]) -> i64 {
    let n = p.len() - 1;
    let bits_n = p[n].bits() as i64;
    let best = p[..n]
        .iter()
        .enumerate()
        .filter(|(_, c)| !c.is_zero())
        .map(|(i, c)| {
            let num = c.bits() as i64 - bits_n + 1;
            let d = (n - i) as i64;
            -(-num).div_euclid(d) // ⌈num / d⌉
        })
        .max();
    match best {
        Some(v) => v + 1,
        None => 0, // c·xⁿ: the only root is 0
    }
}

/// μ with every nonzero root |z| > 2^μ: the upper bound of the reversed
/// polynomial (whose roots are the reciprocals), x-factors removed first.
fn lower_root_exp(p: &[BigInt]) -> i64 {
    let start = p.iter().position(|c| !c.is_zero()).unwrap_or(0);
    let reversed: IPoly = p[start..].iter().rev().cloned().collect();
    if reversed.len() <= 1 {
        return 0; // no nonzero roots: any value will do
    }
    -upper_root_exp(&reversed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::time::{Duration, Instant};

    /// Coefficients (lowest first) of ∏ (x − r)^k over integer roots, expanded
    /// exactly in i128; panics unless each is an exactly representable f64.
    fn from_int_roots(roots: &[(i64, u32)]) -> Vec<f64> {
        let mut c: Vec<i128> = vec![1];
        for &(r, k) in roots {
            for _ in 0..k {
                let mut next = vec![0i128; c.len() + 1];
                for (i, &ci) in c.iter().enumerate() {
                    next[i + 1] += ci;
                    next[i] -= ci * i128::from(r);
                }
                c = next;
            }
        }
        c.iter()
            .map(|&ci| {
                let f = ci as f64;
                assert_eq!(f as i128, ci, "coefficient {ci} is not an exact f64");
                f
            })
            .collect()
    }

    fn rat(n: i64, d: i64) -> BigRational {
        BigRational::new(BigInt::from(n), BigInt::from(d))
    }

    #[test]
    fn triple_root_is_exact() {
        // (x − 1)³ = x³ − 3x² + 3x − 1
        let c = [-1.0, 3.0, -3.0, 1.0];
        assert_eq!(exact_count(&c, 0.0, 3.0), Some(1));
        assert_eq!(exact_roots(&c, 0.0, 3.0, 1e-12), Some(vec![1.0]));
        assert_eq!(exact_roots(&c, -10.0, 10.0, 0.0), Some(vec![1.0]));
        assert_eq!(
            exact_roots_with_multiplicity(&c, 0.0, 3.0, 1e-12),
            Some(vec![(1.0, 3)])
        );
    }

    #[test]
    fn quartic_with_double_root_at_zero() {
        // t⁴ − t² = t²(t − 1)(t + 1)
        let c = [0.0, 0.0, -1.0, 0.0, 1.0];
        assert_eq!(exact_count(&c, -2.0, 2.0), Some(3));
        assert_eq!(
            exact_roots(&c, -2.0, 2.0, 1e-12),
            Some(vec![-1.0, 0.0, 1.0])
        );
        assert_eq!(
            exact_roots_with_multiplicity(&c, -2.0, 2.0, 0.0),
            Some(vec![(-1.0, 1), (0.0, 2), (1.0, 1)])
        );
    }

    #[test]
    fn roots_one_to_ten() {
        let roots: Vec<(i64, u32)> = (1..=10).map(|r| (r, 1)).collect();
        let c = from_int_roots(&roots);
        let expected: Vec<f64> = (1..=10).map(|r| r as f64).collect();
        assert_eq!(exact_count(&c, 0.0, 11.0), Some(10));
        assert_eq!(exact_roots(&c, 0.0, 11.0, 1e-9), Some(expected.clone()));
        assert_eq!(
            exact_roots(&c, f64::NEG_INFINITY, f64::INFINITY, 0.0),
            Some(expected)
        );
        assert_eq!(exact_count(&c, 2.5, 7.0), Some(5));
    }

    #[test]
    fn close_dyadic_roots() {
        // (x − 1 − h)(x − 1 + h) = x² − 2x + (1 − h²), h = 2^-20: exact in f64.
        let h = 2f64.powi(-20);
        let c = [1.0 - h * h, -2.0, 1.0];
        assert_eq!(exact_count(&c, 0.0, 2.0), Some(2));
        assert_eq!(exact_roots(&c, 0.0, 2.0, 0.0), Some(vec![1.0 - h, 1.0 + h]));
        assert_eq!(
            exact_roots(&c, 0.0, 2.0, 1e-15),
            Some(vec![1.0 - h, 1.0 + h])
        );
        assert_eq!(exact_count(&c, 0.0, 1.0), Some(1));

        // Squared, h = 2^-10 (so (1 − h²)² still fits 53 bits): two double roots.
        let h = 2f64.powi(-10);
        let a = 1.0 - h * h;
        let sq = [a * a, -4.0 * a, 4.0 + 2.0 * a, -4.0, 1.0];
        assert_eq!(
            exact_roots_with_multiplicity(&sq, 0.0, 2.0, 1e-12),
            Some(vec![(1.0 - h, 2), (1.0 + h, 2)])
        );
    }

    #[test]
    fn close_roots_from_rounded_coefficients() {
        // x² − 2x + c with c = fl(1 − 1e-12): the roots are 1 ± √(1 − c), and
        // 1 − c is exact in f64 (Sterbenz), so √ is correctly rounded and
        // 1 ± fl(√(1 − c)) is within an ulp or two of each true root.
        let c0 = 1.0 - 1e-12;
        let s = (1.0 - c0).sqrt();
        let c = [c0, -2.0, 1.0];
        let roots = exact_roots(&c, 0.0, 2.0, 0.0).unwrap();
        assert_eq!(roots.len(), 2);
        assert!((roots[0] - (1.0 - s)).abs() <= 4.0 * f64::EPSILON);
        assert!((roots[1] - (1.0 + s)).abs() <= 4.0 * f64::EPSILON);
        assert!(roots[0] < roots[1]);
    }

    #[test]
    fn no_roots() {
        assert_eq!(exact_count(&[1.0, 0.0, 1.0], -10.0, 10.0), Some(0));
        assert_eq!(
            exact_roots(&[1.0, 0.0, 1.0], -10.0, 10.0, 0.0),
            Some(vec![])
        );
        // Roots 1 and 2 lie outside (3, 10].
        assert_eq!(exact_roots(&[2.0, -3.0, 1.0], 3.0, 10.0, 0.0), Some(vec![]));
        // Constants and the zero polynomial.
        assert_eq!(exact_roots(&[5.0], -1.0, 1.0, 0.0), Some(vec![]));
        assert_eq!(exact_roots(&[], -1.0, 1.0, 0.0), Some(vec![]));
        assert_eq!(exact_count(&[0.0, 0.0], -1.0, 1.0), Some(0));
        // Empty interval.
        assert_eq!(exact_count(&[2.0, -3.0, 1.0], 2.0, 1.0), Some(0));
    }

    #[test]
    fn endpoints_half_open() {
        // (x − 1)(x − 2)
        let c = [2.0, -3.0, 1.0];
        assert_eq!(exact_roots(&c, 1.0, 2.0, 0.0), Some(vec![2.0]));
        assert_eq!(exact_roots(&c, 0.0, 1.0, 0.0), Some(vec![1.0]));
        assert_eq!(exact_count(&c, 1.0, 1.5), Some(0));
        assert_eq!(exact_count(&c, 2.0, 3.0), Some(0));
        assert_eq!(exact_count(&c, 1.0, 2.0), Some(1));
        // Multiple root at an endpoint.
        let m = from_int_roots(&[(1, 3), (2, 2)]);
        assert_eq!(
            exact_roots_with_multiplicity(&m, 1.0, 2.0, 0.0),
            Some(vec![(2.0, 2)])
        );
        assert_eq!(
            exact_roots_with_multiplicity(&m, 0.0, 1.0, 0.0),
            Some(vec![(1.0, 3)])
        );
        let sturm = ExactSturm::new(&ExactPoly::from_f64(&m).unwrap());
        assert_eq!(sturm.count(&rat(1, 1), &rat(2, 1)), 1);
        assert_eq!(sturm.count(&rat(0, 1), &rat(1, 1)), 1);
        assert_eq!(sturm.count(&rat(1, 1), &rat(3, 2)), 0);
    }

    #[test]
    fn scaling_by_huge_powers_of_two() {
        let c = from_int_roots(&[(-3, 2), (0, 1), (5, 3)]);
        let expected = exact_roots_with_multiplicity(&c, -10.0, 10.0, 0.0).unwrap();
        assert_eq!(expected, vec![(-3.0, 2), (0.0, 1), (5.0, 3)]);
        for s in [2f64.powi(300), 2f64.powi(-300), -(2f64.powi(300))] {
            let scaled: Vec<f64> = c.iter().map(|x| x * s).collect();
            assert_eq!(
                exact_roots_with_multiplicity(&scaled, -10.0, 10.0, 0.0).unwrap(),
                expected
            );
            assert_eq!(exact_count(&scaled, -10.0, 10.0), Some(3));
            let p = ExactPoly::from_f64(&c).unwrap();
            let ps = ExactPoly::from_f64(&scaled).unwrap();
            assert_eq!(p.square_free().gcd(&p), ps.square_free().gcd(&ps));
        }
    }

    #[test]
    fn rational_root_is_correctly_rounded() {
        // 3x − 1: the root 1/3 is found exactly, then rounded once.
        let r = exact_roots(&[-1.0, 3.0], 0.0, 1.0, 1e-6).unwrap();
        assert_eq!(r, vec![1.0 / 3.0]);
        // (5x − 2)² (7x + 3): roots 2/5 (double) and −3/7.
        // (5x − 2)² = 25x² − 20x + 4; times (7x + 3):
        // 175x³ + 75x² − 140x² − 60x + 28x + 12 = 175x³ − 65x² − 32x + 12.
        let c = [12.0, -32.0, -65.0, 175.0];
        assert_eq!(
            exact_roots_with_multiplicity(&c, -1.0, 1.0, 1e-9),
            Some(vec![(-3.0 / 7.0, 1), (2.0 / 5.0, 2)])
        );
    }

    #[test]
    fn loose_tolerance_still_finds_rational_roots_exactly() {
        // Found by proptest: with tolerance 0.1 taken literally, refinement
        // of the root 12 in (5.5, 23] stopped at (10.97, 12.06], where the
        // simplest rational is 11, and returned the midpoint 11.515625.
        assert_eq!(exact_roots(&[-12.0, 1.0], 5.5, 23.0, 0.1), Some(vec![12.0]));
        assert_eq!(
            exact_roots(&[-12.0, 1.0], 5.5, 23.0, f64::INFINITY),
            Some(vec![12.0])
        );
        // 3/7 and 1000, a small denominator and a large integer:
        // (7x − 3)(x − 1000) = 7x² − 7003x + 3000.
        let c = [3000.0, -7003.0, 7.0];
        assert_eq!(
            exact_roots(&c, 0.0, 2000.0, 0.5),
            Some(vec![3.0 / 7.0, 1000.0])
        );
    }

    #[test]
    fn isolation_certifies_right_answers_only() {
        // (x − 1)(x − 2)(x + 3)² on (−10, 10]: three distinct roots.
        let p = from_int_roots(&[(1, 1), (2, 1), (-3, 2)]);
        let iso = Isolation::new(&p, -10.0, 10.0).unwrap();
        assert_eq!(iso.count(), 3);
        let tol = 1e-12;
        let off = |r: f64, by: f64| r + by * r.abs().max(1.0);
        for relative in [Relative::MagnitudeOrOne, Relative::Magnitude] {
            assert!(iso.certifies(&[-3.0, 1.0, 2.0], tol, relative));
            assert!(iso.certifies(
                &[off(-3.0, 0.5e-12), 1.0, off(2.0, -0.9e-12)],
                tol,
                relative
            ));
            // Too far, too few, too many, out of order, outside (a, b].
            assert!(!iso.certifies(&[off(-3.0, 2e-12), 1.0, 2.0], tol, relative));
            assert!(!iso.certifies(&[-3.0, 2.0], tol, relative));
            assert!(!iso.certifies(&[-3.0, 1.0, 1.0, 2.0], tol, relative));
            assert!(!iso.certifies(&[-3.0, 2.0, 1.0], tol, relative));
            assert!(!iso.certifies(&[-3.0, 1.0, 2.0], 0.0, relative));
            // Two values for one root: the second interval holds no root.
            assert!(!iso.certifies(&[1.0, off(1.0, 0.5e-12), 2.0], tol, relative));
            assert_eq!(iso.count(), 3);
        }
        // 1e28 t² − 1: roots ±1e-14; (0, 1] holds one. 1.4e-14 is within
        // 1e-12 absolute (the renderer's tolerance below 1) but 40% off.
        let c = [-1.0, 0.0, 1e28];
        let iso = Isolation::new(&c, 0.0, 1.0).unwrap();
        assert!(iso.certifies(&[1.4e-14], tol, Relative::MagnitudeOrOne));
        assert!(!iso.certifies(&[1.4e-14], tol, Relative::Magnitude));
        let roots = Isolation::new(&c, 0.0, 1.0)
            .unwrap()
            .roots(tol, Relative::Magnitude)
            .unwrap();
        assert!(iso.certifies(&roots, tol, Relative::Magnitude), "{roots:?}");
        assert!((roots[0] - 1e-14).abs() <= 1e-12 * 1e-14);
        // A root at exactly 0 is certified relatively only as 0 itself.
        let c = [0.0, -1.0, 0.0, 1.0]; // t³ − t
        let iso = Isolation::new(&c, -2.0, 2.0).unwrap();
        assert!(iso.certifies(&[-1.0, 0.0, 1.0], tol, Relative::Magnitude));
        assert!(!iso.certifies(&[-1.0, 1e-300, 1.0], tol, Relative::Magnitude));
        assert!(iso.certifies(&[-1.0, 1e-300, 1.0], tol, Relative::MagnitudeOrOne));
    }

    #[test]
    fn irrational_roots_to_tolerance_and_correctly_rounded() {
        // x² − 2
        let c = [-2.0, 0.0, 1.0];
        let r = exact_roots(&c, -2.0, 2.0, 0.0).unwrap();
        assert_eq!(r, vec![-(2f64.sqrt()), 2f64.sqrt()]); // sqrt is correctly rounded
        let r = exact_roots(&c, 0.0, 2.0, 1e-6).unwrap();
        assert!((r[0] - 2f64.sqrt()).abs() <= 2e-6);
    }

    #[test]
    fn non_finite_input() {
        assert_eq!(exact_roots(&[1.0, f64::NAN], 0.0, 1.0, 0.0), None);
        assert_eq!(exact_count(&[1.0, f64::INFINITY], 0.0, 1.0), None);
        assert_eq!(exact_count(&[1.0, 1.0], f64::NAN, 1.0), None);
        assert_eq!(exact_roots(&[1.0, 1.0], 0.0, 1.0, f64::NAN), None);
        assert!(ExactPoly::from_f64(&[1.0, f64::NEG_INFINITY]).is_none());
    }

    #[test]
    fn exact_poly_operations() {
        // p = (x − 1)²(x + 2) = x³ − 3x + 2
        let p = ExactPoly::from_f64(&[2.0, -3.0, 0.0, 1.0]).unwrap();
        assert_eq!(p.degree(), 3);
        assert_eq!(
            p.derivative(),
            ExactPoly::from_rationals(vec![rat(-3, 1), rat(0, 1), rat(3, 1)])
        );
        // gcd(p, p′) = x − 1, monic.
        assert_eq!(
            p.gcd(&p.derivative()),
            ExactPoly::from_rationals(vec![rat(-1, 1), rat(1, 1)])
        );
        // Square-free part (x − 1)(x + 2) = x² + x − 2, same leading coefficient.
        assert_eq!(
            p.square_free(),
            ExactPoly::from_rationals(vec![rat(-2, 1), rat(1, 1), rat(1, 1)])
        );
        let half = ExactPoly::from_f64(&[1.0, -0.5]).unwrap(); // 1 − x/2
        assert_eq!(half.square_free(), half);
        assert_eq!(p.sign_at(&rat(1, 1)), 0);
        assert_eq!(p.sign_at(&rat(-2, 1)), 0);
        assert_eq!(p.sign_at(&rat(-3, 1)), -1);
        assert_eq!(p.sign_at(&rat(1, 3)), 1);
        let zero = ExactPoly::from_f64(&[0.0, 0.0]).unwrap();
        assert!(zero.is_zero());
        assert_eq!(zero.degree(), 0);
        assert_eq!(zero.gcd(&zero), zero);
        assert_eq!(zero.gcd(&p.derivative()).degree(), 2);
        let s = ExactSturm::new(&p);
        assert_eq!(s.len(), 3); // square-free part has degree 2
        assert_eq!(s.count(&rat(-10, 1), &rat(10, 1)), 2);
        assert_eq!(s.count(&rat(10, 1), &rat(-10, 1)), 0);
        assert!(ExactSturm::new(&zero).is_empty());
    }

    /// Asserts the call finishes within `cap`, returning its result.
    fn timed<T>(cap: Duration, f: impl FnOnce() -> T) -> T {
        let start = Instant::now();
        let out = f();
        let elapsed = start.elapsed();
        assert!(elapsed < cap, "took {elapsed:?}");
        out
    }

    #[test]
    fn wilkinson_sixteen_within_time_cap() {
        let roots: Vec<(i64, u32)> = (1..=16).map(|r| (r, 1)).collect();
        let c = from_int_roots(&roots);
        let expected: Vec<f64> = (1..=16).map(|r| r as f64).collect();
        let got = timed(Duration::from_secs(1), || {
            exact_roots(&c, f64::NEG_INFINITY, f64::INFINITY, 0.0)
        });
        assert_eq!(got, Some(expected));
    }

    #[test]
    fn degree_sixteen_clusters_within_time_cap() {
        let cap = Duration::from_secs(1);
        // (x − 1)¹⁶: binomial coefficients, exact.
        let c = from_int_roots(&[(1, 16)]);
        let got = timed(cap, || exact_roots_with_multiplicity(&c, -5.0, 5.0, 0.0));
        assert_eq!(got, Some(vec![(1.0, 16)]));

        // Mignotte-like x¹⁶ − 2(2^20·x − 1)²: two real roots near 2^-20 far
        // closer than an ulp, which must end as one f64 reported twice.
        let mut c = vec![0.0; 17];
        c[16] = 1.0;
        c[2] = -2.0 * 2f64.powi(40);
        c[1] = 4.0 * 2f64.powi(20);
        c[0] = -2.0;
        let n = exact_count(&c, 0.0, 1e-3).unwrap();
        let roots = timed(cap, || exact_roots(&c, 0.0, 1e-3, 0.0)).unwrap();
        assert_eq!(roots.len(), n);
        assert!(n >= 2);
        assert_eq!(roots[0], roots[1]);
        assert!((roots[0] - 2f64.powi(-20)).abs() < 1e-12);

        // Rounded coefficients of a tight cluster ∏ (x − (1 + j·1e-3)).
        let mut c = vec![1.0f64];
        for j in 0..16 {
            let r = 1.0 + f64::from(j) * 1e-3;
            let mut next = vec![0.0; c.len() + 1];
            for (i, &ci) in c.iter().enumerate() {
                next[i + 1] += ci;
                next[i] -= ci * r;
            }
            c = next;
        }
        let n = exact_count(&c, f64::NEG_INFINITY, f64::INFINITY).unwrap();
        let roots = timed(cap, || {
            exact_roots(&c, f64::NEG_INFINITY, f64::INFINITY, 0.0)
        })
        .unwrap();
        assert_eq!(roots.len(), n);
        assert!(roots.windows(2).all(|w| w[0] <= w[1]));
        // Every reported root is a sign change of the exact polynomial
        // (roots of odd multiplicity here, as rounding separates them).
        let p = ExactPoly::from_f64(&c).unwrap();
        for &r in &roots {
            let below = BigRational::from_float(r - 1e-9).unwrap();
            let above = BigRational::from_float(r + 1e-9).unwrap();
            assert!(ExactSturm::new(&p).count(&below, &above) >= 1);
        }
    }

    prop_compose! {
        /// Distinct integer roots with multiplicities 1–3, total degree ≤ 8.
        fn int_roots()(raw in prop::collection::vec((-12i64..=12, 1u32..=3), 0..=5))
            -> Vec<(i64, u32)> {
            let mut roots: Vec<(i64, u32)> = Vec::new();
            let mut degree = 0;
            for (r, k) in raw {
                if roots.iter().all(|&(s, _)| s != r) && degree + k <= 8 {
                    roots.push((r, k));
                    degree += k;
                }
            }
            roots.sort();
            roots
        }
    }

    proptest! {
        #[test]
        fn integer_root_polynomials(
            roots in int_roots(),
            a2 in -30i64..=30,
            len2 in 0i64..=40,
            scale_exp in -60i32..=60,
            negate in any::<bool>(),
            tol in prop::sample::select(vec![0.0, 1e-12, 1e-6, 0.1, 1.0]),
        ) {
            // Half-integer endpoints, so they sometimes sit on a root.
            let (a, b) = (a2 as f64 / 2.0, (a2 + len2) as f64 / 2.0);
            let s = if negate { -(2f64.powi(scale_exp)) } else { 2f64.powi(scale_exp) };
            let c: Vec<f64> = from_int_roots(&roots).iter().map(|x| x * s).collect();
            let inside: Vec<(f64, u32)> = roots
                .iter()
                .map(|&(r, k)| (r as f64, k))
                .filter(|&(r, _)| a < r && r <= b)
                .collect();
            prop_assert_eq!(exact_count(&c, a, b), Some(inside.len()));
            prop_assert_eq!(
                exact_roots(&c, a, b, tol),
                Some(inside.iter().map(|&(r, _)| r).collect::<Vec<_>>())
            );
            prop_assert_eq!(exact_roots_with_multiplicity(&c, a, b, tol), Some(inside));
        }
    }
}
