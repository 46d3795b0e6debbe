//! The classic material (POV-Ray's finish) in both integrators: the Whitted
//! tree's branches carry its fractions, the path tracer conserves energy in
//! a white furnace, the plan asks only for the rays a finish calls for, and
//! bad values are refused with the line and key.

mod common;

use common::{SQUARE, scratch, write};
use sturmray::accel::{Accel, Backend};
use sturmray::render::{Plan, RayStats, RenderOptions, render};
use sturmray::scene::Scene;

const SPHERE: &str = "type = \"sphere\"\nradius = 1";
/// The square [-1, 1]² in z = 0, facing the camera.
const PLANE: &str = "type = \"mesh\"\nfile = \"square.obj\"";
/// A light along the view axis, for the plan and forced-branch tests.
const LIGHT: &str =
    "[[lights]]\ntype = \"directional\"\ndirection = [0, 0, -1]\nirradiance = [1, 1, 1]";

/// A unit sphere of the classic material `finish` (TOML keys) at the origin,
/// seen from z = 4 through a 1° field of view in front of a background of
/// radiance 1.
fn sphere_scene(name: &str, finish: &str, extra: &str) -> Scene {
    scene(name, finish, SPHERE, 1.0, extra)
}

/// An object (`shape`, its TOML keys) of the classic material `finish` at the
/// origin, seen from z = 4 through a field of view of `fov` degrees.
fn scene(name: &str, finish: &str, shape: &str, fov: f32, extra: &str) -> Scene {
    let dir = scratch(name);
    write(&dir, "square.obj", SQUARE);
    let text = format!(
        r#"background = [1, 1, 1]
[camera]
eye = [0, 0, 4]
look_at = [0, 0, 0]
fov = {fov}
width = 8
height = 8
[render]
spp = 1
max_depth = 8
min_weight = 0
[materials.finish]
type = "classic"
{finish}
[[objects]]
{shape}
material = "finish"
{extra}"#
    );
    Scene::load(&write(&dir, "s.toml", &text)).unwrap()
}

fn run(scene: &Scene) -> (RayStats, Vec<[f32; 3]>) {
    let accel = Accel::build(scene, Backend::Embree, None).unwrap();
    let options = RenderOptions {
        threads: Some(2),
        ..RenderOptions::default()
    };
    let out = render(scene, &accel, &options).unwrap();
    (out.stats, out.film.layers().beauty)
}

/// Every pixel equals `expected` in every channel, within `tol`.
fn all_pixels(image: &[[f32; 3]], expected: [f32; 3], tol: f32) {
    for p in image {
        for c in 0..3 {
            assert!((p[c] - expected[c]).abs() <= tol, "{p:?} vs {expected:?}");
        }
    }
}

#[test]
fn half_a_mirror_in_a_white_world_is_half_white() {
    // No lights and no ambient: the diffuse part gets nothing, and the
    // reflected branch (weight 0.5) sees the background (1) from the convex
    // sphere: 0.5 exactly.
    let s = sphere_scene("half", "reflection = 0.5", "");
    let plan = Plan::for_scene(&s);
    assert!(
        plan.reflection && !plan.refraction && !plan.shadow,
        "{plan}"
    );
    let (stats, image) = run(&s);
    all_pixels(&image, [0.5; 3], 1e-6);
    assert_eq!(stats.reflection, stats.camera);
}

#[test]
fn fresnel_reflection_head_on_is_the_normal_reflectance() {
    // reflection { 0, 1 fresnel on } with ior 1.5 head-on: ((1.5 − 1)/(1.5 + 1))²
    // = 0.04. The plane is met within 0.05° of normal incidence, where F
    // differs from 0.04 by < 1e-7.
    let s = scene(
        "fresnel",
        "reflection = 0\nreflection_max = 1\nfresnel = true\nior = 1.5\ndiffuse = 0",
        PLANE,
        0.1,
        "",
    );
    let (_, image) = run(&s);
    all_pixels(&image, [0.04; 3], 1e-6);
}

