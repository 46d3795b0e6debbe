//! POV-Ray's `clipped_by` as `Op::Clip`, checked on rays worked out by hand:
//! a sphere clipped by a half-space is a bowl open at the cut (its inner
//! wall seen through it, shadow rays passing through it), a clipped object
//! inside an intersection and a difference (where the clip object's face
//! is a boundary no ray sees), nested clips, a clip by an inverted object, a
//! clipped sheet, the node's box and the material of its hits.

mod common;

use glam::{DAffine3, DVec3};

use common::analytic::{placed, tree_shape};
use sturmray::geometry::{Box3, Csg, Leaf, Node, Op, Part, Shape, Surface};

const X: DVec3 = DVec3::X;
const Z: DVec3 = DVec3::Z;

/// A ball as a leaf; the leaf's material is what a hit on it reports.
fn sphere(radius: f64, at: DVec3, material: u32) -> Leaf {
    Leaf {
        part: Part::Solid(placed(Surface::Sphere { radius }, at, None)),
        inverse: false,
        material,
    }
}

/// The half-space n·p < offset.
fn half(normal: DVec3, offset: f64) -> Leaf {
    Leaf {
        part: Part::Plane { normal, offset },
        inverse: false,
        material: 9,
    }
}

fn inverted(mut leaf: Leaf) -> Leaf {
    leaf.inverse = true;
    leaf
}

fn op(op: Op, children: Vec<Node>) -> Node {
    Node::Op {
        op,
        inverse: false,
        children,
    }
}

/// Leaves 0, 1, … of `leaves` under one node of `kind`.
fn flat(kind: Op, n: u32) -> Node {
    op(kind, (0..n).map(Node::Leaf).collect())
}

fn shape(root: Node, leaves: Vec<Leaf>) -> Shape {
    tree_shape(Csg::new(root, leaves).unwrap())
}

/// The hit's t, unit normal and material.
fn hit(s: &Shape, o: DVec3, d: DVec3) -> Option<(f64, DVec3, u32)> {
    s.intersect(o, d, 0.0, f64::INFINITY)
        .map(|h| (h.t, h.normal.normalize(), s.material_of(h.part)))
}

fn assert_hit(s: &Shape, o: DVec3, d: DVec3, t: f64, n: DVec3) {
    let (got_t, got_n, _) = hit(s, o, d).unwrap_or_else(|| panic!("no hit from {o} along {d}"));
    assert!(
        (got_t - t).abs() < 1e-9,
        "from {o}: t {got_t}, expected {t}"
    );
    assert!(
        got_n.abs_diff_eq(n.normalize(), 1e-9),
        "from {o}: normal {got_n}, expected {n} (t {t})"
    );
}

fn assert_miss(s: &Shape, o: DVec3, d: DVec3) {
    assert!(
        hit(s, o, d).is_none(),
        "from {o} along {d}: {:?}",
        hit(s, o, d)
    );
}

/// The unit sphere clipped by z < 0: a bowl, open at the top.
fn bowl() -> Shape {
    shape(
        flat(Op::Clip, 2),
        vec![sphere(1.0, DVec3::ZERO, 1), half(Z, 0.0)],
    )
}

/// √(1 − x²): the height of the unit sphere over the point x of the z = 0 plane.
fn rim(x: f64) -> f64 {
    (1.0 - x * x).sqrt()
}

