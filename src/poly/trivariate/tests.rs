use super::*;
use proptest::prelude::*;

fn torus_direct(p: [f64; 3], big_r: f64, r: f64) -> f64 {
    let [x, y, z] = p;
    let s = x * x + y * y + z * z + big_r * big_r - r * r;
    s * s - 4.0 * big_r * big_r * (x * x + y * y)
}

/// The torus, expanded by hand:
/// (x²+y²+z²)² − 2(R²+r²)(x²+y²) + 2(R²−r²)z² + (R²−r²)².
/// Also the algebraic torus of `geometry::analytic`'s tests.
pub(crate) fn torus(big_r: f64, r: f64) -> Trivariate {
    let (r2, s2) = (big_r * big_r, r * r);
    Trivariate::from_terms([
        ([4, 0, 0], 1.0),
        ([0, 4, 0], 1.0),
        ([0, 0, 4], 1.0),
        ([2, 2, 0], 2.0),
        ([2, 0, 2], 2.0),
        ([0, 2, 2], 2.0),
        ([2, 0, 0], -2.0 * (r2 + s2)),
        ([0, 2, 0], -2.0 * (r2 + s2)),
        ([0, 0, 2], 2.0 * (r2 - s2)),
        ([0, 0, 0], (r2 - s2) * (r2 - s2)),
    ])
}

/// Σ |c| |x^a y^b z^c|: the scale against which rounding errors of an
/// evaluation are judged, so cancellation does not fail a test.
fn abs_scale(p: &Trivariate, q: [f64; 3]) -> f64 {
    p.terms()
        .iter()
        .map(|&(e, c)| {
            c.abs()
                * q[0].abs().powi(i32::from(e[0]))
                * q[1].abs().powi(i32::from(e[1]))
                * q[2].abs().powi(i32::from(e[2]))
        })
        .sum()
}

fn horner(q: &[f64], t: f64) -> f64 {
    q.iter().rev().fold(0.0, |acc, &c| acc * t + c)
}

fn ray_point(o: [f64; 3], d: [f64; 3], t: f64) -> [f64; 3] {
    [o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]]
}

/// Checks Q(t) against F(o + t d) at several t, relative to the scale
/// of the terms involved.
fn check_ray(f: &Trivariate, direct: impl Fn([f64; 3]) -> f64, o: [f64; 3], d: [f64; 3]) {
    let mut q = [f64::NAN; MAX_DEGREE + 1];
    let n = f.substitute_ray(o, d, &mut q);
    assert_eq!(n, f.degree() + 1);
    for &t in &[-2.5, -1.0, -0.3, 0.0, 0.2, 0.7, 1.0, 1.9, 3.3] {
        let p = ray_point(o, d, t);
        let want = direct(p);
        let got = horner(&q[..n], t);
        // The expansion's rounding is bounded by F with every sign made
        // positive, at |o| + |t||d|.
        let bound = std::array::from_fn(|i| o[i].abs() + t.abs() * d[i].abs());
        let scale = abs_scale(f, bound).max(1e-300);
        assert!(
            (got - want).abs() <= 1e-12 * scale,
            "t = {t}: Q(t) = {got}, F(o + t d) = {want}, scale {scale}"
        );
    }
}

#[test]
fn from_terms_merges_sorts_and_drops_zeros() {
    let p = Trivariate::from_terms([
        ([0, 0, 1], 1.0),
        ([2, 0, 0], 3.0),
        ([0, 0, 1], 2.0),
        ([1, 1, 0], 4.0),
        ([1, 1, 0], -4.0),
        ([5, 5, 5], 0.0),
    ]);
    assert_eq!(p.terms(), &[([2, 0, 0], 3.0), ([0, 0, 1], 3.0)]);
    assert_eq!(p.degree(), 2);
    assert!(Trivariate::from_terms([([1, 0, 0], 0.0)]).is_zero());
    assert_eq!(Trivariate::zero().degree(), 0);
}

#[test]
#[should_panic(expected = "exceeds MAX_DEGREE")]
fn from_terms_refuses_degree_above_the_limit() {
    Trivariate::from_terms([([12, 12, 12], 1.0)]);
}

