//! CSG and the crossings it combines, checked against geometry worked out by
//! hand: every crossing of a sphere and a torus with its direction (tangent
//! touches are none), lenses, shells, spheres sharing roots, half-spaces,
//! capped cylinders and cones (through the cap, the side, the rim, along the
//! axis, from inside), boxes, discs with holes, `inverse`, and the normal's
//! side on a subtracted surface.

mod common;

use glam::{DAffine3, DMat3, DVec3};

use common::analytic::{placed, tree_shape};
use common::{scratch, write};

use sturmray::geometry::{Box3, Crossings, Csg, Leaf, Node, Op, Part, Quadric, Shape, Surface};
use sturmray::scene::Scene;

const X: DVec3 = DVec3::X;
const Z: DVec3 = DVec3::Z;

fn sphere(radius: f64, at: DVec3) -> Shape {
    placed(Surface::Sphere { radius }, at, None)
}

fn solid(shape: Shape) -> Leaf {
    Leaf {
        part: Part::Solid(shape),
        inverse: false,
        material: 0,
    }
}

/// A tree of one operation over `leaves`, in their order, as a scene shape.
fn tree(op: Op, leaves: Vec<Leaf>) -> Shape {
    let children = (0..leaves.len() as u32).map(Node::Leaf).collect();
    let root = Node::Op {
        op,
        inverse: false,
        children,
    };
    tree_shape(Csg::new(root, leaves).unwrap())
}

/// The hit's t and unit normal.
fn hit(s: &Shape, o: DVec3, d: DVec3) -> Option<(f64, DVec3)> {
    s.intersect(o, d, 0.0, f64::INFINITY)
        .map(|h| (h.t, h.normal.normalize()))
}

fn assert_hit(s: &Shape, o: DVec3, d: DVec3, t: f64, n: DVec3) {
    let (got_t, got_n) = hit(s, o, d).unwrap_or_else(|| panic!("no hit from {o} along {d}"));
    assert!((got_t - t).abs() < 1e-9, "t {got_t}, expected {t}");
    assert!(
        got_n.abs_diff_eq(n, 1e-9),
        "normal {got_n}, expected {n} (t {t})"
    );
}

/// A cylinder x² + y² < r² with z in [0, h], as a quadric cut by its box.
fn cylinder(r: f64, h: f64) -> Shape {
    let q = Quadric {
        a: DMat3::from_diagonal(DVec3::new(1.0, 1.0, 0.0)),
        b: DVec3::ZERO,
        c: -r * r,
    };
    let clip = Box3 {
        min: DVec3::new(-r, -r, 0.0),
        max: DVec3::new(r, r, h),
    };
    placed(Surface::Quadric(q), DVec3::ZERO, Some(clip))
}

fn crossings(s: &Shape, o: DVec3, d: DVec3, solid: bool) -> Vec<(f64, bool)> {
    let mut out = Crossings::default();
    s.crossings(o, d, f64::NEG_INFINITY, f64::INFINITY, solid, &mut out);
    out.as_slice().iter().map(|c| (c.t, c.entering)).collect()
}

#[test]
fn a_sphere_is_crossed_in_and_out_and_a_tangent_is_no_crossing() {
    let s = sphere(1.0, DVec3::ZERO);
    let found = crossings(&s, DVec3::new(-5.0, 0.0, 0.0), X, true);
    assert_eq!(found.len(), 2, "{found:?}");
    assert!((found[0].0 - 4.0).abs() < 1e-12 && found[0].1);
    assert!((found[1].0 - 6.0).abs() < 1e-12 && !found[1].1);
    // From the centre: the line entered behind the origin.
    let found = crossings(&s, DVec3::ZERO, X, true);
    assert!((found[0].0 + 1.0).abs() < 1e-12 && found[0].1, "{found:?}");
    // Touching at (0, 1, 0): a double root, no crossing.
    assert!(crossings(&s, DVec3::new(-5.0, 1.0, 0.0), X, true).is_empty());
}

#[test]
fn a_torus_is_crossed_four_times_and_touched_on_top_not_at_all() {
    let torus = placed(
        Surface::Torus {
            major: 2.0,
            minor: 0.5,
        },
        DVec3::ZERO,
        None,
    );
    // Along the x axis: x = ±2.5 and ±1.5.
    let found = crossings(&torus, DVec3::new(-5.0, 0.0, 0.0), X, true);
    let expected = [(2.5, true), (3.5, false), (6.5, true), (7.5, false)];
    assert_eq!(found.len(), 4, "{found:?}");
    for ((t, e), (want, want_e)) in found.iter().zip(expected) {
        assert!((t - want).abs() < 1e-9 && *e == want_e, "{found:?}");
    }
    // Along z = r over the top of both tubes: two tangent touches.
    assert!(crossings(&torus, DVec3::new(-5.0, 0.0, 0.5), X, true).is_empty());
}

