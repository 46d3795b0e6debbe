//! The certificate of an answer: for each listed value, an interval with
//! exact dyadic (or rational) ends that holds its root, the exact Sturm
//! count that proves the interval holds exactly that many distinct roots,
//! the root's multiplicity from the exact square-free factorisation, and the
//! error bound that follows (the farther end's distance, rounded up).
//!
//! Built from either source of values, so the one argument covers both: the
//! windows around f64 roots that [`super::Isolation::certify`] proved hold
//! one root each, or the brackets the exact path refined.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{Signed, ToPrimitive, Zero};

use super::dyadic::Dyadic;
use super::ipoly::{
    IPoly, count_variations, count_variations_dyadic, sign_dyadic, sign_rational,
    square_free_factors, sturm_chain,
};
use super::isolate::{Input, Point};

/// Where one listed value's root lies.
pub(super) enum Span {
    /// (lo, hi], holding `distinct` distinct roots (more than one only for
    /// roots closer than f64 resolution, all listed with the same value).
    Interval {
        lo: Dyadic,
        hi: Point,
        distinct: usize,
    },
    /// The value is itself an exact root.
    At(Dyadic),
}

/// A value with the span that proves it.
pub(super) struct Found {
    pub(super) value: f64,
    pub(super) span: Span,
}

/// One root of a certified answer.
#[derive(Clone, Debug, PartialEq)]
pub struct CertifiedRoot {
    /// The reported f64.
    pub value: f64,
    /// Its multiplicity in the input polynomial (exact).
    pub multiplicity: u32,
    /// |root − value| ≤ bound (the interval's farther end, rounded up).
    pub bound: f64,
    /// The interval (lo, hi] that holds the root, exactly, as text
    /// (`m*2^e`, `p/q` or an integer); equal ends mean the value is the root.
    pub interval: [String; 2],
    /// The same interval rounded outwards to f64.
    pub interval_f64: [f64; 2],
    /// How many distinct roots the interval holds (the exact Sturm count):
    /// 1, or more for roots closer together than f64 can tell apart.
    pub distinct_in_interval: usize,
}

/// The proof of an answer: see the module's documentation.
#[derive(Clone, Debug, PartialEq)]
pub struct Certificate {
    /// The exact count of distinct real roots in (a, b]: V(lo) − V(hi).
    pub count: usize,
    /// Sign variations of the exact Sturm chain at the clipped ends.
    pub variations: [usize; 2],
    /// The clipped interval (lo, hi] the count is taken on, exactly.
    pub interval: [String; 2],
    /// The input's degree and that of its square-free part.
    pub degree: usize,
    pub square_free_degree: usize,
    /// Members of the exact Sturm chain.
    pub chain_len: usize,
    /// Degree and multiplicity of each square-free factor fₖ (p = c·∏ fₖᵏ).
    pub factors: Vec<(usize, u32)>,
    /// The roots, increasing, as many as `count`.
    pub roots: Vec<CertifiedRoot>,
}

impl Certificate {
    pub fn values(&self) -> Vec<f64> {
        self.roots.iter().map(|r| r.value).collect()
    }
}

/// The square-free factors' Sturm chains with their multiplicities.
fn factor_chains(input: &Input) -> Vec<(Vec<IPoly>, u32)> {
    if input.square_free.len() == input.poly.len() {
        // Already square-free: one factor, whose chain is at hand.
        return vec![(input.chain.clone(), 1)];
    }
    square_free_factors(&input.poly)
        .into_iter()
        .map(|(f, k)| (sturm_chain(f), k))
        .collect()
}

fn variations_at(chain: &[IPoly], x: &Point) -> usize {
    match x {
        Point::Dyadic(d) => count_variations_dyadic(chain, d),
        Point::Rational(r) => count_variations(chain.iter().map(|p| sign_rational(p, r))),
    }
}

