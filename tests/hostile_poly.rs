//! Hostile polynomials (issue #14): an algebraic surface's F scaled by any
//! finite k ≠ 0 is the same surface, and `sturmray roots` never contradicts
//! itself, whatever the coefficients' magnitudes (subnormal to 1e308).

mod common;
mod fuzz_common;

use std::io::Write;
use std::process::{Command, Stdio};

use glam::{DAffine3, DVec3};
use proptest::prelude::*;
use serde_json::Value;

use common::{SQUARE, plane_scene, scratch, sturmray, write};
use sturmray::geometry::{Box3, Shape, ShapeHit, Surface};
use sturmray::poly::MAX_DEGREE;
use sturmray::poly::exact::{MAX_EXACT_DEGREE, exact_count, exact_roots};
use sturmray::poly::expr;
use sturmray::poly::solve::Solver;

// ---------------------------------------------------------------------------
// k·F is F

/// Algebraic surfaces with their clip box: three of the gallery's (degrees
/// 4, 4 and 6) and two of degree 16. The degree-16 boxes fit closely: from
/// a box corner far outside, Q(t) of x^16 + … cancels so much that any
/// rounding of F (k = 7 as much as a subnormal k) moves a few hits (the
/// solver's conditioning, not scaling; measured: 4 of 931 rays at 1.2).
const SURFACES: [(&str, f64); 5] = [
    ("x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8", 2.2),
    ("x^2*y^2 + y^2*z^2 + z^2*x^2 - x*y*z", 0.55),
    (
        "(x^2 + 2.25*y^2 + z^2 - 1)^3 - x^2*z^3 - 0.1125*y^2*z^3",
        1.3,
    ),
    ("x^16 + y^16 + z^16 - 0.9", 1.0),
    ("(x^2 + y^2 + z^2)^8 - 0.5", 1.0),
];

/// Scale factors from subnormal to the top of the range, both signs, powers
/// of two and not.
const SCALES: [f64; 13] = [
    1e-310, 1e-300, -1e-300, 1e-150, -3.7e-5, 0.1, -1.0, 7.0, 1e150, 1e300, -1e300, 1e308, -1.5e308,
];

fn shape(text: &str, half: f64) -> Option<Shape> {
    let f = expr::parse(text, &[]).ok()?;
    let surface = Surface::Algebraic(Box::new(f));
    Some(
        Shape::new(
            surface,
            DAffine3::IDENTITY,
            Some(Box3::cube(half)),
            0,
            Solver::default(),
        )
        .unwrap(),
    )
}

/// A fan of rays from outside the box through it, some hitting the surface
/// (from outside and, past the first hit, from inside), some missing.
fn rays(half: f64) -> Vec<(DVec3, DVec3)> {
    let eye = DVec3::new(0.7, 0.45, 3.0) * half;
    let mut out = Vec::new();
    for i in 0..13 {
        for j in 0..13 {
            let target = DVec3::new(f64::from(i) / 6.0 - 1.0, f64::from(j) / 6.0 - 1.0, 0.1) * half;
            out.push((eye, target - eye));
        }
    }
    out
}

/// Whether two hits agree: exactly (rel = 0) or to within rel in t and in
/// the unit normal.
fn same_hit(a: Option<ShapeHit>, b: Option<ShapeHit>, rel: f64) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            let (na, nb) = (a.normal.normalize(), b.normal.normalize());
            na.is_finite()
                && if rel == 0.0 {
                    a.t == b.t && na == nb
                } else {
                    (a.t - b.t).abs() <= rel * b.t.abs() && (na - nb).length() <= rel
                }
        }
        _ => false,
    }
}

