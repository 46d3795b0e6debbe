//! POV-Ray's checker as a material's albedo: a checkered floor seen from
//! above shows each cube's colour, shaded as that plain colour would be, in
//! both integrators and in the albedo AOV; the same for any thread count; and
//! bad values in `albedo = { checker … }` are refused with the line and key.

mod common;

use common::{refused_scene, scratch, write};
use sturmray::accel::{Accel, Backend};
use sturmray::render::{RenderOptions, render};
use sturmray::scene::Scene;

const A: [f32; 3] = [0.8, 0.2, 0.1];
const B: [f32; 3] = [0.1, 0.3, 0.9];

/// The square [-3, 3]² of the plane y = −1 (a cube face of the pattern).
const FLOOR: &str = "v -3 -1 -3\nv -3 -1 3\nv 3 -1 3\nv 3 -1 -3\nf 1 2 3 4\n";

/// The floor with the classic material whose `albedo` is given (TOML), lit
/// straight down by a directional light of irradiance 1, seen from (0, 10, 0)
/// with x to the right and z downwards in the image. The 4×4 image spans
/// exactly x, z ∈ [−2, 2] at the floor (11 below the eye: tan(fov/2) = 2/11),
/// so pixel (col, row) sees the square [col − 2, col − 1] × [row − 2, row − 1].
fn floor_scene(name: &str, albedo: &str, integrator: &str) -> Scene {
    let dir = scratch(name);
    write(&dir, "floor.obj", FLOOR);
    let fov = (2.0 * (2.0f64 / 11.0).atan()).to_degrees();
    let text = format!(
        r#"background = [0, 0, 0]
[camera]
eye = [0, 10, 0]
look_at = [0, -1, 0]
up = [0, 0, -1]
fov = {fov}
width = 4
height = 4
[render]
spp = 1
integrator = "{integrator}"
[materials.floor]
type = "classic"
diffuse = 1
ambient = 0.1
albedo = {albedo}
[[objects]]
type = "mesh"
file = "floor.obj"
material = "floor"
[[lights]]
type = "directional"
direction = [0, -1, 0]
irradiance = [1, 1, 1]
"#
    );
    Scene::load(&write(&dir, "s.toml", &text)).unwrap()
}

/// Beauty and albedo layers, rendered on Embree with `threads`.
fn run(scene: &Scene, threads: usize) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
    let accel = Accel::build(scene, Backend::Embree, None).unwrap();
    let options = RenderOptions {
        threads: Some(threads),
        ..RenderOptions::default()
    };
    let layers = render(scene, &accel, &options).unwrap().film.layers();
    (layers.beauty, layers.albedo)
}

/// The colour index of pixel `i` (row-major, 4 wide): its square is cube
/// (col − 2, −1, row − 2) (the floor y = −1 is in cube −1 by POV-Ray's
/// tolerance), whose coordinates sum to col + row − 5: odd, colour B, when
/// col + row is even.
fn expected_index(i: usize) -> usize {
    let (col, row) = (i % 4, i / 4);
    usize::from((col + row) % 2 == 0)
}

const CHECKER: &str = "{ checker = [[0.8, 0.2, 0.1], [0.1, 0.3, 0.9]] }";

#[test]
fn each_pixel_shows_its_cubes_colour_shaded_by_hand() {
    let (beauty, albedo) = run(&floor_scene("hand", CHECKER, "whitted"), 2);
    // The classic finish head-on under irradiance 1 with cos = 1:
    // ambient × albedo + diffuse × albedo / π × 1 = albedo (0.1 + 1/π).
    let gain = 0.1 + std::f32::consts::FRAC_1_PI;
    for (i, (pixel, aov)) in beauty.iter().zip(&albedo).enumerate() {
        let colour = [A, B][expected_index(i)];
        assert_eq!(*aov, colour, "albedo AOV of pixel {i}");
        for c in 0..3 {
            let want = colour[c] * gain;
            // f32 rounding of the sums and the 1/π: a few ulps of values below 1.
            assert!((pixel[c] - want).abs() <= 1e-6, "pixel {i}: {pixel:?}");
        }
    }
}

#[test]
fn checkered_pixels_equal_the_plain_colours_renders_in_both_integrators() {
    for integrator in ["whitted", "path"] {
        let checkered = run(&floor_scene("both", CHECKER, integrator), 2);
        let plain = [A, B].map(|c| {
            let albedo = format!("[{}, {}, {}]", c[0], c[1], c[2]);
            run(&floor_scene("plain", &albedo, integrator), 2)
        });
        // Every path meets the floor once, so a pixel's whole history is
        // the plain colour's: the values must be the same bits.
        for i in 0..16 {
            let want = &plain[expected_index(i)];
            assert_eq!(checkered.0[i], want.0[i], "{integrator} beauty {i}");
            assert_eq!(checkered.1[i], want.1[i], "{integrator} albedo {i}");
        }
        // Both colours show, so the pattern is not one colour.
        assert_ne!(checkered.0, plain[0].0);
        assert_ne!(checkered.0, plain[1].0);
    }
}

