//! A scene file's material parameters given as images (issue 16 §1: "TOML
//! materials can use the same textures"): `albedo`, `specular`,
//! `roughness`, `metallic` and `radiance` each take `{ texture = "f.png" }`
//! and render exactly as the MTL map that drives the same parameter, in
//! both integrators; each map changes the image where it is bright and not
//! where it is dark; the bad forms are refused with their line.

mod common;

use common::{png_bytes, refused_scene, scratch, write};
use sturmray::accel::{Accel, Backend};
use sturmray::lights::Light;
use sturmray::render::{RenderOptions, render};
use sturmray::scene::Scene;

const WIDTH: usize = 32;
const HEIGHT: usize = 8;

/// The square [-1, 1]² at z = 0 with uv along x and y, its material the
/// scene's (`sq.obj`), and the same with `m` from `m.mtl` (`sqm.obj`).
const SQUARE: &str = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n\
                      vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";

/// A 64 × 1 grey PNG: black where u < 0.5, white beyond.
fn half_png() -> Vec<u8> {
    let data: Vec<u8> = (0..64).map(|x| if x < 32 { 0 } else { 255 }).collect();
    png_bytes(64, 1, png::ColorType::Grayscale, &data)
}

/// A scene looking straight down at the square through an orthographic
/// camera that sees x ∈ [-1, 1] across its width (u across the image), box
/// filtered so a pixel sees only its own column of u, lit by `light`; the
/// square's material is `[materials.m]`'s `material`, or the MTL's when
/// `material` is empty.
fn scene_text(integrator: &str, material: &str, light: &str) -> String {
    let (object, materials) = if material.is_empty() {
        ("file = \"sqm.obj\"\n".to_owned(), String::new())
    } else {
        (
            "file = \"sq.obj\"\nmaterial = \"m\"\n".to_owned(),
            format!("[materials.m]\n{material}\n"),
        )
    };
    let spp = if integrator == "path" { 16 } else { 4 };
    format!(
        "background = [0.2, 0.3, 0.4]\n\
         [camera]\ntype = \"orthographic\"\neye = [0, 0, 1.5]\nlook_at = [0, 0, 0]\n\
         view_width = 2\nwidth = {WIDTH}\nheight = {HEIGHT}\n\
         [render]\nspp = {spp}\nfilter = \"box\"\nintegrator = \"{integrator}\"\n\
         {materials}[[objects]]\ntype = \"mesh\"\n{object}{light}"
    )
}

/// The image of one scene, its lights and warnings.
fn image(dir: &std::path::Path, name: &str, text: &str) -> (Vec<[f32; 3]>, Scene) {
    let scene = Scene::load(&write(dir, &format!("{name}.toml"), text)).unwrap();
    assert!(scene.warnings.is_empty(), "{name}: {:?}", scene.warnings);
    let accel = Accel::build(&scene, Backend::Embree, None).unwrap();
    let options = RenderOptions {
        threads: Some(2),
        ..RenderOptions::default()
    };
    let film = render(&scene, &accel, &options).unwrap().film;
    (film.layers().beauty, scene)
}

/// The mean of the green channel over the dark half's columns (u < 0.5)
/// and the bright half's, away from the seam and the wrapping edges, where
/// bilinear filtering blends the halves.
fn halves(image: &[[f32; 3]]) -> (f64, f64) {
    let mean = |columns: std::ops::Range<usize>| {
        let n = (columns.len() * HEIGHT) as f64;
        let sum: f64 = (0..WIDTH * HEIGHT)
            .filter(|i| columns.contains(&(i % WIDTH)))
            .map(|i| f64::from(image[i][1]))
            .sum();
        sum / n
    };
    (mean(2..14), mean(18..30))
}

/// One parameter's case: the scene file's textured material, the MTL
/// material that maps the same parameter, the material at the map's dark
/// value and at its bright one, and the scene's light.
struct Case {
    name: &'static str,
    toml: &'static str,
    mtl: &'static str,
    dark: &'static str,
    bright: &'static str,
    light: &'static str,
}

/// A quad light over the whole square (above the camera, which would see
/// its back), so every point's mirror direction meets it.
const QUAD: &str = "[[lights]]\ntype = \"quad\"\ncorner = [-3, -3, 2]\nedge1 = [0, 6, 0]\n\
                    edge2 = [6, 0, 0]\nradiance = [1, 1, 1]\n";

/// A point light over the middle: a light from one direction, under which
/// a metal and its dielectric counterpart differ (under the quad's nearly
/// uniform light any two materials that keep energy look alike).
const POINT: &str = "[[lights]]\ntype = \"point\"\nposition = [0, 0, 2]\nintensity = [4, 4, 4]\n";

