//! POV-Ray's fog, read from a `.pov` scene, in both integrators: a ray that
//! meets nothing sees the fog's colour alone (a constant fog lets nothing
//! through from infinitely far), one that meets a surface sees it through
//! the fog, and the plan names the fog only where a scene has one.

mod common;

use common::{beauty, scratch, write};
use sturmray::accel::Backend;
use sturmray::render::Plan;
use sturmray::scene::{Integrator, LoadOptions, Scene};

/// A scene of `body` under a camera looking along +z, 8x6 pixels.
fn pov_scene(name: &str, body: &str) -> Scene {
    let dir = scratch(name);
    let text = format!(
        "#version 3.7;\nglobal_settings {{ assumed_gamma 1.0 }}\n\
         camera {{ location <0, 0, -5> look_at 0 angle 10 }}\n\
         background {{ color rgb <0.2, 0.3, 0.6> }}\n{body}"
    );
    let options = LoadOptions {
        size: Some((8, 6)),
        ..LoadOptions::default()
    };
    Scene::load_with(&write(&dir, "s.pov", &text), &options).unwrap()
}

/// The scene's beauty layer by `integrator`, 4 samples a pixel.
fn image(scene: &Scene, integrator: Integrator) -> Vec<[f32; 3]> {
    let mut scene = scene.clone();
    scene.render.integrator = integrator;
    scene.render.spp = 4;
    beauty(&scene, Backend::Embree)
}

#[test]
fn a_ray_that_meets_nothing_sees_the_fog_alone_in_both_integrators() {
    let scene = pov_scene("fog-sky", "fog { distance 10 color rgb <0.9, 0.8, 0.7> }");
    assert!(Plan::for_scene(&scene).fog);
    assert!(Plan::for_scene(&scene).to_string().ends_with(", fog yes"));
    for integrator in [Integrator::Whitted, Integrator::Path] {
        for p in image(&scene, integrator) {
            for (c, want) in p.iter().zip([0.9, 0.8, 0.7]) {
                assert!((c - want).abs() < 1e-6, "{integrator:?}: {p:?}");
            }
        }
    }
    // Without a fog, the background; and the plan does not mention fog.
    let clear = pov_scene("fog-none", "");
    assert!(!Plan::for_scene(&clear).fog);
    assert!(!Plan::for_scene(&clear).to_string().contains("fog"));
}

#[test]
fn a_surface_is_seen_through_the_fog_by_its_distance() {
    // A wall of ambient 1 (the glow of its pigment, 0.5) 10 units off, the
    // camera on its outside, in a fog of distance 10 and colour 1: exp(-1)
    // of the wall and 1 - exp(-1) of the fog. The rays are within 5° of
    // the axis, so their way is at most 10 / cos 5° = 10.04 long: within
    // 0.2% of exp(-1).
    let scene = pov_scene(
        "fog-wall",
        "plane { -z, -5 pigment { color rgb 0.5 } finish { ambient 1 diffuse 0 } }\n\
         fog { distance 10 color rgb 1 }",
    );
    let a = (-1.0f32).exp();
    let want = 0.5 * a + (1.0 - a);
    for p in image(&scene, Integrator::Whitted) {
        assert!((p[0] - want).abs() < 2e-3, "{p:?} vs {want}");
    }
    // Seen from the wall's inside (the camera behind the plane), the way
    // is not through the air: no fog, as in POV-Ray.
    let inside = pov_scene(
        "fog-inside",
        "plane { z, 5 pigment { color rgb 0.5 } finish { ambient 1 diffuse 0 } }\n\
         fog { distance 10 color rgb 1 }",
    );
    for p in image(&inside, Integrator::Whitted) {
        assert!((p[0] - 0.5).abs() < 1e-6, "{p:?}");
    }
}
