//! Every backend gives the same answers: Embree and the two pure-Rust BVHs
//! (obvhs, bvh) on random rays through meshes, camera and shadow rays through
//! a scene with analytic shapes, a scene smaller than a millimetre, and whole
//! renders.

mod common;

use std::path::Path;

use common::{scratch, write};
use sturmray::accel::{Accel, Backend, ShapeSet};
use sturmray::math::{Hit, Ray, Vec3};
use sturmray::render::{RenderOptions, render};
use sturmray::report::bench::incoherent_rays;
use sturmray::scene::Scene;

/// Relative tolerance on t, and absolute on the barycentrics u, v, for triangle
/// hits. Both sides run the same f32 Plücker test, but Embree contracts its
/// cross products into FMAs and divides through an approximate reciprocal
/// refined by one Newton step, so t differs by a few ulps, more where the ray
/// grazes the triangle (dividing by a small dot(Ng, D)). 1e-4 is about 800
/// ulps: loose enough for grazing rays, tight enough that a different
/// triangle or a shifted hit point fails. Analytic hits come from the same f64
/// code on the same f32 ray in every backend, so they must be bit-equal.
const TOLERANCE: f32 = 1e-4;

const RUST_BACKENDS: [Backend; 2] = [Backend::Obvhs, Backend::Bvh];

fn scene_file(relative: &str) -> Scene {
    Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join(relative)).unwrap()
}

fn build(scene: &Scene, backend: Backend) -> Accel {
    Accel::build(scene, backend, Some(2)).unwrap()
}

/// Rays through the centres of a `n`×`n` grid of the camera's pixels.
fn camera_rays(scene: &Scene, n: u32) -> Vec<Ray> {
    let frame = scene.camera.frame();
    let (w, h) = (scene.camera.width as f32, scene.camera.height as f32);
    (0..n * n)
        .map(|i| {
            let (x, y) = ((i % n) as f32 + 0.5, (i / n) as f32 + 0.5);
            frame.ray(x * w / n as f32, y * h / n as f32)
        })
        .collect()
}

/// Asserts `other` agrees with Embree's `reference` on ray `i`.
fn assert_same_hit(reference: &Hit, other: &Hit, shapes_geom_id: u32, what: &str) {
    assert_eq!(
        (reference.geom_id, reference.prim_id),
        (other.geom_id, other.prim_id),
        "{what}: embree {reference:?}, other {other:?}"
    );
    if !reference.is_hit() {
        return;
    }
    if reference.geom_id == shapes_geom_id {
        assert_eq!(reference, other, "{what}: an analytic hit differs");
        return;
    }
    let close = (reference.t - other.t).abs() <= TOLERANCE * reference.t.abs()
        && (reference.u - other.u).abs() <= TOLERANCE
        && (reference.v - other.v).abs() <= TOLERANCE
        && (reference.ng - other.ng).length() <= TOLERANCE * reference.ng.length();
    assert!(close, "{what}: embree {reference:?}, other {other:?}");
}

/// Traces `rays` through Embree and each pure-Rust backend and compares every
/// hit; returns Embree's hits.
fn assert_backends_agree(scene: &Scene, rays: &[Ray], what: &str) -> Vec<Hit> {
    let embree = build(scene, Backend::Embree);
    let reference: Vec<Hit> = rays.iter().map(|r| embree.intersect(r)).collect();
    for backend in RUST_BACKENDS {
        let accel = build(scene, backend);
        for (i, (ray, expected)) in rays.iter().zip(&reference).enumerate() {
            let context = format!("{what}, {}, ray {i} {ray:?}", backend.name());
            assert_same_hit(
                expected,
                &accel.intersect(ray),
                scene.shapes_geom_id(),
                &context,
            );
            assert_eq!(
                embree.occluded(ray),
                accel.occluded(ray),
                "{context}: occluded differs"
            );
        }
        let mut batch = vec![Hit::MISS; rays.len()];
        accel.intersect_batch(rays, &mut batch, false).unwrap();
        for (i, (expected, hit)) in reference.iter().zip(&batch).enumerate() {
            let context = format!("{what}, {} batch, ray {i}", backend.name());
            assert_same_hit(expected, hit, scene.shapes_geom_id(), &context);
        }
        accel.check().unwrap();
    }
    reference
}

