//! The camera: by eye, look_at and a field of view (vertical, or
//! horizontal with `fov_axis = "x"`), orthographic by the width it sees, or
//! by its image plane (POV-Ray's `direction`, `right`, `up`); a pinhole, or a
//! thin lens that focuses one plane ([`Optics`]); and the image size's
//! limits, which scene files and `--width`/`--height` share.

use glam::DVec3;

use super::GIB;
use super::file::physical_memory;
use crate::film::RENDER_BYTES_PER_PIXEL;
use crate::geometry::Pinhole;
use crate::math::{Bounds, RAY_LIMIT, Ray, Ray64, Vec3, sci};
use crate::sampling::warp::concentric_disk;

/// The view direction must make at least this sine with `up`, and eye and
/// look_at must lie at least this fraction of their size apart: closer, and
/// rounding (of the inputs, of the interpolation between keys) decides where
/// the camera looks. An image plane's right and up must make this sine too,
/// and its eye lie this fraction of the plane's size off it.
const MIN_VIEW: f64 = 1e-4;

/// The most pixels on a side of an image (ARCHITECTURE.md's limits).
const MAX_SIDE: u32 = 1 << 16;

/// Which part of an image size is at fault.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum SizeFault {
    Width,
    Height,
    /// Both together: the film does not fit in memory.
    Film,
}

/// Why an image side of `side` pixels is refused, if it is.
pub(super) fn side_problem(side: u32) -> Option<String> {
    (side == 0 || side > MAX_SIDE).then(|| format!("expected 1 to {MAX_SIDE} pixels, found {side}"))
}

/// Why an image of `width` × `height` pixels cannot be rendered, if it
/// cannot: a side of 0 or above [`MAX_SIDE`], or a film larger than this
/// machine's memory, which would abort the render instead of refusing it.
/// A scene file's size and `--width`/`--height` both go through here; each
/// caller names the key or flag at fault.
pub(super) fn size_problem(width: u32, height: u32) -> Option<(SizeFault, String)> {
    for (fault, side) in [(SizeFault::Width, width), (SizeFault::Height, height)] {
        if let Some(message) = side_problem(side) {
            return Some((fault, message));
        }
    }
    let bytes = u64::from(width) * u64::from(height) * RENDER_BYTES_PER_PIXEL;
    let memory = physical_memory()?;
    (bytes > memory).then(|| {
        (
            SizeFault::Film,
            format!(
                "a {width}x{height} image needs {:.1} GiB for its film ({RENDER_BYTES_PER_PIXEL} \
                 bytes per pixel), more than this machine's {:.1} GiB of memory",
                bytes as f64 / GIB,
                memory as f64 / GIB
            ),
        )
    })
}

/// What is wrong with a camera: the key to blame (TOML's, or for an image
/// plane POV-Ray's camera keyword) and why.
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
    /// Field of view in degrees, along `optics.fov_axis` (vertical unless
    /// said); unused by an orthographic camera.
    pub fov: f32,
    pub width: u32,
    pub height: u32,
    /// A camera given by its image plane instead of look_at/fov (POV-Ray's `direction`, `right`, `up`):
    /// the ray through image point (u, v) ∈ [0, 1]², u to the right and v down, has the direction
    /// `direction + (u − ½)·right + (½ − v)·up` (not normalised; the frame normalises as it does now).
    /// Then `look_at` is `eye + direction` and `fov` the vertical angle the plane spans at its
    /// centre, for display only (see [`Camera::with_plane`]). Left out of the serialisation when
    /// absent, so the scene hash of every other camera is what it was before planes existed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub plane: Option<ImagePlane>,
    /// Projection, fov axis and lens. Left out of the serialisation for a
    /// pinhole with a vertical field of view, so the scene hash of every
    /// camera that existed before these did is what it was.
    #[serde(skip_serializing_if = "Optics::is_pinhole")]
    pub optics: Optics,
}

/// How a look_at camera maps the image to rays, beyond eye and direction.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Optics {
    pub projection: Projection,
    /// A thin lens in place of the pinhole: depth of field.
    pub lens: Option<ThinLens>,
}

/// Perspective (rays from the eye) or orthographic (parallel rays).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub enum Projection {
    /// `fov` spans the image's height (`FovAxis::Y`) or width (`FovAxis::X`).
    #[default]
    Perspective,
    PerspectiveX,
    /// Parallel rays along the view, over a view this wide (scene units) at
    /// the image's width; the height follows the aspect ratio.
    Orthographic {
        view_width: f32,
    },
}

/// A thin lens (pbrt's model): rays leave a disc of radius `aperture` around
/// the eye, across the view, and every ray of one image point meets the
/// others at `focus_distance` along the view, so that plane stays sharp.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ThinLens {
    pub aperture: f32,
    pub focus_distance: f32,
}

