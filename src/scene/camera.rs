//! The pinhole camera.

use crate::math::{Bounds, Ray, Vec3};

/// Where the camera is at one frame of an animation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraKey {
    pub frame: u32,
    pub eye: Vec3,
    pub look_at: Vec3,
}

#[derive(Clone, Debug, PartialEq)]
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

    pub fn frame(&self) -> CameraFrame {
        let forward = (self.look_at - self.eye).normalize();
        let right = forward.cross(self.up).normalize();
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
}