/// Every ray meets k·F where it meets F, at the same t and with the same
/// normal: bit for bit when k is a power of two (then k·F is exact and F is
/// scaled back exactly), within 1e-9 otherwise (k·F's coefficients are
/// rounded, to 44 bits when subnormal). Before: F·1e308 overflowed Q(t)
/// and vanished, F·1e-300 had normals that underflowed to zero (black),
/// a degree-16 surface times 1e300 had infinite normals.
#[test]
fn scaling_an_algebraic_surface_keeps_every_hit() {
    for (text, half) in SURFACES {
        let reference = shape(text, half).unwrap();
        let rays = rays(half);
        let hits: Vec<Option<ShapeHit>> = rays
            .iter()
            .map(|&(o, d)| reference.intersect(o, d, 0.0, f64::INFINITY))
            .collect();
        assert!(
            hits.iter().filter(|h| h.is_some()).count() > 10,
            "{text}: the fan must hit the surface"
        );
        // Powers of two that keep k·F normal leave it exact.
        let powers_of_two = [2f64.powi(-1000), 2f64.powi(1000), -(2f64.powi(500))];
        for k in SCALES
            .into_iter()
            .chain(powers_of_two)
            .chain([2f64.powi(-1060)])
        {
            let scaled = format!("{k:e}*({text})");
            let Some(s) = shape(&scaled, half) else {
                // Only where k·F itself is beyond f64: 11.8·1.5e308.
                assert!(k.abs() * 11.8 > f64::MAX, "{scaled} refused");
                continue;
            };
            let rel = if powers_of_two.contains(&k) {
                0.0
            } else {
                1e-9
            };
            for (&(o, d), &want) in rays.iter().zip(&hits) {
                // −F is F with its outside (F > 0) turned in: the gradient flips.
                let got = s.intersect(o, d, 0.0, f64::INFINITY).map(|h| ShapeHit {
                    normal: h.normal * k.signum(),
                    ..h
                });
                assert!(
                    same_hit(got, want, rel),
                    "{scaled}: ray {o} + t {d}: {got:?}, with k = 1 {want:?}"
                );
                if want.is_some() {
                    assert!(s.occluded(o, d, 0.0, f64::INFINITY), "{scaled}: shadow ray");
                }
            }
        }
    }
}

/// A normalised F can still have a huge gradient far from the origin: on
/// x^16 − y^16 + z = 0 near (1e11, 1e11, 0), ∇F ≈ (16x^15, −16y^15, 1) is
/// about 1.6e166, |∇F|² overflowed, and the normal normalised to zero
/// (black). The hit's gradient is now scaled by a power of two first.
#[test]
fn huge_gradients_still_give_unit_normals() {
    let s = shape("x^16 - y^16 + z", 1e12).unwrap();
    // Along the gradient's direction, from 1 off either side to x = y.
    let d = DVec3::new(1.0, -1.0, 0.0).normalize();
    let o = DVec3::new(1e11 - 1.0, 1e11 + 1.0, 0.0);
    let hit = s.intersect(o, d, 0.0, f64::INFINITY).expect("a hit");
    // Coordinates near 1e11 are 1.5e-5 apart: t is no better than that.
    assert!((hit.t - 2f64.sqrt()).abs() <= 1e-4, "{hit:?}");
    let unit = hit.normal.normalize_or_zero();
    assert!((unit - d).length() < 1e-12, "{hit:?}");
}

/// On a thread that reads subnormals as zero (the CLI's main thread, where
/// scenes are parsed, and every render thread), 1e-310·F is still F: its
/// coefficients were subnormal products, and "identically zero".
#[test]
fn subnormal_scales_parse_on_flush_to_zero_threads() {
    let text = "x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8";
    let want = expr::parse(text, &[]).unwrap().normalized().0;
    std::thread::spawn(move || {
        sturmray::accel::ftz::enable_flush_to_zero();
        for k in ["1e-310", "0.5^1070", "1e-300*1e-10"] {
            let got = expr::parse(&format!("{k}*({text})"), &[])
                .unwrap_or_else(|e| panic!("{k}: {e}"))
                .normalized()
                .0;
            assert_eq!(got.terms().len(), want.terms().len(), "{k}: {got}");
            let ratio = got.terms()[0].1 / want.terms()[0].1;
            for (g, w) in got.terms().iter().zip(want.terms()) {
                assert!((g.1 - ratio * w.1).abs() <= 1e-12 * g.1.abs(), "{k}: {got}");
                assert_eq!(g.0, w.0);
            }
        }
    })
    .join()
    .unwrap();
}

