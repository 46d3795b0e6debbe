//! Exact isolation and refinement: the input clipped to an exact root bound,
//! brackets cut by exact Sturm counts until each holds one root, then
//! refined by bisection on its sign (cut at powers of two, f64 rounding
//! boundaries and midpoints) until the tolerance or f64 resolution is met,
//! with the simplest rational in the bracket tried as an exact root.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};

use super::Relative;
use super::dyadic::Dyadic;
use super::ipoly::{
    IPoly, count_variations_dyadic, ipoly_from_f64, lower_root_exp, sign_dyadic, sign_rational,
    square_free_and_chain, sturm_chain, upper_root_exp,
};

/// The shared front end: the input as a primitive integer polynomial, its
/// square-free part with that part's Sturm chain, and the interval clipped to
/// an exact root bound.
pub(super) struct Input {
    pub(super) poly: IPoly,
    pub(super) square_free: IPoly,
    pub(super) chain: Vec<IPoly>,
    /// (lo, hi] with lo < hi, or None when no root can lie in the interval.
    pub(super) interval: Option<(Dyadic, Dyadic)>,
    /// The interval (a, b] as asked.
    pub(super) a: f64,
    pub(super) b: f64,
}

impl Input {
    pub(super) fn new(coeffs: &[f64], a: f64, b: f64) -> Option<Input> {
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
pub(super) struct Group {
    pub(super) lo: Dyadic,
    pub(super) hi: Point,
    pub(super) count: usize,
    pub(super) value: f64,
}

/// A bracket end: dyadic from bisection, or a rational root found exactly.
pub(super) enum Point {
    Dyadic(Dyadic),
    Rational(BigRational),
}

pub(super) struct Solved {
    pub(super) input: Input,
    pub(super) groups: Vec<Group>,
}

impl Solved {
    pub(super) fn new(mut input: Input, tolerance: f64, relative: Relative) -> Option<Solved> {
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
