//! Cameras through the whole pipeline. One given by its image plane
//! (POV-Ray's `direction`, `right`, `up`; made only by the .pov reader): the
//! plane that equals a look_at camera renders its image, and a stretched
//! plane stretches it. A thin lens keeps the plane in focus sharp and blurs
//! one off it; `fov_axis = "x"` and orthographic cameras see the widths they
//! are given; in both integrators and on every backend.

mod common;

use common::{SQUARE, plane_scene, scratch, write};
use sturmray::accel::{Accel, Backend};
use sturmray::film::Layers;
use sturmray::math::DVec3;
use sturmray::render::{RenderOptions, render};
use sturmray::scene::{Camera, ImagePlane, Scene};

/// The depth layer of `scene` as rendered with `camera`.
fn depth(scene: &Scene, camera: Camera) -> Vec<f32> {
    let scene = Scene {
        camera,
        ..scene.clone()
    };
    scene.camera.check().unwrap();
    let accel = Accel::build(&scene, Backend::Embree, None).unwrap();
    let out = render(&scene, &accel, &RenderOptions::default()).unwrap();
    out.film.layers().depth.to_vec()
}

/// Pixels of row `y` (of a 32-wide image) that hit the square.
fn hits_in_row(depth: &[f32], y: usize) -> usize {
    depth[y * 32..(y + 1) * 32]
        .iter()
        .filter(|d| d.is_finite())
        .count()
}

#[test]
fn an_image_plane_renders_as_the_camera_it_equals_and_stretches() {
    let dir = scratch("plane-camera");
    write(&dir, "square.obj", SQUARE);
    // Eye (0, 0, 4) looking down −z at [−1, 1]², fov 40° vertical, 32×24.
    let scene = Scene::load(&write(&dir, "s.toml", &plane_scene(""))).unwrap();
    let own = depth(&scene, scene.camera.clone());
    // The same view as a plane at distance 1: up spans 2·tan 20°, right that
    // times the aspect ratio 32/24.
    let span = 2.0 * 20f64.to_radians().tan();
    let plane = ImagePlane {
        direction: -DVec3::Z,
        right: DVec3::new(span * 32.0 / 24.0, 0.0, 0.0),
        up: DVec3::new(0.0, span, 0.0),
        orthographic: false,
    };
    let eye = scene.camera.eye;
    let same = depth(&scene, Camera::with_plane(eye, plane, 32, 24));
    assert_eq!(own.len(), same.len());
    for (i, (a, b)) in own.iter().zip(&same).enumerate() {
        // The same samples along rays equal up to f32 rounding.
        assert!(a == b || (a - b).abs() < 1e-4, "pixel {i}: {a} against {b}");
    }
    // The middle row sees the square over ±tan⁻¹(1/4) of ±tan⁻¹(0.485), 16.5
    // of 32 pixels; with right twice as long the image is squeezed to half.
    let row = hits_in_row(&own, 12);
    assert!((16..=17).contains(&row), "{row}");
    let squeezed = ImagePlane {
        right: 2.0 * plane.right,
        ..plane
    };
    let half = hits_in_row(
        &depth(&scene, Camera::with_plane(eye, squeezed, 32, 24)),
        12,
    );
    assert!((8..=9).contains(&half), "{half}");
}

/// The scene of `plane_scene` with `camera` lines added to its camera,
/// `spp` samples and `integrator`, rendered on `backend`.
fn layers(camera: &str, spp: u32, integrator: &str, backend: Backend) -> Layers {
    let dir = scratch("camera-optics");
    write(&dir, "square.obj", SQUARE);
    let text = plane_scene("")
        .replace("fov = 40\n", &format!("{camera}\n"))
        .replace(
            "spp = 1",
            &format!("spp = {spp}\nintegrator = \"{integrator}\""),
        );
    let scene = Scene::load(&write(&dir, "s.toml", &text)).unwrap();
    let accel = Accel::build(&scene, backend, None).unwrap();
    render(&scene, &accel, &RenderOptions::default())
        .unwrap()
        .film
        .layers()
}