#[test]
fn a_sphere_clipped_by_a_half_space_is_a_bowl_open_at_the_cut() {
    let bowl = bowl();
    let (x, h) = (0.3, rim(0.3));
    // From above, through the open cut, onto the inner wall of the bottom: the
    // normal is the sphere's own outward one, facing away from the ray.
    assert_hit(
        &bowl,
        DVec3::new(x, 0.0, 5.0),
        -Z,
        5.0 + h,
        DVec3::new(x, 0.0, -h),
    );
    // From below, onto the outside of the bottom.
    assert_hit(
        &bowl,
        DVec3::new(x, 0.0, -5.0),
        Z,
        5.0 - h,
        DVec3::new(x, 0.0, -h),
    );
    // Level with the clipped-away half: nothing; below the cut, the side.
    assert_miss(&bowl, DVec3::new(-5.0, 0.0, 0.5), X);
    let side = rim(0.5);
    assert_hit(
        &bowl,
        DVec3::new(-5.0, 0.0, -0.5),
        X,
        5.0 - side,
        DVec3::new(-side, 0.0, -0.5),
    );
    // From inside the bowl, up and out through the cut: nothing.
    assert_miss(&bowl, DVec3::new(0.0, 0.0, -0.5), Z);
    // The hit's material is the clipped sphere's, not the plane's, and the
    // plane's is not among the materials the shape shows (the render plan's).
    assert_eq!(hit(&bowl, DVec3::new(x, 0.0, 5.0), -Z).unwrap().2, 1);
    assert_eq!(bowl.materials(), [1]);
}

#[test]
fn grazing_and_secondary_rays_in_a_bowl() {
    let bowl = bowl();
    // In the cut plane itself: the plane's inside is z < 0, so the line is
    // outside the clip everywhere and sees nothing.
    assert_miss(&bowl, DVec3::new(-5.0, 0.0, 0.0), X);
    // Tangent to the sphere below the cut, at (0, 0.6, −0.8): a touch, no hit.
    assert_miss(&bowl, DVec3::new(-5.0, 0.6, -0.8), X);
    // Leaving the inner wall at (−√0.75, 0, −0.5) across the bowl: the wall
    // opposite, not the one it starts on.
    let w = 0.75f64.sqrt();
    let o = DVec3::new(-w, 0.0, -0.5);
    let h = bowl.intersect(o, X, 1e-9, f64::INFINITY).unwrap();
    assert!((h.t - 2.0 * w).abs() < 1e-9, "{}", h.t);
    // Leaving the bottom upwards: out through the cut.
    let bottom = DVec3::new(0.0, 0.0, -1.0);
    assert!(bowl.intersect(bottom, Z, 1e-9, f64::INFINITY).is_none());
    assert!(!bowl.occluded(bottom, Z, 1e-9, f64::INFINITY));
}

#[test]
fn shadow_rays_pass_through_the_open_cut() {
    let bowl = bowl();
    let o = DVec3::new(0.0, 0.0, -0.5);
    assert!(!bowl.occluded(o, Z, 0.0, f64::INFINITY));
    // Down onto the bottom, 0.5 away: blocked, but not before it.
    assert!(bowl.occluded(o, -Z, 0.0, f64::INFINITY));
    assert!(!bowl.occluded(o, -Z, 0.0, 0.49));
    // The same sphere cut by an intersection is closed: its flat face blocks.
    let dome = shape(
        flat(Op::Intersection, 2),
        vec![sphere(1.0, DVec3::ZERO, 1), half(Z, 0.0)],
    );
    assert!(dome.occluded(o, Z, 0.0, f64::INFINITY));
    assert_hit(&dome, o, Z, 0.5, Z);
}

#[test]
fn a_clipped_sphere_in_an_intersection_is_a_solid_whose_cut_is_never_seen() {
    // (bowl) ∩ (x < 0): the flat face x = 0 shows where it is inside the
    // sphere and below the cut; the cut z = 0 never shows.
    let quarter = shape(
        op(Op::Intersection, vec![flat(Op::Clip, 2), Node::Leaf(2)]),
        vec![sphere(1.0, DVec3::ZERO, 1), half(Z, 0.0), half(X, 0.0)],
    );
    let h = rim(0.3);
    assert_hit(
        &quarter,
        DVec3::new(-0.3, 0.0, 5.0),
        -Z,
        5.0 + h,
        DVec3::new(-0.3, 0.0, -h),
    );
    assert_miss(&quarter, DVec3::new(0.3, 0.0, 5.0), -Z);
    // The face x = 0 below the cut, seen from +x; above the cut it is outside
    // the clipped solid.
    assert_hit(&quarter, DVec3::new(5.0, 0.0, -0.5), -X, 5.0, X);
    assert_miss(&quarter, DVec3::new(5.0, 0.0, 0.5), -X);
}

