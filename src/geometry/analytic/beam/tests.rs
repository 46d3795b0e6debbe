use glam::{DAffine3, DMat3, DVec3};

use super::{N, Pinhole, halves, quadratic_of, shadow_start_bound, shift, to_bernstein};
use crate::geometry::analytic::surface::Quadric;
use crate::geometry::analytic::{Box3, Shape, Surface};
use crate::poly::solve::Solver;
use crate::poly::trivariate::Trivariate;

fn eval(c: &[f64; N], t: f64) -> f64 {
    c.iter().rev().fold(0.0, |v, &k| v * t + k)
}

/// The Bernstein form's value at t: Σ b_i C(n, i) t^i (1 − t)^(n − i).
fn eval_bernstein(b: &[f64; N], t: f64) -> f64 {
    let n = N - 1;
    let binomial = |k: usize| (0..k).fold(1.0, |c, i| c * (n - i) as f64 / (i + 1) as f64);
    (0..N)
        .map(|i| b[i] * binomial(i) * t.powi(i as i32) * (1.0 - t).powi((n - i) as i32))
        .sum()
}

#[test]
fn shifts_conversions_and_halves_keep_the_polynomial() {
    let p = [0.7, -1.3, 2.1, 0.4, -0.9];
    let (from, width) = (1.5, 0.25);
    let mut shifted = p;
    shift(&mut shifted, from, width);
    let mut bernstein = shifted;
    to_bernstein(&mut bernstein);
    let [low, high] = halves(bernstein);
    for k in 0..=10 {
        let t = f64::from(k) / 10.0;
        let want = eval(&p, from + width * t);
        let close = |v: f64| (v - want).abs() <= 1e-12 * (1.0 + want.abs());
        assert!(close(eval(&shifted, t)), "shift at {t}");
        assert!(close(eval_bernstein(&bernstein, t)), "Bernstein at {t}");
        let half = if t <= 0.5 {
            eval_bernstein(&low, 2.0 * t)
        } else {
            eval_bernstein(&high, 2.0 * t - 1.0)
        };
        assert!(close(half), "halves at {t}");
    }
}

/// A sphere's and a general quadric's F as polynomials agree with the
/// surfaces' own F (the constant of Q(t) along a line from the point).
#[test]
fn quadratic_leaves_as_polynomials_keep_their_f() {
    use crate::geometry::analytic::Quadric;
    let quadric = Quadric {
        a: glam::DMat3::from_cols_array(&[1.0, 0.3, -0.2, 0.5, -2.0, 0.7, 0.1, 0.4, 0.6]),
        b: DVec3::new(0.3, -1.1, 0.8),
        c: -0.9,
    };
    for surface in [Surface::Sphere { radius: 1.7 }, Surface::Quadric(quadric)] {
        let f = quadratic_of(&surface).unwrap();
        for k in 0..20 {
            let p = DVec3::new(
                f64::from(k) * 0.37 - 3.0,
                f64::from(k % 7) - 2.5,
                1.3 - 0.21 * f64::from(k),
            );
            let want = surface.along_line(p, DVec3::X).unwrap()[0];
            let got = f.eval(p.to_array());
            assert!(
                (got - want).abs() <= 1e-12 * (1.0 + want.abs()),
                "{surface:?} at {p}: {got} != {want}"
            );
        }
    }
}

fn quartic(expr: &[([u8; 3], f64)], clip: f64, to_world: DAffine3) -> Shape {
    let f = Trivariate::from_terms(expr.iter().copied());
    let surface = Surface::Algebraic(Box::new(f));
    Shape::new(
        surface,
        to_world,
        Some(Box3::cube(clip)),
        0,
        Solver::default(),
    )
    .unwrap()
}

/// (x² + y² + z²)² − 1: the unit sphere as a quartic.
fn far_sphere() -> Trivariate {
    let squares = Trivariate::from_terms([([2, 0, 0], 1.0), ([0, 2, 0], 1.0), ([0, 0, 2], 1.0)]);
    squares
        .checked_pow(2)
        .unwrap()
        .sub(&Trivariate::constant(1.0))
}