/// How many pixels of the middle row lie strictly between the background
/// and the square (more than 5% of the way from one to the other and less
/// than 95%): the width of its edges, blurred or not.
fn edge_pixels(layers: &Layers) -> usize {
    // Red: the background's 0.1 against the lit square's 0.5 · 2 / π.
    let row: Vec<f32> = layers.beauty[12 * 32..13 * 32]
        .iter()
        .map(|p| p[0])
        .collect();
    let (lo, hi) = (0.1, 0.5 * 2.0 / std::f32::consts::PI);
    row.iter()
        .filter(|&&r| {
            let f = (r - lo) / (hi - lo);
            f > 0.05 && f < 0.95
        })
        .count()
}

#[test]
fn a_thin_lens_keeps_the_focus_plane_sharp_and_blurs_off_it() {
    for integrator in ["whitted", "path"] {
        for backend in [Backend::Embree, Backend::Obvhs, Backend::Bvh] {
            let edges = |camera: &str| edge_pixels(&layers(camera, 64, integrator, backend));
            let pinhole = edges("fov = 40");
            // The square lies 4 from the eye: focused there, its edges are
            // as sharp as the pinhole's (the filter's own spread, 1 or 2
            // pixels each side).
            let sharp = edges("fov = 40\naperture = 0.2\nfocus_distance = 4");
            // Focused at 1.5, a point at 4 spreads over a disc 2 · 0.2 ·
            // (1/1.5 − 1/4) = 0.17 rad across, 5.5 pixels of 0.030 rad.
            let blurred = edges("fov = 40\naperture = 0.2\nfocus_distance = 1.5");
            let at = format!("{integrator} on {backend:?}: {pinhole} {sharp} {blurred}");
            assert!((1..=4).contains(&pinhole), "{at}");
            assert!(sharp <= pinhole + 1, "{at}");
            assert!(blurred >= pinhole + 4, "{at}");
        }
    }
}

#[test]
fn fov_axis_and_orthographic_cameras_see_the_widths_given() {
    let row = |camera: &str| hits_in_row(&layers(camera, 1, "whitted", Backend::Embree).depth, 12);
    // 40° across 32 pixels: the square's ±1 at distance 4 covers 32 · 0.25 /
    // tan 20° = 22 pixels, against 16.5 with 40° up the 24 (tan 20° · 32/24
    // across).
    assert_eq!(row("fov = 40\nfov_axis = \"x\""), 22);
    assert!((16..=17).contains(&row("fov = 40")));
    // Orthographic, 4 wide: the square, 2 wide, covers half the row, and
    // every hit lies 4 from the eye's plane.
    let ortho = layers(
        "type = \"orthographic\"\nview_width = 4",
        1,
        "whitted",
        Backend::Embree,
    );
    assert_eq!(hits_in_row(&ortho.depth, 12), 16);
    assert!(
        ortho
            .depth
            .iter()
            .filter(|d| d.is_finite())
            .all(|&d| (d - 4.0).abs() < 1e-5)
    );
}

/// Optics so large that rays would leave Embree's range (which aborts the
/// process on such a ray) are refused when the scene loads: exit 2, naming
/// the key, never a crash.
#[test]
fn optics_beyond_embrees_range_are_refused_not_a_crash() {
    let dir = scratch("huge-optics");
    write(&dir, "square.obj", SQUARE);
    for (camera, key) in [
        (
            "fov = 40\naperture = 1e30\nfocus_distance = 2",
            "camera.aperture",
        ),
        (
            "fov = 40\naperture = 0.1\nfocus_distance = 1e30",
            "camera.focus_distance",
        ),
        (
            "type = \"orthographic\"\nview_width = 1e30",
            "camera.view_width",
        ),
    ] {
        write(&dir, "s.toml", &plane_scene("").replace("fov = 40", camera));
        let out = common::sturmray(&dir, &["render", "s.toml", "-o", "s.exr"]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{camera}: {stderr}");
        assert!(stderr.contains(key), "{key} not in {stderr}");
    }
}
