//! Integer polynomials: exact conversion from f64, contents and primitive
//! parts, the subresultant pseudo-remainder sequence with its Sturm signs
//! (gcds, square-free parts and factorisations, Sturm chains), exact signs
//! at dyadic and rational points, and root bounds.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};

use super::dyadic::{Dyadic, sign_of};

/// An integer polynomial, lowest degree first, with no trailing zeros (the
/// zero polynomial is empty). Only used inside the exact path.
pub(super) type IPoly = Vec<BigInt>;

/// gcd of |a| and |b| (Euclid with remainders: a small operand is reduced in
/// one division, unlike binary gcd).
pub(super) fn gcd_int(a: &BigInt, b: &BigInt) -> BigInt {
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
pub(super) fn ipoly_from_f64(coeffs: &[f64]) -> Option<IPoly> {
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
pub(super) fn primitive(mut p: IPoly) -> IPoly {
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
pub(super) fn ipoly_gcd(a: &[BigInt], b: &[BigInt]) -> IPoly {
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
pub(super) fn square_free_ipoly(p: &[BigInt]) -> IPoly {
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
pub(super) fn square_free_and_chain(p: &IPoly) -> (IPoly, Vec<IPoly>) {
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
pub(super) fn square_free_factors(p: &[BigInt]) -> Vec<(IPoly, u32)> {
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
pub(super) fn sturm_chain(q: IPoly) -> Vec<IPoly> {
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
pub(super) fn count_variations(signs: impl Iterator<Item = i32>) -> usize {
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

pub(super) fn count_variations_dyadic(chain: &[IPoly], x: &Dyadic) -> usize {
    count_variations(chain.iter().map(|p| sign_dyadic(p, x)))
}

/// The sign of p(m·2^e) without fractions: for e = −k < 0 it is the sign of
/// Σ cᵢ·mⁱ·2^(k(n−i)) (p(x) times the positive 2^(kn)), by Horner with
/// shifts.
pub(super) fn sign_dyadic(p: &[BigInt], x: &Dyadic) -> i32 {
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
pub(super) fn sign_rational(p: &[BigInt], x: &BigRational) -> i32 {
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
pub(super) fn upper_root_exp(p: &[BigInt]) -> i64 {
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
pub(super) fn lower_root_exp(p: &[BigInt]) -> i64 {
    let start = p.iter().position(|c| !c.is_zero()).unwrap_or(0);
    let reversed: IPoly = p[start..].iter().rev().cloned().collect();
    if reversed.len() <= 1 {
        return 0; // no nonzero roots: any value will do
    }
    -upper_root_exp(&reversed)
}