#[test]
fn eval_matches_direct_evaluation() {
    let f = torus(1.0, 0.25);
    for p in [[0.3, -1.2, 0.1], [2.0, 0.5, -0.7], [0.0, 0.0, 0.0]] {
        let want = torus_direct(p, 1.0, 0.25);
        assert!((f.eval(p) - want).abs() <= 1e-13 * abs_scale(&f, p));
    }
    // The tube's centre circle at (R, 0, 0) + r along x lies on the surface.
    assert!(f.eval([1.25, 0.0, 0.0]).abs() < 1e-14);
}

#[test]
fn substitute_ray_torus() {
    let f = torus(1.0, 0.25);
    let direct = |p| torus_direct(p, 1.0, 0.25);
    check_ray(&f, direct, [-3.0, 0.1, 0.05], [1.0, 0.0, 0.0]);
    check_ray(&f, direct, [0.3, -2.0, 1.5], [0.2, 0.9, -0.6]);
    check_ray(&f, direct, [0.0, 0.0, 5.0], [0.0, 0.0, -1.0]);
    // Along x through both tubes: roots at ±0.75 and ±1.25 (t shifted by 3).
    let mut q = [0.0; 5];
    f.substitute_ray([-3.0, 0.0, 0.0], [1.0, 0.0, 0.0], &mut q);
    for root in [1.75, 2.25, 3.75, 4.25] {
        assert!(
            horner(&q, root).abs() < 1e-12,
            "Q({root}) = {}",
            horner(&q, root)
        );
    }
}

/// A degree-6 surface with mixed odd and even terms, evaluated directly.
fn sextic_direct(p: [f64; 3]) -> f64 {
    let [x, y, z] = p;
    (x * x + y * y - 1.0).powi(3) - x * x * y * y * y + 0.5 * z.powi(6) - 2.0 * x * y * z + 0.3
}

fn sextic() -> Trivariate {
    // (x² + y² − 1)³ = x⁶ + 3x⁴y² + 3x²y⁴ + y⁶ − 3x⁴ − 6x²y² − 3y⁴ + 3x² + 3y² − 1
    Trivariate::from_terms([
        ([6, 0, 0], 1.0),
        ([4, 2, 0], 3.0),
        ([2, 4, 0], 3.0),
        ([0, 6, 0], 1.0),
        ([4, 0, 0], -3.0),
        ([2, 2, 0], -6.0),
        ([0, 4, 0], -3.0),
        ([2, 0, 0], 3.0),
        ([0, 2, 0], 3.0),
        ([0, 0, 0], -1.0 + 0.3),
        ([2, 3, 0], -1.0),
        ([0, 0, 6], 0.5),
        ([1, 1, 1], -2.0),
    ])
}

#[test]
fn substitute_ray_degree_6() {
    let f = sextic();
    assert_eq!(f.degree(), 6);
    check_ray(&f, sextic_direct, [0.4, -1.1, 0.3], [0.3, 0.8, -0.5]);
    check_ray(&f, sextic_direct, [-2.0, 0.0, 1.0], [1.0, 0.1, -0.2]);
}

/// Every monomial of total degree <= 16 with a distinct coefficient:
/// the densest polynomial the renderer can meet.
fn dense16() -> Trivariate {
    let mut terms = Vec::new();
    for a in 0..=16u8 {
        for b in 0..=16 - a {
            for c in 0..=16 - a - b {
                let k = f64::from(a) * 0.37 + f64::from(b) * 1.13 - f64::from(c) * 0.71;
                terms.push(([a, b, c], k.sin() + 0.1));
            }
        }
    }
    Trivariate::from_terms(terms)
}

#[test]
fn substitute_ray_degree_16() {
    // (x² + y² + z² − 1)⁸ against its direct evaluation.
    let sphere = Trivariate::from_terms([
        ([2, 0, 0], 1.0),
        ([0, 2, 0], 1.0),
        ([0, 0, 2], 1.0),
        ([0, 0, 0], -1.0),
    ]);
    let f = sphere.checked_pow(8).unwrap();
    assert_eq!(f.degree(), 16);
    let direct = |p: [f64; 3]| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2] - 1.0).powi(8);
    check_ray(&f, direct, [0.2, -0.3, 0.1], [0.5, 0.6, -0.3]);
    check_ray(&f, direct, [1.0, 1.0, 1.0], [-0.4, -0.2, -0.1]);

    let dense = dense16();
    assert_eq!(dense.terms().len(), 969);
    let direct = |p: [f64; 3]| {
        let mut sum = 0.0;
        for &(e, c) in dense.terms() {
            sum += c
                * p[0].powi(i32::from(e[0]))
                * p[1].powi(i32::from(e[1]))
                * p[2].powi(i32::from(e[2]));
        }
        sum
    };
    check_ray(&dense, direct, [0.1, 0.2, -0.3], [0.3, -0.4, 0.5]);
    check_ray(&dense, direct, [0.5, -0.5, 0.2], [0.0, 0.0, 0.3]);
}

