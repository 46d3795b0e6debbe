//! POV-Ray's fog, read from a `.pov` scene, in both integrators: a ray that
//! meets nothing sees the fog's colour alone (a constant fog lets nothing
//! through from infinitely far), one that meets a surface sees it through
//! the fog, and the plan names the fog only where a scene has one. And what
//! lies between a POV-Ray light and a surface: the fog dims a light with
//! `media_attenuation`, and a `shadowless` light casts no shadow.

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

/// A wall 10 units in front of the camera (ambient 0, diffuse 1), lit by a
/// light at the camera, in a black fog of distance 10, with the light's
/// `extra` keywords and `more` in the scene.
fn lit_wall(name: &str, extra: &str, more: &str) -> Scene {
    pov_scene(
        name,
        &format!(
            "background {{ color rgb 0 }}\n\
             plane {{ -z, -5 pigment {{ color rgb 0.5 }} finish {{ ambient 0 diffuse 1 }} }}\n\
             fog {{ distance 10 color rgb 0 }}\n\
             light_source {{ <0, 0, -5> color rgb 1 {extra} }}\n{more}"
        ),
    )
}

#[test]
fn a_light_with_media_attenuation_is_dimmed_by_the_fog_on_its_way() {
    // The light's way back from the wall is the camera ray's: 10 long on
    // the axis, 10 / cos 6.24° = 10.06 at the corners (angle 10 across,
    // 4:3). With `media_attenuation` the wall gets exp(-length / 10) of the
    // light, between exp(-1.006) and exp(-1) (the shadow ray stops 1e-4
    // short of the light, hence the margin above), and without it all of
    // it (the camera ray's fog is the same in both). `media_interaction
    // off` turns the attenuation off again, as in POV-Ray, where it needs
    // both.
    let plain = lit_wall("fog-light-plain", "", "");
    let dimmed = lit_wall("fog-light-dimmed", "media_attenuation on", "");
    let off = lit_wall(
        "fog-light-off",
        "media_attenuation media_interaction off",
        "",
    );
    let (low, high) = ((-1.0065f32).exp(), (-1.0f32).exp() * (1.0 + 2e-4));
    for integrator in [Integrator::Whitted, Integrator::Path] {
        let (plain, dimmed, off) = (
            image(&plain, integrator),
            image(&dimmed, integrator),
            image(&off, integrator),
        );
        for ((p, d), o) in plain.iter().zip(&dimmed).zip(&off) {
            assert!(p[0] > 0.01, "{integrator:?}: the wall is lit: {p:?}");
            let ratio = d[0] / p[0];
            assert!(low < ratio && ratio < high, "{integrator:?}: {ratio}");
            assert_eq!(o, p, "{integrator:?}");
        }
    }
}

#[test]
fn a_shadowless_light_casts_no_shadow() {
    // A sphere behind the camera, between the wall and a light 25 units
    // from it, shades every pixel's point on the wall: a shadowless light
    // lights the wall as if the sphere were not there.
    let blocker = "sphere { <0, 0, -10>, 2 pigment { color rgb 1 } }";
    let light = "light_source { <0, 0, -20> color rgb 1 shadowless }";
    let open = image(
        &lit_wall("shadowless-open", "shadowless", light),
        Integrator::Whitted,
    );
    let behind = image(
        &lit_wall(
            "shadowless-behind",
            "shadowless",
            &format!("{light}\n{blocker}"),
        ),
        Integrator::Whitted,
    );
    let shadowed = image(
        &lit_wall(
            "shadowless-not",
            "shadowless",
            &format!("light_source {{ <0, 0, -20> color rgb 1 }}\n{blocker}"),
        ),
        Integrator::Whitted,
    );
    for ((o, b), s) in open.iter().zip(&behind).zip(&shadowed) {
        assert_eq!(o, b);
        // The light at the camera alone (both are shadowless there).
        assert!(s[0] < 0.75 * o[0], "{s:?} vs {o:?}");
    }
}