/// Surfaces of POV-Ray's quartic samples' kinds: a torus, the cubic of
/// tcubic.pov, quarcyl.pov's thin spindle, two balls as one quartic, and a
/// sphere of degree 4 far off the origin (large terms that cancel on the
/// surface), each turned.
fn shapes() -> Vec<(&'static str, Shape)> {
    let turn = |x: f64, y: f64, at: DVec3| {
        DAffine3::from_translation(at) * DAffine3::from_rotation_x(x) * DAffine3::from_rotation_y(y)
    };
    let torus = crate::poly::trivariate::tests::torus(2.0, 0.5);
    vec![
        (
            "torus",
            Shape::new(
                Surface::Algebraic(Box::new(torus)),
                turn(0.6, 0.3, DVec3::new(0.0, 0.0, 6.0)),
                Some(Box3::cube(2.6)),
                0,
                Solver::default(),
            )
            .unwrap(),
        ),
        (
            "cubic",
            quartic(
                &[
                    ([3, 0, 0], -0.5),
                    ([2, 0, 0], -0.5),
                    ([0, 2, 0], 1.0),
                    ([0, 0, 2], 1.0),
                ],
                2.0,
                turn(0.1, -0.26, DVec3::new(0.0, 0.0, 5.0)),
            ),
        ),
        (
            "spindle",
            quartic(
                &[
                    ([2, 2, 0], 1.0),
                    ([2, 0, 0], 0.01),
                    ([0, 2, 2], 1.0),
                    ([0, 0, 2], 0.01),
                    ([0, 0, 0], -0.01),
                ],
                2.0,
                turn(-0.52, 0.35, DVec3::new(0.0, 0.0, 6.0)),
            ),
        ),
        (
            // (|p − c|² − r²)(|p + c|² − r²), c = (0.8, 0, 0), r = 0.6: two
            // balls, one in the other's shadow from a light on their axis.
            "two spheres",
            quartic(
                &[
                    ([4, 0, 0], 1.0),
                    ([0, 4, 0], 1.0),
                    ([0, 0, 4], 1.0),
                    ([2, 2, 0], 2.0),
                    ([2, 0, 2], 2.0),
                    ([0, 2, 2], 2.0),
                    ([2, 0, 0], -2.0),
                    ([0, 2, 0], 0.56),
                    ([0, 0, 2], 0.56),
                    ([0, 0, 0], 0.0784),
                ],
                1.6,
                turn(0.0, 0.0, DVec3::new(0.0, 0.0, 4.0)),
            ),
        ),
        (
            "far sphere",
            Shape::new(
                Surface::Algebraic(Box::new(far_sphere())),
                turn(0.0, 0.0, DVec3::new(0.3, -0.2, 400.0)),
                Some(Box3::cube(1.5)),
                0,
                Solver::default(),
            )
            .unwrap(),
        ),
    ]
}

/// Whenever a rectangle of pixels is proven missed, no ray through it hits
/// the shape: every ray of a 9 × 9 grid over it, corners and edges
/// included, is searched as a render would. Rectangles of 1 to 16 pixels a
/// side, over the whole image; some must be proven and some not, or the
/// test shows nothing.
#[test]
fn no_ray_through_a_missed_rectangle_hits() {
    let (width, height) = (160.0, 120.0);
    let pinhole = Pinhole {
        eye: DVec3::new(0.1, -0.05, -1.0),
        top_left: DVec3::new(-0.5, 0.375, 1.0),
        right: DVec3::new(1.0 / width, 0.0, 0.0),
        down: DVec3::new(0.0, -0.75 / height, 0.0),
    };
    for (name, shape) in shapes()
        .into_iter()
        .chain(clipped_cubics())
        .chain(quadratics())
    {
        let beams = shape
            .beams(&pinhole, 0.0, &shape.bounds())
            .expect("a quartic in a finite box");
        let (mut proven, mut tried) = (0, 0);
        for side in [1.0, 4.0, 16.0] {
            let mut y0 = 0.0;
            while y0 < height {
                let mut x0 = 0.0;
                while x0 < width {
                    let (xs, ys) = ((x0, x0 + side), (y0, y0 + side));
                    tried += 1;
                    if beams.misses(xs, ys) {
                        proven += 1;
                        for i in 0..=8 {
                            for j in 0..=8 {
                                let x = x0 + side * f64::from(i) / 8.0;
                                let y = y0 + side * f64::from(j) / 8.0;
                                let d = pinhole.dir(x, y).normalize();
                                let hit = shape.intersect(pinhole.eye, d, 0.0, f64::INFINITY);
                                assert!(
                                    hit.is_none(),
                                    "{name}: ({x}, {y}) in [{xs:?}] × [{ys:?}]: {hit:?}"
                                );
                            }
                        }
                    }
                    x0 += side;
                }
                y0 += side;
            }
        }
        assert!(
            proven > tried / 10 && proven < tried,
            "{name}: {proven} of {tried} proven"
        );
    }
}

