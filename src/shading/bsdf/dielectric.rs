//! Smooth glass: Fresnel reflection and Snell refraction, both delta lobes.

use super::{BsdfSample, COS_EPS, Lobe, Transport, mirror};
use crate::math::Vec3;
use crate::shading::fresnel;

/// Smooth glass: Fresnel-weighted choice of mirror reflection or Snell
/// refraction; `tint` filters transmitted light only (reflection off glass
/// is uncoloured).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dielectric {
    pub ior: f32,
    pub tint: Vec3,
}

impl Dielectric {
    /// Zero: no pair of directions has a finite value; only
    /// [`Dielectric::sample`] finds the two directions.
    pub(super) fn eval(&self) -> Vec3 {
        Vec3::ZERO
    }

    /// Zero, as [`Dielectric::eval`].
    pub(super) fn pdf(&self) -> f32 {
        0.0
    }

    /// Reflection with probability F (u0 < F), else refraction, for a local
    /// `wo` on either side: the side tells entering from leaving. `None`
    /// when the refracted direction grazes.
    pub(super) fn sample(&self, wo: Vec3, u0: f32, mode: Transport) -> Option<BsdfSample> {
        let ior = self.ior;
        let reflectance = fresnel::dielectric(wo.z, ior);
        if u0 < reflectance {
            return Some(BsdfSample::new(
                mirror::reflect(wo),
                Vec3::splat(reflectance / wo.z.abs()),
                reflectance,
                Vec3::ONE,
                Lobe::SpecularReflection,
            ));
        }
        // u0 ≥ F means F < 1, so refraction exists (TIR gives F = 1).
        let wi = fresnel::refract(wo, Vec3::Z, ior)?;
        let transmittance = 1.0 - reflectance;
        if wi.z.abs() < COS_EPS || transmittance <= 0.0 {
            return None;
        }
        // η = n_t/n_i seen from wo's side: ior when wo is outside.
        let eta = if wo.z > 0.0 { ior } else { 1.0 / ior };
        let weight = match mode {
            Transport::Radiance => self.tint / (eta * eta),
            Transport::Importance => self.tint,
        };
        Some(BsdfSample::new(
            wi,
            weight * (transmittance / wi.z.abs()),
            transmittance,
            weight,
            Lobe::SpecularTransmission,
        ))
    }
}
