//! An emission map on a triangle light (MTL's `map_Ke`): the light's
//! radiance times the map's colour at the point's texture coordinates.

use crate::math::{Vec2, Vec3};
use crate::shading::Texture;

/// A triangle light's emission map and the texture coordinates of its
/// corners (uv0, and uv1 − uv0, uv2 − uv0 along the light's edges).
///
/// Sampling stays uniform in area and the radiance at the sampled point
/// carries the map, which keeps next-event estimation and photon emission
/// unbiased whatever the map; the light picker weighs the triangle by its
/// area × Ke × the map's mean over the whole image, which only steers
/// samples (a triangle whose footprint is darker than the mean is picked
/// more often than its power deserves, at no bias: the mean is positive
/// wherever the map is anywhere).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct EmissionMap {
    pub texture: Texture,
    pub uv0: Vec2,
    pub du: Vec2,
    pub dv: Vec2,
    /// The mean of the image's texels: the map's factor in the light's power.
    pub mean: Vec3,
}

impl EmissionMap {
    /// The map's factor at barycentrics (b1, b2) of the triangle.
    pub fn at(&self, b1: f32, b2: f32) -> Vec3 {
        self.texture.rgb(self.uv0 + b1 * self.du + b2 * self.dv)
    }
}

/// The factor of a triangle light's radiance at (b1, b2): its map's, or 1.
pub(super) fn factor(map: Option<&EmissionMap>, b1: f32, b2: f32) -> Vec3 {
    map.map_or(Vec3::ONE, |m| m.at(b1, b2))
}

#[cfg(test)]
mod tests {
    use std::f32::consts::PI;
    use std::sync::Arc;

    use super::*;
    use crate::lights::Light;
    use crate::math::Bounds;
    use crate::sampling::Rng;
    use crate::shading::{Image, TextureSource};

    /// A unit right triangle at z = 1 facing down, uv its own x and y,
    /// radiance 2 times a 2 × 1 map: black on the left, white on the right.
    fn lamp() -> Light {
        let texture = Texture::new(Arc::new(Image {
            width: 2,
            height: 1,
            texels: vec![[0.0, 0.0, 0.0, 1.0], [1.0, 1.0, 1.0, 1.0]],
            alpha: false,
            source: TextureSource {
                path: "half.png".into(),
                sha256: String::new(),
                srgb: false,
            },
        }));
        let mean = texture.image.mean();
        Light::Triangle {
            p0: Vec3::new(0.0, 0.0, 1.0),
            edge1: Vec3::Y,
            edge2: Vec3::X,
            radiance: Vec3::splat(2.0),
            map: Some(Box::new(EmissionMap {
                texture,
                uv0: Vec2::ZERO,
                du: Vec2::Y,
                dv: Vec2::X,
                mean,
            })),
        }
    }

    /// The lamp's radiance integrated over its area by the midpoint rule:
    /// its true power is π times this.
    fn integrated_radiance(light: &Light) -> f64 {
        let Light::Triangle { radiance, map, .. } = light else {
            unreachable!()
        };
        let steps = 400;
        let cell = 1.0 / steps as f32;
        let mut sum = 0.0f64;
        for i in 0..steps {
            for j in 0..steps - i {
                let (b1, b2) = ((i as f32 + 0.3) * cell, (j as f32 + 0.3) * cell);
                let l = *radiance * factor(map.as_deref(), b1, b2);
                sum += f64::from(l.x * cell * cell);
            }
        }
        sum
    }

    #[test]
    fn photons_and_light_samples_carry_the_mapped_power() {
        let light = lamp();
        let exact = PI as f64 * integrated_radiance(&light);
        let mut rng = Rng::for_sample(9, 0, 0);
        let count = 100_000;
        let (mut flux, mut irradiance) = (0.0f64, 0.0f64);
        // Far below the lamp, its irradiance on a plane facing up is
        // ≈ power / (π d²) (a small Lambertian source seen head-on).
        let d = 100.0;
        let below = Vec3::new(0.3, 0.3, 1.0 - d);
        for _ in 0..count {
            let [a, b] = rng.next_2d();
            let [c, e] = rng.next_2d();
            flux += f64::from(light.emit([a, b, c, e], Bounds::EMPTY).unwrap().flux.x);
            if let Some(inc) = light.incident(below, [a, b]) {
                irradiance += f64::from(inc.irradiance.x * inc.wi.z);
            }
        }
        let (flux, irradiance) = (flux / count as f64, irradiance / count as f64);
        // Per-sample values are 0 or twice the mean, about: σ/mean ≈ 1 and
        // the standard error 0.3% at 1e5 samples; 2% is over 6 of them.
        assert!((flux - exact).abs() < 0.02 * exact, "{flux} vs {exact}");
        let far = exact / (PI as f64 * f64::from(d * d));
        assert!(
            (irradiance - far).abs() < 0.02 * far,
            "{irradiance} vs {far}"
        );
        // The picker's weight uses the image's mean (1/2): a guide only.
        assert_eq!(light.power(Bounds::EMPTY).x, PI * 0.5 * 2.0 * 0.5);
    }
}
