//! Analytic shapes as Embree user primitives: f32 world rays in, f64 object
//! space math in `geometry`, f32 hits out.

use glam::DVec3;

use super::primitive::{UserHit, UserPrimitive};
use crate::geometry::Shape;
use crate::math::{Bounds, Ray};

fn f64_ray(ray: &Ray) -> (DVec3, DVec3) {
    (ray.origin.as_dvec3(), ray.dir.as_dvec3())
}

impl UserPrimitive for Shape {
    fn bounds(&self) -> Bounds {
        Shape::bounds(self)
    }

    fn intersect(&self, ray: &Ray) -> Option<UserHit> {
        let (o, d) = f64_ray(ray);
        let hit = Shape::intersect(self, o, d, f64::from(ray.tnear), f64::from(ray.tfar))?;
        Some(UserHit {
            t: hit.t as f32,
            ng: hit.normal.normalize_or_zero().as_vec3(),
            // Which CSG leaf was hit, for its material and error bound
            // (`Shape::material_of`): exact in f32 below 2^24 leaves.
            u: hit.part as f32,
            // The bound on t's error, rounded up to f32, for the shading
            // point's offset (`Scene::interaction`).
            v: round_up_f32(hit.error),
        })
    }

    fn occluded(&self, ray: &Ray) -> bool {
        let (o, d) = f64_ray(ray);
        Shape::occluded(self, o, d, f64::from(ray.tnear), f64::from(ray.tfar))
    }
}

/// The least f32 at or above x (x finite and not negative).
fn round_up_f32(x: f64) -> f32 {
    let r = x as f32;
    if f64::from(r) < x { r.next_up() } else { r }
}
