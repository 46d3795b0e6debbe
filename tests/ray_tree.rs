//! The ray tree and its plan: only the effects a scene calls for spawn rays,
//! and the specular branches give the radiance closed forms predict.

mod common;

use common::{SQUARE, scratch, write};
use sturmray::accel::{Accel, Backend};
use sturmray::math::Vec3;
use sturmray::render::{Plan, RayStats, RenderOptions, render};
use sturmray::scene::Scene;

/// A diffuse square lit straight down, seen from above, with `extra` objects
/// and materials appended.
fn scene(name: &str, extra: &str, light: bool) -> Scene {
    let dir = scratch(name);
    write(&dir, "square.obj", SQUARE);
    let light = if light {
        "[[lights]]\ntype = \"directional\"\ndirection = [0, 0, -1]\nirradiance = [2, 2, 2]\n"
    } else {
        ""
    };
    let text = format!(
        r#"background = [0.25, 0.5, 0.75]
[camera]
eye = [0, 0, 4]
look_at = [0, 0, 0]
fov = 40
width = 24
height = 24
[render]
spp = 1
max_depth = 8
[materials.paint]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]
[materials.chrome]
type = "mirror"
albedo = [0.9, 0.8, 0.7]
[materials.glass]
type = "dielectric"
ior = 1.5
[[objects]]
type = "mesh"
file = "square.obj"
material = "paint"
{extra}
{light}"#
    );
    Scene::load(&write(&dir, "s.toml", &text)).unwrap()
}

fn stats(scene: &Scene, all_effects: bool) -> (RayStats, Vec<[f32; 3]>) {
    let accel = Accel::build(scene, Backend::Embree, None).unwrap();
    let options = RenderOptions {
        threads: Some(2),
        all_effects,
        ..RenderOptions::default()
    };
    let out = render(scene, &accel, &options).unwrap();
    (out.stats, out.film.layers().beauty)
}

const MIRROR_SPHERE: &str = "[[objects]]\ntype = \"sphere\"\nradius = 0.5\nmaterial = \"chrome\"\ntransform = { translate = [0, 0, 1] }\n";
const GLASS_SPHERE: &str = "[[objects]]\ntype = \"sphere\"\nradius = 0.5\nmaterial = \"glass\"\ntransform = { translate = [0, 0, 1] }\n";

#[test]
fn a_diffuse_scene_spawns_no_specular_rays() {
    let s = scene("diffuse", "", true);
    let plan = Plan::for_scene(&s);
    assert!(
        plan.shadow && !plan.reflection && !plan.refraction,
        "{plan}"
    );
    let (st, _) = stats(&s, false);
    assert!(st.shadow > 0);
    assert_eq!(
        (st.reflection, st.refraction, st.diffuse, st.photon),
        (0, 0, 0, 0)
    );
}

#[test]
fn no_lights_no_shadow_rays() {
    let s = scene("dark", MIRROR_SPHERE, false);
    assert!(!Plan::for_scene(&s).shadow);
    let (st, _) = stats(&s, false);
    assert_eq!(st.shadow, 0);
    assert!(st.reflection > 0);
}

#[test]
fn mirrors_reflect_and_only_glass_refracts() {
    let (mirror, _) = stats(&scene("mirror", MIRROR_SPHERE, true), false);
    assert!(mirror.reflection > 0);
    assert_eq!(mirror.refraction, 0);
    let (glass, _) = stats(&scene("glass", GLASS_SPHERE, true), false);
    assert!(glass.reflection > 0 && glass.refraction > 0);
    // By depth: camera rays and their shadow rays at 0, the tree below them deeper,
    // and every ray counted once.
    assert!(glass.by_depth[0] >= glass.camera && glass.by_depth[1] > 0 && glass.by_depth[2] > 0);
    assert_eq!(glass.by_depth.iter().sum::<u64>(), glass.total());
}

#[test]
fn an_unused_material_calls_for_nothing() {
    // The file defines chrome and glass, but nothing uses them.
    let plan = Plan::for_scene(&scene("unused", "", true));
    assert!(!plan.reflection && !plan.refraction);
}

#[test]
fn forcing_every_effect_costs_rays_but_changes_no_pixel() {
    let s = scene("forced", "", true);
    let (planned, image) = stats(&s, false);
    let (forced, forced_image) = stats(&s, true);
    assert!(forced.reflection > 0 && forced.refraction > 0);
    assert_eq!(planned.camera, forced.camera);
    assert_eq!(image, forced_image);
}

