//! The environment light: radiance arriving from infinitely far away in every
//! direction, from an equirectangular (latitude-longitude) map or a constant.
//! Rays that leave the scene see it, and the path tracer samples it by
//! importance: a piecewise-constant density over the map's texels in
//! proportion to luminance × sin θ (the texel's share of the sphere), as
//! pbrt-v4's `ImageInfiniteLight` and Mitsuba's `envmap` do.
//!
//! The map's directions are Mitsuba 3's (`envmap`), with +Y up: texel column
//! u ∈ [0, 1) is the azimuth φ = 2π u and row v ∈ [0, 1) (from the top) the
//! polar angle θ = π v from +Y, so the direction is
//! (sin θ sin φ, cos θ, −sin θ cos φ): the top row is straight up, the
//! middle row the horizon, u = 0 looks along −Z and u = 0.5 along +Z.
//! `rotation` then turns the map about +Y by that many degrees,
//! right-handed (u = 0.5 turns from +Z towards +X). Each texel's radiance
//! is constant over the texel (nearest lookup), so the sampling density
//! follows the radiance exactly.

use std::f32::consts::PI;
use std::fmt;
use std::path::PathBuf;

use super::Incident;
use super::emit::bounding_disk;
use crate::math::{Bounds, LUMINANCE, Vec3};
use crate::sampling::Piecewise2D;

/// The rows a constant environment is sampled with: its density then
/// follows sin θ row by row, close to uniform over the sphere.
const CONSTANT_ROWS: usize = 16;

/// What the scene file said, as `info` prints it and the scene hash records
/// it: the map by its contents, not by its path.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct EnvironmentSource {
    /// The map file, or None for a constant radiance.
    #[serde(skip)]
    pub file: Option<PathBuf>,
    /// SHA-256 of the map file, hex.
    pub sha256: Option<String>,
    /// The constant radiance, for an environment without a map.
    pub radiance: Option<[f32; 3]>,
    pub scale: f32,
    /// Degrees about +Y.
    pub rotation: f32,
}

#[derive(Clone, PartialEq)]
pub struct Environment {
    width: usize,
    height: usize,
    /// Radiance (scale applied, negative and NaN values as 0), rows from the top.
    texels: Vec<Vec3>,
    /// cos and sin of the rotation about +Y.
    turn: [f32; 2],
    distribution: Piecewise2D,
    pub source: EnvironmentSource,
}

impl fmt::Debug for Environment {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Environment")
            .field("width", &self.width)
            .field("height", &self.height)
            .field("source", &self.source)
            .finish_non_exhaustive()
    }
}

impl Environment {
    /// The same radiance from every direction.
    pub fn constant(radiance: Vec3) -> Environment {
        let source = EnvironmentSource {
            file: None,
            sha256: None,
            radiance: Some(radiance.to_array()),
            scale: 1.0,
            rotation: 0.0,
        };
        Environment::new(1, vec![radiance; CONSTANT_ROWS], source)
    }

    /// A map of `width` texels a row (rows from the top), each texel's RGB
    /// scaled by `source.scale` and turned by `source.rotation`.
    pub fn map(width: usize, texels: &[[f32; 4]], source: EnvironmentSource) -> Environment {
        let scale = source.scale;
        let texels = texels
            .iter()
            .map(|t| Vec3::new(t[0], t[1], t[2]) * scale)
            .collect();
        Environment::new(width, texels, source)
    }

    fn new(width: usize, texels: Vec<Vec3>, source: EnvironmentSource) -> Environment {
        let texels: Vec<Vec3> = texels
            .into_iter()
            .map(|t| Vec3::from_array(t.to_array().map(|c| if c > 0.0 { c } else { 0.0 })))
            .collect();
        let height = texels.len() / width;
        let weights: Vec<f32> = texels
            .chunks(width)
            .enumerate()
            .flat_map(|(row, texels)| {
                let sin = (PI * (row as f32 + 0.5) / height as f32).sin();
                texels.iter().map(move |t| t.dot(LUMINANCE) * sin)
            })
            .collect();
        let (sin, cos) = source.rotation.to_radians().sin_cos();
        Environment {
            width,
            height,
            distribution: Piecewise2D::new(&weights, width),
            texels,
            turn: [cos, sin],
            source,
        }
    }

