//! Unbounded surfaces under the `.pov` reader: a quartic with no box of its
//! own (`Shape::unclipped`) inside an intersection, a difference or a clip
//! takes its bounded siblings' box from `Csg::new`; a root unbounded as a
//! whole is cut by a world box (`Csg::within`, `Shape::clip_to`). Rays are
//! worked out by hand on the quartic tube x⁴ + y⁴ = 1 (along z, unbounded):
//! along x at height y it is crossed at x = ±(1 − y⁴)^(1/4).

mod common;

use glam::{DAffine3, DVec3};

use common::analytic::{placed, tree_shape};
use sturmray::geometry::{Box3, Csg, Leaf, Node, Op, Part, Quadric, Shape, Surface};
use sturmray::poly::solve::Solver;
use sturmray::poly::trivariate::Trivariate;

const X: DVec3 = DVec3::X;
const Z: DVec3 = DVec3::Z;
const FAR: f64 = f64::INFINITY;

/// The tube x⁴ + y⁴ − 1, with no box.
fn tube() -> Shape {
    let f = Trivariate::from_terms([([4, 0, 0], 1.0), ([0, 4, 0], 1.0), ([0, 0, 0], -1.0)]);
    Shape::unclipped(
        Surface::Algebraic(Box::new(f)),
        DAffine3::IDENTITY,
        0,
        Solver::default(),
    )
    .unwrap()
}

/// Where a line along x at height y crosses the tube: x = ±wall(y).
fn wall(y: f64) -> f64 {
    (1.0 - y.powi(4)).powf(0.25)
}

/// The tube's normal at (x, y, ·): its gradient (4x³, 4y³, 0), shortened.
fn tube_normal(x: f64, y: f64) -> DVec3 {
    DVec3::new(x.powi(3), y.powi(3), 0.0)
}

fn sphere(radius: f64) -> Shape {
    placed(Surface::Sphere { radius }, DVec3::ZERO, None)
}

fn solid(shape: Shape) -> Leaf {
    Leaf {
        part: Part::Solid(shape),
        inverse: false,
        material: 0,
    }
}

fn pair(op: Op) -> Node {
    Node::Op {
        op,
        inverse: false,
        children: vec![Node::Leaf(0), Node::Leaf(1)],
    }
}

fn shape(csg: Csg) -> Shape {
    tree_shape(csg)
}

fn hit(s: &Shape, o: DVec3, d: DVec3, tmin: f64) -> Option<(f64, DVec3)> {
    s.intersect(o, d, tmin, FAR)
        .map(|h| (h.t, h.normal.normalize()))
}

fn assert_hit(s: &Shape, o: DVec3, d: DVec3, t: f64, n: DVec3, tolerance: f64) {
    let (got_t, got_n) = hit(s, o, d, 0.0).unwrap_or_else(|| panic!("no hit from {o} along {d}"));
    assert!(
        (got_t - t).abs() <= tolerance,
        "from {o}: t {got_t}, expected {t} (off by {:e})",
        (got_t - t).abs()
    );
    assert!(
        got_n.abs_diff_eq(n.normalize(), 1e-6),
        "from {o}: normal {got_n}, expected {n}"
    );
    assert!(
        s.occluded(o, d, 0.0, FAR),
        "from {o}: the shadow ray passes"
    );
}

#[test]
fn an_unclipped_quartic_is_unbounded_until_something_bounds_it() {
    assert!(!tube().is_bounded());
    assert!(sphere(1.0).is_bounded());
    // Alone in a union, or intersected only with a half-space: refused.
    for (op, other) in [
        (Op::Union, solid(sphere(2.0))),
        (
            Op::Intersection,
            Leaf {
                part: Part::Plane {
                    normal: Z,
                    offset: 0.0,
                },
                inverse: false,
                material: 0,
            },
        ),
    ] {
        let err = Csg::new(pair(op), vec![solid(tube()), other]).unwrap_err();
        assert!(err.to_string().contains("unbounded"), "{op:?}: {err}");
    }
    // A world box bounds a lone tube, and a union holding one.
    let mut lone = tube();
    lone.clip_to(&Box3::cube(10.0)).unwrap();
    assert!(lone.is_bounded());
    let b = lone.bounds();
    assert!(
        b.min.z >= -10.01 && b.max.z <= 10.01 && b.max.x >= 1.0,
        "{b:?}"
    );
    let within = Csg::within(
        pair(Op::Union),
        vec![solid(tube()), solid(sphere(2.0))],
        Box3::cube(10.0),
    );
    assert!(within.is_ok(), "{within:?}");
}

