//! POV-Ray's perspective and orthographic cameras: `location`,
//! `direction`, `up`, `right`, `sky`, `angle`, `look_at` and transforms,
//! resolved as POV-Ray 3.7 does into the image plane the rays go through
//! (from the location, or, orthographic, parallel from across the plane).

use glam::{DAffine3, DVec3};

use super::parse::{Loc, Parser};
use super::value::Value;
use crate::error::Result;

/// A camera statement as read, before it is resolved.
#[derive(Clone, Debug)]
pub struct CameraSpec {
    pub location: DVec3,
    pub direction: DVec3,
    pub up: DVec3,
    pub right: DVec3,
    pub sky: DVec3,
    pub angle: Option<f64>,
    pub look_at: Option<DVec3>,
    pub transform: DAffine3,
    pub loc: Loc,
    /// Parallel rays (`orthographic`).
    pub orthographic: bool,
    /// Whether this camera block gave `up` or `right`: an orthographic
    /// camera without either sees what the perspective one would at its
    /// `look_at`.
    pub sized: bool,
}

impl Default for CameraSpec {
    /// POV-Ray's defaults.
    fn default() -> CameraSpec {
        CameraSpec {
            location: DVec3::ZERO,
            direction: DVec3::Z,
            up: DVec3::Y,
            right: DVec3::new(1.33, 0.0, 0.0),
            sky: DVec3::Y,
            angle: None,
            look_at: None,
            transform: DAffine3::IDENTITY,
            loc: Loc::default(),
            orthographic: false,
            sized: false,
        }
    }
}

/// A resolved camera: where it is, and the image plane's three vectors
/// (the ray through image point (u, v) ∈ [0, 1]², v down, is
/// `direction + (u − ½) right + (½ − v) up`; orthographic, it leaves
/// `location + (u − ½) right + (½ − v) up` along `direction`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resolved {
    pub location: DVec3,
    pub direction: DVec3,
    pub right: DVec3,
    pub up: DVec3,
    pub orthographic: bool,
}

/// Where POV-Ray's camera looks when no `look_at` is given.
const DEFAULT_LOOK_AT: DVec3 = DVec3::Z;

impl CameraSpec {
    /// The camera as POV-Ray 3.7 sets it up: `angle` fixes the direction's
    /// length from the right vector's; `look_at` turns direction, right and
    /// up about the sky vector, keeping their lengths and the camera's
    /// handedness; the camera's transforms come last.
    pub fn resolve(&self) -> Result<Resolved, String> {
        let (mut direction, mut right, mut up) = (self.direction, self.right, self.up);
        if let Some(angle) = self.angle {
            // An orthographic camera's angle may be 0 (given without a
            // number): it then only sizes the view at look_at, below.
            if !(angle > 0.0 || self.orthographic && angle == 0.0) || angle >= 180.0 {
                return Err(format!(
                    "the camera's angle must be above 0 and below 180 degrees, found {angle}"
                ));
            }
            if angle > 0.0 {
                let length = 0.5 * right.length() / (angle.to_radians() / 2.0).tan();
                direction = direction.normalize_or_zero() * length;
            }
        }
        if let Some(look_at) = self.look_at {
            let handedness = up.cross(direction).dot(right);
            let (dl, ul, rl) = (direction.length(), up.length(), right.length());
            let d = (look_at - self.location).normalize_or_zero();
            if d == DVec3::ZERO {
                return Err("the camera looks at its own location: no view".into());
            }
            // Looking along the sky (a view straight down, say), POV-Ray
            // keeps the right vector given (or its default) and warns (see
            // `sky_along_view`).
            let across = if self.sky_along_view() {
                right
            } else {
                self.sky.cross(d)
            };
            let r = across.normalize_or_zero();
            if r == DVec3::ZERO || r.cross(d) == DVec3::ZERO {
                return Err("the camera looks along its sky and its right vector: no view".into());
            }
            let u = d.cross(r).normalize();
            direction = d * dl;
            right = r * if handedness >= 0.0 { rl } else { -rl };
            up = u * ul;
        }
        // POV-Ray sizes an orthographic view given neither up nor right,
        // or given an angle, to what the perspective camera sees at the
        // look_at distance.
        if self.orthographic && (!self.sized || self.angle.is_some()) {
            let (k1, k2) = (
                (self.look_at.unwrap_or(DEFAULT_LOOK_AT) - self.location).length(),
                direction.length(),
            );
            if k1 > 1e-10 && k2 > 1e-10 {
                right *= k1 / k2;
                up *= k1 / k2;
            }
        }
        let m = self.transform;
        // Whether the three vectors make rays is `Camera::check`'s to say.
        let resolved = Resolved {
            location: m.transform_point3(self.location),
            direction: m.transform_vector3(direction),
            right: m.transform_vector3(right),
            up: m.transform_vector3(up),
            orthographic: self.orthographic,
        };
        Ok(resolved)
    }
}

