//! The environment light (`[environment]`): the white furnace (a white
//! diffuse sphere under a constant sky of radiance 1 is invisible), the sun
//! (a map black but for one small patch lights a plane as a directional light
//! of the same irradiance does), the same bytes for any thread count, and a
//! missing map refused with exit 2 naming it.

mod common;

use std::f32::consts::PI;
use std::path::Path;

use common::{scratch, sturmray, write};
use sturmray::accel::{Accel, Backend};
use sturmray::render::{RenderOptions, render};
use sturmray::scene::Scene;

/// The beauty layer, rendered on Embree with `threads`.
fn beauty(scene: &Scene, threads: usize) -> Vec<[f32; 3]> {
    let accel = Accel::build(scene, Backend::Embree, None).unwrap();
    let options = RenderOptions {
        threads: Some(threads),
        ..RenderOptions::default()
    };
    render(scene, &accel, &options)
        .unwrap()
        .film
        .layers()
        .beauty
}

fn mean(pixels: &[[f32; 3]]) -> f64 {
    let sum: f64 = pixels.iter().flatten().map(|&c| f64::from(c)).sum();
    sum / (3 * pixels.len()) as f64
}

#[test]
fn a_white_sphere_vanishes_in_the_white_furnace() {
    let dir = scratch("furnace");
    // The sphere fills the middle of the frame; its edge and the sky around it
    // must all be 1.
    let text = r#"
[camera]
eye = [0, 0, 4]
look_at = [0, 0, 0]
fov = 30
width = 16
height = 16
[render]
spp = 16
integrator = "path"
max_depth = 8
[environment]
radiance = [1, 1, 1]
[materials.white]
type = "diffuse"
albedo = [1, 1, 1]
[[objects]]
type = "sphere"
radius = 0.9
material = "white"
"#;
    let scene = Scene::load(&write(&dir, "furnace.toml", text)).unwrap();
    let pixels = beauty(&scene, 2);
    // The central 8 × 8 pixels see only the sphere, the corners only the sky.
    let sphere: Vec<[f32; 3]> = (4..12)
        .flat_map(|row| pixels[row * 16 + 4..row * 16 + 12].to_vec())
        .collect();
    assert_eq!(pixels[0], [1.0; 3]);
    assert_eq!(pixels[255], [1.0; 3]);
    // 16 samples a pixel: each pixel is within about 3% (one standard
    // deviation); the sphere's 1024 samples together within 0.4%, the
    // whole image's 4096 within 0.2%.
    let (all, sphere) = (mean(&pixels), mean(&sphere));
    assert!((all - 1.0).abs() < 0.01, "mean {all}");
    assert!((sphere - 1.0).abs() < 0.015, "sphere {sphere}");
}

/// The sky patch: rows 4..6 of 32 (θ from 22.5° to 33.75°), columns 10..12 of
/// 64 (φ from 56.25° to 67.5°), of radiance `L`.
const L: f32 = 40.0;
const ROWS: (u32, u32) = (4, 6);
const COLUMNS: (u32, u32) = (10, 12);

/// Writes the 64 × 32 map, black but for the patch, as Radiance HDR.
fn sun_map(dir: &Path) {
    let mut map = image::Rgb32FImage::new(64, 32);
    for (x, y, texel) in map.enumerate_pixels_mut() {
        if (ROWS.0..ROWS.1).contains(&y) && (COLUMNS.0..COLUMNS.1).contains(&x) {
            *texel = image::Rgb([L; 3]);
        }
    }
    map.save(dir.join("sun.hdr")).unwrap();
}

/// A grey plane y = 0 seen from straight above, lit by `light` (TOML).
fn plane(dir: &Path, name: &str, light: &str) -> Scene {
    write(
        dir,
        "plane.obj",
        "v -50 0 -50\nv -50 0 50\nv 50 0 50\nv 50 0 -50\nf 1 2 3 4\n",
    );
    let text = format!(
        r#"
[camera]
eye = [0, 5, 0]
look_at = [0, 0, 0]
up = [0, 0, -1]
fov = 20
width = 16
height = 16
[render]
spp = 16
integrator = "path"
max_depth = 3
[materials.grey]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]
[[objects]]
type = "mesh"
file = "plane.obj"
material = "grey"
{light}
"#
    );
    Scene::load(&write(dir, name, &text)).unwrap()
}

fn sun_scene(dir: &Path) -> Scene {
    sun_map(dir);
    plane(dir, "sky.toml", "[environment]\nfile = \"sun.hdr\"\n")
}

