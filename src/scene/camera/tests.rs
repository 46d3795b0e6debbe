//! The pinhole camera's tests: hand-worked rays, framing, paths, checks.

use super::*;

fn camera() -> Camera {
    Camera {
        keys: Vec::new(),
        eye: Vec3::new(0.0, 0.0, 5.0),
        look_at: Vec3::ZERO,
        up: Vec3::Y,
        fov: 90.0,
        width: 200,
        height: 100,
        plane: None,
        optics: Optics::default(),
    }
}

#[test]
fn centre_ray_looks_at_the_target() {
    let ray = camera().frame().ray(100.0, 50.0);
    assert!((ray.dir - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
}

#[test]
fn edges_span_the_vertical_field_of_view() {
    let f = camera().frame();
    // 90° vertical: the top edge's ray is 45° up, the image's right edge at
    // tan = aspect = 2.
    let top = f.ray(100.0, 0.0).dir;
    assert!((top.y - top.z.abs()).abs() < 1e-6 && top.y > 0.0);
    let right = f.ray(200.0, 50.0).dir;
    assert!((right.x / right.z.abs() - 2.0).abs() < 1e-5);
}

#[test]
fn framing_sees_the_whole_box() {
    let b = Bounds {
        min: Vec3::splat(-1.0),
        max: Vec3::new(3.0, 1.0, 1.0),
    };
    let cam = Camera::framing(b, 64, 48);
    let forward = (cam.look_at - cam.eye).normalize();
    let half = (0.5 * cam.fov).to_radians();
    for i in 0..8 {
        let corner = Vec3::new(
            if i & 1 == 0 { b.min.x } else { b.max.x },
            if i & 2 == 0 { b.min.y } else { b.max.y },
            if i & 4 == 0 { b.min.z } else { b.max.z },
        );
        let angle = forward.angle_between(corner - cam.eye);
        assert!(angle < half, "corner {corner} at {angle} rad");
    }
}

#[test]
fn a_keyframed_camera_moves_linearly_and_holds_at_the_ends() {
    let key = |frame, x: f32| CameraKey {
        frame,
        eye: Vec3::new(x, 0.0, 5.0),
        look_at: Vec3::new(x, 0.0, 0.0),
    };
    let path = Camera {
        keys: vec![key(10, 0.0), key(20, 4.0), key(30, 2.0)],
        ..camera()
    };
    for (frame, x) in [
        (0, 0.0),
        (10, 0.0),
        (15, 2.0),
        (20, 4.0),
        (25, 3.0),
        (30, 2.0),
        (99, 2.0),
    ] {
        let mut c = path.clone();
        c.go_to_frame(frame);
        assert_eq!(c.eye, Vec3::new(x, 0.0, 5.0), "frame {frame}");
        assert_eq!(c.look_at.x, x);
        assert!(c.keys.is_empty());
    }
    // A still camera stays where it is.
    let mut still = camera();
    still.go_to_frame(7);
    assert_eq!(still, camera());
}

#[test]
fn a_path_is_checked_between_its_keys_not_only_at_them() {
    let key = |frame, d: [f32; 3]| CameraKey {
        frame,
        eye: Vec3::ZERO,
        look_at: Vec3::from(d),
    };
    let path = |d0, d1| Camera {
        keys: vec![key(0, d0), key(7, d1)],
        ..camera()
    };
    // Up is +y. Through it halfway, between frames 3 and 4; then past it at
    // 1e-5 (too close), and at a comfortable 0.45 in sine.
    for (z, ok) in [(0.0, false), (1e-5, false), (0.5, true)] {
        let result = path([1.0, 1.0, z], [-1.0, 1.0, z]).check();
        assert_eq!(result.is_ok(), ok, "z = {z}: {result:?}");
        if let Err(p) = result {
            assert_eq!(p.key, "camera.keys[1]");
            assert!(p.message.contains("camera.up"), "{}", p.message);
        }
    }
    // Eye and look_at swap places: they meet halfway.
    let swap = Camera {
        keys: vec![
            CameraKey {
                frame: 0,
                eye: Vec3::Z,
                look_at: -Vec3::Z,
            },
            CameraKey {
                frame: 1,
                eye: -Vec3::Z,
                look_at: Vec3::Z,
            },
        ],
        ..camera()
    };
    let p = swap.check().unwrap_err();
    assert!(p.message.contains("eye and look_at"), "{}", p.message);
    // Each key on its own, and the still camera, too.
    let mut still = camera();
    still.look_at = Vec3::new(0.0, 1.0, 5.0);
    assert_eq!(still.check().unwrap_err().key, "camera.look_at");
    assert!(camera().check().is_ok());
}

/// POV-Ray's sample camera, tilted up by its `direction <0, 0.1, 1.5>`, at a
/// 4×3 image with `right` of the image's aspect ratio.
fn sample_plane() -> ImagePlane {
    ImagePlane {
        direction: DVec3::new(0.0, 0.1, 1.5),
        right: DVec3::new(4.0 / 3.0, 0.0, 0.0),
        up: DVec3::Y,
        orthographic: false,
    }
}

/// Asserts that `camera`'s ray through image point (x, y) leaves its eye
/// along `expected` (not normalised).
fn assert_ray(camera: &Camera, (x, y): (f32, f32), expected: [f32; 3]) {
    let ray = camera.frame().ray(x, y);
    let expected = Vec3::from(expected).normalize();
    assert_eq!(ray.origin, camera.eye);
    assert!(
        (ray.dir - expected).length() < 1e-6,
        "({x}, {y}): {} against {expected}",
        ray.dir
    );
}

#[test]
fn an_image_plane_makes_the_rays_of_its_corners_and_centre() {
    let c = Camera::with_plane(Vec3::new(1.0, 2.0, 3.0), sample_plane(), 4, 3);
    // direction + (u − ½)·right + (½ − v)·up, at (u, v) = (x/4, y/3), by hand:
    // the corners are direction ± (2/3, 0, 0) ± (0, 0.5, 0).
    assert_ray(&c, (0.0, 0.0), [-2.0 / 3.0, 0.6, 1.5]);
    assert_ray(&c, (4.0, 0.0), [2.0 / 3.0, 0.6, 1.5]);
    assert_ray(&c, (0.0, 3.0), [-2.0 / 3.0, -0.4, 1.5]);
    assert_ray(&c, (4.0, 3.0), [2.0 / 3.0, -0.4, 1.5]);
    assert_ray(&c, (2.0, 1.5), [0.0, 0.1, 1.5]);
    // Pixel (0, 0)'s centre: u = 1/8, v = 1/6, so −3/8 of right (−0.5) and
    // 1/3 of up.
    assert_ray(&c, (0.5, 0.5), [-0.5, 0.1 + 1.0 / 3.0, 1.5]);
}

#[test]
fn an_image_plane_is_stretched_and_skewed_as_given() {
    // `right` twice as long as the image is wide for its height: the image
    // is stretched, not fitted to the aspect ratio.
    let mut plane = sample_plane();
    plane.right = DVec3::new(2.0, 0.0, 0.0);
    let stretched = Camera::with_plane(Vec3::ZERO, plane, 4, 3);
    assert_ray(&stretched, (4.0, 1.5), [1.0, 0.1, 1.5]);
    assert_ray(&stretched, (0.0, 0.0), [-1.0, 0.6, 1.5]);
    // `up` leaning to the right: the top edge's middle moves by half of it.
    let mut plane = sample_plane();
    plane.up = DVec3::new(0.5, 1.0, 0.0);
    let skewed = Camera::with_plane(Vec3::ZERO, plane, 4, 3);
    assert_ray(&skewed, (2.0, 0.0), [0.25, 0.6, 1.5]);
    assert_ray(&skewed, (0.0, 3.0), [-2.0 / 3.0 - 0.25, -0.4, 1.5]);
}

#[test]
fn an_image_plane_at_any_scale_makes_the_same_rays() {
    let c = Camera::with_plane(Vec3::ZERO, sample_plane(), 4, 3);
    for scale in [1e-20, 1e20] {
        let p = sample_plane();
        let scaled = ImagePlane {
            direction: scale * p.direction,
            right: scale * p.right,
            up: scale * p.up,
            orthographic: false,
        };
        let s = Camera::with_plane(Vec3::ZERO, scaled, 4, 3);
        for point in [(0.0, 0.0), (2.0, 1.5), (4.0, 3.0), (0.5, 2.5)] {
            let (a, b) = (
                c.frame().ray(point.0, point.1),
                s.frame().ray(point.0, point.1),
            );
            assert!((a.dir - b.dir).length() < 1e-6, "{scale}: {point:?}");
        }
    }
}

#[test]
fn an_image_plane_shows_its_centre_and_vertical_angle() {
    let plane = ImagePlane {
        direction: DVec3::Z,
        right: DVec3::X,
        up: 2.0 * DVec3::Y,
        orthographic: false,
    };
    let c = Camera::with_plane(Vec3::new(0.0, 0.0, -5.0), plane, 10, 10);
    assert_eq!(c.look_at, Vec3::new(0.0, 0.0, -4.0));
    assert_eq!(c.up, 2.0 * Vec3::Y);
    // From the eye, the top and bottom edges' middles are at (0, ±1, 1): 90° apart.
    assert!((c.fov - 90.0).abs() < 1e-4, "{}", c.fov);
    // A camera without a plane serialises as before (the scene hash is
    // unchanged); one with a plane carries it.
    assert!(!serde_json::to_string(&camera()).unwrap().contains("plane"));
    assert!(serde_json::to_string(&c).unwrap().contains("\"plane\""));
}

#[test]
fn an_image_plane_that_makes_no_rays_is_refused() {
    let with = |edit: fn(&mut ImagePlane)| {
        let mut plane = sample_plane();
        edit(&mut plane);
        Camera::with_plane(Vec3::ZERO, plane, 4, 3).check()
    };
    assert!(with(|_| ()).is_ok());
    type Edit = fn(&mut ImagePlane);
    let cases: [(Edit, &str, &str); 9] = [
        (|p| p.up.y = f64::NAN, "camera.up", "finite"),
        (
            |p| p.direction.z = f64::INFINITY,
            "camera.direction",
            "finite",
        ),
        (|p| p.right = DVec3::ZERO, "camera.right", "parallel"),
        (
            |p| p.right = DVec3::new(0.0, -3.0, 0.0),
            "camera.right",
            "parallel",
        ),
        // A sine of 1e-5 between right and up is too little, 1e-3 enough
        // (below: the accepted case).
        (
            |p| p.up = DVec3::new(1.0, 1e-5, 0.0),
            "camera.right",
            "parallel",
        ),
        (
            |p| p.direction = DVec3::ZERO,
            "camera.direction",
            "plane of right and up",
        ),
        (
            |p| p.direction = DVec3::new(5.0, -2.0, 0.0),
            "camera.direction",
            "plane",
        ),
        // 1.5e-5 off the eye, against vectors up to 4/3 long: too close.
        (|p| p.direction.z = 1.5e-5, "camera.direction", "plane"),
        (|p| p.direction.z = -1e-30, "camera.direction", "plane"),
    ];
    for (i, (edit, key, words)) in cases.into_iter().enumerate() {
        let p = with(edit).unwrap_err();
        assert_eq!(p.key, key, "case {i}: {}", p.message);
        assert!(p.message.contains(words), "case {i}: {}", p.message);
    }
    assert!(with(|p| p.up = DVec3::new(1.0, 1e-3, 0.0)).is_ok());
    // Looking backwards (the plane behind the eye's z) is a view like any other.
    assert!(with(|p| p.direction.z = -1.5).is_ok());
    // The eye is checked as for any camera.
    let mut far = Camera::with_plane(Vec3::ZERO, sample_plane(), 4, 3);
    far.eye.x = 1e19;
    assert_eq!(far.check().unwrap_err().key, "camera.eye");
    // A path of keys does not go with a plane.
    let mut moving = Camera::with_plane(Vec3::ZERO, sample_plane(), 4, 3);
    moving.keys = camera_path();
    assert_eq!(moving.check().unwrap_err().key, "camera.keys");
}

fn camera_path() -> Vec<CameraKey> {
    (0..2)
        .map(|frame| CameraKey {
            frame,
            eye: Vec3::new(frame as f32, 0.0, 5.0),
            look_at: Vec3::ZERO,
        })
        .collect()
}

#[test]
fn fov_axis_x_spans_the_width() {
    // 90° across a 2:1 image: the right edge's ray at 45°, the top edge's
    // at tan = 1/2.
    let across = Camera {
        optics: Optics {
            projection: Projection::PerspectiveX,
            lens: None,
        },
        ..camera()
    };
    let f = across.frame();
    let right = f.ray(200.0, 50.0).dir;
    assert!((right.x - right.z.abs()).abs() < 1e-6 && right.x > 0.0);
    let top = f.ray(100.0, 0.0).dir;
    assert!((top.y / top.z.abs() - 0.5).abs() < 1e-6);
}

#[test]
fn orthographic_rays_are_parallel_and_span_the_view_width() {
    let ortho = Camera {
        optics: Optics {
            projection: Projection::Orthographic { view_width: 4.0 },
            lens: None,
        },
        ..camera()
    };
    let f = ortho.frame();
    for (x, y, origin) in [
        (100.0, 50.0, Vec3::new(0.0, 0.0, 5.0)),
        (0.0, 0.0, Vec3::new(-2.0, 1.0, 5.0)),
        (200.0, 100.0, Vec3::new(2.0, -1.0, 5.0)),
    ] {
        let ray = f.ray(x, y);
        assert!((ray.dir - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
        assert!(
            (ray.origin - origin).length() < 1e-5,
            "{x},{y}: {}",
            ray.origin
        );
    }
}

#[test]
fn a_thin_lens_focuses_its_rays_on_the_focus_plane() {
    let lens = |aperture| Camera {
        optics: Optics {
            projection: Projection::Perspective,
            lens: Some(ThinLens {
                aperture,
                focus_distance: 3.0,
            }),
        },
        ..camera()
    };
    let f = lens(0.5).frame();
    assert!(f.has_lens());
    let pinhole = camera().frame();
    for (x, y) in [(100.0, 50.0), (13.0, 77.0), (190.0, 4.0)] {
        let through = pinhole.ray(x, y);
        // Where the pinhole ray meets the plane z = 5 - 3: every lens ray
        // of this image point passes there too.
        let focus = through.at(3.0 / through.dir.dot(Vec3::NEG_Z));
        let mut origins = Vec::new();
        for lens_uv in [[0.1, 0.9], [0.5, 0.5], [0.99, 0.2], [0.3, 0.0]] {
            let ray = f.lens_ray(x, y, lens_uv);
            let t = (focus.z - ray.origin.z) / ray.dir.z;
            assert!((ray.at(t) - focus).length() < 1e-5, "{x},{y} {lens_uv:?}");
            // The origin lies on the lens disc, in the plane of the eye.
            assert!((ray.origin.z - 5.0).abs() < 1e-6);
            assert!(ray.origin.truncate().length() <= 0.5 + 1e-6);
            origins.push(ray.origin);
        }
        assert!(origins.windows(2).all(|w| w[0] != w[1]));
    }
    // An aperture of 0 is a pinhole, which draws no lens sample.
    assert!(!lens(0.0).frame().has_lens());
    assert!(!camera().frame().has_lens());
}

#[test]
fn optics_are_checked() {
    let with = |optics| Camera { optics, ..camera() };
    let thin = |aperture, focus_distance| Optics {
        projection: Projection::Perspective,
        lens: Some(ThinLens {
            aperture,
            focus_distance,
        }),
    };
    for (optics, key) in [
        (thin(-0.1, 1.0), "camera.aperture"),
        (thin(f32::NAN, 1.0), "camera.aperture"),
        (thin(0.1, 0.0), "camera.focus_distance"),
        (thin(0.1, f32::INFINITY), "camera.focus_distance"),
        (
            Optics {
                projection: Projection::Orthographic { view_width: 0.0 },
                lens: None,
            },
            "camera.view_width",
        ),
        // Finite but beyond Embree's limit: the rays would abort the process.
        (thin(1e30, 2.0), "camera.aperture"),
        (thin(0.1, 1e30), "camera.focus_distance"),
        (
            Optics {
                projection: Projection::Orthographic { view_width: 1e30 },
                lens: None,
            },
            "camera.view_width",
        ),
    ] {
        assert_eq!(with(optics).check().unwrap_err().key, key);
    }
    assert!(with(thin(0.0, 1.0)).check().is_ok());
    // Each within the limit, but the lens's disc around an eye near it reaches past.
    let edge = Camera {
        eye: Vec3::new(RAY_LIMIT * 0.75, 0.0, 0.0),
        look_at: Vec3::new(RAY_LIMIT * 0.75, 0.0, -RAY_LIMIT * 0.5),
        ..with(thin(RAY_LIMIT * 0.5, 1.0))
    };
    let problem = edge.check().unwrap_err();
    assert_eq!(problem.key, "camera.eye", "{}", problem.message);
    let edge = Camera {
        optics: thin(RAY_LIMIT * 0.1, 1.0),
        ..edge
    };
    assert!(edge.check().is_ok());
    // A tall image makes an orthographic view taller than it is wide.
    let tall = Camera {
        width: 1,
        height: 1000,
        ..with(Optics {
            projection: Projection::Orthographic {
                view_width: RAY_LIMIT * 0.01,
            },
            lens: None,
        })
    };
    assert_eq!(tall.check().unwrap_err().key, "camera.view_width");
    // An image plane is a pinhole.
    let mut plane = Camera::with_plane(Vec3::ZERO, sample_plane(), 4, 3);
    plane.optics = thin(0.1, 1.0);
    assert_eq!(plane.check().unwrap_err().key, "camera.direction");
}