/// Spheres and quadrics, proven by their discriminant (`Discriminant`):
/// POV-Ray's `Axes` cylinder (radius 0.01, in a box around the eye, seen
/// along its length and across it), a ball in a box the eye is outside, a
/// tiny ball and a big one whose rim crosses the image, a hyperboloid of
/// one sheet (a form that curves both ways) and a paraboloid (b ≠ 0), each
/// turned.
fn quadratics() -> Vec<(&'static str, Shape)> {
    let quadric = |a: DMat3, b: DVec3, c: f64, to_world: DAffine3, clip: f64| {
        Shape::new(
            Surface::Quadric(Quadric { a, b, c }),
            to_world,
            Some(Box3::cube(clip)),
            0,
            Solver::default(),
        )
        .unwrap()
    };
    let turn = |x: f64, y: f64, at: DVec3| {
        DAffine3::from_translation(at) * DAffine3::from_rotation_x(x) * DAffine3::from_rotation_y(y)
    };
    // Centred at `at`, in its own box.
    let ball = |radius: f64, at: DVec3| {
        Shape::new(
            Surface::Sphere { radius },
            DAffine3::from_translation(at),
            Some(Box3::cube(radius)),
            0,
            Solver::default(),
        )
        .unwrap()
    };
    let thin = DAffine3::from_scale(DVec3::new(1.0, 0.01, 0.01));
    let cylinder = DMat3::from_diagonal(DVec3::new(0.0, 1.0, 1.0));
    vec![
        (
            "thin cylinder across",
            quadric(
                cylinder,
                DVec3::ZERO,
                -1.0,
                turn(0.4, 0.3, DVec3::new(0.0, 0.0, 4.0)) * thin,
                1e6,
            ),
        ),
        (
            "thin cylinder along",
            quadric(
                cylinder,
                DVec3::ZERO,
                -1.0,
                turn(0.1, 1.3, DVec3::new(0.02, 0.01, 4.0)) * thin,
                1e6,
            ),
        ),
        ("ball", ball(0.8, DVec3::new(0.3, 0.2, 5.0))),
        (
            // 0.004 of a pixel across.
            "tiny ball",
            ball(1e-4, DVec3::new(0.05, -0.02, 3.0)),
        ),
        (
            // Terms of 1e4 that cancel to the small values near its rim (at
            // 1e3 only 2% of the rectangles are proven: the margin is taken
            // from the terms at the far corners of its box, where a ray from
            // outside the box forms its Q).
            "big ball",
            ball(100.0, DVec3::new(100.2, 0.0, 4.0)),
        ),
        (
            "hyperboloid",
            quadric(
                DMat3::from_diagonal(DVec3::new(1.0, 1.0, -1.0)),
                DVec3::ZERO,
                -0.04,
                turn(1.2, 0.4, DVec3::new(0.1, 0.0, 6.0)),
                1.5,
            ),
        ),
        (
            "paraboloid",
            quadric(
                DMat3::from_diagonal(DVec3::new(1.0, 1.0, 0.0)),
                DVec3::new(0.0, 0.0, -1.0),
                0.3,
                turn(-0.7, 0.5, DVec3::new(0.0, 0.0, 6.0)),
                2.0,
            ),
        ),
    ]
}