#[test]
fn substitute_ray_sparse_and_constant_pieces() {
    // Gaps in every exponent and a bare constant exercise the Horner
    // bookkeeping: x^16 + y^16 + z^16 + x^3 z^5 − 1.
    let f = Trivariate::from_terms([
        ([16, 0, 0], 1.0),
        ([0, 16, 0], 1.0),
        ([0, 0, 16], 1.0),
        ([3, 0, 5], 1.0),
        ([0, 0, 0], -1.0),
    ]);
    let direct = |p: [f64; 3]| {
        p[0].powi(16) + p[1].powi(16) + p[2].powi(16) + p[0].powi(3) * p[2].powi(5) - 1.0
    };
    check_ray(&f, direct, [0.3, 0.2, -0.1], [0.2, 0.3, 0.25]);
    // A ray with d = 0 along some axes: the leading coefficients vanish.
    let mut q = [f64::NAN; 17];
    assert_eq!(
        f.substitute_ray([0.5, 0.0, 0.0], [0.0, 1.0, 0.0], &mut q),
        17
    );
    assert_eq!(q[16], 1.0);
    assert!(q[1..16].iter().all(|&c| c == 0.0));
    assert_eq!(q[0], 0.5f64.powi(16) - 1.0);
    // A constant: Q(t) is that constant.
    let mut q = [f64::NAN; 3];
    assert_eq!(
        Trivariate::constant(2.5).substitute_ray([1.0; 3], [1.0; 3], &mut q),
        1
    );
    assert_eq!(q[0], 2.5);
    assert_eq!(
        Trivariate::zero().substitute_ray([1.0; 3], [1.0; 3], &mut q),
        1
    );
    assert_eq!(q[0], 0.0);
}

#[test]
fn goursat_ray_along_an_axis() {
    // x⁴ − 5x² + 11.8 on the x axis (y = z = 0, plus y⁴ − 5y² etc. = 0).
    let f = Trivariate::from_terms([
        ([4, 0, 0], 1.0),
        ([2, 0, 0], -5.0),
        ([0, 4, 0], 1.0),
        ([0, 2, 0], -5.0),
        ([0, 0, 4], 1.0),
        ([0, 0, 2], -5.0),
        ([0, 0, 0], 11.8),
    ]);
    let mut q = [0.0; 5];
    f.substitute_ray([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], &mut q);
    assert_eq!(q, [11.8, 0.0, -5.0, 0.0, 1.0]);
}

#[test]
fn gradient_matches_central_differences() {
    for (f, direct) in [
        (
            torus(1.0, 0.3),
            Box::new(|p| torus_direct(p, 1.0, 0.3)) as Box<dyn Fn([f64; 3]) -> f64>,
        ),
        (sextic(), Box::new(sextic_direct)),
    ] {
        let grad = f.gradient();
        for p in [[0.3, -0.8, 0.2], [1.1, 0.4, -0.5], [-0.2, 0.1, 0.9]] {
            let g = f.eval_gradient(p);
            for axis in 0..3 {
                let h = 1e-5;
                let (mut lo, mut hi) = (p, p);
                lo[axis] -= h;
                hi[axis] += h;
                let fd = (direct(hi) - direct(lo)) / (2.0 * h);
                let scale = 1.0 + abs_scale(&f, p);
                assert!(
                    (g[axis] - fd).abs() < 1e-7 * scale,
                    "axis {axis} at {p:?}: {} vs {fd}",
                    g[axis]
                );
                // The polynomial gradient agrees with the allocation-free one.
                assert!((grad[axis].eval(p) - g[axis]).abs() < 1e-13 * scale);
            }
        }
    }
    // d/dx of x³y²z = 3x²y²z.
    let m = Trivariate::from_terms([([3, 2, 1], 2.0)]);
    assert_eq!(m.gradient()[0].terms(), &[([2, 2, 1], 6.0)]);
    assert_eq!(m.gradient()[1].terms(), &[([3, 1, 1], 4.0)]);
    assert_eq!(m.gradient()[2].terms(), &[([3, 2, 0], 2.0)]);
}