#[test]
fn scale_sizes_the_cubes() {
    // Cubes of side 4: the whole view, x, z ∈ [−2, 2], lies in the four cubes
    // around the origin, (−1|0, −1, −1|0), each 2×2 pixels: the top-left
    // quadrant (−1, −1, −1) is odd (B), its neighbours even (A).
    let scene = floor_scene(
        "scale",
        "{ checker = [[0.8, 0.2, 0.1], [0.1, 0.3, 0.9]], scale = 4 }",
        "whitted",
    );
    let (_, albedo) = run(&scene, 2);
    for (i, aov) in albedo.iter().enumerate() {
        let (col, row) = (i % 4, i / 4);
        let odd = (col < 2) == (row < 2);
        assert_eq!(*aov, if odd { B } else { A }, "pixel {i}");
    }
}

#[test]
fn the_same_bytes_for_any_thread_count() {
    let scene = floor_scene("threads", CHECKER, "path");
    let one = run(&scene, 1);
    for threads in [2, 3] {
        assert_eq!(run(&scene, threads), one, "{threads} threads");
    }
}

#[test]
fn a_checker_changes_the_scene_hash_and_a_plain_albedo_does_not_carry_one() {
    let checkered = floor_scene("hash", CHECKER, "whitted");
    let plain = floor_scene("hash", "[0.8, 0.2, 0.1]", "whitted");
    assert!(plain.materials.iter().all(|m| m.checker.is_none()));
    assert_ne!(checkered.content_hash(), plain.content_hash());
}

/// Loads the floor scene with `albedo`, expecting an error containing every part of `expected`.
fn refused(albedo: &str, expected: &[&str]) {
    let dir = scratch("bad");
    write(&dir, "floor.obj", FLOOR);
    let text = format!(
        "[camera]\neye = [0, 10, 0]\nlook_at = [0, -1, 0]\nup = [0, 0, -1]\nfov = 30\nwidth = 4\nheight = 4\n\
         [materials.floor]\ntype = \"classic\"\nalbedo = {albedo}\n\
         [[objects]]\ntype = \"mesh\"\nfile = \"floor.obj\"\nmaterial = \"floor\"\n"
    );
    refused_scene(&dir, &text, expected);
}

#[test]
fn bad_checkers_are_refused_with_line_and_key() {
    let key = "materials.floor.albedo";
    refused(
        "{ checker = [[0, 0, 0], [1, 1, 1]], scale = 0 }",
        &["line 10", &format!("{key}.scale"), "> 0"],
    );
    refused(
        "{ checker = [[0, 0, 0], [1, 1, 1]], scale = -2 }",
        &["line 10", &format!("{key}.scale")],
    );
    refused(
        "{ checker = [[0, 0, 0], [1, 1, 1]], scale = 1e-320 }",
        &["line 10", &format!("{key}.scale"), "inverse"],
    );
    refused(
        "{ checker = [[0, 0, 0], [1e19, 1, 1]] }",
        &["line 10", &format!("{key}.checker"), "at most"],
    );
    refused(
        "{ checker = [[0, 0, -1], [1, 1, 1]] }",
        &["line 10", &format!("{key}.checker")],
    );
    // Serde's own errors, each precise: a misspelt key (with the key
    // meant), one colour, a colour of two values.
    refused(
        "{ checker = [[0, 0, 0], [1, 1, 1]], scael = 2 }",
        &["line 10", "unknown field `scael`", "did you mean `scale`?"],
    );
    refused(
        "{ checker = [[0, 0, 0]] }",
        &["line 10", "expected an array of length 2"],
    );
    refused(
        "{ checker = [[0, 0], [1, 1, 1]] }",
        &["line 10", "expected an array of length 3"],
    );
    // A table that is neither a checker nor an image, or both.
    for albedo in [
        "{}",
        "{ scale = 2 }",
        "{ checker = [[0, 0, 0], [1, 1, 1]], texture = \"a.png\" }",
        "{ texture = \"a.png\", scale = 2 }",
    ] {
        refused(
            albedo,
            &["line 10", key, "checker = [[r, g, b], [r, g, b]]"],
        );
    }
}
