//! Analytic shapes as Embree user primitives: f32 world rays in with their
//! f64 origin and direction (a camera ray's own, see `Ray64`), f64 object
//! space math in `geometry`, f32 hits out.

use super::primitive::{UserHit, UserPrimitive};
use crate::geometry::Shape;
use crate::math::{Bounds, Ray, Ray64};

impl UserPrimitive for Shape {
    fn bounds(&self) -> Bounds {
        Shape::bounds(self)
    }

    fn intersect(&self, ray: &Ray, exact: &Ray64) -> Option<UserHit> {
        let (o, d) = (exact.origin, exact.dir);
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
        let Ray64 { origin, dir } = Ray64::of(ray);
        Shape::occluded(self, origin, dir, f64::from(ray.tnear), f64::from(ray.tfar))
    }
}

/// The least f32 at or above x (x finite and not negative).
fn round_up_f32(x: f64) -> f32 {
    let r = x as f32;
    if f64::from(r) < x { r.next_up() } else { r }
}