const CASES: [Case; 5] = [
    Case {
        name: "albedo",
        toml: "type = \"diffuse\"\nalbedo = { texture = \"half.png\" }",
        mtl: "Kd 0.3 0.3 0.3\nmap_Kd half.png",
        dark: "type = \"diffuse\"\nalbedo = [0, 0, 0]",
        bright: "type = \"diffuse\"\nalbedo = [1, 1, 1]",
        light: QUAD,
    },
    Case {
        name: "specular",
        toml: "type = \"plastic\"\nalbedo = [0.2, 0.2, 0.2]\nshininess = 20\n\
               specular = { texture = \"half.png\" }",
        mtl: "Kd 0.2 0.2 0.2\nKs 1 1 1\nNs 20\nillum 2\nmap_Ks half.png",
        dark: "type = \"plastic\"\nalbedo = [0.2, 0.2, 0.2]\nshininess = 20\nspecular = [0, 0, 0]",
        bright: "type = \"plastic\"\nalbedo = [0.2, 0.2, 0.2]\nshininess = 20\nspecular = [1, 1, 1]",
        light: QUAD,
    },
    Case {
        name: "roughness",
        toml: "type = \"metal\"\nalbedo = [0.9, 0.6, 0.3]\nroughness = { texture = \"half.png\" }",
        mtl: "Kd 0.9 0.6 0.3\nPm 1\nPr 1\nmap_Pr half.png",
        dark: "type = \"metal\"\nalbedo = [0.9, 0.6, 0.3]\nroughness = 0",
        bright: "type = \"metal\"\nalbedo = [0.9, 0.6, 0.3]\nroughness = 1",
        light: QUAD,
    },
    // Where the metalness map is dark the metal is its dielectric
    // counterpart, which no plain material of the scene file is: the dark
    // reference is the metal with a map black throughout.
    Case {
        name: "metallic",
        toml: "type = \"metal\"\nalbedo = [0.9, 0.6, 0.3]\nroughness = 0.4\n\
               metallic = { texture = \"half.png\" }",
        mtl: "Kd 0.9 0.6 0.3\nPm 1\nPr 0.4\nmap_Pm half.png",
        dark: "type = \"metal\"\nalbedo = [0.9, 0.6, 0.3]\nroughness = 0.4\n\
               metallic = { texture = \"black.png\" }",
        bright: "type = \"metal\"\nalbedo = [0.9, 0.6, 0.3]\nroughness = 0.4",
        light: POINT,
    },
    // The lamp alone in the dark, its black albedo reflecting nothing.
    Case {
        name: "radiance",
        toml: "type = \"emissive\"\nalbedo = [0, 0, 0]\nradiance = { texture = \"half.png\" }",
        mtl: "Kd 0 0 0\nKe 1 1 1\nmap_Ke half.png",
        dark: "type = \"emissive\"\nalbedo = [0, 0, 0]\nradiance = { texture = \"black.png\" }",
        bright: "type = \"emissive\"\nalbedo = [0, 0, 0]\nradiance = [1, 1, 1]",
        light: "",
    },
];

#[test]
fn each_parameters_texture_renders_as_its_mtl_map_and_changes_only_its_bright_half() {
    let dir = scratch("toml_maps");
    std::fs::write(dir.join("half.png"), half_png()).unwrap();
    let black = png_bytes(1, 1, png::ColorType::Grayscale, &[0]);
    std::fs::write(dir.join("black.png"), black).unwrap();
    write(&dir, "sq.obj", &format!("{SQUARE}f 1/1 2/2 3/3 4/4\n"));
    write(
        &dir,
        "sqm.obj",
        &format!("mtllib m.mtl\n{SQUARE}usemtl m\nf 1/1 2/2 3/3 4/4\n"),
    );
    for case in &CASES {
        write(&dir, "m.mtl", &format!("newmtl m\n{}\n", case.mtl));
        for integrator in ["whitted", "path"] {
            let what = format!("{} ({integrator})", case.name);
            let text = |material: &str| scene_text(integrator, material, case.light);
            let (textured, scene) = image(&dir, "textured", &text(case.toml));
            // The same values at every hit as the MTL's map gives, so the
            // same image to the bit: the same decoding, the same constant
            // (1, as a map without its constant), the same lights.
            let (mapped, _) = image(&dir, "mapped", &text(""));
            assert!(textured == mapped, "{what}: not the MTL map's image");
            let (dark, _) = image(&dir, "dark", &text(case.dark));
            let (bright, _) = image(&dir, "bright", &text(case.bright));
            let (t, d, b) = (halves(&textured), halves(&dark), halves(&bright));
            // The map's dark half looks like the dark material and its
            // bright half like the bright one. Not to the bit: bilinear
            // weights sum to 1 only up to rounding, so a value of 1 may be
            // 1 − 2⁻²⁴, which a path's random choices can amplify in a
            // pixel; 2% of a half's mean is far below the gap between the
            // two looks, checked next.
            let near = |a: f64, b: f64| (a - b).abs() <= 0.02 * a.abs().max(b.abs()) + 1e-6;
            assert!(near(t.0, d.0), "{what}: dark half {} for {}", t.0, d.0);
            assert!(near(t.1, b.1), "{what}: bright half {} for {}", t.1, b.1);
            // The two looks differ, so the comparisons above can fail.
            assert!(
                (d.1 - b.1).abs() > 0.1 * d.1.max(b.1),
                "{what}: {} and {} look alike",
                d.1,
                b.1
            );
            if case.name == "radiance" {
                // A textured lamp is a light sampled with its map, as
                // map_Ke's (lights::emission_map): each triangle carries it.
                let lamps: Vec<_> = (scene.lights.iter())
                    .filter_map(|l| match l {
                        Light::Triangle { map, .. } => Some(map.is_some()),
                        _ => None,
                    })
                    .collect();
                assert_eq!(lamps, [true, true], "{what}");
            }
        }
    }
}

