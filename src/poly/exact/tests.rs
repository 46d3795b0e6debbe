//! Tests of the exact path: counts, roots and multiplicities against
//! polynomials built from known roots, certificates, time caps.

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
    let c0: f64 = 1.0 - 1e-12;
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
