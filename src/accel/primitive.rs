//! The contract between a primitive that answers for itself (an analytic
//! shape, a mesh triangle) and the BVH that traces it. Embree calls it from its
//! user-geometry callbacks; the pure-Rust backends call it from their
//! traversals. It lives outside `embree/` because it is not Embree's: every
//! backend relies on the same three answers.

use crate::math::{Bounds, Ray, Vec3};

/// What a user primitive reports for a hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UserHit {
    pub t: f32,
    /// Geometric normal (any length; Embree stores it as given).
    pub ng: Vec3,
    pub u: f32,
    pub v: f32,
}

/// A primitive a BVH traces through Rust calls. Embree calls these from many
/// threads at once, hence `&self` only and `Send + Sync`.
pub trait UserPrimitive: Send + Sync + 'static {
    /// World-space bounds.
    fn bounds(&self) -> Bounds;
    /// The nearest hit with t in [ray.tnear, ray.tfar), if any.
    fn intersect(&self, ray: &Ray) -> Option<UserHit>;
    /// Whether any hit lies in [ray.tnear, ray.tfar).
    fn occluded(&self, ray: &Ray) -> bool;
}

/// The most crossings of one primitive `crossings` visits along one ray: far
/// more than any surface of degree `poly::MAX_DEGREE` or CSG tree of them
/// has, a bound only against a primitive that misreports `tnear`.
const MAX_CROSSINGS: usize = 4096;

/// Visits the hits of `prim` along `ray` in [tnear, tfar), nearest first,
/// until `visit` returns true (the hit it keeps); returns that hit. Each
/// next hit is the nearest beyond the last one's t (f32 steps), so a
/// tangent double root is one hit. Both the all-hits queries and the
/// Embree filter protocol walk a shape's crossings through this.
pub fn crossings<T: UserPrimitive>(
    prim: &T,
    ray: &Ray,
    mut visit: impl FnMut(&UserHit) -> bool,
) -> Option<UserHit> {
    let mut rest = *ray;
    for _ in 0..MAX_CROSSINGS {
        let hit = prim
            .intersect(&rest)
            .filter(|h| h.t >= rest.tnear && h.t < rest.tfar && h.t.is_finite())?;
        if visit(&hit) {
            return Some(hit);
        }
        rest.tnear = hit.t.next_up();
        if rest.tnear >= rest.tfar {
            return None;
        }
    }
    None
}
