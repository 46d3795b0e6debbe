//! Closed-form roots for degrees up to four: the stable quadratic that the
//! quadric shapes use directly, and cubic and quartic formulas kept as
//! comparison methods for the accuracy study. Closed forms decide double
//! roots by the sign of a discriminant computed in f64, so they miss some
//! tangent hits that the Sturm path gets; that is what the study measures.
//!
//! All functions take coefficients lowest degree first, write real roots in
//! increasing order and return how many; exactly equal roots are reported
//! once. An exactly zero leading coefficient drops to the lower degree.

use crate::math::larger;
use crate::poly::univariate::pow2_reciprocal;

/// Numerically stable quadratic c2 t^2 + c1 t + c0: q = -(b + sign(b)
/// sqrt(disc)) / 2, roots q/a and c/q, so the small root never comes from
/// the cancellation in -b + sqrt(disc). The discriminant is recomputed with
/// FMA (Kahan's trick) when b^2 and 4ac nearly cancel, which is exactly the
/// tangent-ray case. Coefficients are first scaled by a power of two so b^2
/// neither overflows nor underflows.
pub fn quadratic(c0: f64, c1: f64, c2: f64, out: &mut [f64; 4]) -> usize {
    if c2 == 0.0 {
        return linear(c0, c1, out);
    }
    // A NaN coefficient makes every root NaN, whatever the scale.
    let max = larger(larger(c0.abs(), c1.abs()), c2.abs());
    let s = if max >= f64::MIN_POSITIVE && max.is_finite() {
        pow2_reciprocal(max)
    } else {
        1.0
    };
    let (a, b, c) = (c2 * s, c1 * s, c0 * s);
    let disc = discriminant(a, b, c);
    if disc.is_nan() || disc < 0.0 {
        return 0;
    }
    if disc == 0.0 {
        out[0] = -b / (2.0 * a);
        return 1;
    }
    let q = -0.5 * (b + disc.sqrt().copysign(b));
    let (r1, r2) = (q / a, c / q);
    write_pair(r1, r2, out)
}

/// `write_sorted` of two roots, without its insertion loop and move: the
/// same roots in the same order (a NaN dropped, an equal pair kept once as
/// the first), for a quadratic's many callers, CSG's clip spheres among
/// them, where the general loop took a third of `quadratic`'s
/// instructions (`valgrind --tool=callgrind`, POV-Ray's tcubic.pov).
fn write_pair(r1: f64, r2: f64, out: &mut [f64; 4]) -> usize {
    let pair: &[f64] = match (r1.is_nan(), r2.is_nan()) {
        (true, true) => &[],
        (false, true) => &[r1],
        (true, false) => &[r2],
        _ if r1 == r2 => &[r1],
        _ if r1 > r2 => &[r2, r1],
        _ => &[r1, r2],
    };
    out[..pair.len()].copy_from_slice(pair);
    pair.len()
}

fn linear(c0: f64, c1: f64, out: &mut [f64; 4]) -> usize {
    if c1 == 0.0 {
        return 0;
    }
    out[0] = -c0 / c1;
    1
}

/// b^2 - 4ac, with the rounding of both products recovered by FMA when they
/// nearly cancel (Kahan, "On the cost of floating-point computation without
/// extra-precise arithmetic").
fn discriminant(a: f64, b: f64, c: f64) -> f64 {
    let p = b * b;
    let q = 4.0 * a * c;
    let d = p - q;
    if 3.0 * d.abs() >= p + q.abs() {
        return d;
    }
    let dp = b.mul_add(b, -p);
    let dq = (4.0 * a).mul_add(c, -q);
    d + (dp - dq)
}

/// Real roots of c3 t^3 + c2 t^2 + c1 t + c0: Cardano with the
/// cancellation-free sign choice when there is one real root, the
/// trigonometric form when there are three, then a Newton polish on the
/// original coefficients.
pub fn cubic(c: [f64; 4], out: &mut [f64; 4]) -> usize {
    if c[3] == 0.0 {
        return quadratic(c[0], c[1], c[2], out);
    }
    let (a, b, d) = (c[2] / c[3], c[1] / c[3], c[0] / c[3]);
    let shift = a / 3.0;
    let p = b - a * shift;
    let q = d - shift * b + 2.0 * shift * shift * shift;
    let mut roots = [0.0; 3];
    let n = depressed_cubic(p, q, &mut roots);
    for r in &mut roots[..n] {
        *r = polish(&c, *r - shift);
    }
    write_sorted(&roots[..n], out)
}