#[test]
fn transmitted_light_crosses_twice_whatever_the_ior() {
    // transmit = 0.5 and nothing else: the ray enters (0.5) and leaves the
    // sphere (0.5 again) and sees the uniform background: 0.25, bent or not.
    // No ray inside a sphere meets the critical angle, so no branch reflects.
    for ior in ["1", "1.5"] {
        let s = sphere_scene(
            &format!("transmit-{ior}"),
            &format!("transmit = 0.5\ndiffuse = 0\nior = {ior}"),
            "",
        );
        let plan = Plan::for_scene(&s);
        assert!(plan.refraction && !plan.shadow, "{plan}");
        assert_eq!(plan.reflection, ior != "1", "{plan}");
        let (stats, image) = run(&s);
        all_pixels(&image, [0.25; 3], 1e-6);
        assert_eq!(stats.refraction, 2 * stats.camera);
        assert_eq!(stats.reflection, 0);
    }
}

#[test]
fn local_shading_is_povrays_per_light_sum() {
    // A directional light of irradiance π straight down the view axis is one
    // of POV-Ray's unit lights: head-on, radiance = diffuse·pigment + specular
    // + phong (n·h = r·l = 1), the highlights tinted by metallic.
    let light = "[[lights]]\ntype = \"directional\"\ndirection = [0, 0, -1]\n\
                 irradiance = [3.14159265, 3.14159265, 3.14159265]";
    let finish =
        "albedo = [0.5, 0.25, 1]\ndiffuse = 0.6\nspecular = 0.3\nphong = 0.2\nambient = 0.1";
    let s = scene("local", finish, PLANE, 0.1, light);
    assert!(Plan::for_scene(&s).shadow);
    let (_, image) = run(&s);
    let expect = |c: f32, tint: f32| 0.6 * c + 0.5 * tint + 0.1 * c;
    // The plane's normal is the light's direction; the view rays are within
    // θ = 0.05° (8.7e-4 rad) of it, so n·h = cos(θ/2) and r·l = cos θ, and
    // 0.3(1 − cos^20(θ/2)) + 0.2(1 − cos^40 θ) < 4e-6; π in f32 adds 1e-7.
    let tol = 1e-5;
    all_pixels(
        &image,
        [expect(0.5, 1.0), expect(0.25, 1.0), expect(1.0, 1.0)],
        tol,
    );
    let s = scene(
        "metallic",
        &format!("{finish}\nmetallic = true"),
        PLANE,
        0.1,
        light,
    );
    let (_, image) = run(&s);
    all_pixels(
        &image,
        [expect(0.5, 0.5), expect(0.25, 0.25), expect(1.0, 1.0)],
        tol,
    );
}

#[test]
fn brilliance_raises_the_cosine_at_the_light_to_its_power() {
    // POV-Ray's unit light (irradiance π) at cos θ = 0.6 to the plane's
    // normal: diffuse light 0.6^brilliance, Lambert's 0.6 at brilliance 1.
    let light = "[[lights]]\ntype = \"directional\"\ndirection = [-0.8, 0, -0.6]\n\
                 irradiance = [3.14159265, 3.14159265, 3.14159265]";
    for brilliance in [0.5f32, 1.0, 3.0] {
        let finish = format!("albedo = [1, 1, 1]\ndiffuse = 1\nbrilliance = {brilliance}");
        let s = scene("brilliance", &finish, PLANE, 0.1, light);
        let (_, image) = run(&s);
        // f32 cosines and π: within a few units in the last place.
        all_pixels(&image, [0.6f32.powf(brilliance); 3], 2e-6);
    }
}