#[test]
fn a_quartic_intersected_with_a_sphere_is_cut_by_the_spheres_box() {
    let csg = Csg::new(
        pair(Op::Intersection),
        vec![solid(tube()), solid(sphere(2.0))],
    )
    .unwrap();
    let b = csg.bounds();
    assert!(b.max.z < 2.01 && b.min.z > -2.01, "{b:?}");
    let s = shape(csg);
    // Along x at height 0.5: the tube's wall.
    let x = wall(0.5);
    assert_hit(
        &s,
        DVec3::new(-5.0, 0.5, 0.0),
        X,
        5.0 - x,
        tube_normal(-x, 0.5),
        1e-9,
    );
    // Down the middle: the sphere's top; off the axis too. The box faces that
    // close the tube lie outside the sphere and never show.
    assert_hit(&s, DVec3::new(0.0, 0.0, 5.0), -Z, 3.0, Z, 1e-9);
    let top = (4.0f64 - 0.25).sqrt();
    assert_hit(
        &s,
        DVec3::new(0.5, 0.0, 5.0),
        -Z,
        5.0 - top,
        DVec3::new(0.5, 0.0, top),
        1e-9,
    );
    // From inside, out through the wall; and a secondary ray leaving the wall
    // inwards, which must not stop on the wall it starts on.
    assert_hit(
        &s,
        DVec3::new(0.0, 0.5, 0.0),
        X,
        x,
        tube_normal(x, 0.5),
        1e-9,
    );
    let (t, _) = hit(&s, DVec3::new(-x, 0.5, 0.0), X, 1e-9).unwrap();
    assert!((t - 2.0 * x).abs() < 1e-9, "{t}");
}

#[test]
fn a_quartic_subtracted_or_clipped_takes_the_box_it_needs() {
    // A ball with a square-ish tunnel: the tunnel's wall, seen from inside it.
    let tunnel = shape(
        Csg::new(
            pair(Op::Difference),
            vec![solid(sphere(2.0)), solid(tube())],
        )
        .unwrap(),
    );
    assert_hit(&tunnel, DVec3::new(-5.0, 0.0, 0.0), X, 3.0, -X, 1e-9);
    assert_hit(&tunnel, DVec3::ZERO, X, 1.0, -X, 1e-9);
    // The same as an intersection with the inverted tube.
    let mut inverted = solid(tube());
    inverted.inverse = true;
    let same = shape(Csg::new(pair(Op::Intersection), vec![solid(sphere(2.0)), inverted]).unwrap());
    assert_hit(&same, DVec3::ZERO, X, 1.0, -X, 1e-9);
    // The tube clipped by the ball: its wall, but no cap where the ball cuts
    // it, so a ray down its middle sees nothing.
    let clipped = shape(Csg::new(pair(Op::Clip), vec![solid(tube()), solid(sphere(2.0))]).unwrap());
    assert_hit(&clipped, DVec3::new(-5.0, 0.0, 0.0), X, 4.0, -X, 1e-9);
    assert!(hit(&clipped, DVec3::new(0.0, 0.0, 5.0), -Z, 0.0).is_none());
    assert!(!clipped.occluded(DVec3::new(0.0, 0.0, 5.0), -Z, 0.0, FAR));
}

#[test]
fn a_lone_plane_a_million_away_is_hit_where_it_lies() {
    let world = Box3::cube(1e7);
    // The plane z = 1e6 as a plain shape, F = z − 1e6, cut by the world box.
    let mut plane = Shape::unclipped(
        Surface::Quadric(Quadric {
            a: glam::DMat3::ZERO,
            b: Z,
            c: -1e6,
        }),
        DAffine3::IDENTITY,
        0,
        Solver::default(),
    )
    .unwrap();
    plane.clip_to(&world).unwrap();
    let d = DVec3::new(0.6, 0.0, 0.8);
    // t = 1e6 / 0.8. A surface's root is bisected to the solver's tolerance
    // times its distance (1e-12 relative): that is the bound, at 1e6 too.
    let tolerance = Solver::default().tolerance * 1.25e6;
    assert_hit(&plane, DVec3::ZERO, d, 1.25e6, Z, tolerance);
    // The same half-space as a tree's leaf, with a sphere near the camera.
    let half = Leaf {
        part: Part::Plane {
            normal: Z,
            offset: 1e6,
        },
        inverse: true,
        material: 0,
    };
    let scene = shape(Csg::within(pair(Op::Union), vec![half, solid(sphere(1.0))], world).unwrap());
    assert_hit(&scene, DVec3::new(0.0, 0.0, -5.0), Z, 4.0, -Z, 1e-9);
    assert_hit(
        &scene,
        DVec3::new(0.0, 5.0, 0.0),
        DVec3::new(0.0, 0.6, 0.8),
        1.25e6,
        -Z,
        // A tree's half-space is solved in closed form: a few roundings.
        8.0 * f64::EPSILON * 1.25e6,
    );
}

