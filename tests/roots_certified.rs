//! Issue 17: every answer of `roots` is certified by exact arithmetic, at
//! any degree up to `MAX_EXACT_DEGREE`. Each of the five classes of
//! "wrong answer" is pinned here twice: on the source's printed
//! coefficients, whose rounding moves the roots (the certificate proves the
//! rounded polynomial's own roots, and an exact check independent of it
//! shows they are right), and on exactly representable coefficients, where
//! the source's intended answer is the exact one and must come back, with
//! its multiplicities. Then degrees 36 to 128 and the scaling property.

mod certify;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::Signed;
use proptest::prelude::*;
use sturmray::poly::exact::{Certificate, MAX_EXACT_DEGREE};
use sturmray::poly::solve::{Method, Solver};

fn solve(coeffs: &[f64], a: f64, b: f64) -> Certificate {
    let solver = Solver::default();
    let (c, _) = solver.certified(coeffs, a, b).expect("a valid input");
    certify::check(coeffs, a, b, solver.tolerance, &c)
        .unwrap_or_else(|e| panic!("{coeffs:?}: {e}"));
    c
}

/// The answer is these exact roots (f64 values) with these multiplicities:
/// each within its certified bound of its root (the bound itself is at most
/// the tolerance, checked by `certify::check`).
fn assert_roots(c: &Certificate, want: &[(f64, u32)]) {
    assert_eq!(c.roots.len(), want.len(), "{:?}", c.roots);
    for (got, &(root, m)) in c.roots.iter().zip(want) {
        assert_eq!(got.multiplicity, m, "{got:?} for {root}");
        let err = (rational(got.value) - rational(root)).abs();
        assert!(err <= rational(got.bound), "{got:?} for {root}");
    }
}

fn rational(x: f64) -> BigRational {
    BigRational::from_float(x).unwrap()
}

/// b² − 4c of x² − bx + c, exactly: its sign says two, one or no real roots.
fn discriminant(b: f64, c: f64) -> BigRational {
    let (b, c) = (rational(b), rational(c));
    &b * &b - BigRational::from_integer(BigInt::from(4)) * c
}

const ALL: (f64, f64) = (-f64::MAX, f64::MAX);

/// VTK's x(x − 10⁻⁴)², printed as x³ − 2e-4x² + 1e-8x: a double root
/// "split into two". The printed 2e-4 and 1e-8 are not 2·10⁻⁴ and 10⁻⁸, and
/// for the doubles they are, x² − 2e-4x + 1e-8 has a positive discriminant:
/// two simple roots about 1.7e-12 apart, which is the right answer.
#[test]
fn vtk_double_root_near_1e_4() {
    assert!(discriminant(2e-4, 1e-8) > BigRational::from_integer(0.into()));
    let c = solve(&[0.0, 1e-8, -2e-4, 1.0], ALL.0, ALL.1);
    assert_eq!(c.count, 3);
    assert_eq!(
        c.roots.iter().map(|r| r.multiplicity).collect::<Vec<_>>(),
        [1, 1, 1]
    );
    assert!(c.roots[1].value < 1e-4 && 1e-4 < c.roots[2].value);
    // The double root itself, exact in f64: x(x − 2⁻¹³)².
    let r = 2f64.powi(-13);
    let c = solve(&[0.0, r * r, -2.0 * r, 1.0], ALL.0, ALL.1);
    assert_roots(&c, &[(0.0, 1), (r, 2)]);
    assert_eq!(c.count, 2, "distinct roots, multiplicity apart");
}

