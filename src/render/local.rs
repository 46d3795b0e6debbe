//! Local shading: Lambert plus a Blinn-Phong highlight from every light, each
//! tested with a shadow ray.

use super::RayStats;
use crate::accel::Accel;
use crate::film::Sample;
use crate::math::{Ray, Vec3, gamma, offset};
use crate::scene::Scene;

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
    let mesh = &scene.meshes[hit.geom_id as usize];
    let material = &scene.materials[mesh.materials[hit.prim_id as usize] as usize];
    let [p0, p1, p2] = mesh.triangles[hit.prim_id as usize].map(|i| mesh.positions[i as usize]);
    // The hit point from barycentrics is accurate to the triangle's own scale,
    // unlike o + t·d, whose error grows with the distance travelled.
    let (b1, b2) = (hit.u, hit.v);
    let b0 = 1.0 - b1 - b2;
    let p = b0 * p0 + b1 * p1 + b2 * p2;
    // pbrt bounds each axis by that axis's own terms, which is zero on an axis plane
    // such as x = 0. Embree's triangle test mixes the axes (it works relative to the ray
    // origin), so the bound uses the largest axis for all three: the origin then always
    // leaves the plane by more than Embree's own rounding.
    let error =
        Vec3::splat(gamma(7) * ((b0 * p0).abs() + (b1 * p1).abs() + (b2 * p2).abs()).max_element());
    let mut n = hit.ng.normalize_or_zero();
    if n.dot(ray.dir) > 0.0 {
        n = -n;
    }
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
