//! Hard cases for the analytic surfaces, each checked against exact geometry
//! worked out here (never against the solver itself): tangent and grazing
//! rays, rays through a torus's hole and both tubes, thin tori, far-away and
//! tiny objects, repeated roots, and rays that start on a surface.

mod common;

use glam::{DAffine3, DVec3};

use common::{scratch, write};
use sturmray::accel::{Accel, Backend};
use sturmray::geometry::{Box3, Shape, Surface};
use sturmray::math::{Ray, offset};
use sturmray::poly::expr;
use sturmray::poly::solve::Solver;
use sturmray::scene::Scene;

fn shape(surface: Surface, to_world: DAffine3, clip: Option<Box3>) -> Shape {
    Shape::new(surface, to_world, clip, 0, Solver::default()).unwrap()
}

fn sphere(radius: f64) -> Shape {
    shape(Surface::Sphere { radius }, DAffine3::IDENTITY, None)
}

fn torus(major: f64, minor: f64) -> Shape {
    shape(Surface::Torus { major, minor }, DAffine3::IDENTITY, None)
}

fn algebraic(text: &str, half: f64) -> Shape {
    let f = expr::parse(text, &[]).unwrap();
    shape(
        Surface::Algebraic(Box::new(f)),
        DAffine3::IDENTITY,
        Some(Box3::cube(half)),
    )
}

fn hit_t(s: &Shape, o: DVec3, d: DVec3) -> Option<f64> {
    s.intersect(o, d, 0.0, f64::INFINITY).map(|h| {
        assert!(h.t.is_finite() && h.normal.is_finite(), "finite hit: {h:?}");
        h.t
    })
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * b.abs().max(1.0)
}

#[test]
fn sphere_tangent_and_grazing_rays_follow_the_exact_silhouette() {
    let s = sphere(1.0);
    let d = DVec3::NEG_Z;
    // Exactly tangent: a double root at t = 5, where the ray touches the sphere without
    // entering it. The renderer counts only crossings (a sign change of Q above its
    // rounding noise), so a touch is a miss, for intersect and occluded alike.
    assert_eq!(hit_t(&s, DVec3::new(1.0, 0.0, 5.0), d), None);
    assert!(!s.occluded(DVec3::new(1.0, 0.0, 5.0), d, 0.0, 10.0));
    for k in 3..=12 {
        let e = 10f64.powi(-k);
        // Inside the silhouette: hits at 5 − sqrt(1 − y²); outside: misses. Never NaN.
        let y = 1.0 - e;
        let expected = 5.0 - (1.0 - y * y).sqrt();
        let t =
            hit_t(&s, DVec3::new(0.0, y, 5.0), d).unwrap_or_else(|| panic!("miss at 1 - 1e-{k}"));
        assert!(close(t, expected, 1e-9), "1 - 1e-{k}: {t} vs {expected}");
        assert_eq!(
            hit_t(&s, DVec3::new(0.0, 1.0 + e, 5.0), d),
            None,
            "1 + 1e-{k}"
        );
        assert!(s.occluded(DVec3::new(0.0, y, 5.0), d, 0.0, 10.0));
        assert!(!s.occluded(DVec3::new(0.0, 1.0 + e, 5.0), d, 0.0, 10.0));
    }
}

#[test]
fn torus_tangent_rays() {
    let (big, small) = (1.0, 0.25);
    let t = torus(big, small);
    // Along x in the plane z = r: tangent to the top circle at x = ±R (two double roots).
    // Just below it, two close pairs of roots; the nearest is at x ≈ −R.
    for k in 4..=10 {
        let e = 10f64.powi(-k);
        let z = small * (1.0 - e);
        let o = DVec3::new(-5.0, 0.0, z);
        let half_chord = (small * small - z * z).sqrt();
        // Nearest crossing: the tube around x = −R, entered at x = −R − half_chord.
        let expected = 5.0 - big - half_chord;
        let got = hit_t(&t, o, DVec3::X).unwrap_or_else(|| panic!("miss at r(1 - 1e-{k})"));
        assert!(close(got, expected, 1e-9), "k={k}: {got} vs {expected}");
        assert_eq!(
            hit_t(&t, DVec3::new(-5.0, 0.0, small * (1.0 + e)), DVec3::X),
            None
        );
    }
    // Tangent to the outer equator: along y at x = R + r touches at one point.
    let touch = hit_t(
        &t,
        DVec3::new(big + small * (1.0 - 1e-9), -5.0, 0.0),
        DVec3::Y,
    );
    assert!(touch.is_some_and(|v| close(v, 5.0, 1e-3)), "{touch:?}");
    assert_eq!(
        hit_t(
            &t,
            DVec3::new(big + small * (1.0 + 1e-9), -5.0, 0.0),
            DVec3::Y
        ),
        None
    );
}

