//! The rough conductor: GGX microfacets with Schlick Fresnel.

use super::ggx::{Ggx, reflect_about};
use super::{BsdfSample, COS_EPS, Lobe};
use crate::math::Vec3;
use crate::shading::fresnel;

/// A rough conductor: GGX microfacets (Smith height-correlated masking,
/// Schlick Fresnel with F0 = `f0`), sampled from the distribution of
/// visible normals (Heitz 2018), so a sample's weight is F·G2/G1 ≤ 1.
/// `roughness` is GGX α (perceptual roughness squared), clamped to
/// [`MIN_ALPHA`, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metal {
    pub f0: Vec3,
    pub roughness: f32,
}

impl Metal {
    /// f for two upper-hemisphere directions.
    pub(super) fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        Ggx::new(self.roughness).reflection(self.f0, wo, wi)
    }

    /// The density with which [`Metal::sample`] picks `wi`.
    pub(super) fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        Ggx::new(self.roughness).pdf(wo, wi)
    }

    /// `wo` mirrored about a visible normal (from u[1], u[2]); `None` below
    /// the horizon.
    pub(super) fn sample(&self, wo: Vec3, u: [f32; 3]) -> Option<BsdfSample> {
        let ggx = Ggx::new(self.roughness);
        let h = ggx.sample_normal(wo, u[1], u[2]);
        let wi = reflect_about(wo, h);
        if wi.z < COS_EPS {
            return None;
        }
        let pdf = ggx.pdf(wo, wi);
        if !pdf.is_finite() || pdf <= 0.0 {
            return None;
        }
        let f = ggx.reflection(self.f0, wo, wi);
        // f·cos/pdf simplifies to F·G2(wo, wi)/G1(wo): no division by
        // a small pdf or cosine, and ≤ F by construction.
        let (lo, li) = (ggx.lambda(wo), ggx.lambda(wi));
        let weight = fresnel::schlick(self.f0, wi.dot(h)) * ((1.0 + lo) / (1.0 + lo + li));
        Some(BsdfSample::new(wi, f, pdf, weight, Lobe::GlossyReflection))
    }
}