/// Real roots of x^3 + p x + q, unsorted.
fn depressed_cubic(p: f64, q: f64, out: &mut [f64; 3]) -> usize {
    let h = 0.5 * q;
    let k = p / 3.0;
    let disc = h * h + k * k * k;
    if disc > 0.0 || k >= 0.0 {
        // One real root; -h - sign(h) sqrt(disc) adds magnitudes.
        let u = (-h - disc.max(0.0).sqrt().copysign(h)).cbrt();
        out[0] = if u == 0.0 { 0.0 } else { u - k / u };
        return 1;
    }
    let r = (-k).sqrt();
    let cos3 = (-h / (r * r * r)).clamp(-1.0, 1.0);
    let theta = cos3.acos() / 3.0;
    let third = 2.0 * std::f64::consts::FRAC_PI_3;
    for (j, slot) in out.iter_mut().enumerate() {
        *slot = 2.0 * r * (theta - third * j as f64).cos();
    }
    3
}

/// Real roots of c4 t^4 + ... + c0 by Ferrari: depress, take the largest
/// root m of the resolvent cubic, split into two quadratics, polish.
pub fn quartic(c: [f64; 5], out: &mut [f64; 4]) -> usize {
    if c[4] == 0.0 {
        return cubic([c[0], c[1], c[2], c[3]], out);
    }
    let (a, b, cc, d) = (c[3] / c[4], c[2] / c[4], c[1] / c[4], c[0] / c[4]);
    let aa = a * a;
    let p = b - 0.375 * aa;
    let q = cc - 0.5 * a * b + 0.125 * aa * a;
    let r = d - 0.25 * a * cc + aa * b / 16.0 - 3.0 * aa * aa / 256.0;
    let mut roots = [0.0; 4];
    let n = depressed_quartic(p, q, r, &mut roots);
    let shift = 0.25 * a;
    for x in &mut roots[..n] {
        *x = polish(&c, *x - shift);
    }
    write_sorted(&roots[..n], out)
}

/// Real roots of x^4 + p x^2 + q x + r, unsorted.
fn depressed_quartic(p: f64, q: f64, r: f64, out: &mut [f64; 4]) -> usize {
    let mut m_roots = [0.0; 4];
    let nm = cubic([-0.125 * q * q, 0.25 * p * p - r, p, 1.0], &mut m_roots);
    let m = if nm > 0 { m_roots[nm - 1] } else { 0.0 };
    // m <= 0 (or NaN) only through round-off when q is tiny.
    if q == 0.0 || m.is_nan() || m <= 0.0 {
        return biquadratic(p, r, out);
    }
    let s = (2.0 * m).sqrt();
    let t = 0.5 * q / s;
    let base = 0.5 * p + m;
    let mut pair = [0.0; 4];
    let mut n = 0;
    for (lin, cst) in [(-s, base + t), (s, base - t)] {
        let k = quadratic(cst, lin, 1.0, &mut pair);
        out[n..n + k].copy_from_slice(&pair[..k]);
        n += k;
    }
    n
}

/// x^4 + p x^2 + r: a quadratic in y = x^2, keeping y >= 0.
fn biquadratic(p: f64, r: f64, out: &mut [f64; 4]) -> usize {
    let mut ys = [0.0; 4];
    let ny = quadratic(r, p, 1.0, &mut ys);
    let mut n = 0;
    for &y in &ys[..ny] {
        if y > 0.0 {
            let x = y.sqrt();
            out[n] = -x;
            out[n + 1] = x;
            n += 2;
        } else if y == 0.0 {
            out[n] = 0.0;
            n += 1;
        }
    }
    n
}

/// Up to two Newton steps on the original polynomial, each kept only if it
/// lowers |p|: the closed forms lose digits to cancellation, Newton earns
/// them back, and the guard keeps it from wandering at a double root.
fn polish<const N: usize>(c: &[f64; N], mut x: f64) -> f64 {
    let (mut f, mut df) = eval_with_derivative(c, x);
    for _ in 0..2 {
        if f == 0.0 || df == 0.0 {
            break;
        }
        let next = x - f / df;
        let (nf, ndf) = eval_with_derivative(c, next);
        let better = nf.abs() < f.abs();
        if !better {
            break;
        }
        (x, f, df) = (next, nf, ndf);
    }
    x
}

fn eval_with_derivative(c: &[f64], t: f64) -> (f64, f64) {
    let (last, rest) = c.split_last().expect("non-empty coefficients");
    let mut value = *last;
    let mut slope = 0.0;
    for &ci in rest.iter().rev() {
        slope = slope * t + value;
        value = value * t + ci;
    }
    (value, slope)
}

