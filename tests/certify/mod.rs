//! An independent check of a certified `roots` answer, shared by the
//! corpus, the issue-17 cases and the fuzz target: it trusts nothing the
//! certificate says but the numbers, and re-derives each claim from the
//! polynomial's exact rational coefficients with `ExactPoly`'s own
//! evaluation and Sturm counts (rational arithmetic, not the dyadic
//! isolation that built the certificate).
#![allow(dead_code)] // each test crate uses a different subset

use num_rational::BigRational;
use sturmray::poly::exact::{Certificate, ExactPoly, ExactSturm};

fn rational(x: f64) -> BigRational {
    BigRational::from_float(x).expect("finite")
}

/// One unit in the last place at |x| (the smallest subnormal at 0).
pub fn ulp(x: f64) -> f64 {
    let x = x.abs();
    (x.next_up() - x).max(f64::from_bits(1))
}

/// Checks `c`, the answer for `coeffs` (lowest degree first) on (a, b] at
/// relative tolerance `tolerance`; Err says which claim failed.
pub fn check(
    coeffs: &[f64],
    a: f64,
    b: f64,
    tolerance: f64,
    c: &Certificate,
) -> Result<(), String> {
    let p = ExactPoly::from_f64(coeffs).ok_or("not finite")?;
    let sturm = ExactSturm::new(&p);
    let count = sturm.count(&rational(a), &rational(b));
    if c.count != count || c.roots.len() != count {
        return Err(format!(
            "count {} with {} roots listed; the exact Sturm count is {count}",
            c.count,
            c.roots.len()
        ));
    }
    let derivative = p.derivative();
    let mut previous = f64::NEG_INFINITY;
    for r in &c.roots {
        let (x, d) = (r.value, r.bound);
        if !(a < x && x <= b) || x < previous {
            return Err(format!("{x} outside ({a}, {b}] or out of order"));
        }
        previous = x;
        // The bound is the exact window rounded up: a few ulps of slack.
        if !(d <= tolerance * x.abs() * (1.0 + 4.0 * f64::EPSILON) || d <= ulp(x)) {
            return Err(format!("{x}: bound {d} above the tolerance {tolerance}"));
        }
        if r.multiplicity == 0 {
            return Err(format!("{x}: multiplicity 0"));
        }
        if d == 0.0 {
            if p.sign_at(&rational(x)) != 0 {
                return Err(format!("{x}: bound 0 but not a root"));
            }
            // A root of multiplicity 1 is not a root of p′, and one of
            // higher multiplicity is.
            let on_derivative = derivative.sign_at(&rational(x)) == 0;
            if on_derivative != (r.multiplicity > 1) {
                return Err(format!(
                    "{x}: multiplicity {} disagrees with p′",
                    r.multiplicity
                ));
            }
            continue;
        }
        let (lo, hi) = (rational(x) - rational(d), rational(x) + rational(d));
        if sturm.count(&lo, &hi) + usize::from(p.sign_at(&lo) == 0) == 0 {
            return Err(format!("{x} ± {d} holds no root"));
        }
        // A root of odd multiplicity is a sign change within the window.
        let (s_lo, s_hi) = (p.sign_at(&lo), p.sign_at(&hi));
        if r.multiplicity % 2 == 1 && r.distinct_in_interval == 1 && s_lo * s_hi > 0 {
            return Err(format!("{x} ± {d}: odd multiplicity, no sign change"));
        }
        // Even multiplicity: p and p′ share the root, so gcd(p, p′) has one
        // in the window.
        if r.multiplicity > 1 {
            let g = p.gcd(&derivative);
            if g.is_zero() || ExactSturm::new(&g).count(&lo, &hi) == 0 {
                return Err(format!(
                    "{x} ± {d}: multiplicity {} but no root of gcd(p, p′)",
                    r.multiplicity
                ));
            }
        }
    }
    Ok(())
}