/// A surface whose F has only subnormal coefficients is not "identically
/// zero" and renders like F; through the scene file and the CLI, images
/// of F and k·F are byte for byte the same for a power of two k and the
/// same 8-bit preview for any k.
#[test]
fn scaled_surfaces_render_the_same_image() {
    let dir = scratch("poly-scaled-render");
    write(&dir, "square.obj", SQUARE);
    // The gallery's quartic, small, above the square it shadows.
    let scene = |expr: &str| {
        plane_scene(&format!(
            "[[objects]]\ntype = \"algebraic\"\nexpr = \"{expr}\"\n\
             clip = {{ min = [-2.2, -2.2, -2.2], max = [2.2, 2.2, 2.2] }}\n\
             material = \"paint\"\ntransform = {{ translate = [0, 0, 1], scale = 0.3 }}\n"
        ))
    };
    let base = "x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8";
    let render = |name: &str, expr: &str| {
        write(&dir, &format!("{name}.toml"), &scene(expr));
        let out = sturmray(
            &dir,
            &[
                "render",
                &format!("{name}.toml"),
                "-o",
                &format!("{name}.exr"),
            ],
        );
        assert!(
            out.status.success(),
            "{expr}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let exr = std::fs::read(dir.join(format!("{name}.exr"))).unwrap();
        let png = std::fs::read(dir.join(format!("{name}.png"))).unwrap();
        (exr, png)
    };
    let (exr, png) = render("f", base);
    write(&dir, "empty.toml", &plane_scene(""));
    assert!(sturmray(&dir, &["render", "empty.toml"]).status.success());
    let empty = std::fs::read(dir.join("out/empty.png")).unwrap();
    assert!(png != empty, "the surface must show in the image");
    for (i, k) in ["0.5^1000", "2^1000", "1e-310", "1e-300", "1e300", "-1e150"]
        .iter()
        .enumerate()
    {
        let (k_exr, k_png) = render(&format!("k{i}"), &format!("{k}*({base})"));
        assert!(k_png == png, "k = {k}: the preview differs");
        if k.contains('^') {
            assert!(k_exr == exr, "k = {k}: the EXR differs");
        }
    }
}

// ---------------------------------------------------------------------------
// `sturmray roots`

/// Runs `sturmray roots` on these JSON lines; one reply per line.
fn roots_cli(lines: &[String]) -> Vec<Value> {
    let dir = scratch("poly-roots-cli");
    let mut child = Command::new(env!("CARGO_BIN_EXE_sturmray"))
        .arg("roots")
        .current_dir(&dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    for line in lines {
        writeln!(stdin, "{line}").unwrap();
    }
    drop(stdin);
    let out = child.wait_with_output().unwrap();
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

fn roots_of(reply: &Value) -> Vec<f64> {
    reply["roots"]
        .as_array()
        .unwrap_or_else(|| panic!("no roots in {reply}"))
        .iter()
        .map(|r| r.as_f64().unwrap())
        .collect()
}

fn query(coeffs: &[f64], interval: Option<(f64, f64)>) -> String {
    let c: Vec<String> = coeffs.iter().map(|c| format!("{c:e}")).collect();
    match interval {
        Some((a, b)) => format!(
            r#"{{"coeffs": [{}], "interval": [{a:e}, {b:e}]}}"#,
            c.join(", ")
        ),
        None => format!(r#"{{"coeffs": [{}]}}"#, c.join(", ")),
    }
}

fn close(got: f64, want: f64, rel: f64) -> bool {
    (got - want).abs() <= rel * want.abs()
}

/// The issue's cases and their kin: count and list agree, every root is
/// right relative to its own size, and subnormal coefficients are numbers.
/// Before: count 0 with two roots listed; count 2 with one root 42% off;
/// "identically zero" for subnormal coefficients.
#[test]
fn roots_never_contradicts_itself() {
    // Coefficients, interval (None: the default), the roots.
    type Case = (Vec<f64>, Option<(f64, f64)>, Vec<f64>);
    let cases: Vec<Case> = vec![
        (
            vec![1e300, 0.0, -1e-300],
            Some((-1e308, 1e308)),
            vec![-1e300, 1e300],
        ),
        (vec![-1.0, 0.0, 1e28], None, vec![-1e-14, 1e-14]),
        (vec![-1e28, 0.0, 1.0], None, vec![-1e14, 1e14]),
        (vec![-1e-310, 0.0, 1e-310], None, vec![-1.0, 1.0]),
        (vec![5e-324, 5e-324], None, vec![-1.0]),
        (vec![-1e-310, 1.0], None, vec![1e-310]),
        (
            vec![-3e-300, 0.0, 1e300],
            None,
            vec![-(3f64.sqrt()) * 1e-300, 3f64.sqrt() * 1e-300],
        ),
        (
            vec![1e-320, 0.0, 0.0, 1e-10],
            None,
            vec![-(1e-320f64 / 1e-10).cbrt()],
        ),
        // (t − 2^-600)(t + 2^700): roots 2^-600 apart from 2^700.
        (
            vec![-(2f64.powi(100)), 2f64.powi(700) - 2f64.powi(-600), 1.0],
            None,
            vec![-(2f64.powi(700)), 2f64.powi(-600)],
        ),
    ];
    let lines: Vec<String> = cases.iter().map(|(c, i, _)| query(c, *i)).collect();
    let replies = roots_cli(&lines);
    assert_eq!(replies.len(), cases.len());
    for ((c, _, want), reply) in cases.iter().zip(&replies) {
        let got = roots_of(reply);
        assert_eq!(
            reply["count"].as_u64(),
            Some(got.len() as u64),
            "{c:?}: {reply}"
        );
        assert_eq!(got.len(), want.len(), "{c:?}: {reply}");
        for (&g, &w) in got.iter().zip(want) {
            // 1e-12 is the default tolerance; 4e-12 covers the rounding of
            // the expected values themselves (sqrt, cbrt of a subnormal).
            assert!(close(g, w, 4e-12), "{c:?}: {g} for {w}: {reply}");
        }
    }
    // Zeros and constants are decided exactly, from the bits.
    let replies = roots_cli(&[query(&[0.0, -0.0], None), query(&[1e-320], None)]);
    assert!(
        replies[0]["error"]
            .as_str()
            .unwrap()
            .contains("identically zero")
    );
    assert!(replies[1]["error"].as_str().unwrap().contains("constant"));
}

/// Scaling the coefficients by a power of two, however large, changes no
/// answer (the roots are the same numbers).
#[test]
fn roots_ignore_power_of_two_scaling() {
    let c = [-2.0, 3.5, 1.25, -0.75, 0.125];
    let scales = [
        1.0,
        2f64.powi(-1070 + 3),
        2f64.powi(-600),
        2f64.powi(600),
        2f64.powi(1020),
    ];
    let lines: Vec<String> = scales
        .iter()
        .map(|s| query(&c.map(|x| x * s), None))
        .collect();
    let replies = roots_cli(&lines);
    let first = roots_of(&replies[0]);
    assert!(!first.is_empty());
    for (s, reply) in scales.iter().zip(&replies) {
        assert_eq!(roots_of(reply), first, "scale {s:e}: {reply}");
        assert_eq!(reply["count"], replies[0]["count"]);
    }
}

/// Coefficients with magnitudes from the subnormal range to 1e308, mixed
/// (mantissa · 10^e, e uniform in [-310, 308], zeros and signs among them).
fn extreme_polynomial(max_degree: usize) -> impl Strategy<Value = Vec<f64>> {
    let coefficient = prop_oneof![
        6 => (1.0..10.0f64, -310i32..=307, any::<bool>()).prop_map(|(m, e, negative)| {
            let c = format!("{}{m}e{e}", if negative { "-" } else { "" });
            c.parse::<f64>().unwrap()
        }),
        1 => Just(0.0),
    ];
    prop::collection::vec(coefficient, 2..=max_degree + 1)
        .prop_filter("not constant", |c| c[1..].iter().any(|&x| x != 0.0))
}

/// Degree of the property test: up to the limit. The exact path's cost
/// grows with the spread of exponents (integers of ~2000 bits) and the
/// degree: about 20 ms a case at degree 16, so `cargo test` runs 48.
const FUZZ_DEGREE: usize = MAX_DEGREE;

proptest! {
    #![proptest_config(fuzz_common::config(48))]

    /// For any such polynomial on (-MAX, MAX]: as many roots as the exact
    /// Sturm count, increasing, each within the tolerance of the exact root
    /// at its place (the correctly rounded roots of the exact path, which
    /// are the reference; a subnormal root can be no closer than an ulp).
    #[test]
    fn fuzz_roots_at_extreme_scales(c in extreme_polynomial(FUZZ_DEGREE), method in 0usize..3) {
        let solver = Solver {
            method: ["sturm-newton", "sturm-bisect", "closed"][method].parse().unwrap(),
            ..Solver::default()
        };
        let (a, b) = (-f64::MAX, f64::MAX);
        let got = solver.certified_roots(&c, a, b).expect("finite input");
        let count = exact_count(&c, a, b).expect("finite input");
        prop_assert_eq!(got.len(), count, "{:?}: {:?}", c, got);
        let want = exact_roots(&c, a, b, 0.0).expect("finite input");
        prop_assert_eq!(want.len(), count);
        for (&g, &w) in got.iter().zip(&want) {
            let ulp = (w.abs().next_up() - w.abs()).max(f64::from_bits(1));
            prop_assert!(
                (g - w).abs() <= solver.tolerance * w.abs() + ulp,
                "{:?}: {} for the exact {} in {:?}", c, g, w, got
            );
        }
    }
}

// ---------------------------------------------------------------------------
// Degree 35 (issue #20): POV-Ray's `poly` limit

/// The Chebyshev polynomial T_35 by its recurrence T_(n+1) = 2x T_n −
/// T_(n−1): integer coefficients below 2^42, so exact in f64, and its roots
/// are known in closed form, cos((2k − 1)π/70).
fn chebyshev_35() -> Vec<f64> {
    let (mut prev, mut cur) = (vec![1.0], vec![0.0, 1.0]);
    for _ in 1..35 {
        let mut next = vec![0.0; cur.len() + 1];
        for (i, c) in cur.iter().enumerate() {
            next[i + 1] += 2.0 * c;
        }
        for (i, c) in prev.iter().enumerate() {
            next[i] -= c;
        }
        (prev, cur) = (cur, next);
    }
    cur
}

/// (t − 1)^m (t − r)^n expanded: for (m, n, r) = (34, 1, 1 + 2^-11) and
/// (33, 2, 1 + 2^-10) every coefficient is exact in f64 (checked in exact
/// rationals when the cases were chosen; (33, 2, 1 + 2^-11) is not, and a
/// 33-fold root moved by one rounding spreads by some 1e-16^(1/33)), so the
/// roots are exactly 1 and r.
fn cluster(m: usize, r: f64, n: usize) -> Vec<f64> {
    let mut c = vec![1.0];
    for root in std::iter::repeat_n(1.0, m).chain(std::iter::repeat_n(r, n)) {
        let mut next = vec![0.0; c.len() + 1];
        for (i, &ci) in c.iter().enumerate() {
            next[i + 1] += ci;
            next[i] -= root * ci;
        }
        c = next;
    }
    c
}

/// `roots` at degree 35: the 35 simple roots of T_35, a root of
/// multiplicity 35, a 34-fold root 2^-11 from a simple one (the f64 chain
/// cannot hold them apart; the exact path answers), degree 36 answered by
/// the exact path and degree 129 refused with the limit named.
#[test]
fn roots_at_degree_35() {
    let t35 = chebyshev_35();
    assert_eq!(t35.len(), MAX_DEGREE + 1);
    let (r, r2) = (1.0 + 2f64.powi(-11), 1.0 + 2f64.powi(-10));
    let replies = roots_cli(&[
        query(&t35, Some((-2.0, 2.0))),
        query(&cluster(35, 1.0, 0), Some((0.0, 2.0))),
        query(&cluster(34, r, 1), Some((0.0, 2.0))),
        query(&cluster(33, r2, 2), Some((0.0, 2.0))),
        query(&[1.0; MAX_DEGREE + 2], None),
        query(&[1.0; MAX_EXACT_DEGREE + 2], None),
    ]);
    let got = roots_of(&replies[0]);
    assert_eq!(replies[0]["count"], 35, "{}", replies[0]);
    for (k, &t) in got.iter().enumerate() {
        // Increasing order: k = 35 down to 1. The cosine itself is rounded
        // (T_35's root at 0 comes out as 6e-17), hence absolute slack of a
        // few ulps on top of the 1e-12 tolerance.
        let want = (f64::from(2 * (35 - k as i32) - 1) * std::f64::consts::PI / 70.0).cos();
        assert!(
            (t - want).abs() <= 1e-12 * want.abs() + 1e-15,
            "root {k}: {t} vs {want}"
        );
    }
    assert_eq!(roots_of(&replies[1]), [1.0], "{}", replies[1]);
    assert_eq!(roots_of(&replies[2]), [1.0, r], "{}", replies[2]);
    assert_eq!(roots_of(&replies[3]), [1.0, r2], "{}", replies[3]);
    // 1 + x + ... + x^36: above the f64 path's 35 the exact path answers
    // (no real roots: at -1 the 37 terms sum to 1); above 128, an error.
    assert_eq!(replies[4]["count"], 0, "{}", replies[4]);
    let error = replies[5]["error"].as_str().unwrap();
    assert!(error.contains("degree <= 128"), "{error}");
}

/// x^20 + y^20 + z^20 = 1, a rounded cube of degree 20, crosses each axis
/// at exactly ±1 (simple roots: the gradient there is 20 along the axis),
/// and the diagonal at 3^(-1/20) per coordinate. Times a sphere of radius
/// 0.5 (degree 22), and times a sixfold sphere of radius 2 as well (degree
/// 34), it keeps those crossings and adds the inner sphere's at ±0.5.
#[test]
fn degree_20_to_34_surfaces_hit_where_known() {
    let cube = "x^20 + y^20 + z^20 - 1";
    let sphere = "(x^2 + y^2 + z^2 - 0.25)";
    let cases = [
        // The surface, t from 0.75 out along an axis, inwards (the far side
        // of the cube at -1, or the sphere at 0.5), and the error allowed.
        (cube.to_string(), 1.75, 1e-12),
        (format!("({cube}) * {sphere}"), 0.25, 1e-12),
        // Not the tolerance: measured 4.7e-8 at the cube's crossing. The f64
        // path's error at degree 34 with a sixfold factor; whether Q(t)'s
        // rounded coefficients or the solver cost it is not separated here.
        (
            format!("({cube}) * {sphere} * (x^2 + y^2 + z^2 - 4)^6"),
            0.25,
            1e-6,
        ),
    ];
    for (text, inner, tol) in &cases {
        let s = shape(text, 2.5).unwrap_or_else(|| panic!("{text} did not parse"));
        for axis in [DVec3::X, DVec3::Y, DVec3::Z, -DVec3::X, -DVec3::Z] {
            // From 1.75 (inside the sixfold sphere): the cube at 1 first.
            for (start, want) in [(1.75, 0.75), (0.75, *inner)] {
                let hit = s.intersect(axis * start, -axis, 0.0, 10.0).expect("a hit");
                assert!(
                    (hit.t - want).abs() <= *tol,
                    "{text} along {axis}: {}",
                    hit.t
                );
                let along = hit.normal.normalize().dot(axis).abs();
                assert!(along >= 1.0 - tol, "{text}: {}", hit.normal);
            }
        }
    }
    // Along the diagonal, the cube's crossing 3^(-1/20) per coordinate.
    let s = shape(cube, 2.5).unwrap();
    let d = DVec3::ONE.normalize();
    let hit = s.intersect(DVec3::ONE * 2.0, -d, 0.0, 10.0).expect("a hit");
    let want = (2.0 - 3f64.powf(-1.0 / 20.0)) * 3f64.sqrt();
    assert!((hit.t - want).abs() <= 1e-12, "{} vs {want}", hit.t);
    assert!(hit.normal.normalize().dot(d) >= 1.0 - 1e-12);
}