/// Writes `roots` to `out` in increasing order, exactly equal ones once.
fn write_sorted(roots: &[f64], out: &mut [f64; 4]) -> usize {
    let mut n = 0;
    for &r in roots {
        if r.is_nan() {
            continue;
        }
        let mut i = n;
        while i > 0 && out[i - 1] > r {
            i -= 1;
        }
        if i > 0 && out[i - 1] == r {
            continue;
        }
        out.copy_within(i..n, i + 1);
        out[i] = r;
        n += 1;
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_roots(got: &[f64], want: &[f64], rel: f64) {
        assert_eq!(got.len(), want.len(), "got {got:?}, want {want:?}");
        for (g, w) in got.iter().zip(want) {
            let err = (g - w).abs() / w.abs().max(1.0);
            assert!(err <= rel, "got {got:?}, want {want:?}");
        }
    }

    fn quad(c0: f64, c1: f64, c2: f64) -> Vec<f64> {
        let mut out = [0.0; 4];
        let n = quadratic(c0, c1, c2, &mut out);
        out[..n].to_vec()
    }

    fn cub(c: [f64; 4]) -> Vec<f64> {
        let mut out = [0.0; 4];
        let n = cubic(c, &mut out);
        out[..n].to_vec()
    }

    fn quar(c: [f64; 5]) -> Vec<f64> {
        let mut out = [0.0; 4];
        let n = quartic(c, &mut out);
        out[..n].to_vec()
    }

    #[test]
    fn quadratic_small_root_keeps_full_relative_precision() {
        // t^2 + 1e8 t + 1: roots -1e8 (1 - 1e-16 ...) and -1e-8 (1 + 1e-16 ...).
        let r = quad(1.0, 1e8, 1.0);
        assert_eq!(r.len(), 2);
        let small = -1e-8 * (1.0 + 1e-16);
        assert!(
            ((r[1] - small) / small).abs() <= 2.0 * f64::EPSILON,
            "{r:?}"
        );
        assert!(((r[0] + 1e8) / 1e8).abs() <= 2.0 * f64::EPSILON, "{r:?}");
        // The textbook formula loses the small root entirely here.
        let naive = (-1e8 + (1e16f64 - 4.0).sqrt()) / 2.0;
        assert!(((naive - small) / small).abs() > 0.1);
    }

    #[test]
    fn quadratic_cases() {
        assert_roots(&quad(-1.0, 0.0, 1.0), &[-1.0, 1.0], 0.0);
        assert_roots(&quad(1.0, 0.0, 1.0), &[], 0.0);
        assert_roots(&quad(1.0, -2.0, 1.0), &[1.0], 0.0);
        assert_roots(&quad(0.0, 0.0, 1.0), &[0.0], 0.0);
        assert_roots(&quad(0.0, 3.0, 1.0), &[-3.0, 0.0], 0.0);
        assert_roots(&quad(-6.0, 2.0, 0.0), &[3.0], 0.0);
        assert_roots(&quad(1.0, 0.0, 0.0), &[], 0.0);
        assert_roots(&quad(6e200, -5e200, 1e200), &[2.0, 3.0], 1e-15);
        assert_roots(&quad(6e-200, -5e-200, 1e-200), &[2.0, 3.0], 1e-15);
        // (t - 0.1)^2 with rounded coefficients: the FMA discriminant sees
        // the true sign of what the coefficients say, and never NaN.
        let r = quad(0.1 * 0.1, -0.2, 1.0);
        assert!(
            r.len() <= 2 && r.iter().all(|x| (x - 0.1).abs() < 1e-7),
            "{r:?}"
        );
    }

    #[test]
    fn discriminant_recovers_cancelled_digits() {
        // b^2 - 4ac = (1 + 2^-30)^2 - 4 * 1 * (1 + 2^-29) / 4 ... = 2^-60.
        let b = 1.0 + 2f64.powi(-30);
        let c = (1.0 + 2f64.powi(-29)) / 4.0;
        assert_eq!(discriminant(1.0, b, c), 2f64.powi(-60));
    }

    #[test]
    fn cubic_against_known_roots() {
        // (t-1)(t-2)(t-3)
        assert_roots(&cub([-6.0, 11.0, -6.0, 1.0]), &[1.0, 2.0, 3.0], 1e-14);
        // (t-2)(t^2+1): one real root
        assert_roots(&cub([-2.0, 1.0, -2.0, 1.0]), &[2.0], 1e-14);
        // -2 (t+0.5)(t-0.25)(t-4), negative leading coefficient
        assert_roots(&cub([-1.0, 2.25, 7.5, -2.0]), &[-0.5, 0.25, 4.0], 1e-14);
        // t^3: triple root at zero
        assert_roots(&cub([0.0, 0.0, 0.0, 1.0]), &[0.0], 0.0);
        // t^3 - 8: one real root
        assert_roots(&cub([-8.0, 0.0, 0.0, 1.0]), &[2.0], 1e-15);
        // Widely spread roots 1e-3, 1, 1e3.
        let (r1, r2, r3) = (1e-3, 1.0, 1e3);
        let c = [
            -r1 * r2 * r3,
            r1 * r2 + r1 * r3 + r2 * r3,
            -(r1 + r2 + r3),
            1.0,
        ];
        assert_roots(&cub(c), &[r1, r2, r3], 1e-12);
        // Degree drop to a quadratic.
        assert_roots(&cub([-1.0, 0.0, 1.0, 0.0]), &[-1.0, 1.0], 0.0);
    }

    #[test]
    fn cubic_double_root_is_found_approximately() {
        // (t-1)^2 (t-2): a closed form may or may not resolve the double
        // root (that is the comparison), but whatever it reports is near a
        // true root and the simple root is always there.
        let r = cub([-2.0, 5.0, -4.0, 1.0]);
        assert!(r.iter().any(|x| (x - 2.0).abs() < 1e-12), "{r:?}");
        assert!(
            r.iter()
                .all(|x| (x - 2.0).abs() < 1e-12 || (x - 1.0).abs() < 1e-6),
            "{r:?}"
        );
    }

    #[test]
    fn quartic_against_known_roots() {
        // (t-1)(t-2)(t-3)(t-4)
        assert_roots(
            &quar([24.0, -50.0, 35.0, -10.0, 1.0]),
            &[1.0, 2.0, 3.0, 4.0],
            1e-13,
        );
        // Biquadratic (t^2-1)(t^2-9): a ray through both tubes of a torus.
        assert_roots(
            &quar([9.0, 0.0, -10.0, 0.0, 1.0]),
            &[-3.0, -1.0, 1.0, 3.0],
            1e-15,
        );
        // (t^2+1)(t-1)(t-2) = t^4 - 3t^3 + 3t^2 - 3t + 2: two real roots
        assert_roots(&quar([2.0, -3.0, 3.0, -3.0, 1.0]), &[1.0, 2.0], 1e-14);
        // (t^2+1)(t^2+4): none
        assert_roots(&quar([4.0, 0.0, 5.0, 0.0, 1.0]), &[], 0.0);
        // 3 (t+2)(t-0.5)(t-1.5)(t-7), scaled
        let roots = [-2.0, 0.5, 1.5, 7.0];
        let e1: f64 = roots.iter().sum();
        let e2 = pairs(&roots);
        let e3 = -roots[0] * roots[1] * roots[2]
            - roots[0] * roots[1] * roots[3]
            - roots[0] * roots[2] * roots[3]
            - roots[1] * roots[2] * roots[3];
        let e4: f64 = roots.iter().product();
        let c = [3.0 * e4, 3.0 * e3, 3.0 * e2, -3.0 * e1, 3.0];
        assert_roots(&quar(c), &roots, 1e-13);
        // Degree drop.
        assert_roots(&quar([-6.0, 11.0, -6.0, 1.0, 0.0]), &[1.0, 2.0, 3.0], 1e-14);
    }

    fn pairs(r: &[f64]) -> f64 {
        let mut s = 0.0;
        for i in 0..r.len() {
            for j in i + 1..r.len() {
                s += r[i] * r[j];
            }
        }
        s
    }

    #[test]
    fn write_sorted_orders_and_dedupes() {
        let mut out = [0.0; 4];
        let n = write_sorted(&[3.0, -1.0, 3.0, 0.5], &mut out);
        assert_eq!(&out[..n], &[-1.0, 0.5, 3.0]);
        let n = write_sorted(&[f64::NAN, 2.0], &mut out);
        assert_eq!(&out[..n], &[2.0]);
    }

    #[test]
    fn write_pair_is_write_sorted_of_two() {
        let values = [f64::NAN, -1.0, -0.0, 0.0, 0.5, 3.0, f64::INFINITY];
        for &r1 in &values {
            for &r2 in &values {
                let (mut pair, mut sorted) = ([9.0; 4], [9.0; 4]);
                let n = write_pair(r1, r2, &mut pair);
                assert_eq!(n, write_sorted(&[r1, r2], &mut sorted), "{r1}, {r2}");
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&pair[..n]), bits(&sorted[..n]), "{r1}, {r2}");
            }
        }
    }
}