#[test]
fn a_lens_is_bounded_by_both_spheres() {
    // Unit spheres at x = ±0.5: on the axis the lens runs from −0.5 to 0.5.
    let lens = tree(
        Op::Intersection,
        vec![
            solid(sphere(1.0, DVec3::new(-0.5, 0.0, 0.0))),
            solid(sphere(1.0, DVec3::new(0.5, 0.0, 0.0))),
        ],
    );
    assert_hit(&lens, DVec3::new(-5.0, 0.0, 0.0), X, 4.5, -X);
    assert_hit(&lens, DVec3::new(5.0, 0.0, 0.0), -X, 4.5, X);
    // The rim: the circle x = 0, y² + z² = 3/4; a ray at y = 0.9 misses.
    assert!(hit(&lens, DVec3::new(-5.0, 0.9, 0.0), X).is_none());
    // From inside, out through the far face.
    assert_hit(&lens, DVec3::ZERO, X, 0.5, X);
}

#[test]
fn a_shell_shows_its_inner_surface_facing_the_hollow() {
    let shell = tree(
        Op::Difference,
        vec![
            solid(sphere(1.0, DVec3::ZERO)),
            solid(sphere(0.5, DVec3::ZERO)),
        ],
    );
    assert_hit(&shell, DVec3::new(-5.0, 0.0, 0.0), X, 4.0, -X);
    // From the hollow's centre: the inner sphere, whose normal out of the
    // shell points back into the hollow.
    assert_hit(&shell, DVec3::ZERO, X, 0.5, -X);
    // From within the shell's wall: out through the outer sphere.
    assert_hit(&shell, DVec3::new(0.75, 0.0, 0.0), X, 0.25, X);
    // The same shell as an intersection with an inverted inner sphere.
    let mut inner = solid(sphere(0.5, DVec3::ZERO));
    inner.inverse = true;
    let inverted = tree(
        Op::Intersection,
        vec![solid(sphere(1.0, DVec3::ZERO)), inner],
    );
    for o in [
        DVec3::new(-5.0, 0.0, 0.0),
        DVec3::ZERO,
        DVec3::new(0.75, 0.0, 0.0),
    ] {
        assert_eq!(hit(&shell, o, X), hit(&inverted, o, X), "from {o}");
    }
}

#[test]
fn shared_roots_are_decided_together() {
    // A sphere minus the same sphere is empty.
    let empty = tree(
        Op::Difference,
        vec![
            solid(sphere(1.0, DVec3::ZERO)),
            solid(sphere(1.0, DVec3::ZERO)),
        ],
    );
    for o in [
        DVec3::new(-5.0, 0.0, 0.0),
        DVec3::new(-5.0, 0.3, 0.2),
        DVec3::ZERO,
    ] {
        assert!(hit(&empty, o, X).is_none(), "from {o}");
    }
    // Two unit spheres touching at the origin: the left one ends where the
    // right one begins.
    let pair = |op| {
        tree(
            op,
            vec![
                solid(sphere(1.0, DVec3::new(-1.0, 0.0, 0.0))),
                solid(sphere(1.0, DVec3::new(1.0, 0.0, 0.0))),
            ],
        )
    };
    let inside_left = DVec3::new(-1.0, 0.0, 0.0);
    // A merge has no surface between them; a union keeps both spheres'
    // surfaces, which meet there.
    assert_hit(&pair(Op::Merge), inside_left, X, 3.0, X);
    assert_eq!(hit(&pair(Op::Union), inside_left, X).unwrap().0, 1.0);
    // An intersection of the two is the point alone: nothing to hit.
    assert!(hit(&pair(Op::Intersection), DVec3::new(-5.0, 0.0, 0.0), X).is_none());
}

#[test]
fn a_hemisphere_is_a_sphere_cut_by_a_half_space() {
    let half = Leaf {
        part: Part::Plane {
            normal: Z,
            offset: 0.0,
        },
        inverse: false,
        material: 0,
    };
    let dome = tree(
        Op::Intersection,
        vec![solid(sphere(1.0, DVec3::ZERO)), half],
    );
    // The flat face z = 0, from above; the sphere's bottom from below.
    assert_hit(&dome, DVec3::new(0.3, 0.2, 5.0), -Z, 5.0, Z);
    assert_hit(&dome, DVec3::new(0.0, 0.0, -5.0), Z, 4.0, -Z);
    // Above the dome, along x: nothing.
    assert!(hit(&dome, DVec3::new(-5.0, 0.0, 0.5), X).is_none());
}