#[test]
fn torus_axis_through_the_hole_and_through_both_tubes() {
    let (big, small) = (1.0, 0.25);
    let t = torus(big, small);
    // Down the axis: through the hole, nothing.
    assert_eq!(hit_t(&t, DVec3::new(0.0, 0.0, 5.0), DVec3::NEG_Z), None);
    // Along x through the centre: four roots in two close pairs, x = −1.25, −0.75, 0.75, 1.25.
    let o = DVec3::new(-5.0, 0.0, 0.0);
    let mut tmin = 0.0;
    let mut found = Vec::new();
    while let Some(h) = t.intersect(o, DVec3::X, tmin, f64::INFINITY) {
        found.push(o.x + h.t);
        tmin = h.t + 1e-9;
    }
    let expected = [-big - small, -big + small, big - small, big + small];
    assert_eq!(found.len(), 4, "{found:?}");
    for (f, e) in found.iter().zip(expected) {
        assert!(close(*f, e, 1e-10), "{found:?}");
    }
}

#[test]
fn thin_torus() {
    let (big, small) = (1.0, 1e-3);
    let t = torus(big, small);
    // Straight down through the tube's centre circle: hits at z = r.
    let got = hit_t(&t, DVec3::new(big, 0.0, 1.0), DVec3::NEG_Z).unwrap();
    assert!(close(got, 1.0 - small, 1e-12), "{got}");
    // Across the tube in the plane z = 0 from outside: the outer circle R + r.
    let got = hit_t(&t, DVec3::new(5.0, 0.0, 0.0), DVec3::NEG_X).unwrap();
    assert!(close(got, 5.0 - big - small, 1e-12), "{got}");
    // Rays through the tube at many angles around the axis: every one hits, at the
    // distance exact geometry gives (down through the circle of radius R).
    for i in 0..360 {
        let a = f64::from(i).to_radians();
        let c = DVec3::new(big * a.cos(), big * a.sin(), 0.0);
        let got = hit_t(&t, c + DVec3::Z, DVec3::NEG_Z);
        assert!(
            got.is_some_and(|v| close(v, 1.0 - small, 1e-9)),
            "angle {i}: {got:?}"
        );
        // Passing beside the tube by 1.5 r misses.
        assert_eq!(
            hit_t(&t, c * (1.0 + 1.5 * small) + DVec3::Z, DVec3::NEG_Z),
            None,
            "angle {i}"
        );
    }
}

#[test]
fn far_away_and_tiny_objects() {
    // A unit sphere moved to 1e6: the search starts at the box, so no precision is lost.
    let far = shape(
        Surface::Sphere { radius: 1.0 },
        DAffine3::from_translation(DVec3::new(1e6, 0.0, 0.0)),
        None,
    );
    let got = hit_t(&far, DVec3::new(1e6, 0.5, 10.0), DVec3::NEG_Z).unwrap();
    assert!(close(got, 10.0 - 0.75f64.sqrt(), 1e-9), "{got}");
    // A torus scaled down to 1e-6.
    let tiny = shape(
        Surface::Torus {
            major: 1.0,
            minor: 0.25,
        },
        DAffine3::from_scale(DVec3::splat(1e-6)),
        None,
    );
    let got = hit_t(&tiny, DVec3::new(-1.0, 0.0, 0.0), DVec3::X).unwrap();
    assert!((got - (1.0 - 1.25e-6)).abs() < 1e-15, "{got}");
    let n = tiny
        .intersect(DVec3::new(-1.0, 0.0, 0.0), DVec3::X, 0.0, 2.0)
        .unwrap()
        .normal
        .normalize();
    assert!((n - DVec3::NEG_X).length() < 1e-9, "{n}");
    // And far and tiny together: a 1e-6 sphere at 1e6.
    let both = shape(
        Surface::Sphere { radius: 1.0 },
        DAffine3::from_translation(DVec3::splat(1e6)) * DAffine3::from_scale(DVec3::splat(1e-6)),
        None,
    );
    let got = hit_t(&both, DVec3::new(1e6, 1e6, 1e6 + 1.0), DVec3::NEG_Z).unwrap();
    assert!((got - (1.0 - 1e-6)).abs() < 1e-9, "{got}");
}

