//! POV-Ray's `bounded_by` as a ray gate on a `Shape` (`Shape::set_gate`),
//! on rays worked out by hand: a ray that misses the gate misses the shape
//! even where it would hit it; a ray that crosses the gate anywhere beyond
//! its start (past its tmax too) or starts inside it sees every hit of the
//! shape, outside the gate too; a sheet gates by its crossings alone; a CSG
//! gate's inside is its tree's state; shadow rays are gated the same way.

mod common;

use glam::{DAffine3, DMat3, DVec3};

use common::analytic::{placed, tree_shape};
use sturmray::geometry::{Box3, Csg, Leaf, Node, Op, Part, Quadric, Shape, Surface};

const X: DVec3 = DVec3::X;
const Z: DVec3 = DVec3::Z;
const FAR: f64 = f64::INFINITY;

fn sphere(radius: f64, at: DVec3) -> Shape {
    placed(Surface::Sphere { radius }, at, None)
}

fn gated(shape: Shape, gate: Shape) -> Shape {
    let mut shape = shape;
    shape.set_gate(gate);
    shape
}

fn tree(root: Node, leaves: Vec<Leaf>) -> Shape {
    tree_shape(Csg::new(root, leaves).unwrap())
}

fn leaf(part: Part) -> Leaf {
    Leaf {
        part,
        inverse: false,
        material: 0,
    }
}

fn t_of(s: &Shape, o: DVec3, d: DVec3, tmax: f64) -> Option<f64> {
    s.intersect(o, d, 0.0, tmax).map(|h| h.t)
}

/// The gated shape's hit equals `expected` and its shadow ray agrees; the
/// ungated `plain` shape is hit at `plain_t`.
fn check(s: &Shape, plain: &Shape, o: DVec3, d: DVec3, tmax: f64, expected: Option<f64>) {
    let got = t_of(s, o, d, tmax);
    match (got, expected) {
        (Some(a), Some(b)) => assert!((a - b).abs() < 1e-9, "from {o}: t {a}, expected {b}"),
        (None, None) => {}
        _ => panic!("from {o} along {d}: {got:?}, expected {expected:?}"),
    }
    assert_eq!(s.occluded(o, d, 0.0, tmax), expected.is_some(), "from {o}");
    // The ungated shape is hit: the gate alone decides.
    assert!(
        plain.occluded(o, d, 0.0, tmax),
        "from {o}: the plain shape is missed"
    );
}

#[test]
fn a_sphere_gated_by_a_smaller_one_is_seen_only_by_rays_through_the_gate() {
    let plain = sphere(1.0, DVec3::ZERO);
    let s = gated(plain.clone(), sphere(0.5, DVec3::ZERO));
    // At height 0.7 the ray misses the gate, though it would hit the sphere.
    check(&s, &plain, DVec3::new(-5.0, 0.7, 0.0), X, FAR, None);
    // At height 0.3 it crosses the gate: the sphere's nearest hit counts,
    // at x = −√0.91, outside the gate.
    let t = 5.0 - 0.91f64.sqrt();
    check(&s, &plain, DVec3::new(-5.0, 0.3, 0.0), X, FAR, Some(t));
    // From inside the gate: the sphere from within.
    check(&s, &plain, DVec3::new(0.2, 0.0, 0.0), X, FAR, Some(0.8));
    // The box of the shape is still its own: the gate cuts rays, not space.
    assert_eq!(s.bounds(), plain.bounds());
}

#[test]
fn the_gate_counts_along_the_whole_ray_but_not_behind_it() {
    let plain = sphere(1.0, DVec3::ZERO);
    // A gate beyond the sphere: the ray crosses it at t = 7.5, past its tmax
    // of 5, and the sphere's hit at t = 4 counts.
    let beyond = gated(plain.clone(), sphere(0.5, DVec3::new(3.0, 0.0, 0.0)));
    check(
        &beyond,
        &plain,
        DVec3::new(-5.0, 0.0, 0.0),
        X,
        5.0,
        Some(4.0),
    );
    // Above the gate's reach: nothing.
    check(&beyond, &plain, DVec3::new(-5.0, 0.0, 0.8), X, FAR, None);
    // A gate behind the ray's origin does not count; from inside it, it does.
    let behind = gated(plain.clone(), sphere(0.5, DVec3::new(-3.0, 0.0, 0.0)));
    check(&behind, &plain, DVec3::new(-2.0, 0.0, 0.0), X, FAR, None);
    check(
        &behind,
        &plain,
        DVec3::new(-3.0, 0.0, 0.0),
        X,
        FAR,
        Some(2.0),
    );
    // A ray that starts at tmin = 2 from (−5, 0, 0) starts at (−3, 0, 0),
    // inside the gate: the sphere's hit at t = 4 counts. From tmin = 3 it
    // starts past the gate, and nothing does.
    let o = DVec3::new(-5.0, 0.0, 0.0);
    let t = behind.intersect(o, X, 2.0, FAR).map(|h| h.t);
    assert!(t.is_some_and(|t| (t - 4.0).abs() < 1e-9), "{t:?}");
    assert!(behind.occluded(o, X, 2.0, FAR));
    assert!(behind.intersect(o, X, 3.0, FAR).is_none());
    assert!(!behind.occluded(o, X, 3.0, FAR));
}