#[test]
fn a_capped_cylinder_is_hit_on_its_caps_its_side_and_from_inside() {
    let c = tree(Op::Union, vec![solid(cylinder(1.0, 2.0))]);
    // Along the axis, down onto the top cap at z = 2; up onto the bottom one.
    assert_hit(&c, DVec3::new(0.0, 0.0, 5.0), -Z, 3.0, Z);
    assert_hit(&c, DVec3::new(0.0, 0.0, -5.0), Z, 5.0, -Z);
    // Through a cap off the axis.
    assert_hit(&c, DVec3::new(0.5, 0.5, 3.0), -Z, 1.0, Z);
    // Through the side at height 1.
    assert_hit(&c, DVec3::new(-5.0, 0.0, 1.0), X, 4.0, -X);
    // From inside: out through the top cap, and out through the side.
    assert_hit(&c, DVec3::new(0.0, 0.0, 1.0), Z, 1.0, Z);
    assert_hit(&c, DVec3::new(0.0, 0.0, 1.0), X, 1.0, X);
    // Onto the rim (−1, 0, 2), where cap and side meet: d = (4, 0, −1) from
    // (−5, 0, 3) gets there at t = 1; the normal is the cap's or the side's.
    let (t, n) = hit(&c, DVec3::new(-5.0, 0.0, 3.0), DVec3::new(4.0, 0.0, -1.0)).unwrap();
    assert!((t - 1.0).abs() < 1e-12, "{t}");
    assert!(n.abs_diff_eq(Z, 1e-9) || n.abs_diff_eq(-X, 1e-9), "{n}");
    // Level with the top cap, just above the rim: a miss; just below: the side.
    assert!(hit(&c, DVec3::new(-5.0, 0.0, 2.0 + 1e-9), X).is_none());
    assert_hit(&c, DVec3::new(-5.0, 0.0, 2.0 - 1e-9), X, 4.0, -X);
}

/// The cube [−1, 1]³ as a tree: F = −1 (inside everywhere) cut by its box.
fn unit_box() -> Shape {
    let inside_everywhere = Quadric {
        a: DMat3::ZERO,
        b: DVec3::ZERO,
        c: -1.0,
    };
    tree(
        Op::Union,
        vec![solid(placed(
            Surface::Quadric(inside_everywhere),
            DVec3::ZERO,
            Some(Box3::cube(1.0)),
        ))],
    )
}

#[test]
fn a_box_is_a_constant_inside_cut_by_its_box() {
    let b = unit_box();
    assert_hit(&b, DVec3::new(0.2, 0.3, 5.0), -Z, 4.0, Z);
    assert_hit(&b, DVec3::ZERO, X, 1.0, X);
    assert_hit(&b, DVec3::new(0.0, 0.0, 0.5), -X, 1.0, -X);
}

#[test]
fn a_hit_on_a_face_of_a_leafs_box_is_as_sure_as_the_face() {
    // A box's F is a constant, so the surface's error bound at its faces
    // was the box's size: 2 units on this cube, and rays spawned from a
    // face (shadows, reflections, refractions) started that far off. A
    // glass slab let light through one face only (POV-Ray's iortest.pov).
    // The bound of a face hit is the slab's rounding, as for a plane's.
    let b = unit_box();
    let c = tree(Op::Union, vec![solid(cylinder(1.0, 2.0))]);
    for (shape, o, d) in [
        (&b, DVec3::new(0.2, 0.3, 5.0), -Z),
        (&b, DVec3::ZERO, X),
        (&c, DVec3::new(0.5, 0.5, 3.0), -Z),
        (&c, DVec3::new(0.0, 0.0, 1.0), Z),
    ] {
        let h = shape.intersect(o, d, 0.0, f64::INFINITY).unwrap();
        assert!(h.error < 1e-12, "error {} of the hit at t {}", h.error, h.t);
    }
    // The side of the cylinder keeps the surface's own bound, small too.
    let side = c
        .intersect(DVec3::new(-5.0, 0.0, 1.0), X, 0.0, f64::INFINITY)
        .unwrap();
    assert!(side.error < 1e-9, "{}", side.error);
}