#[test]
fn repeated_roots_on_an_algebraic_surface() {
    // The unit sphere cubed: every hit is a triple root of Q(t), which f64 blurs into a
    // cluster, yet Q changes sign there. It must hit exactly where the sphere does, to
    // the cube root of the rounding (~1e-5).
    let plain = sphere(1.0);
    let cubed = algebraic("(x^2 + y^2 + z^2 - 1)^3", 1.5);
    for i in 0..50 {
        let y = -0.98 + 0.04 * f64::from(i);
        let o = DVec3::new(0.1, y, 5.0);
        let want = hit_t(&plain, o, DVec3::NEG_Z).unwrap();
        let got = hit_t(&cubed, o, DVec3::NEG_Z).unwrap_or_else(|| panic!("miss at y = {y}"));
        assert!(close(got, want, 1e-4), "y = {y}: {got} vs {want}");
    }
    // Squared, the sphere has no inside: Q touches zero without changing sign, so there
    // is nothing to cross, and no ray reports a hit.
    let squared = algebraic("(x^2 + y^2 + z^2 - 1)^2", 1.5);
    assert_eq!(
        hit_t(&squared, DVec3::new(0.1, 0.2, 5.0), DVec3::NEG_Z),
        None
    );
}

/// Near the rim of the heart surface (x² + 9/4 y² + z² − 1)³ = x²z³ + 9/80 y²z³,
/// where F's gradient vanishes along z = 0, rounding turns complex root pairs into
/// real ones, and F is so flat that its value drowns in rounding over ~1e-4. No ray
/// may stop at a phantom: every hit lies within its own error bound
/// (`ShapeHit::error`, which spawned rays clear) of a sign change of F, checked
/// here by evaluating F directly on both sides.
#[test]
fn no_phantom_hits_where_the_gradient_vanishes() {
    let heart = algebraic(
        "(x^2 + 2.25*y^2 + z^2 - 1)^3 - x^2*z^3 - 0.1125*y^2*z^3",
        1.3,
    );
    let f = expr::parse(
        "(x^2 + 2.25*y^2 + z^2 - 1)^3 - x^2*z^3 - 0.1125*y^2*z^3",
        &[],
    )
    .unwrap();
    let mut hits = 0;
    for i in 0..2000 {
        // Rays from outside, aimed at points just around the rim z = 0.
        let a = f64::from(i) * 0.0031;
        let aim = DVec3::new(a.cos(), a.sin() / 1.5, 1e-4 * (f64::from(i) * 0.37).sin());
        let o = aim + DVec3::new(0.3, 0.5, 3.0);
        let d = (aim - o).normalize();
        let Some(hit) = heart.intersect(o, d, 0.0, f64::INFINITY) else {
            continue;
        };
        hits += 1;
        // The bound the hit carries, which the renderer uses, and the one
        // computed afresh at its t.
        let (t, h) = (hit.t, hit.error);
        let fresh = heart.hit_error(o, d, t);
        assert!(
            h < 1e-3 && fresh < 1e-3,
            "ray {i}: error bounds {h}, {fresh}"
        );
        for h in [h, fresh] {
            let before = f.eval((o + (t - h) * d).to_array());
            let after = f.eval((o + (t + h) * d).to_array());
            assert!(
                before * after < 0.0,
                "ray {i}: no sign change of F within {h} of t = {t}"
            );
        }
    }
    assert!(hits > 1000, "{hits}");
}