impl Optics {
    pub fn is_pinhole(&self) -> bool {
        *self == Optics::default()
    }

    /// How far from the eye a ray may start: the lens's radius plus, for an
    /// orthographic view, the distance from its centre to a corner.
    fn reach(&self, aspect: f32) -> f32 {
        let lens = self.lens.map_or(0.0, |l| l.aperture);
        let view = match self.projection {
            Projection::Orthographic { view_width } => view_width * Self::view_scale(aspect),
            _ => 0.0,
        };
        lens + view
    }

    /// An orthographic view's half-diagonal per unit of its width.
    fn view_scale(aspect: f32) -> f32 {
        0.5 * (1.0 + 1.0 / (aspect * aspect)).sqrt()
    }
}

/// A camera's image plane, as POV-Ray gives it: none of the three vectors
/// need be perpendicular to another, and right and up need not have the
/// image's aspect ratio (the image is then stretched, as POV-Ray's is).
/// In f64, as POV-Ray resolves it: a ray that grazes a surface by less than
/// an f32 ulp of its direction is hit or missed as POV-Ray's is only if the
/// plane is not rounded to f32 first.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ImagePlane {
    /// From the eye to the image's centre.
    pub direction: DVec3,
    /// Across the whole image, from its left edge to its right.
    pub right: DVec3,
    /// Across the whole image, from its bottom edge to its top.
    pub up: DVec3,
    /// Parallel rays along `direction`, each from its point of the plane
    /// of `right` and `up` through the eye (POV-Ray's `orthographic`): the
    /// view is as large as `right` and `up` are. Left out of the
    /// serialisation when false, so a perspective plane's scene hash is
    /// what it was.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub orthographic: bool,
}

/// The camera's frame, precomputed once per render, in f64: the rays are
/// made in f64 ([`CameraFrame::ray64`]) and traced as such by the analytic
/// shapes, their f32 rounding by the BVH (see `Ray64`).
#[derive(Clone, Copy, Debug)]
pub struct CameraFrame {
    eye: DVec3,
    /// Image-plane axes, scaled so pixel (0,0)..(w,h) spans the view (at
    /// distance 1 for a look_at camera; any distance does, as rays are
    /// normalised). For an orthographic camera they span the view's own
    /// size, as offsets of the ray's origin from the eye.
    right: DVec3,
    down: DVec3,
    top_left: DVec3,
    /// Parallel rays along this direction (orthographic), or none.
    parallel: Option<DVec3>,
    lens: Option<LensFrame>,
}

