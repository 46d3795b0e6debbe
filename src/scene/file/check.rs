//! Validation of a scene file's values: the range and consistency checks, each
//! failure an error naming the file, the line and the key at fault.

use std::path::Path;

use glam::DVec3;

use super::super::camera::{SizeFault, size_problem};
use super::super::obj::MAX_COORDINATE;
use super::super::{MAX_COLOUR, MAX_DEPTH, PhotonSettings, RenderSettings, locate};
use crate::error::{Error, Result};
use crate::math::{Bounds, Vec3};

/// The machine's memory in bytes, where the system says (Linux), so an image
/// whose film cannot be allocated is refused at load instead of aborting the
/// render. None elsewhere: then only the limit on each side applies.
pub(in crate::scene) fn physical_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Reports the problems of one scene file, each named by its line and key.
pub(super) struct Check<'a> {
    pub path: &'a Path,
    pub text: &'a str,
}

impl Check<'_> {
    pub fn error(&self, key: &str, message: impl std::fmt::Display) -> Error {
        Error::Scene {
            path: self.path.to_owned(),
            message: format!("{}: {message}", self.place(key)),
        }
    }

    /// The key with its line, where it has one: `line 12, materials.m.albedo`.
    pub fn place(&self, key: &str) -> String {
        let line = locate::line_of(self.text, key).map_or(String::new(), |l| format!("line {l}, "));
        format!("{line}{key}")
    }

    /// A position or vector within [`MAX_COORDINATE`].
    pub fn finite(&self, key: &str, v: [f32; 3]) -> Result<Vec3> {
        self.finite64(key, v.map(f64::from)).map(|v| v.as_vec3())
    }

    pub fn finite64(&self, key: &str, v: [f64; 3]) -> Result<DVec3> {
        if v.iter().all(|x| x.abs() <= MAX_COORDINATE) {
            Ok(DVec3::from(v))
        } else {
            Err(self.error(
                key,
                format!("expected finite numbers of size at most {MAX_COORDINATE:e}, found {v:?}"),
            ))
        }
    }

    /// World-space geometry within [`MAX_COORDINATE`]: a transform can scale
    /// coordinates that are each within it far beyond it.
    pub fn bounds(&self, key: &str, bounds: Bounds) -> Result<()> {
        super::super::bounds_problem(bounds).map_or(Ok(()), |message| Err(self.error(key, message)))
    }

    pub fn colour(&self, key: &str, v: [f32; 3]) -> Result<Vec3> {
        if !v.iter().all(|x| (0.0..=MAX_COLOUR).contains(x)) {
            return Err(self.error(
                key,
                format!("expected values >= 0 and at most {MAX_COLOUR:e}, found {v:?}"),
            ));
        }
        Ok(Vec3::from(v))
    }

    pub fn direction(&self, key: &str, v: [f32; 3]) -> Result<Vec3> {
        let d = self.finite(key, v)?;
        if d.length_squared() == 0.0 {
            return Err(self.error(key, "a direction cannot be zero"));
        }
        Ok(d)
    }

    /// A number > 0 and finite, such as an index of refraction or a threshold.
    pub fn positive(&self, key: &str, v: impl Into<f64> + std::fmt::Display + Copy) -> Result<()> {
        let x: f64 = v.into();
        if x > 0.0 && x.is_finite() {
            Ok(())
        } else {
            Err(self.error(key, format!("expected a number > 0, found {v}")))
        }
    }

    /// A fraction in [0, 1], such as a classic finish's `diffuse` or `reflection`.
    pub fn fraction(&self, key: &str, v: f32) -> Result<f32> {
        if (0.0..=1.0).contains(&v) {
            Ok(v)
        } else {
            Err(self.error(key, format!("expected a number from 0 to 1, found {v}")))
        }
    }

    /// The camera's field of view and image size, and the film's memory.
    pub fn image(&self, fov: f32, width: u32, height: u32) -> Result<()> {
        if !(fov > 0.0 && fov < 180.0) {
            return Err(self.error(
                "camera.fov",
                format!("expected degrees in (0, 180), found {fov}"),
            ));
        }
        match size_problem(width, height) {
            None => Ok(()),
            Some((fault, message)) => Err(self.error(
                match fault {
                    SizeFault::Width => "camera.width",
                    SizeFault::Height => "camera.height",
                    SizeFault::Film => "camera",
                },
                message,
            )),
        }
    }

    /// The render settings' ranges, and adaptive sampling's rounds against spp.
    pub fn render(&self, render: &RenderSettings) -> Result<()> {
        if let Some(a) = &render.adaptive {
            // Disagreement needs two samples to measure, and a round to grow by.
            if render.spp < 2 || a.max_spp < render.spp {
                return Err(self.error(
                    "render.adaptive.max_spp",
                    format!(
                        "adaptive sampling takes rounds of spp ({}) samples, which must be at \
                         least 2, up to max_spp ({}), which must be at least spp",
                        render.spp, a.max_spp
                    ),
                ));
            }
            self.positive("render.adaptive.threshold", a.threshold)?;
        }
        if let Some(radius) = render.photons.radius {
            self.positive("render.photons.radius", radius)?;
        }
        if !(render.min_weight >= 0.0 && render.min_weight < 1.0) {
            return Err(self.error(
                "render.min_weight",
                format!("expected a number in [0, 1), found {}", render.min_weight),
            ));
        }
        if render.spp == 0 {
            return Err(self.error("render.spp", "expected at least 1 sample per pixel"));
        }
        if render.max_depth > MAX_DEPTH {
            return Err(self.error(
                "render.max_depth",
                format!(
                    "expected at most {MAX_DEPTH} bounces (the ray tree's stack limit), found {}",
                    render.max_depth
                ),
            ));
        }
        PhotonSettings::check_count(render.photons.count)
            .map_err(|e| self.error("render.photons.count", e))
    }
}
