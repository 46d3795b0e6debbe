//! A camera given by its image plane (POV-Ray's `direction`, `right`, `up`;
//! made only by the .pov reader) renders through the whole pipeline: the
//! plane that equals a look_at camera renders its image, and a stretched
//! plane stretches it.

mod common;

use common::{SQUARE, plane_scene, scratch, write};
use sturmray::accel::{Accel, Backend};
use sturmray::math::Vec3;
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
    let span = 2.0 * 20f32.to_radians().tan();
    let plane = ImagePlane {
        direction: -Vec3::Z,
        right: Vec3::new(span * 32.0 / 24.0, 0.0, 0.0),
        up: Vec3::new(0.0, span, 0.0),
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
