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