impl CameraSpec {
    /// Whether `look_at` lies along the sky vector from the camera, where
    /// the sky gives no right vector: POV-Ray's test, each component of
    /// sky × the unit view below its EPSILON (1e-10).
    pub fn sky_along_view(&self) -> bool {
        self.look_at.is_some_and(|look_at| {
            let d = (look_at - self.location).normalize_or_zero();
            self.sky.cross(d).abs().max_element() < 1e-10
        })
    }
}

impl Parser {
    /// `camera { … }` after its keyword.
    pub fn camera_block(&mut self) -> Result<CameraSpec> {
        let mut c = CameraSpec {
            loc: self.last(),
            ..CameraSpec::default()
        };
        self.expect('{')?;
        // `camera { Declared … }` goes on from the declared camera.
        if let Some(w) = self.peek_word()?
            && let Some(Value::Camera(base)) = self.symbol(&w)
        {
            c = CameraSpec {
                loc: c.loc,
                sized: false,
                ..(**base).clone()
            };
            self.next()?;
        }
        // A camera of another kind (read as a perspective one) may see 180
        // degrees or more, which no perspective camera can.
        let mut other_kind = false;
        while !self.eat('}')? {
            let loc = self.here();
            let word = self.word()?;
            if let Some(t) = self.transform_item(&word)? {
                c.transform = t * c.transform;
                continue;
            }
            match word.as_str() {
                "location" => c.location = self.vector()?,
                "direction" => c.direction = self.vector()?,
                "up" => {
                    c.up = self.vector()?;
                    c.sized = true;
                }
                "right" => {
                    c.right = self.vector()?;
                    c.sized = true;
                }
                "sky" => c.sky = self.vector()?,
                "look_at" => c.look_at = Some(self.vector()?),
                // An orthographic camera's angle may stand alone.
                "angle" if c.orthographic && !self.starts_number()? => c.angle = Some(0.0),
                "angle" => {
                    let angle = self.float()?;
                    // A spherical camera's second, vertical angle.
                    if other_kind && self.eat(',')? && self.starts_number()? {
                        self.float()?;
                    }
                    if other_kind && angle >= 180.0 {
                        self.warn(
                            loc,
                            format!(
                                "angle {angle}: a perspective camera sees less than 180 \
                                 degrees, so POV-Ray's default angle is used"
                            ),
                        );
                    } else {
                        c.angle = Some(angle);
                    }
                }
                "perspective" => c.orthographic = false,
                "orthographic" => c.orthographic = true,
                "fisheye" | "ultra_wide_angle" | "omnimax" | "panoramic" | "cylinder"
                | "spherical" => {
                    self.skip_warning(loc, &word, "the camera is read as a perspective one");
                    other_kind = true;
                    c.orthographic = false;
                    if word == "cylinder" {
                        self.float()?;
                    }
                }
                "aperture" | "blur_samples" | "focal_point" | "confidence" | "variance" => {
                    self.skip_warning(loc, &word, "no depth of field: everything is in focus");
                    self.expression(false)?;
                }
                other => self.unknown_item(loc, other, "camera")?,
            }
        }
        Ok(c)
    }
}
