//! Plastic: a diffuse base under a glossy GGX coat.

use std::f32::consts::{FRAC_1_PI, PI};

use super::ggx::{Ggx, reflect_about};
use super::{BsdfSample, COS_EPS, Lobe};
use crate::math::Vec3;
use crate::sampling::warp;
use crate::shading::fresnel;

/// A diffuse base under a glossy coat: GGX with Schlick Fresnel (F0 =
/// `specular`) plus Ashikhmin & Shirley's (2000) coupled diffuse term,
/// which passes the base only what the coat's Fresnel lets through
/// (1 − F0 head-on, nothing at grazing, where the coat reflects all), so
/// the sum stays ≤ 1 at every angle (plain Lambert + coat exceeds 1 near
/// grazing) and stays reciprocal. A white base keeps 0.89–0.97 of the
/// light up to 45°. `roughness` is GGX α, clamped to
/// [`MIN_ALPHA`, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plastic {
    pub albedo: Vec3,
    pub specular: Vec3,
    pub roughness: f32,
}

impl Plastic {
    /// Coat plus coupled diffuse, for two upper-hemisphere directions. The
    /// diffuse is 28/(23π) · albedo · (1 − F0) · (1 − (1 − cos_o/2)^5)(1 −
    /// (1 − cos_i/2)^5); its directional albedo is albedo·(1 − F0)·(1 − (1 −
    /// cos_o/2)^5), and with the coat's ≈ Schlick(F0, cos_o) the two sum to
    /// at most 1.
    pub(super) fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let diffuse = self.albedo
            * (Vec3::ONE - self.specular)
            * (28.0 / (23.0 * PI) * coat_transmission(wo.z) * coat_transmission(wi.z));
        diffuse + Ggx::new(self.roughness).reflection(self.specular, wo, wi)
    }

    /// The density with which [`Plastic::sample`] picks `wi`: the two lobes'
    /// densities mixed by the probability of choosing each.
    pub(super) fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let p = self.glossy_probability(wo.z);
        p * Ggx::new(self.roughness).pdf(wo, wi) + (1.0 - p) * wi.z * FRAC_1_PI
    }

    /// u[0] picks the coat (a visible-normal reflection) or the base (the
    /// cosine), u[1] and u[2] the direction; `None` below the horizon.
    pub(super) fn sample(&self, wo: Vec3, u: [f32; 3]) -> Option<BsdfSample> {
        let p = self.glossy_probability(wo.z);
        let (wi, kind) = if u[0] < p {
            let h = Ggx::new(self.roughness).sample_normal(wo, u[1], u[2]);
            (reflect_about(wo, h), Lobe::GlossyReflection)
        } else {
            (
                warp::cosine_hemisphere([u[1], u[2]]),
                Lobe::DiffuseReflection,
            )
        };
        if wi.z < COS_EPS {
            return None;
        }
        let f = self.eval(wo, wi);
        let pdf = self.pdf(wo, wi);
        if !pdf.is_finite() || pdf <= 0.0 {
            return None;
        }
        let weight = f * (wi.z / pdf);
        Some(BsdfSample::new(wi, f, pdf, weight, kind))
    }

    /// The probability of sampling the coat rather than the base, from the
    /// two lobes' approximate directional albedos at `cos_o`, so each lobe is
    /// sampled about as often as it contributes. Depends on wo only (pdf()
    /// must be able to recompute it).
    fn glossy_probability(&self, cos_o: f32) -> f32 {
        let glossy = fresnel::schlick(self.specular, cos_o).max_element();
        let diffuse =
            (self.albedo * (Vec3::ONE - self.specular)).max_element() * coat_transmission(cos_o);
        let total = glossy + diffuse.max(0.0);
        if total > 0.0 { glossy / total } else { 1.0 }
    }
}

/// The factor (1 − (1 − cos/2)^5) of Ashikhmin & Shirley's diffuse term: the
/// part of the light the coat lets through, averaged over the coat's Fresnel.
pub(super) fn coat_transmission(cos: f32) -> f32 {
    1.0 - (1.0 - 0.5 * cos).powi(5)
}