/// The path-traced sphere of `finish` in the white furnace (background 1):
/// the mean over the pixels of 64 paths each, and its standard error.
fn furnace(name: &str, finish: &str) -> (f64, f64) {
    let mut s = sphere_scene(name, finish, "");
    s.render.integrator = sturmray::scene::Integrator::Path;
    s.render.spp = 64;
    let (_, image) = run(&s);
    let pixels = image.len() as f64;
    let mean = image.iter().map(|p| f64::from(p[0])).sum::<f64>() / pixels;
    let var = image
        .iter()
        .map(|p| (f64::from(p[0]) - mean).powi(2))
        .sum::<f64>()
        / pixels;
    let se = (var / pixels).sqrt();
    eprintln!(
        "{name}: mean {mean:.4} ± {se:.4} over {} paths",
        pixels * 64.0
    );
    (mean, se)
}

#[test]
fn the_path_tracer_never_gains_energy_in_a_white_furnace() {
    // White pigment, every part at its top: the layered BSDF returns at most
    // what it receives. Delta lobes only (reflection + transmit = 1) lose
    // nothing but what the depth limit cuts.
    for (name, finish, low) in [
        (
            "furnace-all",
            "diffuse = 1\nspecular = 1\nphong = 1\nreflection = 0.2\ntransmit = 0.3\nior = 1.5",
            0.5,
        ),
        (
            "furnace-delta",
            "diffuse = 0\nreflection = 0.4\ntransmit = 0.6\nior = 1.5",
            0.97,
        ),
    ] {
        let (mean, se) = furnace(name, &format!("albedo = [1, 1, 1]\n{finish}"));
        assert!(mean <= 1.0 + 4.0 * se + 1e-6, "{name}: {mean} ± {se}");
        assert!(mean >= low, "{name}: {mean} ± {se}");
    }
}

#[test]
fn fractions_that_fit_keep_their_values_in_the_path_tracer() {
    // diffuse 0.6 × pigment 0.7 + reflection 0.5 = 0.92 ≤ 1: nothing is
    // scaled, and the convex sphere's every bounce sees the background, so
    // the furnace shows 0.42 + 0.5.
    let (mean, se) = furnace("fits", "albedo = [0.7, 0.7, 0.7]\nreflection = 0.5");
    assert!((mean - 0.92).abs() <= 4.0 * se + 1e-6, "{mean} ± {se}");
}

#[test]
fn bad_finish_values_name_the_line_and_key() {
    let dir = scratch("classic-bad");
    for (body, key) in [
        ("reflection = 1.5", "materials.finish.reflection"),
        ("transmit = -0.1", "materials.finish.transmit"),
        ("phong_size = 0", "materials.finish.phong_size"),
        ("roughness = 0", "materials.finish.roughness"),
        ("brilliance = 0", "materials.finish.brilliance"),
        ("metallic = 2", "materials.finish.metallic"),
        ("specular = [1, 1, 1]", "materials.finish.specular"),
        ("shininess = 20", "materials.finish.shininess"),
    ] {
        let text = format!(
            "[camera]\neye = [0, 0, 4]\nlook_at = [0, 0, 0]\nfov = 40\nwidth = 4\nheight = 4\n\
             [materials.finish]\ntype = \"classic\"\n{body}\n"
        );
        let err = Scene::load(&write(&dir, "s.toml", &text))
            .unwrap_err()
            .to_string();
        assert!(err.contains("line 9") && err.contains(key), "{body}: {err}");
    }
    // The finish keys belong to the classic type alone.
    let text = "[camera]\neye = [0, 0, 4]\nlook_at = [0, 0, 0]\nfov = 40\nwidth = 4\nheight = 4\n\
                [materials.paint]\ntype = \"diffuse\"\nreflection = 0.5\n";
    let err = Scene::load(&write(&dir, "s.toml", text))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("line 9")
            && err.contains("materials.paint.reflection")
            && err.contains("classic"),
        "{err}"
    );
}

