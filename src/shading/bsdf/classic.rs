//! The classic material (POV-Ray's finish) as an energy-conserving layered
//! BSDF: delta reflection and transmission, and beside them a diffuse base and
//! two GGX lobes for the Blinn and Phong highlights.

use std::f32::consts::FRAC_1_PI;

use super::ggx::{Ggx, reflect_about};
use super::{BsdfSample, COS_EPS, Lobe, Transport, mirror, shininess_to_alpha};
use crate::math::Vec3;
use crate::sampling::warp;
use crate::shading::{Finish, fresnel};

/// A classic finish for the path tracer. The delta lobes take the finish's
/// fractions as they are: reflection R(θ) (tinted by `metallic`) and
/// transmission `transmit`, which total internal reflection turns into
/// reflection; where R + transmit exceeds 1 both shrink to sum to 1. The
/// non-delta lobes (diffuse (1 − transmit)·diffuse·pigment/π, and GGX lobes
/// of weight `specular` and `phong`, tinted, with unit Fresnel so that each
/// reflects at most its weight) share what the delta lobes leave at their
/// largest, 1 − max R − transmit: when their weights sum to more, one
/// constant scales them down, so f stays reciprocal and the total albedo
/// never exceeds 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Classic {
    pub albedo: Vec3,
    pub finish: Finish,
    pub ior: f32,
}

/// The lobes' weights, derived from the finish where they are needed.
struct Weights {
    diffuse: Vec3,
    specular: Vec3,
    phong: Vec3,
    /// GGX α of the Blinn lobe (exponent 1/roughness) and of the Phong lobe
    /// (a Phong exponent n is close to a Blinn exponent 4n).
    alpha_specular: f32,
    alpha_phong: f32,
    /// Probabilities of sampling the delta reflection and the delta
    /// transmission (the rest goes to the non-delta lobes); then, within
    /// those, of the diffuse and the Blinn lobe (the rest Phong). The
    /// reflection's follows its fraction at |cos θo| seen from outside, so
    /// that a Fresnel glass is sampled about as it reflects; they depend on
    /// |cos θo| alone, which `pdf` sees too. Any such choice is unbiased as
    /// long as it is nonzero wherever the fraction is, which holds: the
    /// reflected fraction inside is zero only where it is outside.
    pick_reflection: f32,
    pick_transmission: f32,
    pick_diffuse: f32,
    pick_specular: f32,
}

impl Classic {
    /// The largest reflected fraction over all angles.
    fn max_reflection(&self) -> f32 {
        self.finish.reflection.max(self.finish.reflection_max)
    }

    /// What the delta lobes leave to the others at most.
    fn left(&self) -> f32 {
        1.0 - (self.max_reflection() + self.finish.transmit).min(1.0)
    }

    fn weights(&self, cos_o: f32) -> Weights {
        let f = &self.finish;
        let tint = f.tint(self.albedo).max_element();
        let diffuse = f.diffuse_colour(self.albedo);
        let wanted = diffuse.max_element() + (f.specular + f.phong) * tint;
        let left = self.left();
        let scale = if wanted > left { left / wanted } else { 1.0 };
        let (d, s, p) = (
            diffuse.max_element() * scale,
            f.specular * tint * scale,
            f.phong * tint * scale,
        );
        let r = self.finish.reflectance(cos_o, self.ior) * tint;
        let total = r + f.transmit + d + s + p;
        let share = |x: f32| if total > 0.0 { x / total } else { 0.0 };
        let rest = d + s + p;
        let within = |x: f32| if rest > 0.0 { x / rest } else { 0.0 };
        let tint = f.tint(self.albedo);
        Weights {
            diffuse: diffuse * scale,
            specular: tint * (f.specular * scale),
            phong: tint * (f.phong * scale),
            alpha_specular: shininess_to_alpha(1.0 / f.roughness),
            alpha_phong: shininess_to_alpha(4.0 * f.phong_size),
            pick_reflection: share(r),
            pick_transmission: share(f.transmit),
            pick_diffuse: within(d),
            pick_specular: within(s),
        }
    }

    /// Whether any non-delta lobe is left (else only `sample` finds light).
    pub(super) fn has_local(&self) -> bool {
        self.finish.shades_locally() && self.left() > 0.0
    }