/// Trees as POV-Ray's samples make them: tcubic.pov's cubic and
/// folium.pov's, each intersected with a clear ball, which the reader
/// makes a clip (`scene::pov`), with the cubic cut to a box just around
/// the ball's. Folium's points are lit from the cubic's inside. And
/// grafbic.pov's form: tcubic's cubic between two half-spaces.
fn clipped_cubics() -> Vec<(&'static str, Shape)> {
    use crate::geometry::analytic::csg::{Csg, Leaf, Node, Op, Part};
    let solver = Solver::default();
    let clipped = |terms: &[([u8; 3], f64)], cut: f64, radius: f64, to_world: DAffine3| {
        let f = Trivariate::from_terms(terms.iter().copied());
        let surface = Surface::Algebraic(Box::new(f));
        let mut cubic = Shape::unclipped(surface, to_world, 0, solver).unwrap();
        cubic.clip_within(&Box3::cube(cut), to_world).unwrap();
        let ball = Shape::new(Surface::Sphere { radius }, to_world, None, 0, solver).unwrap();
        let leaves = [cubic, ball].map(|s| Leaf {
            part: Part::Solid(s),
            inverse: false,
            material: 0,
        });
        let root = Node::Op {
            op: Op::Clip,
            inverse: false,
            children: vec![Node::Leaf(0), Node::Leaf(1)],
        };
        let tree = Csg::within(root, leaves.into(), Box3::cube(100.0)).unwrap();
        let surface = Surface::Csg(Box::new(tree));
        Shape::new(surface, DAffine3::IDENTITY, None, 0, solver).unwrap()
    };
    let turn = |x: f64, y: f64, at: DVec3, scale: f64| {
        DAffine3::from_translation(at)
            * DAffine3::from_rotation_x(x)
            * DAffine3::from_rotation_y(y)
            * DAffine3::from_scale(DVec3::splat(scale))
    };
    let folium_at = turn(0.2, 0.9, DVec3::new(0.0, 0.0, 6.0), 0.2);
    // grafbic.pov's form: a quartic clipped by two half-spaces (world).
    let between_planes = |terms: &[([u8; 3], f64)]| {
        let f = Trivariate::from_terms(terms.iter().copied());
        let to_world = turn(0.3, -0.4, DVec3::new(0.2, 0.0, 5.0), 1.0);
        let mut cubic =
            Shape::unclipped(Surface::Algebraic(Box::new(f)), to_world, 0, solver).unwrap();
        cubic.clip_within(&Box3::cube(2.0), to_world).unwrap();
        let normal = to_world.transform_vector3(DVec3::Y);
        let at = to_world.translation.dot(normal);
        let leaf = |part| Leaf {
            part,
            inverse: false,
            material: 0,
        };
        let leaves = vec![
            leaf(Part::Solid(cubic)),
            leaf(Part::Plane {
                normal,
                offset: at + 0.6,
            }),
            leaf(Part::Plane {
                normal: -normal,
                offset: 0.4 - at,
            }),
        ];
        let root = Node::Op {
            op: Op::Clip,
            inverse: false,
            children: vec![Node::Leaf(0), Node::Leaf(1), Node::Leaf(2)],
        };
        let tree = Csg::within(root, leaves, Box3::cube(100.0)).unwrap();
        Shape::new(
            Surface::Csg(Box::new(tree)),
            DAffine3::IDENTITY,
            None,
            0,
            solver,
        )
        .unwrap()
    };
    let tcubic = [
        ([3, 0, 0], -0.5),
        ([2, 0, 0], -0.5),
        ([0, 2, 0], 1.0),
        ([0, 0, 2], 1.0),
    ];
    let folium = [
        ([3, 0, 0], 2.0),
        ([1, 2, 0], -3.0),
        ([1, 0, 2], -3.0),
        ([0, 2, 0], 1.0),
        ([0, 0, 2], 1.0),
    ];
    vec![
        (
            "cubic in a ball",
            clipped(
                &tcubic,
                2.002,
                2.0,
                turn(0.1, -0.26, DVec3::new(0.0, 0.0, 5.0), 1.0),
            ),
        ),
        ("folium in a ball", clipped(&folium, 10.01, 10.0, folium_at)),
        ("cubic between planes", between_planes(&tcubic)),
    ]
}