#[test]
fn a_quartic_near_the_camera_in_a_world_box_is_hit_accurately() {
    let world = Box3::cube(1e7);
    let mut lone = tube();
    lone.clip_to(&world).unwrap();
    // In a union with a sphere far down the tube, as one tree in the box:
    // the tube's crossings start near the ray, not 1e7 behind it.
    let far = placed(
        Surface::Sphere { radius: 1.0 },
        DVec3::new(0.0, 0.0, 100.0),
        None,
    );
    let union =
        shape(Csg::within(pair(Op::Union), vec![solid(tube()), solid(far)], world).unwrap());
    let x = wall(0.5);
    for s in [&lone, &union] {
        assert_hit(
            s,
            DVec3::new(-5.0, 0.5, 3.0),
            X,
            5.0 - x,
            tube_normal(-x, 0.5),
            1e-9,
        );
        // From inside the tube, out through the wall.
        assert_hit(
            s,
            DVec3::new(0.0, 0.5, -7.0),
            X,
            x,
            tube_normal(x, 0.5),
            1e-9,
        );
        // A secondary ray leaving the wall inwards crosses to the far side.
        let (t, _) = hit(s, DVec3::new(-x, 0.5, 0.0), X, 1e-9).unwrap();
        assert!((t - 2.0 * x).abs() < 1e-9, "{t}");
    }
}

/// How far a quartic leaf can be cut by its context's box: the tube
/// intersected with a ball of radius r, hit along x at height 0.5 by a ray
/// from outside the ball, whose crossings of the tube start where the line
/// enters the box, about r from the wall. Q formed there has coefficients of
/// r⁴ around roots a unit apart; the polish re-forms Q at the root, so the
/// hit keeps the solver's tolerance, relative to its distance from where
/// the search starts: the error grows as r, not as r⁴.
/// `cargo test --test unbounded -- --nocapture` prints the error per radius
/// (docs/analytic.md has the table).
#[test]
fn a_quartic_cut_by_a_large_box_keeps_its_hits_to_the_tolerance() {
    let x = wall(0.5);
    let tolerance = Solver::default().tolerance;
    for k in 1..=9 {
        let r = 10f64.powi(k);
        let csg = Csg::new(
            pair(Op::Intersection),
            vec![solid(tube()), solid(sphere(r))],
        )
        .unwrap();
        let s = shape(csg);
        let o = DVec3::new(-(r + 5.0), 0.5, 0.0);
        let expected = r + 5.0 - x;
        let got = hit(&s, o, X, 0.0).map(|h| h.0);
        let error = got.map_or(f64::INFINITY, |t| (t - expected).abs());
        eprintln!(
            "ball radius 1e{k}: t error {error:.3e}, {:.2} tolerances of r",
            error / (tolerance * r)
        );
        // Bisected to a width of the tolerance times the distance searched
        // (about r): the error stays within that, measured at 0.1–0.5 of it.
        assert!(error <= tolerance * r, "ball radius 1e{k}: error {error:e}");
    }
}

#[test]
fn a_placed_quartic_is_cut_where_it_is_placed() {
    // The tube scaled by 2, turned by 90° about y (its axis along x, its
    // wall at |z| = 2 where y = 0) and moved to (10, 0, 0), intersected
    // with a ball of radius 3 there: the ball's box, mapped into the tube's
    // own space, must land around the tube, not around (10, 0, 0) of it.
    let f = Trivariate::from_terms([([4, 0, 0], 1.0), ([0, 4, 0], 1.0), ([0, 0, 0], -1.0)]);
    let at = DVec3::new(10.0, 0.0, 0.0);
    let to_world = DAffine3::from_translation(at)
        * DAffine3::from_rotation_y(std::f64::consts::FRAC_PI_2)
        * DAffine3::from_scale(DVec3::splat(2.0));
    let placed_tube = Shape::unclipped(
        Surface::Algebraic(Box::new(f)),
        to_world,
        0,
        Solver::default(),
    )
    .unwrap();
    let ball = placed(Surface::Sphere { radius: 3.0 }, at, None);
    let s = shape(
        Csg::new(
            pair(Op::Intersection),
            vec![solid(placed_tube), solid(ball)],
        )
        .unwrap(),
    );
    // Down onto the wall z = 2 over the middle.
    assert_hit(&s, DVec3::new(10.0, 0.0, 5.0), -Z, 3.0, Z, 1e-9);
    // Along the axis: inside the tube all the way, into the ball at x = 7.
    assert_hit(&s, DVec3::ZERO, X, 7.0, -X, 1e-9);
}