#[test]
fn a_disc_with_a_hole_is_a_ring_and_clipped_by_an_intersection() {
    let disc = || Leaf {
        part: Part::Disc {
            to_object: DAffine3::IDENTITY,
            radius: 1.0,
            hole: 0.5,
            half_space: false,
        },
        inverse: false,
        material: 0,
    };
    let ring = tree(Op::Union, vec![disc()]);
    let (t, n) = hit(&ring, DVec3::new(0.75, 0.0, 5.0), -Z).unwrap();
    assert!((t - 5.0).abs() < 1e-12 && n.abs_diff_eq(Z, 1e-12));
    assert!(hit(&ring, DVec3::new(0.25, 0.0, 5.0), -Z).is_none());
    assert!(hit(&ring, DVec3::new(1.5, 0.0, 5.0), -Z).is_none());
    // Clipped to the half-space x < 0.8 of a box around it.
    let slab = Quadric {
        a: DMat3::ZERO,
        b: DVec3::ZERO,
        c: -1.0,
    };
    let clip = Box3 {
        min: DVec3::splat(-2.0),
        max: DVec3::new(0.8, 2.0, 2.0),
    };
    let cut = tree(
        Op::Intersection,
        vec![
            disc(),
            solid(placed(Surface::Quadric(slab), DVec3::ZERO, Some(clip))),
        ],
    );
    assert!(hit(&cut, DVec3::new(0.75, 0.0, 5.0), -Z).is_some());
    assert!(hit(&cut, DVec3::new(0.9, 0.0, 5.0), -Z).is_none());
}

mod gallery {
    //! scenes/gallery/csg.toml: known rays through each object, on every
    //! backend, and renders by both integrators without NaN.

    use std::path::Path;

    use sturmray::accel::{Accel, Backend};
    use sturmray::math::{Ray, Vec3};
    use sturmray::render::{RenderOptions, render};
    use sturmray::scene::{Integrator, Scene};

    const BACKENDS: [Backend; 3] = [Backend::Embree, Backend::Obvhs, Backend::Bvh];

    fn scene() -> Scene {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/gallery/csg.toml");
        Scene::load(&path).unwrap()
    }

    /// A known ray: from `o` along the unit `d`, the hit's t, normal and material.
    struct Known {
        what: &'static str,
        o: Vec3,
        d: Vec3,
        t: f32,
        n: Vec3,
        material: &'static str,
    }

    fn known() -> Vec<Known> {
        let diagonal = Vec3::ONE.normalize();
        // The tangle cube's corner lobe on the diagonal x = y = z = s ends
        // where 3s⁴ − 15s² + 11.8 = 0, at s² = (15 + √83.4) / 6; scaled by
        // 0.4, at 0.4 √3 s from the centre (1.5, 1.1, 0).
        let outer = 0.4 * (3.0 * (15.0 + 83.4f64.sqrt()) / 6.0).sqrt() as f32;
        let goursat = Vec3::new(1.5, 1.1, 0.0);
        vec![
            Known {
                what: "floor's top face",
                o: Vec3::new(0.0, 5.0, 3.0),
                d: -Vec3::Y,
                t: 5.0,
                n: Vec3::Y,
                material: "floor",
            },
            Known {
                what: "cylinder's cap, down the axis",
                o: Vec3::new(-4.5, 5.0, 0.0),
                d: -Vec3::Y,
                t: 3.0,
                n: Vec3::Y,
                material: "teal",
            },
            Known {
                what: "cylinder's side",
                o: Vec3::new(-7.5, 1.0, 0.0),
                d: Vec3::X,
                t: 2.3,
                n: -Vec3::X,
                material: "teal",
            },
            Known {
                what: "lens, entering on its axis at x = -2",
                o: Vec3::new(-3.5, 1.0, 0.0),
                d: Vec3::X,
                t: 1.5,
                n: -Vec3::X,
                material: "orange",
            },
            Known {
                what: "lens, from its far side: 0.8 thick",
                o: Vec3::new(0.0, 1.0, 0.0),
                d: -Vec3::X,
                t: 1.2,
                n: Vec3::X,
                material: "orange",
            },
            Known {
                what: "goursat's lobe, inside the subtracted sphere",
                o: goursat,
                d: diagonal,
                t: 0.88,
                n: -diagonal,
                material: "teal",
            },
            Known {
                what: "goursat's lobe from outside",
                o: goursat + 5.0 * diagonal,
                d: -diagonal,
                t: 5.0 - outer,
                n: diagonal,
                material: "white",
            },
            Known {
                what: "torus's cut face x = 0",
                o: Vec3::new(6.0, 0.35, 0.9),
                d: -Vec3::X,
                t: 1.5,
                n: Vec3::X,
                material: "white",
            },
            Known {
                what: "torus's cut face z = 0",
                o: Vec3::new(5.4, 0.35, 1.5),
                d: -Vec3::Z,
                t: 1.5,
                n: Vec3::Z,
                material: "white",
            },
            Known {
                what: "torus's whole side, at x = R + r",
                o: Vec3::new(1.5, 0.35, 0.0),
                d: Vec3::X,
                t: 1.75,
                n: -Vec3::X,
                material: "orange",
            },
        ]
    }