/// A thin lens in the camera's frame.
#[derive(Clone, Copy, Debug)]
struct LensFrame {
    /// The lens disc's axes, each as long as its radius.
    right: DVec3,
    up: DVec3,
    forward: DVec3,
    focus_distance: f64,
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
            plane: None,
            optics: Optics::default(),
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
            plane: None,
            optics: Optics::default(),
        }
    }

    /// A still camera at `eye` that sees through `plane`, with `look_at`, `up`
    /// and `fov` filled in for display: the plane's centre, its up, and the
    /// angle between the rays through the middle of its top and bottom edges.
    pub fn with_plane(eye: Vec3, plane: ImagePlane, width: u32, height: u32) -> Camera {
        let (direction, up) = (plane.direction, plane.up);
        let fov = (direction + 0.5 * up).angle_between(direction - 0.5 * up);
        Camera {
            keys: Vec::new(),
            eye,
            look_at: (eye.as_dvec3() + direction).as_vec3(),
            up: up.as_vec3(),
            fov: fov.to_degrees() as f32,
            width,
            height,
            plane: Some(plane),
            optics: Optics::default(),
        }
    }

    /// Checks that every frame of the camera makes valid rays: the eye within
    /// Embree's limit and, at every point of the path between keys (they
    /// are interpolated linearly, so the whole segment, not only its integer
    /// frames), a view direction that exists and is not along `up`.
    ///
    /// A camera given by its image plane has no path (the .pov reader never
    /// makes one), and its plane must make rays: see [`ImagePlane::problem`].
    pub fn check(&self) -> Result<(), CameraProblem> {
        let problem = |key: String, message: String| Err(CameraProblem { key, message });
        let aspect = self.width as f32 / self.height as f32;
        if let Some(problem) = self.optics.problem(aspect) {
            return Err(problem);
        }
        // Rays leave from up to `reach` away from the eye (the lens's disc, an
        // orthographic view), so the eye must stay that far inside the limit.
        let reach = self.optics.reach(aspect)
            + self
                .plane
                .filter(|p| p.orthographic)
                .map_or(0.0, |p| (0.5 * (p.right.length() + p.up.length())) as f32);
        let eye_problem =
            |name: &str, eye: Vec3| {
                (!(eye.abs() + Vec3::splat(reach)).cmple(Vec3::splat(RAY_LIMIT)).all()).then(|| {
                let beside = if reach > 0.0 {
                    format!(" once the lens or view adds {reach:e}")
                } else {
                    String::new()
                };
                CameraProblem {
                    key: format!("{name}.eye"),
                    message: format!(
                        "{} lies beyond {RAY_LIMIT:e}, the largest ray origin Embree takes{beside}",
                        sci(eye)
                    ),
                }
            })
            };
        if let Some(plane) = &self.plane {
            if !self.optics.is_pinhole() {
                return problem(
                    "camera.direction".into(),
                    "a camera given by its image plane is a pinhole: it takes no lens, \
                     fov_axis or orthographic projection"
                        .into(),
                );
            }
            if !self.keys.is_empty() {
                return problem(
                    "camera.keys".into(),
                    "a camera given by its image plane cannot also follow a path of keys".into(),
                );
            }
            // The plane first: its vectors size an orthographic view's reach.
            if let Some((key, message)) = plane.problem() {
                return problem(key.into(), message);
            }
            return eye_problem("camera", self.eye).map_or(Ok(()), Err);
        }
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
            if let Some(p) = eye_problem(&name, k.eye) {
                return Err(p);
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
        if let Some(plane) = &self.plane {
            return plane.frame(self.eye, self.width, self.height);
        }
        // In f64: a view a billionth long, or ten billion, still has a direction.
        let eye = self.eye.as_dvec3();
        let forward = (self.look_at.as_dvec3() - eye).normalize_or_zero();
        let right = forward.cross(self.up.as_dvec3()).normalize_or_zero();
        let true_up = right.cross(forward);
        let aspect = f64::from(self.width) / f64::from(self.height);
        let half_fov = (0.5 * f64::from(self.fov)).to_radians().tan();
        let (half_w, half_h, centre, parallel) = match self.optics.projection {
            Projection::Perspective => (half_fov * aspect, half_fov, forward, None),
            Projection::PerspectiveX => (half_fov, half_fov / aspect, forward, None),
            Projection::Orthographic { view_width } => {
                let half = 0.5 * f64::from(view_width);
                (half, half / aspect, DVec3::ZERO, Some(forward))
            }
        };
        let pixel = 2.0 * half_h / f64::from(self.height);
        let lens = self.optics.lens.map(|l| LensFrame {
            right: right * f64::from(l.aperture),
            up: true_up * f64::from(l.aperture),
            forward,
            focus_distance: f64::from(l.focus_distance),
        });
        CameraFrame {
            eye,
            right: right * pixel,
            down: -true_up * pixel,
            top_left: centre - right * half_w + true_up * half_h,
            parallel,
            lens,
        }
    }
}

impl Optics {
    /// What keeps these optics from making rays, if anything: a view width,
    /// aperture or focus distance that is not a finite positive number (an
    /// aperture may be 0: a pinhole), or one so large that rays would start
    /// or aim beyond Embree's limit (`RAY_LIMIT`; a ray Embree rejects aborts
    /// the process). An orthographic view's height is its width over the
    /// image's `aspect`, so a tall image bounds the width more.
    fn problem(&self, aspect: f32) -> Option<CameraProblem> {
        let bad = |key: &str, value: f32, zero: bool, scale: f32| {
            let ok = value.is_finite() && (value > 0.0 || zero && value == 0.0);
            let limit = RAY_LIMIT / scale;
            if !ok {
                Some(format!(
                    "expected a finite number {} 0, found {value}",
                    if zero { "of at least" } else { "above" }
                ))
            } else {
                (value > limit).then(|| {
                    format!("expected at most {limit:e} (rays must stay within {RAY_LIMIT:e}), found {value:e}")
                })
            }
            .map(|message| CameraProblem {
                key: format!("camera.{key}"),
                message,
            })
        };
        let width = match self.projection {
            Projection::Orthographic { view_width } => {
                bad("view_width", view_width, false, Self::view_scale(aspect))
            }
            _ => None,
        };
        width.or_else(|| {
            self.lens.and_then(|l| {
                bad("aperture", l.aperture, true, 1.0)
                    .or_else(|| bad("focus_distance", l.focus_distance, false, 1.0))
            })
        })
    }
}