/// Loads a one-material scene, expecting an error containing every part of
/// `expected`.
fn refused(material: &str, expected: &[&str]) {
    let dir = scratch("toml_maps_bad");
    write(&dir, "sq.obj", &format!("{SQUARE}f 1/1 2/2 3/3 4/4\n"));
    refused_scene(&dir, &scene_text("whitted", material, QUAD), expected);
}

#[test]
fn bad_texture_forms_are_refused_with_their_line() {
    // [materials.m] is line 13 of `scene_text`'s file; its keys follow.
    refused(
        "type = \"metal\"\nroughness = { textur = \"a.png\" }",
        &[
            "line 15",
            "unknown field `textur`",
            "did you mean `texture`?",
        ],
    );
    refused(
        "type = \"plastic\"\nspecular = { texture = 3 }",
        &["line 15", "expected a string"],
    );
    refused(
        "type = \"plastic\"\nspecular = \"a.png\"",
        &["line 15", "a colour [r, g, b] or a number or { texture"],
    );
    refused(
        "type = \"emissive\"\nradiance = { texture = \"a.png\", scale = 2 }",
        &["line 15", "unknown field `scale`"],
    );
    // A texture where the type has no parameter the map drives.
    refused(
        "type = \"plastic\"\nroughness = { texture = \"a.png\" }",
        &[
            "line 15",
            "materials.m.roughness",
            "type \"metal\" only, not \"plastic\"",
        ],
    );
    refused(
        "type = \"classic\"\nspecular = { texture = \"a.png\" }",
        &[
            "line 15",
            "materials.m.specular",
            "\"plastic\" or \"mirror\"",
        ],
    );
    refused(
        "type = \"diffuse\"\nradiance = { texture = \"a.png\" }",
        &["line 15", "materials.m.radiance", "\"emissive\" only"],
    );
    refused(
        "type = \"classic\"\nmetallic = { texture = \"a.png\" }",
        &["line 15", "materials.m.metallic", "\"metal\" only"],
    );
    refused(
        "type = \"metal\"\nmetallic = 0.5",
        &["line 15", "materials.m.metallic", "takes only a map"],
    );
}

#[test]
fn a_texture_that_cannot_be_read_warns_once_and_keeps_the_constant_one() {
    let dir = scratch("toml_maps_missing");
    write(&dir, "sq.obj", &format!("{SQUARE}f 1/1 2/2 3/3 4/4\n"));
    std::fs::create_dir(dir.join("folder.png")).unwrap();
    let mut text = scene_text(
        "whitted",
        "type = \"metal\"\nroughness = { texture = \"gone.png\" }\n\
         metallic = { texture = \"folder.png\" }",
        QUAD,
    );
    // Two more materials reading the same missing file, as data and as
    // colour: one warning for it.
    text += "[materials.n]\ntype = \"metal\"\nroughness = { texture = \"gone.png\" }\n\
             [materials.o]\ntype = \"plastic\"\nspecular = { texture = \"gone.png\" }\n";
    let scene = Scene::load(&write(&dir, "s.toml", &text)).unwrap();
    let warnings = scene.warnings.join("\n");
    assert_eq!(scene.warnings.len(), 2, "{warnings}");
    assert!(
        warnings.contains("line 15, materials.m.roughness.texture: texture")
            && warnings.contains("gone.png"),
        "{warnings}"
    );
    assert!(
        warnings.contains("materials.m.metallic.texture") && warnings.contains("folder.png"),
        "{warnings}"
    );
    // The neutral value: no map, the constant 1 a map alone would scale.
    let m = scene.materials.iter().find(|m| m.name == "m").unwrap();
    assert!(m.maps.is_empty(), "{:?}", m.maps);
    assert_eq!(m.roughness, 1.0);
}