    #[test]
    fn known_rays_hit_where_the_closed_forms_say_on_every_backend() {
        let scene = scene();
        for backend in BACKENDS {
            let accel = Accel::build(&scene, backend, Some(2)).unwrap();
            for k in known() {
                let ray = Ray::new(k.o, k.d);
                let hit = accel.intersect(&ray);
                let what = format!("{}: {}", backend.name(), k.what);
                assert!(hit.is_hit(), "{what}: no hit");
                // f32 rays and hits: t and the normal to a few f32 roundings.
                assert!(
                    (hit.t - k.t).abs() <= 1e-5 * k.t,
                    "{what}: t {}, expected {}",
                    hit.t,
                    k.t
                );
                let at = scene.interaction(&ray, &hit);
                let outward = if at.front { at.n } else { -at.n };
                assert!(
                    outward.abs_diff_eq(k.n, 1e-5),
                    "{what}: normal {outward}, expected {}",
                    k.n
                );
                let name = &scene.materials[at.material as usize].name;
                assert_eq!(name, k.material, "{what}");
            }
        }
    }

    #[test]
    fn both_integrators_render_it_without_nan() {
        let mut scene = scene();
        (scene.camera.width, scene.camera.height) = (64, 40);
        let options = RenderOptions {
            threads: Some(2),
            spp: Some(2),
            ..RenderOptions::default()
        };
        for integrator in [Integrator::Whitted, Integrator::Path] {
            scene.render.integrator = integrator;
            let accel = Accel::build(&scene, Backend::Embree, Some(2)).unwrap();
            let out = render(&scene, &accel, &options).unwrap();
            let beauty = out.film.layers().beauty;
            assert!(
                beauty.iter().flatten().all(|v| v.is_finite()),
                "{integrator:?}: a pixel is not finite"
            );
            let lit = beauty
                .iter()
                .filter(|p| p.iter().sum::<f32>() > 0.0)
                .count();
            assert!(
                lit > beauty.len() / 2,
                "{integrator:?}: only {lit} lit pixels"
            );
        }
    }
}