#[test]
fn a_clipped_sphere_subtracted_leaves_a_hollow_open_to_the_inside() {
    // S(1) − (S(0.5) clipped by z < 0): the lower half of the inner ball is
    // taken away; its cut, the disc z = 0 of radius 0.5, has no surface.
    let leaves = || {
        vec![
            sphere(1.0, DVec3::ZERO, 1),
            sphere(0.5, DVec3::ZERO, 2),
            half(Z, 0.0),
        ]
    };
    let hollow = shape(
        op(
            Op::Difference,
            vec![
                Node::Leaf(0),
                op(Op::Clip, vec![Node::Leaf(1), Node::Leaf(2)]),
            ],
        ),
        leaves(),
    );
    let o = DVec3::new(0.2, 0.0, -0.2);
    // Up from inside the hollow: through the cut, out through the outer sphere.
    let top = rim(0.2);
    assert_hit(&hollow, o, Z, 0.2 + top, DVec3::new(0.2, 0.0, top));
    // Down: the hollow's floor, the inner sphere, its normal into the hollow.
    let floor = (0.25f64 - 0.04).sqrt();
    assert_hit(&hollow, o, -Z, floor - 0.2, DVec3::new(-0.2, 0.0, floor));
    assert_eq!(hit(&hollow, o, -Z).unwrap().2, 2);
    // The same with an intersection in place of the clip closes the hollow
    // with a flat face at z = 0.
    let closed = shape(
        op(
            Op::Difference,
            vec![
                Node::Leaf(0),
                op(Op::Intersection, vec![Node::Leaf(1), Node::Leaf(2)]),
            ],
        ),
        leaves(),
    );
    assert_hit(&closed, o, Z, 0.2, -Z);
    // Shadow rays agree with the hits.
    assert!(!hollow.occluded(o, Z, 0.0, 1.0));
    assert!(closed.occluded(o, Z, 0.0, 1.0));
}

#[test]
fn nested_clips_are_one_clip_by_all_their_clip_objects() {
    // The bowl clipped again by x < 0, and the sphere clipped by both at once.
    let nested = shape(
        op(Op::Clip, vec![flat(Op::Clip, 2), Node::Leaf(2)]),
        vec![sphere(1.0, DVec3::ZERO, 1), half(Z, 0.0), half(X, 0.0)],
    );
    let both = shape(
        flat(Op::Clip, 3),
        vec![sphere(1.0, DVec3::ZERO, 1), half(Z, 0.0), half(X, 0.0)],
    );
    let h = rim(0.3);
    for s in [&nested, &both] {
        assert_hit(
            s,
            DVec3::new(-0.3, 0.0, 5.0),
            -Z,
            5.0 + h,
            DVec3::new(-0.3, 0.0, -h),
        );
        assert_miss(s, DVec3::new(0.3, 0.0, 5.0), -Z);
        // Along −x below the cut: the cut x = 0 is no surface either; the
        // inner wall at x = −√(1 − 0.25).
        let side = rim(0.5);
        assert_hit(
            s,
            DVec3::new(5.0, 0.0, -0.5),
            -X,
            5.0 + side,
            DVec3::new(-side, 0.0, -0.5),
        );
        assert!(!s.occluded(DVec3::new(-0.2, 0.0, -0.2), X, 0.0, f64::INFINITY));
    }
}