    /// The map's (u, v) for the unit world direction `dir`, and sin θ.
    fn uv(&self, dir: Vec3) -> ([f32; 2], f32) {
        let [cos, sin] = self.turn;
        let (x, z) = (cos * dir.x - sin * dir.z, sin * dir.x + cos * dir.z);
        let y = dir.y.clamp(-1.0, 1.0);
        let u = x.atan2(-z) / (2.0 * PI);
        let u = if u < 0.0 { u + 1.0 } else { u };
        ([u, y.acos() / PI], (1.0 - y * y).max(0.0).sqrt())
    }

    /// The world direction of the map's (u, v), with sin θ.
    fn direction(&self, [u, v]: [f32; 2]) -> (Vec3, f32) {
        let (sin_phi, cos_phi) = (2.0 * PI * u).sin_cos();
        let (sin_theta, cos_theta) = (PI * v).sin_cos();
        let (x, z) = (sin_theta * sin_phi, -sin_theta * cos_phi);
        let [cos, sin] = self.turn;
        let world = Vec3::new(cos * x + sin * z, cos_theta, -sin * x + cos * z);
        (world, sin_theta)
    }

    fn texel(&self, [u, v]: [f32; 2]) -> Vec3 {
        let index = |t: f32, n: usize| ((t * n as f32) as usize).min(n - 1);
        self.texels[index(v, self.height) * self.width + index(u, self.width)]
    }

    /// The radiance arriving along `-dir`, seen looking in the unit direction `dir`.
    pub fn radiance(&self, dir: Vec3) -> Vec3 {
        self.texel(self.uv(dir).0)
    }

    /// A direction drawn with density ∝ luminance, for next-event
    /// estimation; None when the map is black (or at the poles' edge, where
    /// the density in solid angle is undefined).
    pub fn incident(&self, u: [f32; 2]) -> Option<Incident> {
        let sample = self.distribution.sample(u)?;
        let (wi, _) = self.direction(sample.point);
        // The radiance and density of the direction as a bounce that found
        // it sees them (rounding can move a point on a texel's edge across
        // it), so the two MIS weights of a direction always sum to one.
        let pdf = self.pdf(wi);
        (pdf > 0.0).then(|| Incident {
            wi,
            distance: f32::INFINITY,
            irradiance: self.radiance(wi) / pdf,
            pdf,
        })
    }

    /// The solid-angle density with which [`Environment::incident`] draws the
    /// unit direction `dir`.
    pub fn pdf(&self, dir: Vec3) -> f32 {
        let (uv, sin_theta) = self.uv(dir);
        if sin_theta <= 0.0 {
            return 0.0;
        }
        self.distribution.pdf(uv) / (2.0 * PI * PI * sin_theta)
    }

    /// The flux that crosses the scene's bounding disk: π r² ∫ L dω (pbrt-v4's
    /// `ImageInfiniteLight::Phi`), for picking it among the area lights.
    pub fn power(&self, bounds: Bounds) -> Vec3 {
        let (_, radius) = bounding_disk(bounds);
        let (w, h) = (self.width as f32, self.height as f32);
        let integral: Vec3 = self
            .texels
            .chunks(self.width)
            .enumerate()
            .map(|(row, texels)| {
                let band = (PI * row as f32 / h).cos() - (PI * (row + 1) as f32 / h).cos();
                texels.iter().sum::<Vec3>() * (2.0 * PI / w * band)
            })
            .sum();
        PI * radius * radius * integral
    }
}

#[cfg(test)]
mod tests;