#[test]
fn a_mirror_shows_what_it_faces_times_its_reflectance() {
    // A mirror square facing up at z = 0, seen from above: the camera sees the
    // background reflected, scaled by the mirror's reflectance, and nothing else.
    let s = scene("mirrorplane", "", false);
    let mut s = s;
    let chrome = s.materials.iter().position(|m| m.name == "chrome").unwrap() as u32;
    for m in &mut s.meshes[0].materials {
        *m = chrome;
    }
    let (st, image) = stats(&s, false);
    let centre = Vec3::from(image[12 * 24 + 12]);
    let expected = Vec3::new(0.9, 0.8, 0.7) * Vec3::new(0.25, 0.5, 0.75);
    assert!((centre - expected).abs().max_element() < 1e-6, "{centre}");
    assert!(st.reflection > 0);
}

#[test]
fn a_glass_sphere_in_a_uniform_environment_disappears() {
    // No lights, a uniform background: every branch of the tree ends in the
    // background, and Fresnel's reflected and refracted weights sum to one, so the
    // sphere has the background's radiance, less what the depth limit cuts off.
    let mut s = scene("furnace", GLASS_SPHERE, false);
    s.meshes.clear();
    s.render.max_depth = 40;
    s.render.min_weight = 0.0;
    let (_, image) = stats(&s, false);
    let background = Vec3::new(0.25, 0.5, 0.75);
    for p in image {
        let rel = ((Vec3::from(p) - background) / background)
            .abs()
            .max_element();
        assert!(rel < 2e-3, "{p:?}");
    }
}

/// Both samplers: each must pass the known answers.
const SAMPLERS: [&str; 2] = ["sobol", "independent"];

/// A uniform environment of radiance 1 around one sphere, no lights, path
/// traced with `sampler`.
fn furnace(name: &str, material: &str, spp: u32, sampler: &str) -> (RayStats, Vec<[f32; 3]>) {
    let dir = scratch(&format!("{name}-{sampler}"));
    let text = format!(
        r#"background = [1, 1, 1]
[camera]
eye = [0, 0, 4]
look_at = [0, 0, 0]
fov = 30
width = 16
height = 16
[render]
spp = {spp}
max_depth = 50
integrator = "path"
sampler = "{sampler}"
[materials.grey]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]
[materials.glass]
type = "dielectric"
ior = 1.5
[[objects]]
type = "sphere"
radius = 1
material = "{material}"
"#
    );
    let scene = Scene::load(&write(&dir, "s.toml", &text)).unwrap();
    stats(&scene, false)
}

#[test]
fn white_furnace_a_diffuse_sphere_renders_at_its_albedo() {
    // A convex sphere never sees itself: every bounce escapes to the environment,
    // so each sample is exactly albedo · 1 (cosine sampling's weight is the albedo).
    for sampler in SAMPLERS {
        let (st, image) = furnace("furnace-diffuse", "grey", 4, sampler);
        assert!(st.diffuse > 0 && st.shadow == 0, "{st:?}");
        // The sphere fills the central 8×8 pixels (it spans ±0.93 of the ±1.07 view);
        // pixels on its outline mix sphere and environment.
        for y in 4..12 {
            for x in 4..12 {
                let p = Vec3::from(image[y * 16 + x]);
                assert!(
                    (p - Vec3::splat(0.5)).abs().max_element() < 1e-6,
                    "{sampler} ({x}, {y}): {p}"
                );
            }
        }
        assert_eq!(image[0], [1.0; 3], "the corner sees the environment");
    }
}

#[test]
fn white_furnace_a_glass_sphere_disappears_under_path_tracing() {
    // Fresnel picks reflection or refraction; entering scales radiance by 1/η² and
    // leaving by η², so every path carries weight 1 back to the environment, except
    // where Russian roulette reweights long internal paths (unbiased, so the mean
    // stays 1; 64 samples per pixel keep it within 2%).
    for sampler in SAMPLERS {
        let (st, image) = furnace("furnace-glass", "glass", 64, sampler);
        assert!(st.refraction > 0);
        let mean: f32 = image.iter().map(|p| p[1]).sum::<f32>() / image.len() as f32;
        assert!((mean - 1.0).abs() < 0.02, "{sampler}: {mean}");
        for p in &image {
            assert!((p[1] - 1.0).abs() < 0.15, "{sampler}: {p:?}");
        }
    }
}

#[test]
fn whitted_scenes_bounce_no_diffuse_rays_and_path_scenes_do() {
    let s = scene("whitted-gi", "", true);
    assert!(!Plan::for_scene(&s).diffuse);
    let mut p = s.clone();
    p.render.integrator = sturmray::scene::Integrator::Path;
    assert!(Plan::for_scene(&p).diffuse);
    let (st, image) = stats(&p, false);
    assert!(st.diffuse > 0);
    // At the square's centre: the direct light, plus the background seen through
    // the cosine lobe (the square is flat, so every bounce escapes): albedo/π · E +
    // albedo · background, exactly, as cosine sampling's weight is the albedo.
    let expected = 0.5 / std::f32::consts::PI * 2.0 + 0.5 * 0.25;
    assert!(
        (image[12 * 24 + 12][0] - expected).abs() < 1e-6,
        "{:?}",
        image[12 * 24 + 12]
    );
}