/// Builds the certificate of `found` (increasing, proven by the caller to
/// list every root in (lo, hi] once).
pub(super) fn certify(
    input: &Input,
    interval: Option<&(Dyadic, Dyadic)>,
    variations: [usize; 2],
    found: Vec<Found>,
) -> Certificate {
    let factors = factor_chains(input);
    let mut roots = Vec::new();
    for Found { value, span } in found {
        match span {
            Span::At(x) => {
                let multiplicity = factors
                    .iter()
                    .find(|(chain, _)| sign_dyadic(&chain[0], &x) == 0)
                    .map_or(1, |(_, k)| *k);
                let text = dyadic_text(&x);
                roots.push(CertifiedRoot {
                    value,
                    multiplicity,
                    bound: 0.0,
                    interval: [text.clone(), text],
                    interval_f64: [value, value],
                    distinct_in_interval: 1,
                });
            }
            Span::Interval { lo, hi, distinct } => {
                let hi_rational = match &hi {
                    Point::Dyadic(d) => d.to_rational(),
                    Point::Rational(r) => r.clone(),
                };
                let v = BigRational::from_float(value).unwrap_or_default();
                let is_root = value.is_finite()
                    && distinct == 1
                    && sign_dyadic(&input.square_free, &Dyadic::from_f64(value)) == 0;
                let bound = match &hi {
                    // The value is the root (one exact evaluation to know it).
                    _ if is_root => 0.0,
                    // An exact rational root: the value's own error.
                    Point::Rational(r) => up(&(r - &v).abs()),
                    Point::Dyadic(_) => {
                        let lo_r = lo.to_rational();
                        up(&(&v - &lo_r).abs().max((&hi_rational - &v).abs()))
                    }
                };
                let interval = [dyadic_text(&lo), point_text(&hi)];
                let interval_f64 = [down(&lo.to_rational()), up(&hi_rational)];
                let mut found_here = 0;
                for (chain, k) in &factors {
                    let n = count_variations_dyadic(chain, &lo)
                        .saturating_sub(variations_at(chain, &hi));
                    found_here += n;
                    for _ in 0..n {
                        roots.push(CertifiedRoot {
                            value,
                            multiplicity: *k,
                            bound,
                            interval: interval.clone(),
                            interval_f64,
                            distinct_in_interval: distinct,
                        });
                    }
                }
                debug_assert_eq!(found_here, distinct, "factor counts add up");
            }
        }
    }
    let interval = match interval {
        Some((lo, hi)) => [dyadic_text(lo), dyadic_text(hi)],
        None => ["empty".to_string(), "empty".to_string()],
    };
    Certificate {
        count: variations[0].saturating_sub(variations[1]),
        variations,
        interval,
        degree: input.poly.len().saturating_sub(1),
        square_free_degree: input.square_free.len().saturating_sub(1),
        chain_len: input.chain.len(),
        factors: factors
            .iter()
            .map(|(chain, k)| (chain[0].len().saturating_sub(1), *k))
            .collect(),
        roots,
    }
}

/// The smallest f64 at or above x (x finite; +∞ past the range).
fn up(x: &BigRational) -> f64 {
    let f = x.to_f64().unwrap_or(f64::NAN);
    match BigRational::from_float(f) {
        Some(r) if r < *x => f.next_up(),
        _ => f,
    }
}

/// The largest f64 at or below x.
fn down(x: &BigRational) -> f64 {
    -up(&-x)
}

fn dyadic_text(d: &Dyadic) -> String {
    if d.e >= 0 {
        (&d.m << d.e as u64).to_string()
    } else {
        format!("{}*2^{}", d.m, d.e)
    }
}

fn point_text(p: &Point) -> String {
    match p {
        Point::Dyadic(d) => dyadic_text(d),
        Point::Rational(r) if r.denom() == &BigInt::from(1) || r.is_zero() => r.numer().to_string(),
        Point::Rational(r) => format!("{}/{}", r.numer(), r.denom()),
    }
}