/// Shadow rays from each hit towards `target`, starting a little off the surface.
fn shadow_rays(rays: &[Ray], hits: &[Hit], target: Vec3) -> Vec<Ray> {
    rays.iter()
        .zip(hits)
        .filter(|(_, h)| h.is_hit())
        .map(|(ray, hit)| {
            let p = ray.at(hit.t);
            let n = hit.ng.normalize();
            let n = if n.dot(ray.dir) > 0.0 { -n } else { n };
            let origin = p + 1e-4 * p.abs().max_element().max(1.0) * n;
            let mut shadow = Ray::new(origin, target - origin);
            shadow.tfar = 1.0;
            shadow
        })
        .collect()
}

#[test]
fn random_rays_through_the_cornell_box_agree() {
    let scene = scene_file("scenes/cornell.toml");
    let rays = incoherent_rays(scene.bounds(), 20_000, 1);
    let hits = assert_backends_agree(&scene, &rays, "cornell random");
    // The rays start inside and around a closed-ish box: most hit something.
    let hit = hits.iter().filter(|h| h.is_hit()).count();
    assert!(hit > rays.len() / 2, "only {hit} hits");
}

#[test]
fn camera_and_shadow_rays_through_meshes_and_analytic_shapes_agree() {
    let scene = scene_file("scenes/gallery/mixed.toml");
    let rays = camera_rays(&scene, 96);
    let hits = assert_backends_agree(&scene, &rays, "mixed camera");
    let shapes = hits
        .iter()
        .filter(|h| h.geom_id == scene.shapes_geom_id())
        .count();
    let meshes = hits
        .iter()
        .filter(|h| h.geom_id < scene.shapes_geom_id())
        .count();
    assert!(
        shapes > 100 && meshes > 100,
        "{shapes} shape hits, {meshes} mesh hits"
    );
    // Towards the point light: some are blocked by the shapes and the knot.
    let light = Vec3::new(0.278, 0.5278, 0.2795);
    let shadows = shadow_rays(&rays, &hits, light);
    assert_backends_agree(&scene, &shadows, "mixed shadow");
    let embree = build(&scene, Backend::Embree);
    let blocked = shadows.iter().filter(|r| embree.occluded(r)).count();
    assert!(
        blocked > 0 && blocked < shadows.len(),
        "{blocked} of {} blocked",
        shadows.len()
    );
}

/// The Cornell box and a sphere scaled into half a millimetre: obvhs on its own
/// skips every node a ray leaves before t = 1e-4, i.e. most hits here.
#[test]
fn a_scene_smaller_than_a_millimetre_agrees() {
    let dir = scratch("tiny");
    let obj = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell/cornell.obj");
    let text = format!(
        r#"[camera]
eye = [0.000278, 0.000273, -0.0008]
look_at = [0.000278, 0.000273, 0]
fov = 39.3
width = 64
height = 64
[materials.grey]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]
[[objects]]
type = "mesh"
file = {obj:?}
transform = {{ scale = 0.001 }}
[[objects]]
type = "sphere"
radius = 0.00009
material = "grey"
transform = {{ translate = [0.0004, 0.00009, 0.00017] }}
"#
    );
    let scene = Scene::load(&write(&dir, "tiny.toml", &text)).unwrap();
    let size = scene.bounds().diagonal().max_element();
    assert!(size < 1e-3, "the scene is {size} across");
    let mut rays = incoherent_rays(scene.bounds(), 5_000, 2);
    rays.extend(camera_rays(&scene, 48));
    let hits = assert_backends_agree(&scene, &rays, "tiny");
    let near = hits.iter().filter(|h| h.is_hit() && h.t < 1e-4).count();
    assert!(near > 1000, "only {near} hits closer than 1e-4");
    assert!(hits.iter().any(|h| h.geom_id == scene.shapes_geom_id()));
}

#[test]
fn renders_through_every_backend_agree() {
    let mut scene = scene_file("scenes/gallery/mixed.toml");
    (scene.camera.width, scene.camera.height) = (40, 40);
    let options = RenderOptions {
        threads: Some(2),
        spp: Some(1),
        ..RenderOptions::default()
    };
    let image = |backend| {
        let out = render(&scene, &build(&scene, backend), &options).unwrap();
        out.film.layers().beauty
    };
    let reference = image(Backend::Embree);
    let lit = reference
        .iter()
        .filter(|p| p.iter().sum::<f32>() > 0.0)
        .count();
    assert!(lit > reference.len() / 2, "only {lit} lit pixels");
    for backend in RUST_BACKENDS {
        let other = image(backend);
        for (i, (a, b)) in reference.iter().zip(&other).enumerate() {
            let (a, b) = (Vec3::from(*a), Vec3::from(*b));
            // Hits agree to TOLERANCE, and shading is smooth in the hit point.
            assert!(
                (a - b).abs().max_element() <= 1e-3 * a.max_element().max(1.0),
                "{}: pixel {i}: embree {a}, other {b}",
                backend.name()
            );
        }
    }
}