/// The square under a light (TOML text, plus files it needs) about 1 above
/// its centre, seen from the side so the light does not hide the centre;
/// `integrator` whitted or path, with `sampler`. Returns the stats and the
/// mean of the four centre pixels (the image is 8×8; they see points within
/// 0.02 of the axis).
fn under_a_light(
    name: &str,
    (integrator, sampler): (&str, &str),
    light: &str,
    files: &[File],
) -> (RayStats, f32) {
    let dir = scratch(&format!("{name}-{integrator}-{sampler}"));
    write(&dir, "square.obj", SQUARE);
    for (file, text) in files {
        write(&dir, file, text);
    }
    let text = format!(
        r#"[camera]
eye = [2, 0, 3]
look_at = [0, 0, 0]
fov = 10
width = 8
height = 8
[render]
spp = 256
integrator = "{integrator}"
sampler = "{sampler}"
[materials.paint]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]
[[objects]]
type = "mesh"
file = "square.obj"
material = "paint"
{light}"#
    );
    let (st, image) = stats(&Scene::load(&write(&dir, "s.toml", &text)).unwrap(), false);
    let centre = [(3, 3), (4, 3), (3, 4), (4, 4)]
        .iter()
        .map(|&(x, y)| image[y * 8 + x][0])
        .sum::<f32>()
        / 4.0;
    (st, centre)
}

/// A file the scene needs: name and text.
type File<'a> = (&'a str, &'a str);

const QUAD_LIGHT: &str = r#"[[lights]]
type = "quad"
corner = [-0.25, -0.25, 1]
edge1 = [0, 0.5, 0]
edge2 = [0.5, 0, 0]
radiance = [4, 4, 4]
"#;

/// The same square of light as an OBJ panel with an emissive MTL material,
/// wound to face down (`down`) or up.
fn panel(down: bool) -> String {
    let face = if down { "f 1 2 3 4" } else { "f 4 3 2 1" };
    format!(
        "mtllib panel.mtl\nv -0.25 -0.25 1\nv -0.25 0.25 1\nv 0.25 0.25 1\nv 0.25 -0.25 1\n\
         usemtl glow\n{face}\n"
    )
}

const PANEL_MTL: &str = "newmtl glow\nKd 0 0 0\nKe 4 4 4\n";

const PANEL_OBJECT: &str = "[[objects]]\ntype = \"mesh\"\nfile = \"panel.obj\"\n";

#[test]
fn area_lights_give_the_form_factor_irradiance_once() {
    // On the light's axis at height 1, a square of half-side 0.25 gives, by the
    // closed form for rectangles (four quarters with a' = b' = 0.25),
    // E = 4 · L/2 · 2 · 0.25/√1.0625 · atan(0.25/√1.0625); the centre shows
    // albedo/π · E. The path tracer must agree: it reaches the light both by
    // light sampling and by bouncing, and MIS weights the two to sum to one.
    // The square comes as a TOML quad light and as an emissive OBJ panel.
    let k = 0.25 / 1.0625f32.sqrt();
    let e = 4.0 * 4.0 / 2.0 * 2.0 * k * k.atan();
    let expected = 0.5 / std::f32::consts::PI * e;
    let down = panel(true);
    let lights: [(&str, &str, &[File]); 2] = [
        ("quad", QUAD_LIGHT, &[]),
        (
            "panel",
            PANEL_OBJECT,
            &[("panel.obj", down.as_str()), ("panel.mtl", PANEL_MTL)],
        ),
    ];
    for (light, text, files) in lights {
        for integrator in ["whitted", "path"] {
            for sampler in SAMPLERS {
                let (st, centre) = under_a_light(light, (integrator, sampler), text, files);
                // 1024 one-point light samples: a few percent of noise at most.
                assert!(
                    (centre - expected).abs() < 0.03 * expected,
                    "{light} {integrator} {sampler}: {centre} vs {expected}"
                );
                assert!(st.shadow > 0);
            }
        }
    }
}