#[test]
fn an_origin_inside_the_gate_opens_it_without_a_crossing() {
    // The gate is the half-space z < 0 (F = z) inside a large box: a ray
    // leaving it upwards crosses z = 0, one leaving downwards crosses no
    // surface (a box's face is no surface of a plain shape), and gets in by
    // its origin alone.
    let slab = Quadric {
        a: DMat3::ZERO,
        b: Z,
        c: 0.0,
    };
    let gate = || {
        placed(
            Surface::Quadric(slab.clone()),
            DVec3::ZERO,
            Some(Box3::cube(100.0)),
        )
    };
    let below = sphere(1.0, DVec3::new(0.0, 0.0, -3.0));
    let s = gated(below.clone(), gate());
    check(&s, &below, DVec3::new(0.0, 0.0, -1.0), -Z, FAR, Some(1.0));
    // Above, moving away from the gate: it stays shut.
    let above = sphere(1.0, DVec3::new(0.0, 0.0, 3.0));
    let s = gated(above.clone(), gate());
    check(&s, &above, DVec3::new(0.0, 0.0, 1.0), Z, FAR, None);
}

#[test]
fn a_csg_gate_opens_by_its_trees_state_and_its_seen_crossings() {
    // The gate is the ball of radius 10 clipped by z < 0: from (0, 0, −1)
    // up, the ray crosses only the cut, which is no surface, and gets in
    // because it starts inside; from (0, 0, 1) up, it crosses only the
    // clipped-away top, and stays out.
    let gate = || {
        tree(
            Node::Op {
                op: Op::Clip,
                inverse: false,
                children: vec![Node::Leaf(0), Node::Leaf(1)],
            },
            vec![
                leaf(Part::Solid(sphere(10.0, DVec3::ZERO))),
                leaf(Part::Plane {
                    normal: Z,
                    offset: 0.0,
                }),
            ],
        )
    };
    let plain = sphere(1.0, DVec3::new(0.0, 0.0, 3.0));
    let s = gated(plain.clone(), gate());
    check(&s, &plain, DVec3::new(0.0, 0.0, -1.0), Z, FAR, Some(3.0));
    check(&s, &plain, DVec3::new(0.0, 0.0, 1.0), Z, FAR, None);
    // From below the ball, up: it crosses the ball's bottom and gets in.
    check(&s, &plain, DVec3::new(0.0, 0.0, -20.0), Z, FAR, Some(22.0));
}

#[test]
fn a_sheet_gates_by_its_crossings_alone() {
    // A disc of radius 2 in the plane z = 0 gating a sphere below it.
    let disc = tree(
        Node::Op {
            op: Op::Union,
            inverse: false,
            children: vec![Node::Leaf(0)],
        },
        vec![leaf(Part::Disc {
            to_object: DAffine3::IDENTITY,
            radius: 2.0,
            hole: 0.0,
            half_space: false,
        })],
    );
    let plain = sphere(1.0, DVec3::new(0.0, 0.0, -3.0));
    let s = gated(plain.clone(), disc);
    check(&s, &plain, DVec3::new(0.0, 0.0, 5.0), -Z, FAR, Some(7.0));
    // Starting under the disc: it has no inside to start in.
    check(&s, &plain, DVec3::new(0.0, 0.0, -1.0), -Z, FAR, None);
}

#[test]
fn a_gated_tree_is_gated_as_a_whole() {
    // A lens of two unit spheres at x = ±0.5 gated by a ball of radius 0.2
    // on its axis: rays along x at height 0.5 miss the gate.
    let lens = tree(
        Node::Op {
            op: Op::Intersection,
            inverse: false,
            children: vec![Node::Leaf(0), Node::Leaf(1)],
        },
        vec![
            leaf(Part::Solid(sphere(1.0, DVec3::new(-0.5, 0.0, 0.0)))),
            leaf(Part::Solid(sphere(1.0, DVec3::new(0.5, 0.0, 0.0)))),
        ],
    );
    let s = gated(lens.clone(), sphere(0.2, DVec3::ZERO));
    check(&s, &lens, DVec3::new(-5.0, 0.0, 0.0), X, FAR, Some(4.5));
    check(&s, &lens, DVec3::new(-5.0, 0.5, 0.0), X, FAR, None);
}

/// A gate that touches its shape all round (a sphere of radius R + r about
/// a torus) loses none of its hits, even for rays that graze both at the
/// torus's outer equator, where the gate's own test (no refined root, only
/// whether Q comes within its rounding of zero) is decided by noise.
#[test]
fn a_gate_touching_its_shape_loses_no_hit_of_grazing_rays() {
    let (major, minor) = (2.0, 0.5);
    let plain = placed(Surface::Torus { major, minor }, DVec3::ZERO, None);
    let s = gated(plain.clone(), sphere(major + minor, DVec3::ZERO));
    let mut grazing = 0;
    for i in 0..4000 {
        let a = f64::from(i) * 0.0113;
        // A point of the outer equator, and a ray along the tangent there,
        // moved in or out by 1e-6 down to 1e-15: inwards it cuts a chord of
        // the tube and the gate, outwards it misses both; the smallest moves
        // are within the gate's rounding noise.
        let n = DVec3::new(a.cos(), a.sin(), 0.0);
        let p = (major + minor) * n;
        let d = DVec3::new(-a.sin(), a.cos(), 0.0);
        let size = 10f64.powf(-6.0 - 9.0 * f64::from(i % 100) / 99.0);
        let side = if i % 2 == 0 { 1.0 } else { -1.0 };
        let o = p + side * size * n - 3.0 * d;
        let want = t_of(&plain, o, d, FAR);
        let got = t_of(&s, o, d, FAR);
        grazing += usize::from(want.is_some());
        assert_eq!(got, want, "ray {i} from {o} along {d}");
        assert_eq!(s.occluded(o, d, 0.0, FAR), plain.occluded(o, d, 0.0, FAR));
    }
    // Both sides of the tangent are drawn: about half the rays hit.
    assert!((1000..3000).contains(&grazing), "{grazing}");
}