#[test]
fn compose_affine_matches_direct_evaluation() {
    let m = [[0.8, -0.6, 0.1], [0.6, 0.8, -0.2], [0.05, 0.3, 1.5]];
    let c = [0.4, -1.2, 0.7];
    let map = |p: [f64; 3]| -> [f64; 3] {
        std::array::from_fn(|i| m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + c[i])
    };
    for (f, direct) in [
        (
            torus(1.0, 0.25),
            Box::new(|p| torus_direct(p, 1.0, 0.25)) as Box<dyn Fn([f64; 3]) -> f64>,
        ),
        (sextic(), Box::new(sextic_direct)),
    ] {
        let g = f.compose_affine(m, c);
        assert_eq!(g.degree(), f.degree());
        for p in [
            [0.3, -0.8, 0.2],
            [1.1, 0.4, -0.5],
            [-0.2, 0.1, 0.9],
            [0.0; 3],
        ] {
            let want = direct(map(p));
            let scale = abs_scale(&g, p).max(abs_scale(&f, map(p)));
            assert!((g.eval(p) - want).abs() <= 1e-12 * scale);
        }
    }
    // The identity map changes nothing; a translation of x² is exact.
    let id = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let f = sextic();
    assert_eq!(f.compose_affine(id, [0.0; 3]), f);
    let x2 = Trivariate::from_terms([([2, 0, 0], 1.0)]);
    assert_eq!(
        x2.compose_affine(id, [3.0, 0.0, 0.0]).terms(),
        &[([2, 0, 0], 1.0), ([1, 0, 0], 6.0), ([0, 0, 0], 9.0)]
    );
    // Degree 16 too.
    let dense = dense16();
    let g = dense.compose_affine(m, c);
    for p in [[0.1, -0.2, 0.05], [-0.3, 0.2, -0.1]] {
        let q = map(p);
        let scale = abs_scale(&g, p).max(abs_scale(&dense, q));
        assert!((g.eval(p) - dense.eval(q)).abs() <= 1e-11 * scale);
    }
}

#[test]
fn arithmetic_and_degree_limits() {
    let x = Trivariate::variable(0);
    let y = Trivariate::variable(1);
    let s = x.add(&y);
    // (x + y)² = x² + 2xy + y²
    assert_eq!(
        s.checked_pow(2).unwrap().terms(),
        &[([2, 0, 0], 1.0), ([1, 1, 0], 2.0), ([0, 2, 0], 1.0)]
    );
    assert_eq!(s.sub(&x), y);
    assert!(s.sub(&s).is_zero());
    assert_eq!(s.checked_pow(0).unwrap(), Trivariate::constant(1.0));
    assert!(s.checked_pow(36).is_none());
    assert!(s.checked_pow(u32::MAX).is_none());
    let x17 = x.checked_pow(17).unwrap();
    let x18 = x17.checked_mul(&x).unwrap();
    assert!(x17.checked_mul(&x18).is_some());
    assert!(x18.checked_mul(&x18).is_none());
    assert_eq!(s.scale(0.0), Trivariate::zero());
    assert_eq!(
        Trivariate::constant(3.0).div_scalar(2.0).constant_value(),
        Some(1.5)
    );
    assert_eq!(x.constant_value(), None);
}

#[test]
fn display_reads_as_an_expression() {
    let f = Trivariate::from_terms([
        ([4, 0, 0], 1.0),
        ([2, 0, 0], -5.0),
        ([1, 1, 1], -1.0),
        ([0, 0, 0], 11.8),
    ]);
    assert_eq!(f.to_string(), "x^4 - 5*x^2 - x*y*z + 11.8");
    assert_eq!(Trivariate::constant(-2.0).to_string(), "-2");
    assert_eq!(Trivariate::zero().to_string(), "0");
    assert_eq!(
        Trivariate::from_terms([([0, 1, 0], 1e-20)]).to_string(),
        "1e-20*y"
    );
}

fn arb_trivariate(max_terms: usize) -> impl Strategy<Value = Trivariate> {
    let exps = (0u8..=8, 0u8..=4, 0u8..=4);
    let coef = prop_oneof![-10.0..10.0f64, Just(1.0), Just(-1.0), -1e-9..1e-9f64];
    prop::collection::vec((exps, coef), 1..max_terms)
        .prop_map(|v| Trivariate::from_terms(v.into_iter().map(|((a, b, c), k)| ([a, b, c], k))))
}