#[test]
fn an_emissive_sphere_is_a_sampled_light() {
    // A sphere of radius 0.4 centred 1 above the point gives E = π L (0.4/1)²
    // (a sphere light's closed form), so the centre shows albedo · L · 0.16. A
    // sphere this close fills a wide cone, so the path tracer's bounces hit it
    // often: the MIS weights of both strategies are far from 0 and 1.
    let sphere = "[materials.glow]\ntype = \"emissive\"\nradiance = [4, 4, 4]\n\
                  [[objects]]\ntype = \"sphere\"\nradius = 0.4\nmaterial = \"glow\"\n\
                  transform = { translate = [0, 0, 1] }\n";
    let expected = 0.5 * 4.0 * 0.16;
    for integrator in ["whitted", "path"] {
        for sampler in SAMPLERS {
            let (st, centre) = under_a_light("sphere", (integrator, sampler), sphere, &[]);
            assert!(
                (centre - expected).abs() < 0.03 * expected,
                "{integrator} {sampler}: {centre} vs {expected}"
            );
            assert!(st.shadow > 0, "the emissive sphere is sampled");
        }
    }
}

#[test]
fn area_lights_shine_from_their_front_only() {
    // The panel wound to face up lights nothing below it, by either strategy.
    let up = panel(false);
    for integrator in ["whitted", "path"] {
        let files = [("panel.obj", up.as_str()), ("panel.mtl", PANEL_MTL)];
        let (_, centre) = under_a_light("up", (integrator, "sobol"), PANEL_OBJECT, &files);
        assert_eq!(centre, 0.0, "{integrator}");
    }
}

#[test]
fn explain_gives_each_path_node_the_radiance_it_brings_back() {
    let dir = scratch("explain-path");
    write(&dir, "square.obj", SQUARE);
    let text = format!(
        "[camera]\neye = [2, 0, 3]\nlook_at = [0, 0, 0]\nfov = 10\nwidth = 8\nheight = 8\n\
         [render]\nspp = 4\nintegrator = \"path\"\n\
         [materials.paint]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n\
         [[objects]]\ntype = \"mesh\"\nfile = \"square.obj\"\nmaterial = \"paint\"\n{QUAD_LIGHT}"
    );
    let scene = Scene::load(&write(&dir, "s.toml", &text)).unwrap();
    let accel = Accel::build(&scene, Backend::Embree, Some(1)).unwrap();
    let mut bounced = 0;
    for k in 0..4 {
        let (sample, _, tree) =
            sturmray::render::explain(&scene, &accel, (4, 4), k, false).unwrap();
        // The camera ray brings back the whole sample: its weight is 1.
        let camera = Vec3::from(tree[0].radiance);
        assert!(
            (camera - sample.radiance).abs().max_element() <= 1e-5 * sample.radiance.max_element(),
            "{camera} vs {}",
            sample.radiance
        );
        assert!(sample.radiance.x > 0.0, "the square is lit");
        // Every later node carries its own weight and what it brings back, so
        // radiance × weight never exceeds what the node above it brought back.
        for pair in tree.windows(2) {
            let (above, below) = (Vec3::from(pair[0].radiance), &pair[1]);
            let carried = Vec3::from(below.radiance) * Vec3::from(below.weight);
            assert!(
                carried
                    .cmple(above * Vec3::from(pair[0].weight) * (1.0 + 1e-5))
                    .all(),
                "{tree:?}"
            );
        }
        bounced += tree.len() - 1;
    }
    assert!(bounced > 0, "the path tracer bounces off the square");
}

#[test]
fn adaptive_sampling_spends_samples_on_edges_only() {
    // The square seen from above fills the middle of the image; with a
    // directional light every sample inside it (or outside, on the background)
    // agrees, and only pixels on its outline disagree.
    let mut s = scene("adaptive", "", true);
    s.render.spp = 4;
    s.render.adaptive = Some(sturmray::scene::Adaptive {
        max_spp: 32,
        threshold: 0.01,
    });
    let accel = Accel::build(&s, Backend::Embree, None).unwrap();
    let out = render(&s, &accel, &RenderOptions::default()).unwrap();
    let counts: Vec<u32> = out.film.pixels.iter().map(|p| p.samples).collect();
    assert!(counts.iter().all(|&n| n % 4 == 0 && (4..=32).contains(&n)));
    let (corner, centre) = (counts[0], counts[12 * 24 + 12]);
    assert_eq!((corner, centre), (4, 4), "flat regions keep the base count");
    let most = *counts.iter().max().unwrap();
    assert_eq!(most, 32, "the outline takes the most");
    let edges = counts.iter().filter(|&&n| n > 4).count();
    assert!(
        edges > 0 && edges < counts.len() / 2,
        "{edges} of {}",
        counts.len()
    );
    assert_eq!(
        out.stats.camera,
        counts.iter().map(|&n| u64::from(n)).sum::<u64>()
    );
}
