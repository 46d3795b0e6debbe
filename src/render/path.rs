//! The path tracer: global illumination by BSDF sampling, next-event
//! estimation towards the point and directional lights (delta lights, so no
//! MIS is needed for them), and Russian roulette after a few bounces. Emissive
//! surfaces and the background are reached by BSDF sampling.

use super::Plan;
use super::tally::{Node, RayKind, Tally};
use crate::accel::Accel;
use crate::film::Sample;
use crate::math::{Ray, Vec3, offset};
use crate::sampling::Rng;
use crate::scene::{Interaction, Scene};
use crate::shading::{Bsdf, Frame, Lobe};

/// Bounces before Russian roulette may end a path.
const ROULETTE_AFTER: u32 = 3;

pub struct PathTracer<'a> {
    pub scene: &'a Scene,
    pub accel: &'a Accel,
    pub plan: Plan,
}

impl PathTracer<'_> {
    pub fn sample(&self, camera: &Ray, rng: &mut Rng, tally: &mut Tally) -> Sample {
        let mut radiance = Vec3::ZERO;
        let mut beta = Vec3::ONE;
        let mut ray = *camera;
        let mut kind = RayKind::Camera;
        let mut first = None;
        for depth in 0..=self.plan.max_depth {
            tally.count(kind, depth);
            let hit = self.accel.intersect(&ray);
            if !hit.is_hit() {
                radiance += beta * self.scene.background;
                tally.open(|| Node::of_hit(self.scene, &hit, kind, depth, beta));
                break;
            }
            let it = self.scene.interaction(&ray, &hit);
            let material = &self.scene.materials[it.material as usize];
            // Built only when explain records the tree: nothing is allocated per ray.
            tally.open(|| Node::of_hit(self.scene, &hit, kind, depth, beta));
            if depth == 0 {
                first = Some((hit.t, it.n, material.albedo));
            }
            // Area lights are reached by next-event estimation from non-specular
            // surfaces; counting their emission on BSDF-sampled hits too would count
            // them twice.
            if !material.sampled_light || kind != RayKind::Diffuse {
                radiance += beta * material.emission;
            }
            let bsdf = Bsdf::from_material(material);
            // The BSDF tells inside from outside by the surface's own normal.
            let frame = Frame::from_normal(if it.front { it.n } else { -it.n });
            let wo = -ray.dir;
            if self.plan.shadow && !bsdf.is_delta() {
                radiance += beta * self.direct(&it, &bsdf, &frame, wo, depth, rng, tally);
            }
            let u = [rng.next_f32(), rng.next_f32(), rng.next_f32()];
            let Some(s) = bsdf.sample(&frame, wo, u) else {
                break;
            };
            kind = match s.kind {
                Lobe::DiffuseReflection | Lobe::GlossyReflection => RayKind::Diffuse,
                Lobe::SpecularReflection => RayKind::Reflection,
                Lobe::SpecularTransmission => RayKind::Refraction,
            };
            let allowed = match kind {
                RayKind::Diffuse => self.plan.diffuse,
                RayKind::Reflection => self.plan.reflection,
                _ => self.plan.refraction,
            };
            if !allowed {
                break;
            }
            beta *= s.weight;
            if depth >= ROULETTE_AFTER {
                let survive = beta.max_element().min(0.95);
                if rng.next_f32() >= survive {
                    break;
                }
                beta /= survive;
            }
            ray = Ray::new(offset(it.p, it.error, it.n, s.wi), s.wi);
        }
        let (depth, normal, albedo) = first.unwrap_or((f32::INFINITY, Vec3::ZERO, Vec3::ZERO));
        Sample {
            radiance,
            weight: 1.0,
            depth,
            normal,
            albedo,
        }
    }

    /// Next-event estimation: each light (area lights at one sampled point),
    /// through a shadow ray.
    #[allow(clippy::too_many_arguments)]
    fn direct(
        &self,
        it: &Interaction,
        bsdf: &Bsdf,
        frame: &Frame,
        wo: Vec3,
        depth: u32,
        rng: &mut Rng,
        tally: &mut Tally,
    ) -> Vec3 {
        let mut sum = Vec3::ZERO;
        for light in &self.scene.lights {
            let Some(incident) = light.incident(it.p, rng.next_2d()) else {
                continue;
            };
            let cos = it.n.dot(incident.wi);
            if cos <= 0.0 {
                continue;
            }
            let f = bsdf.eval(frame, wo, incident.wi);
            if f == Vec3::ZERO {
                continue;
            }
            let mut shadow = Ray::new(offset(it.p, it.error, it.n, incident.wi), incident.wi);
            shadow.tfar = incident.distance * (1.0 - 1e-4);
            tally.count(RayKind::Shadow, depth);
            if !self.accel.occluded(&shadow) {
                sum += f * incident.irradiance * cos;
            }
        }
        sum
    }
}