#[test]
fn degenerate_quadrics_cone_apex_and_parallel_rays() {
    use glam::DMat3;
    use sturmray::geometry::Quadric;
    // A cone x² + y² = z² (both nappes in the clip box): a ray through the apex along
    // the axis meets the surface only at the apex (a triple contact).
    let cone = shape(
        Surface::Quadric(Quadric {
            a: DMat3::from_diagonal(DVec3::new(1.0, 1.0, -1.0)),
            b: DVec3::ZERO,
            c: 0.0,
        }),
        DAffine3::IDENTITY,
        Some(Box3::cube(1.0)),
    );
    let got = hit_t(&cone, DVec3::new(0.0, 0.0, 0.9), DVec3::NEG_Z);
    assert!(got.is_none_or(|v| close(v, 0.9, 1e-9)), "{got:?}");
    // A ray across the apex at 45° lies on the surface: no NaN, whatever is reported.
    let _ = hit_t(
        &cone,
        DVec3::new(-0.5, 0.0, -0.5),
        DVec3::new(1.0, 0.0, 1.0),
    );
    // Off-axis through the lower nappe from below: hits at z = −|x|.
    let got = hit_t(&cone, DVec3::new(0.3, 0.0, -0.9), DVec3::Z).unwrap();
    assert!(close(got, 0.6, 1e-12), "{got}");
    // A cylinder x² + y² = 0.25, a ray parallel to its axis: the t² and t terms vanish.
    let cylinder = shape(
        Surface::Quadric(Quadric {
            a: DMat3::from_diagonal(DVec3::new(1.0, 1.0, 0.0)),
            b: DVec3::ZERO,
            c: -0.25,
        }),
        DAffine3::IDENTITY,
        Some(Box3::cube(1.0)),
    );
    assert_eq!(
        hit_t(&cylinder, DVec3::new(0.1, 0.0, 5.0), DVec3::NEG_Z),
        None
    );
    assert_eq!(
        hit_t(&cylinder, DVec3::new(0.7, 0.0, 5.0), DVec3::NEG_Z),
        None
    );
    // Across the axis: the wall at x = −0.5.
    let got = hit_t(&cylinder, DVec3::new(-5.0, 0.0, 0.0), DVec3::X).unwrap();
    assert!(close(got, 4.5, 1e-12), "{got}");
}

/// Rays that start on a surface, spawned as the renderer spawns them: offset by the
/// hit point's error bound along the normal. Leaving along the outward normal
/// nothing is hit; going in, the far side of the tube is hit, never the start.
#[test]
fn rays_leaving_a_surface_do_not_hit_their_start() {
    let dir = scratch("spawn");
    let path = write(
        &dir,
        "s.toml",
        r#"
[camera]
eye = [0, 0, 5]
look_at = [0, 0, 0]
fov = 40
width = 8
height = 8
[[objects]]
type = "torus"
major = 1.0
minor = 0.25
[[objects]]
type = "sphere"
radius = 0.5
transform = { translate = [0, 0, 3] }
"#,
    );
    let scene = Scene::load(&path).unwrap();
    let accel = Accel::build(&scene, Backend::Embree, None).unwrap();
    let mut spawned = 0;
    for i in 0..400 {
        // Camera-like rays from a ring of eyes, aimed at points of the torus's outer half.
        let a = f64::from(i) * 0.9;
        let target = DVec3::new(1.2 * a.cos(), 1.2 * a.sin(), 0.1 * (a * 3.0).sin());
        let eye = target * 4.0 + DVec3::new(0.0, 0.0, 2.0);
        let ray = Ray::new(eye.as_vec3(), (target - eye).normalize().as_vec3());
        let hit = accel.intersect(&ray);
        if hit.geom_id != scene.shapes_geom_id() || hit.prim_id != 0 {
            continue;
        }
        let it = scene.interaction(&ray, &hit);
        let p = it.p.as_dvec3();
        let radial = DVec3::new(p.x, p.y, 0.0).normalize() * 1.0;
        let outward = (p - radial).normalize();
        if outward.dot(DVec3::new(p.x, p.y, 0.0)) < 0.0 {
            continue; // inner half: the normal line crosses the hole
        }
        spawned += 1;
        let n = outward.as_vec3();
        let out = Ray::new(offset(it.p, it.error, it.n, n), n);
        let again = accel.intersect(&out);
        assert!(
            !again.is_hit() || (again.geom_id, again.prim_id) == (scene.shapes_geom_id(), 1),
            "ray {i} leaving along the normal hit {again:?}"
        );
        let inward = Ray::new(offset(it.p, it.error, it.n, -n), -n);
        let through = accel.intersect(&inward);
        assert_eq!(
            (through.geom_id, through.prim_id),
            (scene.shapes_geom_id(), 0)
        );
        // Along the tube's diameter: the far wall is 2r = 0.5 away.
        assert!((through.t - 0.5).abs() < 1e-3, "ray {i}: {}", through.t);
    }
    assert!(spawned > 50, "only {spawned} rays landed on the outer half");
    accel.check().unwrap();
}