/// VTK's x³ − 2e-6x² + 0.999999999999999e-12x: "a close pair near 1e-6
/// comes back as one root". The pair is 6.1e-14 apart, 6e-8 relative, far
/// above the tolerance: two roots, each with its own interval.
#[test]
fn close_pair_near_1e_6() {
    assert!(discriminant(2e-6, 0.999999999999999e-12) > BigRational::from_integer(0.into()));
    let c = solve(&[0.0, 0.999999999999999e-12, -2e-6, 1.0], ALL.0, ALL.1);
    assert_eq!(c.count, 3);
    let (p, q) = (&c.roots[1], &c.roots[2]);
    assert!(
        p.value + p.bound < q.value - q.bound,
        "disjoint intervals: {p:?} {q:?}"
    );
    // Exactly: (x − 2⁻²⁰)² − 2⁻⁹⁰, the pair 2⁻²⁰ ± 2⁻⁴⁵.
    let (m, h) = (2f64.powi(-20), 2f64.powi(-45));
    let c = solve(&[m * m - h * h, -2.0 * m, 1.0], ALL.0, ALL.1);
    assert_roots(&c, &[(m - h, 1), (m + h, 1)]);
}

/// Flocke's cubic 5, (x − 10¹⁴)²(x + 1) as printed: "three roots where it
/// has two". The printed coefficients are not that product's (1e28 −
/// 2e14 rounds), and the exact count of the rounded cubic is 3; the
/// certificate's three intervals are checked independently. With 2⁴⁶ for
/// 10¹⁴ the coefficients are exact and the double root comes back once.
#[test]
fn flocke_double_root_at_1e14() {
    let c = solve(
        &[1e28, 0.99999999999998e28, -1.99999999999999e14, 1.0],
        ALL.0,
        ALL.1,
    );
    assert_eq!(c.count, 3);
    let r = 2f64.powi(46);
    let c = solve(&[r * r, r * r - 2.0 * r, 1.0 - 2.0 * r, 1.0], ALL.0, ALL.1);
    assert_roots(&c, &[(-1.0, 1), (r, 2)]);
}

/// "A quartic with no real roots comes back with two roots 2e-8 apart": a
/// complex pair 2⁻²⁰ off the real axis, (x² − 2x + 1 + 2⁻⁴⁰)(x² + 1), whose
/// f64 Sturm chain sees a near-double root. Exactly: none. Flocke's
/// quartics 9-13 (no real roots) are in the corpus.
#[test]
fn quartic_without_real_roots() {
    let e = 2f64.powi(-40);
    let c = [1.0 + e, -2.0, 2.0 + e, -2.0, 1.0];
    for method in Method::ALL {
        let solver = Solver {
            method: *method,
            ..Solver::default()
        };
        let (cert, _) = solver.certified(&c, ALL.0, ALL.1).unwrap();
        assert_eq!(cert.count, 0, "{method:?}");
        assert!(cert.roots.is_empty(), "{method:?}");
    }
}

/// "One quartic root is 7e-9 off where the case asks for 1e-12": Flocke's
/// quartic 2 as printed has roots 7.4e-8 from 1, 1.001, 1.002, 1.003
/// (the printed coefficients are rounded), and each reported root is within
/// 1e-12 of the rounded quartic's own root: the bound says so and the exact
/// check confirms a sign change inside it, away from the source's 1.
#[test]
fn quartic_root_within_the_tolerance_of_its_own_root() {
    let coeffs = [1.006011006, -4.018022006, 6.018011, -4.006, 1.0];
    let c = solve(&coeffs, ALL.0, ALL.1);
    assert_eq!(c.count, 4);
    let first = &c.roots[0];
    assert!(first.bound <= 1e-12 * first.value.abs() * (1.0 + 1e-15));
    assert!(
        first.value - first.bound > 1.0,
        "the rounded quartic's root is not 1: {first:?}"
    );
    for r in &c.roots {
        assert!(r.bound <= 1e-12 * r.value.abs() * (1.0 + 1e-15), "{r:?}");
    }
}