#[test]
fn a_small_bright_patch_lights_as_a_sun_of_the_same_irradiance() {
    let dir = scratch("sun");
    let sky = sun_scene(&dir);
    // The patch's irradiance on the upward plane: L ∫ cos θ dω over it,
    // L Δφ (sin² θ1 − sin² θ0) / 2, from the direction of its centre
    // (Mitsuba's map: (sin θ sin φ, cos θ, −sin θ cos φ)).
    let angle = |i: u32, n: u32, span: f32| span * i as f32 / n as f32;
    let (t0, t1) = (angle(ROWS.0, 32, PI), angle(ROWS.1, 32, PI));
    let (p0, p1) = (
        angle(COLUMNS.0, 64, 2.0 * PI),
        angle(COLUMNS.1, 64, 2.0 * PI),
    );
    let e = L * (p1 - p0) * (t1.sin().powi(2) - t0.sin().powi(2)) / 2.0;
    let (t, p) = ((t0 + t1) / 2.0, (p0 + p1) / 2.0);
    let towards = [t.sin() * p.sin(), t.cos(), -t.sin() * p.cos()];
    // A directional light's irradiance is on a surface facing it.
    let e_facing = e / t.cos();
    let sun = format!(
        "[[lights]]\ntype = \"directional\"\ndirection = [{}, {}, {}]\nirradiance = [{e_facing}, {e_facing}, {e_facing}]\n",
        -towards[0], -towards[1], -towards[2]
    );
    let sun = plane(&dir, "sun.toml", &sun);
    let (sky, sun) = (mean(&beauty(&sky, 2)), mean(&beauty(&sun, 2)));
    let exact = f64::from(0.5 / PI * e);
    // The directional light is noiseless; the patch's estimate, 4096
    // samples drawn by the map's density (all on the patch), is within 1%.
    assert!((sun - exact).abs() < 1e-3 * exact, "sun {sun} vs {exact}");
    assert!((sky - exact).abs() < 0.01 * exact, "sky {sky} vs {exact}");
}

#[test]
fn the_same_bytes_for_any_thread_count() {
    let dir = scratch("env-threads");
    let scene = sun_scene(&dir);
    let bits = |threads| -> Vec<u32> {
        let pixels = beauty(&scene, threads);
        pixels.iter().flatten().map(|c| c.to_bits()).collect()
    };
    let one = bits(1);
    assert_eq!(bits(2), one);
    assert_eq!(bits(3), one);
}

#[test]
fn the_environment_is_in_the_hash_and_scenes_without_one_keep_theirs() {
    let dir = scratch("env-hash");
    let sky = sun_scene(&dir);
    let turned = plane(
        &dir,
        "turned.toml",
        "[environment]\nfile = \"sun.hdr\"\nrotation = 90\n",
    );
    let constant = plane(
        &dir,
        "constant.toml",
        "[environment]\nradiance = [1, 1, 1]\n",
    );
    let none = plane(&dir, "none.toml", "");
    let hashes = [&sky, &turned, &constant, &none].map(Scene::content_hash);
    for (i, a) in hashes.iter().enumerate() {
        for b in &hashes[i + 1..] {
            assert_ne!(a, b);
        }
    }
    // Same scene, no environment: the hash of a scene written before there
    // were environments.
    let mut stripped = sky.clone();
    stripped.environment = None;
    assert_eq!(stripped.content_hash(), none.content_hash());
}

#[test]
fn a_missing_or_broken_map_exits_2_naming_it() {
    let dir = scratch("env-missing");
    let text =
        "[environment]\nfile = \"nowhere.exr\"\n[[objects]]\ntype = \"sphere\"\nradius = 1\n";
    write(&dir, "missing.toml", text);
    write(&dir, "broken.hdr", "#?RADIANCE\nnot really\n");
    write(
        &dir,
        "broken.toml",
        &text.replace("nowhere.exr", "broken.hdr"),
    );
    for (scene, file) in [
        ("missing.toml", "nowhere.exr"),
        ("broken.toml", "broken.hdr"),
    ] {
        let out = sturmray(&dir, &["info", scene]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(
            stderr.contains(file) && stderr.contains("environment.file"),
            "{stderr}"
        );
    }
    // Both a map and a constant, or neither: refused too.
    for body in ["file = \"x.hdr\"\nradiance = [1, 1, 1]", "scale = 2"] {
        let text = format!("[environment]\n{body}\n[[objects]]\ntype = \"sphere\"\nradius = 1\n");
        let err = Scene::load(&write(&dir, "both.toml", &text)).unwrap_err();
        assert!(err.to_string().contains("environment"), "{err}");
    }
}
