//! The pinhole camera.

use glam::DVec3;

use crate::math::{Bounds, RAY_LIMIT, Ray, Vec3, sci, unit};

/// The view direction must make at least this sine with `up`, and eye and
/// look_at must lie at least this fraction of their size apart: closer, and
/// rounding (of the inputs, of the interpolation between keys) decides where
/// the camera looks.
const MIN_VIEW: f64 = 1e-4;

/// What is wrong with a camera: the TOML key to blame and why.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraProblem {
    pub key: String,
    pub message: String,
}

/// Where the camera is at one frame of an animation.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct CameraKey {
    pub frame: u32,
    pub eye: Vec3,
    pub look_at: Vec3,
}

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Camera {
    /// A keyframed path, frames increasing; empty for a still camera.
    pub keys: Vec<CameraKey>,
    pub eye: Vec3,
    pub look_at: Vec3,
    pub up: Vec3,
    /// Vertical field of view in degrees.
    pub fov: f32,
    pub width: u32,
    pub height: u32,
}

/// The camera's frame, precomputed once per render.
#[derive(Clone, Copy, Debug)]
pub struct CameraFrame {
    eye: Vec3,
    /// Image-plane axes at distance 1, scaled so pixel (0,0)..(w,h) spans the view.
    right: Vec3,
    down: Vec3,
    top_left: Vec3,
}

impl Default for Camera {
    /// At (0, 0, 1) looking at the origin, 40° vertical field of view, 640×480.
    fn default() -> Self {
        Camera {
            keys: Vec::new(),
            eye: Vec3::Z,
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            fov: 40.0,
            width: 640,
            height: 480,
        }
    }
}

impl Camera {
    /// Moves the camera to `frame` of its path: linear between the keys around
    /// it, held at the first and last key outside them. The path is then
    /// spent (a frame's scene is a still), so equal frames hash equally.
    pub fn go_to_frame(&mut self, frame: u32) {
        let keys = std::mem::take(&mut self.keys);
        let after = keys.partition_point(|k| k.frame <= frame);
        let (eye, look_at) = match (
            after.checked_sub(1).map(|i| keys[i]),
            keys.get(after).copied(),
        ) {
            (Some(a), Some(b)) => {
                let t = (frame - a.frame) as f32 / (b.frame - a.frame) as f32;
                (a.eye.lerp(b.eye, t), a.look_at.lerp(b.look_at, t))
            }
            (Some(k), None) | (None, Some(k)) => (k.eye, k.look_at),
            (None, None) => return,
        };
        self.eye = eye;
        self.look_at = look_at;
    }

    /// Frames `bounds` from the front, slightly above and to the right, with a
    /// vertical field of view of 40 degrees.
    pub fn framing(bounds: Bounds, width: u32, height: u32) -> Camera {
        let fov = 40.0f32;
        let center = bounds.center();
        let radius = (0.5 * bounds.diagonal().length()).max(1e-6);
        let half = (0.5 * fov).to_radians();
        // Fit the bounding sphere in the narrower of the two fields of view.
        let aspect = width as f32 / height as f32;
        let half_narrow = if aspect < 1.0 {
            (half.tan() * aspect).atan()
        } else {
            half
        };
        let distance = 1.1 * radius / half_narrow.sin();
        let dir = Vec3::new(0.35, 0.3, 1.0).normalize();
        Camera {
            keys: Vec::new(),
            eye: center + distance * dir,
            look_at: center,
            up: Vec3::Y,
            fov,
            width,
            height,
        }
    }

    /// Checks that every frame of the camera makes valid rays: the eye within
    /// Embree's limit and, at every point of the path between keys (they
    /// are interpolated linearly, so the whole segment, not only its integer
    /// frames), a view direction that exists and is not along `up`.
    pub fn check(&self) -> Result<(), CameraProblem> {
        let problem = |key: String, message: String| Err(CameraProblem { key, message });
        let still = CameraKey {
            frame: 0,
            eye: self.eye,
            look_at: self.look_at,
        };
        let named = std::iter::once(("camera".to_string(), still)).chain(
            self.keys
                .iter()
                .enumerate()
                .map(|(i, &k)| (format!("camera.keys[{i}]"), k)),
        );
        for (name, k) in named {
            if !k.eye.abs().cmple(Vec3::splat(RAY_LIMIT)).all() {
                return problem(
                    format!("{name}.eye"),
                    format!(
                        "{} lies beyond {RAY_LIMIT:e}, the largest ray origin Embree takes",
                        sci(k.eye)
                    ),
                );
            }
            if let Some(message) = view_problem(k, k, self.up) {
                return problem(format!("{name}.look_at"), message);
            }
        }
        for (i, pair) in self.keys.windows(2).enumerate() {
            if let Some(message) = view_problem(pair[0], pair[1], self.up) {
                let (a, b) = (pair[0].frame, pair[1].frame);
                return problem(
                    format!("camera.keys[{}]", i + 1),
                    format!(
                        "on the way from camera.keys[{i}] (frame {a}) to camera.keys[{}] \
                         (frame {b}), {message}",
                        i + 1
                    ),
                );
            }
        }
        Ok(())
    }