/// Camera rays offered only the shapes their rectangle of pixels may hit
/// (`ListBeams`, through Embree's shape list) render the same bytes as
/// the pure-Rust BVH, which offers every ray every shape: POV-Ray's
/// quarcyl spindle in its `bounded_by` sphere (unbounded, so its box
/// reaches far past the sphere), tcubic's cubic clipped by a sphere
/// (a tree, proven outside the ball by its discriminant) and a quartic
/// cut by a hyperboloid around the eye (a discriminant that proves the
/// lines inside, not out), at one sample a pixel (pixel centres) and at four (the
/// filter's jitter, up to its radius from the centre). The proofs must
/// skip the shapes on some tiles, or the test shows nothing.
#[test]
fn rays_that_skip_shapes_proven_missed_render_the_same_bytes() {
    let dir = scratch("beams");
    let scenes = [
        "quartic { < 0,0,0,0,1,0,0,0,0,0.01, 0,0,0,0,0,0,0,0,0,0, 0,0,0,1,0,0,0,0,0,0, \
         0,0,0.01,0,-0.01 > bounded_by { sphere { 0, 2 } } scale 1.5 rotate <-30, 20, 50> \
         translate 3*z pigment { rgb 1 } }",
        "intersection { quartic { < 0,0,0,-0.5,0,0,0,0,0,-0.5, 0,0,0,0,0,0,0,0,0,0, \
         0,0,0,0,0,1,0,0,0,0, 0,0,1,0,0 > } sphere { 0, 2 } \
         bounded_by { sphere { 0, 2.2 } } rotate <0, -15, 0> translate 3*z pigment { rgb 1 } }",
        // The eye inside a hyperboloid's hole, whose lines near its axis
        // never meet it: they stay inside, so the tree is not missed there.
        "intersection { quadric { <1, 1, -1>, <0, 0, 0>, <0, 0, 0>, -1 } \
         quartic { < 1,0,0,0,2,0,0,2,0,-104, 0,0,0,0,0,0,0,0,0,0, 1,0,0,2,0,56,0,0,0,0, \
         1,0,-104,0,784 > scale 0.1 rotate 70*x translate 3*z } \
         bounded_by { sphere { 3*z, 1.2 } } pigment { rgb 1 } }",
    ];
    for (i, body) in scenes.iter().enumerate() {
        let text = format!(
            "camera {{ location <0, 0, -3> angle 55 }}\n\
             light_source {{ <20, 30, -40> color rgb 1 }}\n{body}\n"
        );
        let path = write(&dir, &format!("beams{i}.pov"), &text);
        let options = sturmray::scene::LoadOptions {
            size: Some((64, 48)),
            ..sturmray::scene::LoadOptions::default()
        };
        let scene = Scene::load_with(&path, &options).unwrap();
        let listed = build(&scene, Backend::Embree);
        let frame = scene.camera.frame();
        let beams = listed.camera_beams(&frame.pinhole().unwrap()).unwrap();
        let sets: Vec<ShapeSet> = (0..12)
            .flat_map(|y| (0..16).map(move |x| (x, y)))
            .map(|(x, y)| {
                let span = |a: usize| (4.0 * a as f64, 4.0 * a as f64 + 4.0);
                beams.may_hit(span(x), span(y), ShapeSet::ALL)
            })
            .collect();
        let skipped = sets.iter().filter(|&&s| s != beams.listed()).count();
        assert!(
            skipped >= 16,
            "scene {i}: only {skipped} of 192 squares of 4 pixels skip the shape"
        );
        // Pixels offered no shape at all take the background untraced at
        // one sample a pixel (`Tracer::constant_miss`).
        assert!(
            sets.contains(&ShapeSet::NONE),
            "scene {i}: no square meets no shape"
        );
        for spp in [1, 4] {
            let options = RenderOptions {
                threads: Some(2),
                spp: Some(spp),
                ..RenderOptions::default()
            };
            let image = |accel: &Accel| {
                render(&scene, accel, &options)
                    .unwrap()
                    .film
                    .layers()
                    .beauty
            };
            let (a, b) = (image(&listed), image(&build(&scene, Backend::Obvhs)));
            assert!(a == b, "scene {i}, {spp} spp: the images differ");
        }
    }
}