#[test]
fn the_plan_traces_only_what_a_finish_calls_for() {
    // POV-Ray's default finish (diffuse 0.6) under a light: shadow rays, and
    // no reflected or refracted ray at all.
    let s = sphere_scene("plain", "", LIGHT);
    let plan = Plan::for_scene(&s);
    assert!(
        plan.shadow && !plan.reflection && !plan.refraction,
        "{plan}"
    );
    let (stats, _) = run(&s);
    assert!(stats.shadow > 0);
    assert_eq!((stats.reflection, stats.refraction), (0, 0));
    // A pure mirror finish needs no shadow rays, even with a light.
    let s = sphere_scene("mirror-only", "diffuse = 0\nreflection = 1", LIGHT);
    let plan = Plan::for_scene(&s);
    assert!(
        !plan.shadow && plan.reflection && !plan.refraction,
        "{plan}"
    );
    // `sturmray info` prints the plan.
    let dir = scratch("classic-info");
    write(&dir, "square.obj", SQUARE);
    let text = format!(
        "[camera]\neye = [0, 0, 4]\nlook_at = [0, 0, 0]\nfov = 40\nwidth = 4\nheight = 4\n\
         [materials.glass]\ntype = \"classic\"\ndiffuse = 0\ntransmit = 0.9\nior = 1.5\n\
         [[objects]]\n{SPHERE}\nmaterial = \"glass\"\n"
    );
    write(&dir, "s.toml", &text);
    let out = common::sturmray(&dir, &["info", "s.toml"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("shadow rays no, reflection rays yes, refraction rays yes"),
        "{stdout}"
    );
}

#[test]
fn shadows_through_a_transparent_surface_are_filtered_at_each_face() {
    // The square at z = 0 (the default finish) lit along (−1, 0, −1); a
    // ball of transmit 0.5 at (2, 0, 2) stands between its centre, which the
    // 1° camera sees, and the light. As in POV-Ray, the shadow ray crosses
    // both of the ball's faces, each letting half through: a quarter of the
    // light, where it had been a full shadow. An opaque ball still casts one.
    let light = "[[lights]]\ntype = \"directional\"\ndirection = [-1, 0, -1]\n\
                 irradiance = [1, 1, 1]";
    let ball = |transmit: f32| {
        format!(
            "[materials.ball]\ntype = \"classic\"\ndiffuse = 0\ntransmit = {transmit}\n\
             [[objects]]\n{SPHERE}\nmaterial = \"ball\"\n\
             transform = {{ translate = [2, 0, 2] }}\n{light}"
        )
    };
    let lit = |extra: &str, name: &str| {
        let s = scene(name, "", PLANE, 1.0, extra);
        let (_, image) = run(&s);
        (Plan::for_scene(&s), image[image.len() / 2 + 4][0])
    };
    let (_, open) = lit(light, "filter-open");
    let (plan, glass) = lit(&ball(0.5), "filter-glass");
    let (opaque_plan, opaque) = lit(&ball(0.0), "filter-opaque");
    assert!(open > 0.05, "{open}");
    assert!(plan.filtered_shadows && !opaque_plan.filtered_shadows);
    assert!(
        (glass / open - 0.25).abs() < 1e-4,
        "{glass} of {open}: {}",
        glass / open
    );
    assert_eq!(opaque, 0.0);
    assert!(
        plan.to_string()
            .contains("shadow rays yes (filtered by transparent surfaces)")
    );
}

#[test]
fn forcing_every_branch_changes_no_classic_pixel() {
    let s = sphere_scene("forced", "reflection = 0.5\nspecular = 0.5", LIGHT);
    let (planned, image) = run(&s);
    let accel = Accel::build(&s, Backend::Embree, None).unwrap();
    let options = RenderOptions {
        threads: Some(2),
        all_effects: true,
        ..RenderOptions::default()
    };
    let out = render(&s, &accel, &options).unwrap();
    assert!(out.stats.refraction > 0 && planned.refraction == 0);
    assert_eq!(image, out.film.layers().beauty);
}

#[test]
fn total_internal_reflection_sends_the_light_back() {
    // The eye inside a unit sphere at (0, 0, 0.9), looking along +x: every
    // ray's line passes 0.9 (±0.01 over the 1° view) from the centre, so it
    // meets the surface from inside at sin θ = 0.9, θ = 64°. With ior 1.5
    // the critical angle is asin(1/1.5) = 41.8°: the light turns wholly
    // into reflection, and the chord keeps its angle, so the ray stays
    // trapped until the depth limit and brings back nothing. With ior 1.1
    // (critical angle 65.4°) it leaves and sees the background: 1.
    for (ior, expected) in [("1.5", 0.0), ("1.1", 1.0)] {
        let dir = scratch(&format!("tir-{ior}"));
        let text = format!(
            "background = [1, 1, 1]\n[camera]\neye = [0, 0, 0.9]\nlook_at = [1, 0, 0.9]\n\
             fov = 1\nwidth = 4\nheight = 4\n[render]\nspp = 1\nmax_depth = 8\nmin_weight = 0\n\
             [materials.glass]\ntype = \"classic\"\ndiffuse = 0\ntransmit = 1\nior = {ior}\n\
             [[objects]]\n{SPHERE}\nmaterial = \"glass\"\n"
        );
        let s = Scene::load(&write(&dir, "s.toml", &text)).unwrap();
        let (stats, image) = run(&s);
        all_pixels(&image, [expected; 3], 1e-6);
        if expected == 0.0 {
            assert_eq!(stats.refraction, 0);
            assert_eq!(stats.reflection, 8 * stats.camera);
        } else {
            assert_eq!(stats.refraction, stats.camera);
        }
    }
}

#[test]
fn total_internal_reflection_carries_all_the_light_as_povray_s_does() {
    // The square seen from behind (its inside) at 71.6° from its normal,
    // past the critical angle of ior 1.5: POV-Ray 3.7 traces the mirrored
    // ray with all of the light, neither filtered by transmit 0.5 nor
    // joined by the surface's own reflection 0.2, so the background (1)
    // comes back whole; adding the two fractions gave 0.7.
    let dir = scratch("tir-whole");
    write(&dir, "square.obj", SQUARE);
    let text = format!(
        "background = [1, 1, 1]\n[camera]\neye = [0, -3, -1]\nlook_at = [0, 0, 0]\n\
         fov = 1\nwidth = 4\nheight = 4\n[render]\nspp = 1\nmax_depth = 4\nmin_weight = 0\n\
         [materials.glass]\ntype = \"classic\"\ndiffuse = 0\ntransmit = 0.5\n\
         reflection = 0.2\nior = 1.5\n[[objects]]\n{PLANE}\nmaterial = \"glass\"\n"
    );
    let s = Scene::load(&write(&dir, "s.toml", &text)).unwrap();
    let (stats, image) = run(&s);
    all_pixels(&image, [1.0; 3], 1e-6);
    assert_eq!(stats.refraction, 0);
    assert_eq!(stats.reflection, stats.camera);
}

#[test]
fn a_value_of_the_wrong_kind_says_what_was_expected() {
    let dir = scratch("classic-kind");
    for (body, expected) in [
        ("metallic = \"yes\"", "true, false or a number from 0 to 1"),
        ("specular = \"shiny\"", "a colour [r, g, b] or a number"),
    ] {
        let text = format!(
            "[camera]\neye = [0, 0, 4]\nlook_at = [0, 0, 0]\nfov = 40\nwidth = 4\nheight = 4\n\
             [materials.finish]\ntype = \"classic\"\n{body}\n"
        );
        let err = Scene::load(&write(&dir, "s.toml", &text))
            .unwrap_err()
            .to_string();
        assert!(
            err.contains(expected) && err.contains("line 9"),
            "{body}: {err}"
        );
    }
}