    pub fn frame(&self) -> CameraFrame {
        // `unit`: a view a billionth long, or ten billion, still has a direction.
        let forward = unit(self.look_at - self.eye);
        let right = unit(forward.cross(self.up));
        let true_up = right.cross(forward);
        let half_h = (0.5 * self.fov).to_radians().tan();
        let half_w = half_h * self.width as f32 / self.height as f32;
        let pixel = 2.0 * half_h / self.height as f32;
        CameraFrame {
            eye: self.eye,
            right: right * pixel,
            down: -true_up * pixel,
            top_left: forward - right * half_w + true_up * half_h,
        }
    }
}

/// What goes wrong with the view on the way from key `a` to key `b` (equal
/// for a still camera), if anything: eye and look_at (nearly) meet, or the
/// view direction turns (nearly) along `up`. d(t) = look_at(t) − eye(t) is
/// linear in t ∈ [0, 1]; the extremes of |d|² and of sin² = |d × up|² / |d|²
/// (a ratio of quadratics in t) are found exactly, in f64.
fn view_problem(a: CameraKey, b: CameraKey, up: Vec3) -> Option<String> {
    let up = up.as_dvec3().normalize();
    let (d0, d1) = (
        (a.look_at - a.eye).as_dvec3(),
        (b.look_at - b.eye).as_dvec3(),
    );
    let at = |t: f64| d0 + t * (d1 - d0);
    let size = [a.eye, a.look_at, b.eye, b.look_at]
        .map(|p| f64::from(p.abs().max_element()))
        .into_iter()
        .fold(0.0, f64::max);
    let slope = d1 - d0;
    let nearest = if slope == DVec3::ZERO {
        0.0
    } else {
        (-d0.dot(slope) / slope.dot(slope)).clamp(0.0, 1.0)
    };
    let closest = at(nearest).length();
    if closest == 0.0 || closest < MIN_VIEW * size {
        return Some(format!(
            "eye and look_at come within {closest:.3e} of each other, at positions of size \
             {size:.3e}: they must stay at least {MIN_VIEW:e} of that apart"
        ));
    }
    let sine = |t: f64| at(t).cross(up).length() / at(t).length();
    let smallest = stationary_points(d0, d1, up)
        .into_iter()
        .chain([0.0, 1.0])
        .map(sine)
        .fold(f64::INFINITY, f64::min);
    (smallest < MIN_VIEW).then(|| {
        format!(
            "the view direction comes within {:.2e} degrees of camera.up; it must stay at \
             least {:.2e} degrees away",
            smallest.asin().to_degrees(),
            MIN_VIEW.asin().to_degrees()
        )
    })
}

/// The t in (0, 1) where sin² of the angle between d(t) = d0 + t·(d1 − d0)
/// and `up` is stationary: f/g with f = |d × up|², g = |d|², quadratics in
/// t, has (f/g)′ = 0 where f′g − fg′ = 0, a quadratic (the cubic terms cancel).
fn stationary_points(d0: DVec3, d1: DVec3, up: DVec3) -> Vec<f64> {
    let quadratic = |v0: DVec3, v1: DVec3| {
        let s = v1 - v0;
        [v0.dot(v0), 2.0 * v0.dot(s), s.dot(s)]
    };
    let [f0, f1, f2] = quadratic(d0.cross(up), d1.cross(up));
    let [g0, g1, g2] = quadratic(d0, d1);
    let (qa, qb, qc) = (
        f2 * g1 - f1 * g2,
        2.0 * (f2 * g0 - f0 * g2),
        f1 * g0 - f0 * g1,
    );
    let roots = if qa == 0.0 {
        if qb == 0.0 { vec![] } else { vec![-qc / qb] }
    } else {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc < 0.0 {
            vec![]
        } else {
            // The stable pair: no cancellation between -qb and the root.
            let q = -0.5 * (qb + qb.signum() * disc.sqrt());
            let mut r = vec![q / qa];
            if q != 0.0 {
                r.push(qc / q);
            }
            r
        }
    };
    roots.into_iter().filter(|t| *t > 0.0 && *t < 1.0).collect()
}

impl CameraFrame {
    /// The primary ray through image-plane point (x, y), in pixels from the
    /// top-left corner: pixel (i, j)'s centre is (i + 0.5, j + 0.5).
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        let dir = (self.top_left + x * self.right + y * self.down).normalize();
        Ray::new(self.eye, dir)
    }
}

#[cfg(test)]
mod tests {
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
}