#[test]
fn a_clip_by_an_inverted_object_keeps_the_surface_outside_it() {
    // The unit sphere clipped by the outside of z < 0: a bowl open downwards.
    let dome = shape(
        flat(Op::Clip, 2),
        vec![sphere(1.0, DVec3::ZERO, 1), inverted(half(Z, 0.0))],
    );
    let h = rim(0.3);
    assert_hit(
        &dome,
        DVec3::new(0.3, 0.0, 5.0),
        -Z,
        5.0 - h,
        DVec3::new(0.3, 0.0, h),
    );
    assert_hit(
        &dome,
        DVec3::new(0.3, 0.0, -5.0),
        Z,
        5.0 + h,
        DVec3::new(0.3, 0.0, h),
    );
    // Clipped by the outside of the unit sphere at (1, 0, 0): along −x, the
    // near pole (1, 0, 0) is inside that sphere and gone; the far one, at 2
    // from its centre, is seen from within.
    let bitten = shape(
        flat(Op::Clip, 2),
        vec![sphere(1.0, DVec3::ZERO, 1), inverted(sphere(1.0, X, 2))],
    );
    assert_hit(&bitten, DVec3::new(5.0, 0.0, 0.0), -X, 6.0, -X);
    assert_hit(&bitten, DVec3::new(-5.0, 0.0, 0.0), X, 4.0, -X);
}

#[test]
fn a_clipped_sheet_shows_only_inside_the_clip_objects() {
    let disc = Leaf {
        part: Part::Disc {
            to_object: DAffine3::IDENTITY,
            radius: 1.0,
            hole: 0.0,
            half_space: false,
        },
        inverse: false,
        material: 1,
    };
    let cut = shape(flat(Op::Clip, 2), vec![disc, half(X, 0.5)]);
    assert_hit(&cut, DVec3::new(0.25, 0.0, 5.0), -Z, 5.0, Z);
    assert_miss(&cut, DVec3::new(0.75, 0.0, 5.0), -Z);
}

#[test]
fn a_clip_is_bounded_by_the_overlap_of_its_childrens_boxes() {
    // A half-space does not shrink the box: the sphere's, padded.
    let bounds = Csg::new(
        flat(Op::Clip, 2),
        vec![sphere(1.0, DVec3::ZERO, 1), half(Z, 0.0)],
    )
    .unwrap()
    .bounds();
    let unit = Box3::cube(1.0);
    let close = |a: DVec3, b: DVec3| a.abs_diff_eq(b, 1e-6);
    assert!(
        close(bounds.min, unit.min) && close(bounds.max, unit.max),
        "{bounds:?}"
    );
    // Two unit spheres 1.5 apart overlap in x ∈ [0.5, 1].
    let bounds = Csg::new(
        flat(Op::Clip, 2),
        vec![
            sphere(1.0, DVec3::ZERO, 1),
            sphere(1.0, DVec3::new(1.5, 0.0, 0.0), 2),
        ],
    )
    .unwrap()
    .bounds();
    assert!(
        close(bounds.min, DVec3::new(0.5, -1.0, -1.0)) && close(bounds.max, DVec3::ONE),
        "{bounds:?}"
    );
    // A clip that is a half-space alone is unbounded: refused.
    assert!(Csg::new(flat(Op::Clip, 2), vec![half(Z, 0.0), half(X, 0.0)]).is_err());
}

#[test]
fn a_cut_inside_a_union_is_no_inner_surface() {
    // A union keeps its children's inner surfaces, but the bowl's cut is no
    // surface: from within the small ball, down through the cut, the first
    // surface is the small ball's own bottom.
    let both = shape(
        op(Op::Union, vec![flat(Op::Clip, 2), Node::Leaf(2)]),
        vec![
            sphere(1.0, DVec3::ZERO, 1),
            half(Z, 0.0),
            sphere(0.5, DVec3::ZERO, 2),
        ],
    );
    assert_hit(&both, DVec3::new(0.0, 0.0, 0.25), -Z, 0.75, -Z);
    assert_eq!(hit(&both, DVec3::new(0.0, 0.0, 0.25), -Z).unwrap().2, 2);
}

/// A torus (R = 1, r = 0.4, about z) as a leaf, cut by `cut` if given: a
/// quartic, so a clip of it takes the shadow rays' shortcut (`Csg::events`,
/// `seen_only`).
fn torus(part: fn(Shape) -> Part, cut: Option<Box3>) -> Leaf {
    let surface = Surface::Torus {
        major: 1.0,
        minor: 0.4,
    };
    Leaf {
        part: part(placed(surface, DVec3::ZERO, cut)),
        inverse: false,
        material: 1,
    }
}