/// The shadow rays a tile's proofs spare (`render::lit`: a shape's own lit
/// points proven to cast no shadow on themselves towards a point light)
/// change nothing: a torus, quarcyl's spindle (its needle reaching past
/// its gate) and two balls as one quartic, lit by a far light, a near one
/// that throws the torus's ring onto itself, and one on the balls' axis
/// that puts one in the other's shadow, render through the list (with the
/// proofs) as through obvhs (without), at one sample a pixel and at four;
/// so do cubics cut by clear balls, and a torus behind a ball that filters
/// its shadows.
#[test]
fn shadow_rays_spared_by_light_proofs_render_the_same_bytes() {
    let dir = scratch("lights");
    let scenes = [
        "quartic { < 1,0,0,0,2,0,0,2,0,-104, 0,0,0,0,0,0,0,0,0,0, 1,0,0,2,0,56,0,0,0,0, \
         1,0,-104,0,784 > scale 0.2 rotate <-50, 20, 0> translate 3*z pigment { rgb 1 } }",
        "quartic { < 0,0,0,0,1,0,0,0,0,0.01, 0,0,0,0,0,0,0,0,0,0, 0,0,0,1,0,0,0,0,0,0, \
         0,0,0.01,0,-0.01 > bounded_by { sphere { 0, 2 } } scale 1.5 rotate <-30, 20, 50> \
         translate 3*z pigment { rgb 1 } }",
        // Two balls as one quartic, one in the other's shadow from the
        // light on their axis.
        "quartic { < 1,0,0,0,2,0,0,2,0,-2, 0,0,0,0,0,0,0,0,0,0, 1,0,0,2,0,0.56,0,0,0,0, \
         1,0,0.56,0,0.0784 > translate 3*z pigment { rgb 1 } }",
        // tcubic.pov's and folium.pov's cubics, each cut by a clear ball
        // (which the reader makes a clip, not a filtering surface);
        // folium's points are lit from the cubic's inside.
        "intersection { quartic { < 0,0,0,-0.5,0,0,0,0,0,-0.5, 0,0,0,0,0,0,0,0,0,0, \
         0,0,0,0,0,1,0,0,0,0, 0,0,1,0,0 > pigment { rgb 1 } } \
         sphere { 0, 2 pigment { rgbf 1 } } rotate <0, -15, 0> scale 0.7 translate 3*z }",
        "intersection { quartic { < 0,0,0,0,0,0,0,0,0,2, 0,0,-3,0,0,0,0,-3,0,0, \
         0,0,0,0,0,1,0,0,0,0, 0,0,1,0,0 > pigment { rgb 1 } } \
         sphere { 0, 10 pigment { rgbf 1 } } rotate <0, 50, 10> scale 0.15 translate 3*z }",
        // A torus behind a ball that filters its shadows: past the ball's
        // surfaces, every shape is offered again.
        "quartic { < 1,0,0,0,2,0,0,2,0,-104, 0,0,0,0,0,0,0,0,0,0, 1,0,0,2,0,56,0,0,0,0, \
         1,0,-104,0,784 > scale 0.2 rotate <-50, 20, 0> translate 3*z pigment { rgb 1 } } \
         sphere { <0.4, 0.3, 1.8>, 0.35 pigment { rgbf <1, 0.8, 0.6, 0.7> } }",
    ];
    for (i, body) in scenes.iter().enumerate() {
        let text = format!(
            "camera {{ location <0, 0, -3> angle 55 }}\n\
             light_source {{ <200, 30, -300> color rgb 1 }}\n\
             light_source {{ <-2, 3, 1> color rgb <1, 0.5, 0.2> }}\n\
             light_source {{ <-20, 0.1, 3> color rgb <0.2, 0.5, 1> }}\n{body}\n"
        );
        let path = write(&dir, &format!("lights{i}.pov"), &text);
        let options = sturmray::scene::LoadOptions {
            size: Some((96, 72)),
            ..sturmray::scene::LoadOptions::default()
        };
        let scene = Scene::load_with(&path, &options).unwrap();
        for spp in [1, 4] {
            let options = RenderOptions {
                threads: Some(2),
                spp: Some(spp),
                ..RenderOptions::default()
            };
            let image = |backend| {
                let accel = build(&scene, backend);
                render(&scene, &accel, &options)
                    .unwrap()
                    .film
                    .layers()
                    .beauty
            };
            let (a, b) = (image(Backend::Embree), image(Backend::Obvhs));
            assert!(a == b, "scene {i}, {spp} spp: the images differ");
        }
    }
}