    /// The non-delta lobes for two upper-hemisphere directions.
    pub(super) fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let w = self.weights(wo.z);
        // Unit F0: Schlick is then exactly 1, so the lobe's albedo is at most its weight.
        let lobe = |weight: Vec3, alpha: f32| {
            if weight.max_element() > 0.0 {
                weight * Ggx::new(alpha).reflection(Vec3::ONE, wo, wi).x
            } else {
                Vec3::ZERO
            }
        };
        w.diffuse * FRAC_1_PI + lobe(w.specular, w.alpha_specular) + lobe(w.phong, w.alpha_phong)
    }

    /// The density of a non-delta sample at `wi`, for upper-hemisphere directions.
    pub(super) fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let w = self.weights(wo.z);
        let pick_phong = 1.0 - w.pick_diffuse - w.pick_specular;
        let local = w.pick_diffuse * wi.z * FRAC_1_PI
            + w.pick_specular * Ggx::new(w.alpha_specular).pdf(wo, wi)
            + pick_phong.max(0.0) * Ggx::new(w.alpha_phong).pdf(wo, wi);
        (1.0 - w.pick_reflection - w.pick_transmission).max(0.0) * local
    }

    /// u[0] picks the lobe, u[1] and u[2] the direction, for a local `wo` on
    /// either side (the side tells entering from leaving for refraction).
    /// Non-delta samples come back in wo's hemisphere, as the caller's
    /// two-sided wrapper expects them in the upper one: `flip` moves them.
    pub(super) fn sample(&self, wo: Vec3, u: [f32; 3], mode: Transport) -> Option<BsdfSample> {
        let cos = wo.z.abs();
        let w = self.weights(cos);
        let tint = self.finish.tint(self.albedo);
        let reflectance = self.finish.reflectance(wo.z, self.ior);
        let transmit = self.finish.transmit;
        // Where R + transmit exceeds 1 (only if the finish asks for more
        // than all the light), both shrink to fit.
        let fit = 1.0 / (reflectance + transmit).max(1.0);
        let mirror = |fraction: Vec3, pick: f32| {
            let weight = fraction * (fit / pick);
            (weight.max_element() > 0.0).then(|| {
                BsdfSample::new(
                    mirror::reflect(wo),
                    fraction * (fit / cos),
                    pick,
                    weight,
                    Lobe::SpecularReflection,
                )
            })
        };
        if u[0] < w.pick_reflection {
            return mirror(tint * reflectance, w.pick_reflection);
        }
        if u[0] < w.pick_reflection + w.pick_transmission {
            let pick = w.pick_transmission;
            // Total internal reflection: the transmitted fraction reflects.
            let transmitted = self.finish.transmitted(self.albedo);
            let Some(wi) = fresnel::refract(wo, Vec3::Z, self.ior) else {
                return mirror(transmitted, pick);
            };
            if wi.z.abs() < COS_EPS {
                return None;
            }
            let eta = if wo.z > 0.0 { self.ior } else { 1.0 / self.ior };
            let scale = match mode {
                Transport::Radiance => 1.0 / (eta * eta),
                Transport::Importance => 1.0,
            };
            let fraction = transmitted * (fit * scale);
            return Some(BsdfSample::new(
                wi,
                fraction / wi.z.abs(),
                pick,
                fraction / pick,
                Lobe::SpecularTransmission,
            ));
        }
        // The non-delta lobes, in the upper hemisphere.
        let pick_local = 1.0 - w.pick_reflection - w.pick_transmission;
        if pick_local <= 0.0 {
            return None;
        }
        let up = Vec3::new(wo.x, wo.y, cos);
        let local = (u[0] - w.pick_reflection - w.pick_transmission) / pick_local;
        let (wi, kind) = if local < w.pick_diffuse {
            (
                warp::cosine_hemisphere([u[1], u[2]]),
                Lobe::DiffuseReflection,
            )
        } else {
            let alpha = if local < w.pick_diffuse + w.pick_specular {
                w.alpha_specular
            } else {
                w.alpha_phong
            };
            let h = Ggx::new(alpha).sample_normal(up, u[1], u[2]);
            (reflect_about(up, h), Lobe::GlossyReflection)
        };
        if wi.z < COS_EPS {
            return None;
        }
        let f = self.eval(up, wi);
        let pdf = self.pdf(up, wi);
        if !pdf.is_finite() || pdf <= 0.0 {
            return None;
        }
        let side = 1.0f32.copysign(wo.z);
        Some(BsdfSample::new(
            Vec3::new(wi.x, wi.y, side * wi.z),
            f,
            pdf,
            f * (wi.z / pdf),
            kind,
        ))
    }
}
