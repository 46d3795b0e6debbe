//! Local shading: Lambert plus a Blinn-Phong highlight from every light, each
//! tested with a shadow ray.

use super::RayStats;
use crate::accel::Accel;
use crate::film::Sample;
use crate::math::{Ray, Vec3, offset};
use crate::scene::{Interaction, Scene};

/// Shades the first hit of a camera ray.
pub fn shade(scene: &Scene, accel: &Accel, ray: &Ray, stats: &mut RayStats) -> Sample {
    let hit = accel.intersect(ray);
    if !hit.is_hit() {
        return Sample {
            radiance: scene.background,
            depth: f32::INFINITY,
            normal: Vec3::ZERO,
            albedo: Vec3::ZERO,
        };
    }
    let Interaction {
        p,
        error,
        n,
        material,
    } = scene.interaction(ray, &hit);
    let material = &scene.materials[material as usize];
    let wo = -ray.dir;

    let mut radiance = material.emission;
    for light in &scene.lights {
        let incident = light.incident(p);
        let cos = n.dot(incident.wi);
        if cos <= 0.0 {
            continue;
        }
        let mut shadow = Ray::new(offset(p, error, n, incident.wi), incident.wi);
        // Stop just short of a point light: it is not geometry and cannot occlude itself.
        shadow.tfar = incident.distance * (1.0 - 1e-4);
        stats.shadow += 1;
        if accel.occluded(&shadow) {
            continue;
        }
        radiance += material.local_brdf(n, wo, incident.wi) * incident.irradiance * cos;
    }
    Sample {
        radiance,
        depth: hit.t,
        normal: n,
        albedo: material.albedo,
    }
}
