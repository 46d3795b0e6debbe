//! The Whitted ray tree: local shading with shadow rays at diffuse and plastic
//! surfaces, and recursive specular reflection and Snell refraction at mirrors
//! and dielectrics, down to a depth limit or until a branch's weight is too
//! small to matter. Which of these rays exist at all is the plan's decision.

use super::{Plan, RayStats};
use crate::accel::Accel;
use crate::film::Sample;
use crate::math::{Ray, Vec3, offset};
use crate::scene::{Interaction, Scene};
use crate::shading::{Material, MaterialKind};

/// The kinds of secondary ray the tree spawns, for the statistics.
#[derive(Clone, Copy)]
enum Branch {
    Reflection,
    Refraction,
}

pub struct Whitted<'a> {
    pub scene: &'a Scene,
    pub accel: &'a Accel,
    pub plan: Plan,
}

impl Whitted<'_> {
    /// The radiance along a camera ray, with the first hit's AOVs.
    pub fn sample(&self, ray: &Ray, stats: &mut RayStats) -> Sample {
        let hit = self.accel.intersect(ray);
        if !hit.is_hit() {
            return Sample {
                radiance: self.scene.background,
                depth: f32::INFINITY,
                normal: Vec3::ZERO,
                albedo: Vec3::ZERO,
            };
        }
        let it = self.scene.interaction(ray, &hit);
        Sample {
            radiance: self.shade(ray, &it, 0, Vec3::ONE, stats),
            depth: hit.t,
            normal: it.n,
            albedo: self.scene.materials[it.material as usize].albedo,
        }
    }

    fn trace(&self, ray: &Ray, depth: u32, weight: Vec3, stats: &mut RayStats) -> Vec3 {
        let hit = self.accel.intersect(ray);
        if !hit.is_hit() {
            return self.scene.background;
        }
        let it = self.scene.interaction(ray, &hit);
        self.shade(ray, &it, depth, weight, stats)
    }

    fn shade(
        &self,
        ray: &Ray,
        it: &Interaction,
        depth: u32,
        weight: Vec3,
        stats: &mut RayStats,
    ) -> Vec3 {
        let material = &self.scene.materials[it.material as usize];
        let wo = -ray.dir;
        let mut radiance = material.emission;
        match material.kind {
            MaterialKind::Mirror => {
                if self.plan.reflection {
                    let r = material.reflectance();
                    let dir = fresnel::reflect(ray.dir, it.n);
                    radiance +=
                        r * self.spawn(it, dir, depth, weight * r, Branch::Reflection, stats);
                }
            }
            MaterialKind::Dielectric => {
                // Snell and Fresnel need to know which side the ray comes from: the
                // interaction's normal faces the ray, `front` says whether that is outside.
                let outward = if it.front { it.n } else { -it.n };
                let f = fresnel::dielectric(wo.dot(outward), material.ior);
                if self.plan.reflection {
                    let dir = fresnel::reflect(ray.dir, it.n);
                    radiance +=
                        f * self.spawn(it, dir, depth, weight * f, Branch::Reflection, stats);
                }
                if self.plan.refraction
                    && f < 1.0
                    && let Some(dir) = fresnel::refract(wo, outward, material.ior)
                {
                    let t = 1.0 - f;
                    radiance +=
                        t * self.spawn(it, dir, depth, weight * t, Branch::Refraction, stats);
                }
            }
            MaterialKind::Diffuse | MaterialKind::Plastic | MaterialKind::Emissive => {
                if self.plan.shadow {
                    radiance += self.direct(it, material, wo, stats);
                }
                if self.plan.forced {
                    // What a renderer without a plan pays: both branches, weighted by zero.
                    let back = -wo;
                    let mirror = fresnel::reflect(ray.dir, it.n);
                    let _ = self.spawn(it, mirror, depth, weight, Branch::Reflection, stats);
                    let _ = self.spawn(it, back, depth, weight, Branch::Refraction, stats);
                }
            }
        }
        radiance
    }

    /// A secondary ray from `it` along `dir`, if the depth limit and the branch's
    /// weight allow it.
    fn spawn(
        &self,
        it: &Interaction,
        dir: Vec3,
        depth: u32,
        weight: Vec3,
        branch: Branch,
        stats: &mut RayStats,
    ) -> Vec3 {
        if depth >= self.plan.max_depth || weight.max_element() < self.scene.render.min_weight {
            return Vec3::ZERO;
        }
        match branch {
            Branch::Reflection => stats.reflection += 1,
            Branch::Refraction => stats.refraction += 1,
        }
        let ray = Ray::new(offset(it.p, it.error, it.n, dir), dir);
        self.trace(&ray, depth + 1, weight, stats)
    }

    /// Local shading from every light, each tested with a shadow ray.
    fn direct(
        &self,
        it: &Interaction,
        material: &Material,
        wo: Vec3,
        stats: &mut RayStats,
    ) -> Vec3 {
        let mut radiance = Vec3::ZERO;
        for light in &self.scene.lights {
            let incident = light.incident(it.p);
            let cos = it.n.dot(incident.wi);
            if cos <= 0.0 {
                continue;
            }
            let mut shadow = Ray::new(offset(it.p, it.error, it.n, incident.wi), incident.wi);
            // Stop just short of a point light: it is not geometry and cannot occlude itself.
            shadow.tfar = incident.distance * (1.0 - 1e-4);
            stats.shadow += 1;
            if self.accel.occluded(&shadow) {
                continue;
            }
            radiance += material.local_brdf(it.n, wo, incident.wi) * incident.irradiance * cos;
        }
        radiance
    }
}

/// Stand-ins until shading::fresnel lands (same signatures).
mod fresnel {
    use crate::math::Vec3;

    pub fn reflect(v: Vec3, n: Vec3) -> Vec3 {
        v - 2.0 * v.dot(n) * n
    }

    pub fn dielectric(cos_i: f32, ior: f32) -> f32 {
        let (cos_i, eta) = if cos_i >= 0.0 {
            (cos_i, ior)
        } else {
            (-cos_i, 1.0 / ior)
        };
        let sin_t2 = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
        if sin_t2 >= 1.0 {
            return 1.0;
        }
        let cos_t = (1.0 - sin_t2).sqrt();
        let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
        let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
        0.5 * (rs * rs + rp * rp)
    }

    pub fn refract(wo: Vec3, n: Vec3, ior: f32) -> Option<Vec3> {
        let cos_i = wo.dot(n);
        let (n, eta, cos_i) = if cos_i >= 0.0 {
            (n, ior, cos_i)
        } else {
            (-n, 1.0 / ior, -cos_i)
        };
        let sin_t2 = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
        if sin_t2 >= 1.0 {
            return None;
        }
        let cos_t = (1.0 - sin_t2).sqrt();
        Some((-wo / eta + (cos_i / eta - cos_t) * n).normalize())
    }
}