/// Degree 36 to 128: the exact path answers alone (the f64 path's storage
/// stops at 35), with multiplicities. (x² − 2)⁵⁰ has exact coefficients
/// C(50, k)·2^(50−k) and two irrational roots of multiplicity 50.
#[test]
fn degree_100_with_multiplicity_50() {
    let mut c = vec![0.0; 101];
    let mut binomial = 1.0f64; // C(50, k), exact below 2^53
    for k in 0..=50 {
        c[2 * k] = binomial * 2f64.powi(50 - k as i32) * if (50 - k) % 2 == 0 { 1.0 } else { -1.0 };
        binomial = binomial * (50 - k) as f64 / (k + 1) as f64;
    }
    let cert = solve(&c, ALL.0, ALL.1);
    let s = 2f64.sqrt();
    // √2 is irrational: the bound holds for the root, and fl(√2) is within
    // half an ulp of it.
    assert_eq!(
        cert.roots
            .iter()
            .map(|r| r.multiplicity)
            .collect::<Vec<_>>(),
        [50, 50]
    );
    for (r, want) in cert.roots.iter().zip([-s, s]) {
        assert!(
            (r.value - want).abs() <= r.bound + certify::ulp(want),
            "{r:?}"
        );
    }
    assert_eq!(cert.degree, 100);
    assert_eq!(cert.square_free_degree, 2);
}

#[test]
fn degree_limit() {
    let solver = Solver::default();
    let mut c = vec![0.0; MAX_EXACT_DEGREE + 1];
    c[0] = -1.0;
    c[MAX_EXACT_DEGREE] = 1.0; // x^128 − 1: ±1
    let (cert, _) = solver.certified(&c, ALL.0, ALL.1).unwrap();
    assert_eq!(cert.values(), [-1.0, 1.0]);
    c.push(1.0);
    assert!(
        solver.certified(&c, ALL.0, ALL.1).is_none(),
        "degree 129 is refused"
    );
}

prop_compose! {
    /// A product of roots on a grid of eighths with multiplicities up to 4,
    /// times free coefficients: degree up to 40 (the property runs in
    /// `cargo test`; tests/fuzz_poly.rs goes to 100).
    fn polynomial()(
        roots in prop::collection::vec((-16i32..=16, 1u32..=4), 0..6),
        free in prop::collection::vec(-1e3..1e3f64, 1..8),
    ) -> Vec<f64> {
        let mut c = free;
        for (r, m) in roots {
            for _ in 0..m {
                let r = f64::from(r) / 8.0;
                let mut next = vec![0.0; c.len() + 1];
                for (i, &ci) in c.iter().enumerate() {
                    next[i + 1] += ci;
                    next[i] -= r * ci;
                }
                c = next;
            }
        }
        c
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Scaling every coefficient by the same power of two changes no part
    /// of the answer (values, multiplicities, bounds), over the whole double
    /// range, subnormal coefficients included, whenever the scaling is
    /// exact (no coefficient rounds or overflows).
    #[test]
    fn scaling_by_a_power_of_two_changes_nothing(c in polynomial(), k in -1100i32..=1000) {
        let s = 2f64.powi(k.clamp(-1022, 1023)) * 2f64.powi(k - k.clamp(-1022, 1023));
        let scaled: Vec<f64> = c.iter().map(|x| x * s).collect();
        let exact = scaled.iter().zip(&c).all(|(y, x)| y.is_finite() && y / s == *x);
        prop_assume!(exact && scaled.iter().any(|&y| y != 0.0));
        let solver = Solver::default();
        let (a, b) = (-1e300, 1e300);
        let (one, _) = solver.certified(&c, a, b).unwrap();
        let (two, _) = solver.certified(&scaled, a, b).unwrap();
        prop_assert_eq!(&one.roots, &two.roots, "scale 2^{}", k);
        certify::check(&scaled, a, b, solver.tolerance, &two).map_err(TestCaseError::fail)?;
    }
}

/// The ends of the double range in one polynomial: the smallest subnormal
/// and the largest double as coefficients, MAX·x² − 2⁻¹⁰⁷⁴, with roots
/// ±√(2⁻¹⁰⁷⁴ / MAX) = ±2⁻¹⁰⁴⁹·(1 + ε/4 + …), themselves subnormal, where
/// f64's spacing is 2⁻¹⁰⁷⁴: answered as ±2⁻¹⁰⁴⁹, correctly rounded.
#[test]
fn smallest_subnormal_and_largest_double() {
    let tiny = f64::from_bits(1);
    let c = solve(&[-tiny, 0.0, f64::MAX], ALL.0, ALL.1);
    assert_eq!(c.count, 2);
    let root = 2f64.powi(-1049);
    assert_eq!(c.values(), [-root, root]);
}