/// Loads a scene of `objects` (TOML) and returns its error message.
fn load_error(name: &str, objects: &str) -> String {
    let dir = scratch(&format!("csg-{name}"));
    let text = format!(
        "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 40\nwidth = 8\nheight = 8\n\n{objects}"
    );
    let path = write(&dir, "scene.toml", &text);
    match Scene::load(&path) {
        Ok(_) => panic!("{name}: loaded"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn bad_csg_and_primitives_are_named_by_line_and_key() {
    let nested = |levels| {
        let mut child = "{ type = \"sphere\", radius = 1 }".to_string();
        for _ in 0..levels {
            child = format!("{{ type = \"csg\", op = \"union\", children = [{child}] }}");
        }
        format!("[[objects]]\ntype = \"csg\"\nop = \"union\"\nchildren = [{child}]\n")
    };
    let cases: Vec<(&str, String, &[&str])> = vec![
        (
            "no-children",
            "[[objects]]\ntype = \"csg\"\nop = \"union\"\nchildren = []\n".into(),
            &["line 11", "objects[0].children", "at least one child"],
        ),
        (
            "unknown-op",
            "[[objects]]\ntype = \"csg\"\nop = \"xor\"\nchildren = [{ type = \"sphere\", radius = 1 }]\n".into(),
            &["line 10", "objects[0].op", "unknown op `xor`", "union"],
        ),
        (
            "base-is-cap",
            "[[objects]]\ntype = \"cylinder\"\nbase = [0, 1, 0]\ncap = [0, 1, 0]\nradius = 1\n".into(),
            &["line 11", "objects[0].cap", "no length"],
        ),
        (
            "negative-radius",
            "[[objects]]\ntype = \"csg\"\nop = \"merge\"\nchildren = [\n  { type = \"sphere\", radius = -1 },\n]\n".into(),
            &["line 12", "objects[0].children[0].radius", "expected a number > 0"],
        ),
        (
            "box-inside-out",
            "[[objects]]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [1, -1, 1]\n".into(),
            &["line 11", "objects[0].max", "max > min"],
        ),
        (
            "too-deep",
            nested(34),
            &["line 11", "objects[0].children[0]", "deeper than 32"],
        ),
        // The TOML parser stops far deeper nesting itself, with no stack overflow.
        ("far-too-deep", nested(1000), &["line 11", "recurse"]),
        (
            "mesh-child",
            "[[objects]]\ntype = \"csg\"\nop = \"union\"\nchildren = [{ type = \"mesh\", file = \"a.obj\" }]\n".into(),
            &["objects[0].children[0]", "a mesh cannot be part of a csg"],
        ),
        (
            "unbounded",
            "[[objects]]\ntype = \"csg\"\nop = \"union\"\nchildren = [{ type = \"plane\", normal = [0, 1, 0] }]\n".into(),
            &["line 8", "objects[0]", "unbounded"],
        ),
        (
            "inverse-disc",
            "[[objects]]\ntype = \"csg\"\nop = \"intersection\"\nchildren = [\n  { type = \"sphere\", radius = 1 },\n  { type = \"disc\", radius = 1, inverse = true },\n]\n".into(),
            &["line 13", "objects[0].children[1].inverse", "cannot be inverted"],
        ),
        (
            "plane-alone",
            "[[objects]]\ntype = \"plane\"\nnormal = [0, 1, 0]\n".into(),
            &["line 8", "objects[0]", "give it a `clip` box"],
        ),
    ];
    for (name, objects, expected) in cases {
        let err = load_error(name, &objects);
        assert!(err.contains("scene.toml"), "{name}: {err}");
        for e in expected {
            assert!(err.contains(e), "{name}: expected {e:?} in: {err}");
        }
    }
}

/// The one shape of a scene of `objects`.
fn loaded(name: &str, objects: &str) -> Shape {
    let dir = scratch(&format!("csg-{name}"));
    let text = format!(
        "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 40\nwidth = 8\nheight = 8\n\n{objects}"
    );
    let scene = Scene::load(&write(&dir, "scene.toml", &text)).unwrap();
    scene.shapes[0].clone()
}

#[test]
fn a_capped_cone_is_hit_on_its_caps_its_side_and_from_inside() {
    // Radius r(y) = 1 − y/4 from y = 0 to y = 2: F = x² + z² − r(y)², whose
    // gradient (2x, r(y)/2, 2z) at (−0.75, 1, 0) is (−1.5, 0.375, 0).
    let cone = loaded(
        "cone",
        "[[objects]]\ntype = \"cone\"\nbase = [0, 0, 0]\nradius = 1\ncap = [0, 2, 0]\ncap_radius = 0.5\n",
    );
    let y = DVec3::Y;
    assert_hit(&cone, DVec3::new(0.0, 5.0, 0.0), -y, 3.0, y);
    assert_hit(&cone, DVec3::new(0.0, -5.0, 0.0), y, 5.0, -y);
    assert_hit(&cone, DVec3::new(0.2, 3.0, 0.1), -y, 1.0, y);
    let side = DVec3::new(-1.5, 0.375, 0.0).normalize();
    assert_hit(&cone, DVec3::new(-5.0, 1.0, 0.0), X, 4.25, side);
    assert_hit(
        &cone,
        DVec3::new(0.0, 1.0, 0.0),
        X,
        0.75,
        side * DVec3::new(-1.0, 1.0, 1.0),
    );
    // From inside, up the axis and out through the cap.
    assert_hit(&cone, DVec3::new(0.0, 1.0, 0.0), y, 1.0, y);
    // Level with the top cap: just above the rim a miss, just below the side
    // at x = −r(2) = −0.5.
    assert!(hit(&cone, DVec3::new(-5.0, 2.0 + 1e-9, 0.0), X).is_none());
    let (t, _) = hit(&cone, DVec3::new(-5.0, 2.0 - 1e-9, 0.0), X).unwrap();
    assert!((t - 4.5).abs() < 1e-8, "{t}");
    // A cone to a point: down the axis onto the apex at y = 1, where the
    // gradient vanishes; the hit is there, with the cap's normal.
    let pointed = loaded(
        "apex",
        "[[objects]]\ntype = \"cone\"\nbase = [0, 0, 0]\nradius = 1\ncap = [0, 1, 0]\ncap_radius = 0\n",
    );
    let (t, n) = hit(&pointed, DVec3::new(0.0, 5.0, 0.0), -y).unwrap();
    assert!((t - 4.0).abs() < 1e-9 && n.is_finite(), "{t} {n}");
}

#[test]
fn a_pov_cylinder_is_placed_between_base_and_cap() {
    // Axis from (1, 0, 0) to (1, 0, 3) (along z), radius 0.5.
    let c = loaded(
        "pov-cylinder",
        "[[objects]]\ntype = \"cylinder\"\nbase = [1, 0, 0]\ncap = [1, 0, 3]\nradius = 0.5\n",
    );
    assert_hit(&c, DVec3::new(1.0, 0.0, 5.0), -Z, 2.0, Z);
    assert_hit(&c, DVec3::new(1.0, 0.0, -5.0), Z, 5.0, -Z);
    assert_hit(&c, DVec3::new(-5.0, 0.0, 1.5), X, 5.5, -X);
    // Open: through where the cap would be, onto the inside of the far wall.
    let open = loaded(
        "open-cylinder",
        "[[objects]]\ntype = \"cylinder\"\nbase = [1, 0, 0]\ncap = [1, 0, 3]\nradius = 0.5\ncaps = false\n",
    );
    let (t, _) = hit(&open, DVec3::new(1.0, 0.0, 5.0), -Z).map_or((f64::NAN, X), |h| h);
    assert!(
        t.is_nan(),
        "down the axis of an open tube: no wall to hit, got {t}"
    );
}

#[test]
fn an_open_tube_in_a_tree_has_no_cap_at_its_open_end() {
    // An open tube along z from 0 to 3, radius 0.5, in a union with a box
    // off to the side (so a tree, whose leaves give crossings). A line
    // that crosses the wall inwards and leaves by the open top once had a
    // phantom crossing there, the box's face, seen from inside the tube.
    let tree = loaded(
        "open-tube-union",
        "[[objects]]\ntype = \"csg\"\nop = \"union\"\nchildren = [\n  \
         { type = \"cylinder\", base = [0, 0, 0], cap = [0, 0, 3], radius = 0.5, caps = false },\n  \
         { type = \"box\", min = [4, 0, 0], max = [5, 1, 1] },\n]\n",
    );
    // From outside, through the wall at (0.1, √0.24), out of the top.
    let (o, d) = (DVec3::new(0.1, 2.0, 1.6), DVec3::new(0.0, -1.0, 0.8));
    let wall = 0.24f64.sqrt();
    let (t, n) = hit(&tree, o, d).expect("the wall");
    assert!((t - (2.0 - wall)).abs() < 1e-9, "{t}");
    assert!(n.abs_diff_eq(DVec3::new(0.2, 2.0 * wall, 0.0), 1e-9), "{n}");
    // From inside, on the same line past the wall: nothing ahead.
    let inside = o + 1.6 * d;
    assert!(
        hit(&tree, inside, d).is_none(),
        "{:?}",
        hit(&tree, inside, d)
    );
    assert!(!tree.occluded(inside, d, 0.0, f64::INFINITY));
}

#[test]
fn the_plan_sees_the_materials_of_a_trees_children() {
    // The tree's own material is diffuse; one child is glass: refraction rays
    // are planned only because of the child.
    let dir = scratch("csg-plan");
    let text = "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 40\nwidth = 8\nheight = 8\n\n\
        [materials.matte]\ntype = \"diffuse\"\n\n[materials.clear]\ntype = \"dielectric\"\n\n\
        [[objects]]\ntype = \"csg\"\nop = \"union\"\nmaterial = \"matte\"\nchildren = [\n  \
        { type = \"sphere\", radius = 1 },\n  { type = \"box\", min = [1, 0, 0], max = [2, 1, 1], material = \"clear\" },\n]\n";
    let scene = Scene::load(&write(&dir, "scene.toml", text)).unwrap();
    let plan = sturmray::render::Plan::for_scene(&scene);
    assert!(plan.refraction, "{plan:?}");
    let matte_only = text.replace(", material = \"clear\"", "");
    let scene = Scene::load(&write(&dir, "matte.toml", &matte_only)).unwrap();
    assert!(!sturmray::render::Plan::for_scene(&scene).refraction);
}

#[test]
fn tiny_and_far_away_lenses_keep_their_thickness() {
    // The lens of `a_lens_is_bounded_by_both_spheres` scaled by s and moved to
    // c: on its axis it runs from c − s/2 to c + s/2.
    for (s, c) in [(1e-6, 0.0), (1.0, 1e6), (1e-3, -1e4)] {
        let lens = tree(
            Op::Intersection,
            vec![
                solid(sphere(s, DVec3::new(c - 0.5 * s, 0.0, 0.0))),
                solid(sphere(s, DVec3::new(c + 0.5 * s, 0.0, 0.0))),
            ],
        );
        let o = DVec3::new(c - 5.0 * s, 0.0, 0.0);
        let (t, n) = hit(&lens, o, X).unwrap();
        // Rounding of the coordinates, c·ε, on a distance of 4.5 s.
        let tolerance = 1e-9 * s + 4.0 * f64::EPSILON * c.abs();
        assert!((t - 4.5 * s).abs() <= tolerance, "s {s}, c {c}: t {t}");
        assert!(n.abs_diff_eq(-X, 1e-6), "{n}");
        // From the middle, out through the far face: half the thickness.
        let (t, _) = hit(&lens, DVec3::new(c, 0.0, 0.0), X).unwrap();
        assert!((t - 0.5 * s).abs() <= tolerance, "s {s}, c {c}: t {t}");
    }
}

#[test]
fn crossings_in_an_interval_are_those_of_the_whole_line_within_it() {
    let torus = placed(
        Surface::Torus {
            major: 2.0,
            minor: 0.5,
        },
        DVec3::ZERO,
        None,
    );
    let (o, d) = (DVec3::new(-5.0, 0.0, 0.0), X);
    let all = crossings(&torus, o, d, false);
    let mut out = Crossings::default();
    torus.crossings(o, d, 3.0, 7.0, false, &mut out);
    let inside: Vec<(f64, bool)> = out.as_slice().iter().map(|c| (c.t, c.entering)).collect();
    let expected: Vec<(f64, bool)> = all.into_iter().filter(|c| c.0 > 3.0 && c.0 < 7.0).collect();
    // x = −1.5 (leaving the near tube) and x = 1.5 (entering the far one).
    assert_eq!(inside.len(), 2, "{inside:?}");
    for (a, b) in inside.iter().zip(&expected) {
        assert!(
            (a.0 - b.0).abs() < 1e-12 && a.1 == b.1,
            "{inside:?} {expected:?}"
        );
    }
}

/// A sphere as a general algebraic surface: the same solid as
/// `Surface::Sphere`, but costly to the tree (see `Csg::cost`).
fn algebraic_sphere(radius: f64, at: DVec3) -> Shape {
    use sturmray::poly::trivariate::Trivariate;
    let f = Trivariate::from_terms([
        ([2, 0, 0], 1.0),
        ([0, 2, 0], 1.0),
        ([0, 0, 2], 1.0),
        ([0, 0, 0], -radius * radius),
    ]);
    let pad = 1.01 * radius;
    placed(
        Surface::Algebraic(Box::new(f)),
        at,
        Some(Box3 {
            min: DVec3::splat(-pad),
            max: DVec3::splat(pad),
        }),
    )
}

/// An intersection or a clip searches its costly children (a torus here)
/// only where its cheap ones (a sphere, a half-space) are all inside. The
/// hits must be those of the same tree whose sphere is written as an
/// algebraic surface, which is costly too, so nothing is narrowed: rays
/// from outside and inside, through the sphere's rim and the torus's tube.
#[test]
fn narrowing_to_where_the_cheap_children_are_inside_keeps_every_hit() {
    let torus = || {
        solid(placed(
            Surface::Torus {
                major: 2.0,
                minor: 0.6,
            },
            DVec3::ZERO,
            None,
        ))
    };
    let half_space = || Leaf {
        part: Part::Plane {
            normal: DVec3::new(0.3, 0.2, 1.0).normalize(),
            offset: 0.25,
        },
        inverse: false,
        material: 0,
    };
    let at = DVec3::new(1.5, 0.5, 0.0);
    for op in [Op::Intersection, Op::Clip] {
        let narrowed = tree(op, vec![torus(), solid(sphere(1.2, at)), half_space()]);
        let whole = tree(
            op,
            vec![torus(), solid(algebraic_sphere(1.2, at)), half_space()],
        );
        let mut hits = 0;
        for i in 0..3000 {
            let k = f64::from(i);
            let o = DVec3::new(
                4.0 * (k * 0.71).sin(),
                4.0 * (k * 0.53).cos(),
                2.0 * (k * 0.29).sin(),
            );
            let aim = at + 1.3 * DVec3::new((k * 0.17).cos(), (k * 0.23).sin(), (k * 0.31).cos());
            let d = (aim - o).normalize();
            let tmin = if i % 3 == 0 { 2.0 } else { 0.0 };
            let (a, b) = (
                narrowed.intersect(o, d, tmin, f64::INFINITY),
                whole.intersect(o, d, tmin, f64::INFINITY),
            );
            match (a, b) {
                (Some(a), Some(b)) => {
                    hits += 1;
                    assert!(
                        (a.t - b.t).abs() < 1e-9 && a.part == b.part,
                        "{op:?} ray {i}: {a:?} against {b:?}"
                    );
                }
                (None, None) => {}
                _ => panic!("{op:?} ray {i} from {o} along {d}: {a:?} against {b:?}"),
            }
            assert_eq!(
                narrowed.occluded(o, d, tmin, f64::INFINITY),
                whole.occluded(o, d, tmin, f64::INFINITY),
                "{op:?} ray {i}"
            );
        }
        assert!(hits > 300, "{op:?}: {hits} hits");
    }
}