impl ImagePlane {
    /// What keeps this plane from making rays, if anything, with the key to
    /// blame (POV-Ray's names): a vector that is not finite; right and up zero
    /// or (nearly) parallel, so they span no plane; or a plane that (nearly)
    /// passes through the eye, where rays at the image's centre would have no
    /// direction. "Nearly" is [`MIN_VIEW`], relative to the vectors' sizes, so
    /// the plane's scale never matters (its rays are normalised).
    fn problem(&self) -> Option<(&'static str, String)> {
        let named = [
            ("camera.direction", self.direction),
            ("camera.right", self.right),
            ("camera.up", self.up),
        ];
        if let Some((key, v)) = named.iter().find(|(_, v)| !v.is_finite()) {
            return Some((key, format!("expected finite numbers, found {}", sci(*v))));
        }
        let [d, r, u] = [self.direction, self.right, self.up];
        let normal = r.cross(u);
        // NaN when right or up is zero.
        let sine = normal.length() / (r.length() * u.length());
        if sine.is_nan() || sine < MIN_VIEW {
            return Some((
                "camera.right",
                format!(
                    "right {} and up {} must span the image plane: they are zero or parallel \
                     (at a sine of {sine:.2e}; it must be at least {MIN_VIEW:e})",
                    sci(self.right),
                    sci(self.up)
                ),
            ));
        }
        // The eye's distance from the plane, against the largest of its vectors.
        let distance = d.dot(normal).abs() / normal.length();
        let size = d.length().max(r.length()).max(u.length());
        (distance < MIN_VIEW * size).then(|| {
            (
                "camera.direction",
                format!(
                    "direction {} lies (nearly) in the plane of right and up, {distance:.3e} \
                     from it at vectors of size {size:.3e}: it must leave it by at least \
                     {MIN_VIEW:e} of that",
                    sci(self.direction)
                ),
            )
        })
    }

    /// The frame of an image of `width` × `height` pixels seen through this
    /// plane from `eye`.
    fn frame(&self, eye: Vec3, width: u32, height: u32) -> CameraFrame {
        let [d, r, u] = [self.direction, self.right, self.up];
        if self.orthographic {
            // The plane's size is the view's: not scaled.
            return CameraFrame {
                eye: eye.as_dvec3(),
                right: r / f64::from(width),
                down: -u / f64::from(height),
                top_left: 0.5 * (u - r),
                parallel: Some(d.normalize()),
                lens: None,
            };
        }
        // Rays are normalised, so the plane may be scaled at will: at unit size
        // the sums of the ray directions can neither overflow nor underflow.
        let scale = 1.0 / d.abs().max(r.abs()).max(u.abs()).max_element();
        let (d, r, u) = (scale * d, scale * r, scale * u);
        CameraFrame {
            eye: eye.as_dvec3(),
            right: r / f64::from(width),
            down: -u / f64::from(height),
            top_left: d - 0.5 * r + 0.5 * u,
            parallel: None,
            lens: None,
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
    /// top-left corner: pixel (i, j)'s centre is (i + 0.5, j + 0.5); from
    /// the lens's centre when there is a lens.
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        self.ray64(x, y).rounded()
    }

    /// [`CameraFrame::ray`] in f64, before its rounding to f32.
    pub fn ray64(&self, x: f32, y: f32) -> Ray64 {
        let at = self.top_left + f64::from(x) * self.right + f64::from(y) * self.down;
        match self.parallel {
            Some(forward) => Ray64 {
                origin: self.eye + at,
                dir: forward,
            },
            None => Ray64 {
                origin: self.eye,
                dir: at.normalize(),
            },
        }
    }

    /// The rays of [`CameraFrame::ray64`] as one family from the eye, for a
    /// camera without a lens whose rays all leave the eye; None for others.
    pub fn pinhole(&self) -> Option<Pinhole> {
        (self.parallel.is_none() && !self.has_lens()).then_some(Pinhole {
            eye: self.eye,
            top_left: self.top_left,
            right: self.right,
            down: self.down,
        })
    }

    /// Whether rays need a lens sample ([`CameraFrame::lens_ray`]).
    pub fn has_lens(&self) -> bool {
        self.lens.is_some_and(|l| l.right != DVec3::ZERO)
    }

    /// The ray through (x, y) from the lens point `lens` ∈ [0, 1)² (warped
    /// to the disc concentrically, so stratified samples stay stratified):
    /// aimed at where the pinhole ray meets the plane in focus.
    pub fn lens_ray(&self, x: f32, y: f32, lens: [f32; 2]) -> Ray {
        self.lens_ray64(x, y, lens).rounded()
    }

    /// [`CameraFrame::lens_ray`] in f64, before its rounding to f32.
    pub fn lens_ray64(&self, x: f32, y: f32, lens: [f32; 2]) -> Ray64 {
        let pinhole = self.ray64(x, y);
        let Some(l) = self.lens else {
            return pinhole;
        };
        let [u, v] = concentric_disk(lens).map(f64::from);
        let focus = pinhole.origin + (l.focus_distance / pinhole.dir.dot(l.forward)) * pinhole.dir;
        let origin = pinhole.origin + u * l.right + v * l.up;
        Ray64 {
            origin,
            dir: (focus - origin).normalize(),
        }
    }
}

#[cfg(test)]
mod tests;