#[test]
fn shadow_rays_of_a_clipped_quartic_agree_with_its_hits() {
    // A shadow ray (`occluded`) may stop at the first sign that the clip's
    // first child crosses nothing where the clip objects are all inside; it
    // must answer what the full walk of a camera ray (`intersect`) finds,
    // from far away, from inside, and from just off the surface towards
    // every side, as shadow rays start.
    let trees = [
        // A torus clipped by a ball and a half-space, as helix.pov's quartics.
        shape(
            flat(Op::Clip, 3),
            vec![
                torus(Part::Solid, None),
                sphere(1.2, DVec3::new(0.5, 0.0, 0.0), 2),
                half(Z, 0.2),
            ],
        ),
        // Clipped by an inverted ball: a torus with a bite out of it.
        shape(
            flat(Op::Clip, 2),
            vec![
                torus(Part::Solid, None),
                inverted(sphere(0.8, DVec3::new(1.0, 0.0, 0.0), 2)),
            ],
        ),
        // Cut flat at z = 0.2 by its own box: a solid whose face is seen.
        shape(
            flat(Op::Clip, 2),
            vec![
                torus(
                    Part::Solid,
                    Some(Box3 {
                        min: DVec3::splat(-2.0),
                        max: DVec3::new(2.0, 2.0, 0.2),
                    }),
                ),
                sphere(1.2, DVec3::new(0.5, 0.0, 0.0), 2),
            ],
        ),
        // The torus as a sheet: no inside of its own.
        shape(
            flat(Op::Clip, 2),
            vec![torus(Part::Sheet, None), half(X, 0.3)],
        ),
    ];
    for (k, tree) in trees.iter().enumerate() {
        let (mut blocked, mut clear) = (0, 0);
        let mut check = |o: DVec3, d: DVec3, tmax: f64| {
            let full = tree.intersect(o, d, 0.0, tmax);
            let shadow = tree.occluded(o, d, 0.0, tmax);
            // The one difference allowed: a ray that starts exactly on the
            // surface, where the walk may place the root it starts on a
            // rounding above 0 (a self-hit) and the shortcut's certified
            // count finds none above 0. Shadow rays start off the surface.
            let self_hit = full.as_ref().is_some_and(|h| h.t < 1e-12);
            assert!(
                shadow == full.is_some() || (self_hit && !shadow),
                "tree {k}, from {o} along {d} to {tmax}: occluded {shadow}, hit {:?}",
                full.map(|h| h.t)
            );
            if full.is_some() {
                blocked += 1;
            } else {
                clear += 1;
            }
        };
        for i in 0..400 {
            let a = f64::from(i);
            let o = 3.0 * DVec3::new((a * 0.7).sin(), (a * 0.3).cos(), (a * 0.11).sin());
            let aim = DVec3::new(
                1.2 * (a * 0.37).cos(),
                1.2 * (a * 0.53).sin(),
                0.3 * a.cos(),
            );
            let d = (aim - o).normalize();
            check(o, d, f64::INFINITY);
            check(0.2 * o, d, 2.0);
            // Shadow rays from the hit, just off the surface, to lights all around.
            let Some(h) = tree.intersect(o, d, 0.0, f64::INFINITY) else {
                continue;
            };
            let (p, n) = (o + h.t * d, h.normal.normalize());
            for j in 0..8 {
                let b = f64::from(j) * 0.785 + a;
                let wi = DVec3::new(b.cos(), b.sin(), (b * 1.3).cos()).normalize();
                let side = if wi.dot(n) > 0.0 { n } else { -n };
                check(p + 1e-9 * side, wi, 100.0);
            }
        }
        assert!(
            blocked > 200 && clear > 200,
            "tree {k}: {blocked} blocked, {clear} clear"
        );
    }
}