/// Whenever a tile's lit points are proven to cast no shadow on
/// themselves towards a light, no shadow ray from them, made as the
/// Whitted tracer makes it (from the f32 point, offset off the surface,
/// towards the light, stopping short of it), meets the shape. Tiles of
/// 8 × 8 pixels over the whole image, a far light, a near one and one
/// that puts one of two balls in the other's shadow; some
/// tiles must be proven (many, of the torus and the cubic) and some not.
#[test]
fn no_shadow_ray_from_a_proven_tile_meets_its_shape() {
    use crate::math::{Vec3, gamma, offset};
    let (width, height) = (160.0, 120.0);
    let camera = Pinhole {
        eye: DVec3::new(0.1, -0.05, -1.0),
        top_left: DVec3::new(-0.5, 0.375, 1.0),
        right: DVec3::new(1.0 / width, 0.0, 0.0),
        down: DVec3::new(0.0, -0.75 / height, 0.0),
    };
    let short = 1e-4;
    let (mut proven, mut tried) = (0, 0);
    for (name, shape) in shapes().into_iter().chain(clipped_cubics()) {
        let (mut shape_proven, mut rays) = (0, 0);
        let lights = [
            DVec3::new(200.0, 30.0, -300.0),
            DVec3::new(-4.0, 5.0, 1.0),
            // On the two spheres' axis: the one in front shades the other.
            DVec3::new(-20.0, 0.1, 4.0),
        ];
        for light in lights {
            let box_ = shape.bounds();
            let centre = 0.5 * (box_.min + box_.max).as_dvec3();
            let pinhole = Pinhole::toward(light, centre).unwrap();
            let beams = (shape.beams(&pinhole, (centre - light).length(), &box_))
                .expect("a quartic in a finite box");
            for ty in 0..15 {
                for tx in 0..20 {
                    // Each lit hit: its point, the bound on its shadow
                    // ray's start, and that shadow ray.
                    let mut lit = Vec::new();
                    for y in 8 * ty..8 * ty + 8 {
                        for x in 8 * tx..8 * tx + 8 {
                            let d = camera.dir(f64::from(x) + 0.5, f64::from(y) + 0.5);
                            let Some(hit) = shape.intersect(camera.eye, d, 0.0, f64::INFINITY)
                            else {
                                continue;
                            };
                            let p = camera.eye + hit.t * d;
                            if hit.normal.dot(light - p) * hit.normal.dot(-d) <= 0.0 {
                                continue;
                            }
                            let pad = shadow_start_bound(camera.eye, d, hit.t, hit.error);
                            // As `Scene::interaction` and `Whitted::direct`.
                            let (o32, d32) = (camera.eye.as_vec3(), d.as_vec3());
                            let t = hit.t as f32;
                            let p32 = o32 + t * d32;
                            let error = (hit.error as f32 + t.abs() * f32::EPSILON) * d32.abs()
                                + gamma(3) * (o32.abs() + (t * d32).abs());
                            let to = light.as_vec3() - p32;
                            let wi = to / to.length();
                            let n = hit.normal.as_vec3().normalize();
                            let start = offset(p32, error, n, wi);
                            let tfar = to.length() * (1.0 - short as f32);
                            assert!(
                                (start.as_dvec3() - p).length() <= pad,
                                "{name}: a start {} from its point, bound {pad}",
                                (start.as_dvec3() - p).length()
                            );
                            lit.push((hit.part as usize, (p, pad), (start, wi, tfar)));
                        }
                    }
                    // Each leaf's points on their own, as a render's.
                    let mut leaves: Vec<usize> = lit.iter().map(|h| h.0).collect();
                    leaves.sort_unstable();
                    leaves.dedup();
                    for leaf in leaves {
                        let lit: Vec<_> = lit.iter().filter(|h| h.0 == leaf).collect();
                        if lit.is_empty() {
                            continue;
                        }
                        tried += 1;
                        let points: Vec<_> = lit.iter().map(|&&(_, point, _)| point).collect();
                        if !beams.lights(leaf, &points, short) {
                            continue;
                        }
                        (proven, shape_proven) = (proven + 1, shape_proven + 1);
                        for &&(_, _, (start, wi, tfar)) in &lit {
                            let (o, d): (Vec3, Vec3) = (start, wi);
                            rays += 1;
                            assert!(
                                !shape.occluded(o.as_dvec3(), d.as_dvec3(), 0.0, f64::from(tfar)),
                                "{name}: the shadow ray from {o} towards {light} meets the shape"
                            );
                        }
                    }
                }
            }
        }
        // The far sphere covers a few pixels, the spindle's light rays
        // pass its needle: the torus and the cubics are proven widely.
        if ["torus", "cubic", "cubic in a ball", "folium in a ball"].contains(&name) {
            assert!(
                shape_proven >= 50 && rays > 1000,
                "{name}: {shape_proven} tiles proven"
            );
        }
    }
    assert!(proven < tried, "every one of {tried} tiles proven");
}