proptest! {
    #[test]
    fn prop_substitute_ray_agrees_with_eval(
        f in arb_trivariate(30),
        o in prop::array::uniform3(-2.0..2.0f64),
        d in prop::array::uniform3(-1.0..1.0f64),
        t in -2.0..2.0f64,
    ) {
        let mut q = [0.0; MAX_DEGREE + 1];
        let n = f.substitute_ray(o, d, &mut q);
        let p = ray_point(o, d, t);
        let bound = std::array::from_fn(|i| o[i].abs() + t.abs() * d[i].abs());
        let scale = abs_scale(&f, bound).max(1e-300);
        prop_assert!((horner(&q[..n], t) - f.eval(p)).abs() <= 1e-12 * scale);
    }

    #[test]
    fn prop_compose_then_eval_is_eval_of_map(
        f in arb_trivariate(12),
        m in prop::array::uniform3(prop::array::uniform3(-1.5..1.5f64)),
        c in prop::array::uniform3(-1.0..1.0f64),
        p in prop::array::uniform3(-1.0..1.0f64),
    ) {
        let g = f.compose_affine(m, c);
        let q: [f64; 3] = std::array::from_fn(|i| m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + c[i]);
        // Rounding is bounded by F with all signs made positive, at the
        // point the map sends p to with all signs made positive.
        let q_abs: [f64; 3] = std::array::from_fn(|i| {
            (0..3).map(|j| m[i][j].abs() * p[j].abs()).sum::<f64>() + c[i].abs()
        });
        let scale = abs_scale(&f, q_abs).max(1e-300);
        prop_assert!((g.eval(p) - f.eval(q)).abs() <= 1e-12 * scale);
    }
}

proptest! {
    /// `substitute_ray` sizes its accumulators by the degree; the smaller
    /// ones must give the bits of the full-size ones.
    #[test]
    fn substitution_is_the_same_in_any_accumulator_size(
        coeffs in proptest::collection::vec(-100.0f64..100.0, 35),
        o in proptest::array::uniform3(-10.0f64..10.0),
        d in proptest::array::uniform3(-1.0f64..1.0),
    ) {
        // Every term of degree 4 or less: 35 of them.
        let mut exps = Vec::new();
        for i in 0..=4u8 {
            for j in 0..=4 - i {
                for k in 0..=4 - i - j {
                    exps.push([i, j, k]);
                }
            }
        }
        let f = Trivariate::from_terms(exps.into_iter().zip(coeffs));
        let (mut quartic, mut full) = ([0.0; SIDE], [0.0; SIDE]);
        let n = f.substitute_in::<QUARTIC_SLOTS>(o, d, &mut quartic);
        prop_assert_eq!(n, f.substitute_in::<SIDE>(o, d, &mut full));
        prop_assert_eq!(quartic.map(f64::to_bits), full.map(f64::to_bits));
    }
}

proptest! {
    /// The table walk of `quartic` skips groups without terms and products
    /// with the zeros above each polynomial's degree, and adds the rest in
    /// the order of the term list's walk, which it replaced: so the same
    /// bits for every term pattern of degree ≤ 4 (only the sign of a zero
    /// may differ, where a zero product is no longer added to it).
    #[test]
    fn quartic_table_gives_the_term_walks_bits(
        terms in prop::collection::vec(((0u8..=4, 0u8..=4, 0u8..=4), -100.0f64..100.0), 1..36),
        o in prop::array::uniform3(-10.0f64..10.0),
        d in prop::array::uniform3(-1.0f64..1.0),
    ) {
        let f = Trivariate::from_terms(
            terms.into_iter().filter(|((a, b, c), _)| a + b + c <= 4).map(|((a, b, c), k)| ([a, b, c], k)),
        );
        prop_assume!(!f.is_zero());
        let (mut table, mut walk) = ([0.0f64; QUARTIC_SLOTS], [0.0f64; QUARTIC_SLOTS]);
        let n = f.substitute_ray(o, d, &mut table);
        let m = if f.degree() == 3 {
            f.substitute_sparse::<4>(o, d, &mut walk)
        } else {
            f.substitute_sparse::<QUARTIC_SLOTS>(o, d, &mut walk)
        };
        prop_assert_eq!(n, m);
        for (a, b) in table[..n].iter().zip(&walk[..n]) {
            prop_assert!(a.to_bits() == b.to_bits() || (*a == 0.0 && *b == 0.0), "{a} against {b}");
        }
    }
}
