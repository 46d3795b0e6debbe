//! The GGX (Trowbridge-Reitz) microfacet distribution the rough lobes share:
//! D, Smith's Λ with G1 and the height-correlated G2, the microfacet BRDF with
//! Schlick Fresnel, and sampling of the visible normals with its pdf (the
//! model is pbrt-v4's `TrowbridgeReitzDistribution`). Directions are local,
//! in the upper hemisphere with z ≥ [`COS_EPS`](super::COS_EPS).

use std::f32::consts::{PI, TAU};

use crate::math::Vec3;
use crate::shading::fresnel;

/// The smallest GGX α used. Below it the peak D = 1/(πα²) and the sampled
/// half-vectors stop being representable well in f32; a smoother surface is
/// a mirror and should use [`Bsdf::Mirror`](super::Bsdf::Mirror).
pub const MIN_ALPHA: f32 = 1e-3;

/// Maps a Blinn-Phong exponent s to a GGX α by α = √(2/(s+2)), the usual
/// match of the two distributions' widths (Walter et al. 2007 give
/// s = 2α⁻² − 2). s = 0 (or missing) gives α = 1; the result is clamped to
/// [`MIN_ALPHA`, 1].
pub fn shininess_to_alpha(shininess: f32) -> f32 {
    (2.0 / (shininess.max(0.0) + 2.0))
        .sqrt()
        .clamp(MIN_ALPHA, 1.0)
}

/// An isotropic GGX distribution of microfacet normals.
#[derive(Clone, Copy, Debug)]
pub(super) struct Ggx {
    alpha: f32,
}

impl Ggx {
    /// The distribution of a lobe's `roughness` (GGX α), clamped to
    /// [`MIN_ALPHA`, 1]; NaN becomes the smoothest, so a bad value cannot
    /// produce NaN.
    pub(super) fn new(roughness: f32) -> Ggx {
        let alpha = if roughness.is_nan() {
            MIN_ALPHA
        } else {
            roughness.clamp(MIN_ALPHA, 1.0)
        };
        Ggx { alpha }
    }

    /// D(h) = α² / (π (h_x² + h_y² + α² h_z²)²) for a unit h: the same as the
    /// textbook α²/(π((α²−1)cos²+1)²) but without the cancellation that form
    /// suffers near the peak for small α.
    fn d(&self, h: Vec3) -> f32 {
        let a = self.alpha;
        let a2 = a * a;
        let d = h.x * h.x + h.y * h.y + a2 * h.z * h.z;
        a2 / (PI * d * d)
    }

    /// Smith's Λ, (√(1 + α² tan²θ) − 1)/2, written as x / (2(1 + √(1 + x)))
    /// with x = α² tan²θ to avoid cancellation for small x. w.z ≥ COS_EPS
    /// here, so tan² ≤ 1e12 stays finite.
    pub(super) fn lambda(&self, w: Vec3) -> f32 {
        let a = self.alpha;
        let tan2 = (w.x * w.x + w.y * w.y) / (w.z * w.z);
        let x = a * a * tan2;
        x / (2.0 * (1.0 + (1.0 + x).sqrt()))
    }

    /// The masking of one direction, G1(w) = 1/(1 + Λ(w)).
    fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// The height-correlated masking-shadowing G2 = 1/(1 + Λ(wo) + Λ(wi)),
    /// symmetric in its arguments.
    fn g2(&self, wo: Vec3, wi: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// The microfacet BRDF with Schlick Fresnel (F0 = `f0`) and G2, so f is
    /// reciprocal: a metal, and plastic's coat.
    pub(super) fn reflection(&self, f0: Vec3, wo: Vec3, wi: Vec3) -> Vec3 {
        // wo + wi has z > 0, so h exists and wo·h = |wo + wi|/2 > 0.
        let h = (wo + wi).normalize();
        let g2 = self.g2(wo, wi);
        fresnel::schlick(f0, wi.dot(h)) * (self.d(h) * g2 / (4.0 * wo.z * wi.z))
    }

    /// The density of wi when h is drawn from the visible normals of wo
    /// ([`Ggx::sample_normal`]) and wi is wo mirrored about h: D_wo(h) /
    /// (4 wo·h) with D_wo(h) = G1(wo) (wo·h) D(h) / wo.z, which simplifies to
    /// G1(wo) D(h) / (4 wo.z).
    pub(super) fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let h = (wo + wi).normalize();
        let g1 = self.g1(wo);
        g1 * self.d(h) / (4.0 * wo.z)
    }

    /// A microfacet normal drawn from the normals visible from `wo`, by
    /// Heitz 2018 ("Sampling the GGX Distribution of Visible Normals"):
    /// stretch wo to the hemisphere configuration, sample a point on the
    /// projected disk, unstretch. Unlike sampling D(h) cos θh, the weight
    /// F·G2/G1 never exceeds 1, so glossy paths have bounded variance.
    pub(super) fn sample_normal(&self, wo: Vec3, u1: f32, u2: f32) -> Vec3 {
        let a = self.alpha;
        let vh = Vec3::new(a * wo.x, a * wo.y, wo.z).normalize();
        let len2 = vh.x * vh.x + vh.y * vh.y;
        let t1 = if len2 > 0.0 {
            Vec3::new(-vh.y, vh.x, 0.0) / len2.sqrt()
        } else {
            Vec3::X
        };
        let t2 = vh.cross(t1);
        let r = u1.sqrt();
        let phi = TAU * u2;
        let p1 = r * phi.cos();
        let s = 0.5 * (1.0 + vh.z);
        let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
        let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * vh;
        // α ≥ MIN_ALPHA and nh is a unit vector, so this is never the zero vector.
        Vec3::new(a * nh.x, a * nh.y, nh.z.max(0.0)).normalize()
    }
}

/// The mirror image of `wo` about the (micro)normal `h`.
pub(super) fn reflect_about(wo: Vec3, h: Vec3) -> Vec3 {
    2.0 * wo.dot(h) * h - wo
}