/// Whether the ray o + t·d, t > 0, meets the box [lo, hi] (slabs, in f64).
fn meets_box(o: DVec3, d: DVec3, lo: DVec3, hi: DVec3) -> bool {
    let (a, b) = ((lo - o) / d, (hi - o) / d);
    let near = a.min(b).max_element();
    let far = a.max(b).min_element();
    near <= far && far > 0.0
}

/// No ray through a pixel outside a box's screen rectangle meets the box,
/// for cameras whose `right` and `down` are neither orthogonal nor of one
/// length (POV-Ray's `right` and `up` may be anything), boxes thin, flat,
/// long, near and far; rays inside it do meet the box, so it is no wider
/// than the image of the box. A box around the eye, behind it, or across
/// the plane of the eye has no rectangle.
#[test]
fn no_ray_outside_a_box_screen_rectangle_meets_the_box() {
    // Kronecker points in (0, 1): irrational multiples, each case its own
    // (geometry may not use `sampling`).
    let mut k = 0.0;
    let mut random = move || {
        k += 1.0;
        (k * std::f64::consts::SQRT_2 * 1e3).fract()
    };
    let (mut inside, mut outside) = (0, 0);
    for case in 0..200 {
        let pinhole = Pinhole {
            eye: DVec3::new(random() - 0.5, random() - 0.5, -2.0 - random()),
            top_left: DVec3::new(-0.6 + 0.2 * random(), 0.4 + 0.1 * random(), 1.0),
            right: DVec3::new(0.01 * (0.5 + random()), 0.002 * (random() - 0.5), 0.0),
            down: DVec3::new(
                0.003 * (random() - 0.5),
                -0.01 * (0.5 + random()),
                0.001 * random(),
            ),
        };
        let size = DVec3::new(random(), random(), random()).powf(3.0) * 2.0 + DVec3::splat(1e-6);
        let centre = DVec3::new(2.0 * random() - 1.0, 2.0 * random() - 1.0, 4.0 * random());
        let (lo, hi) = (centre - size, centre + size);
        let [x0, x1, y0, y1] = pinhole.screen(lo, hi).expect("a box in front of the eye");
        assert!(x0 < x1 && y0 < y1, "case {case}: {x0} {x1} {y0} {y1}");
        // A grid reaching half the rectangle's size past each side.
        let (wide, high) = (x1 - x0, y1 - y0);
        for i in 0..=40 {
            for j in 0..=40 {
                let x = x0 - 0.5 * wide + 2.0 * wide * f64::from(i) / 40.0;
                let y = y0 - 0.5 * high + 2.0 * high * f64::from(j) / 40.0;
                let meets = meets_box(pinhole.eye, pinhole.dir(x, y), lo, hi);
                let within = (x0..=x1).contains(&x) && (y0..=y1).contains(&y);
                assert!(within || !meets, "case {case}: ({x}, {y}) meets the box");
                inside += usize::from(within && meets);
                outside += usize::from(!within);
            }
        }
    }
    assert!(
        inside > 10_000 && outside > 100_000,
        "{inside} met inside, {outside} outside"
    );
    let pinhole = Pinhole {
        eye: DVec3::ZERO,
        top_left: DVec3::new(-0.5, 0.5, 1.0),
        right: DVec3::new(0.01, 0.0, 0.0),
        down: DVec3::new(0.0, -0.01, 0.0),
    };
    for (lo, hi) in [
        (DVec3::splat(-1.0), DVec3::splat(1.0)),
        (DVec3::new(-1.0, -1.0, -5.0), DVec3::new(1.0, 1.0, -3.0)),
        (DVec3::new(-1.0, -1.0, -1.0), DVec3::new(1.0, 1.0, 3.0)),
        (
            DVec3::new(-1.0, -1.0, 2.0),
            DVec3::new(1.0, 1.0, f64::INFINITY),
        ),
    ] {
        assert_eq!(pinhole.screen(lo, hi), None, "{lo} {hi}");
    }
}
