//! The contract between a primitive that answers for itself (an analytic
//! shape, a mesh triangle) and the BVH that traces it. Embree calls it from its
//! user-geometry callbacks; the pure-Rust backends call it from their
//! traversals. It lives outside `embree/` because it is not Embree's: every
//! backend relies on the same three answers.

use crate::math::{Bounds, Ray, Ray64, Vec3};

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
    /// The nearest hit with t in [ray.tnear, ray.tfar), if any. `exact` is
    /// the ray's origin and direction in f64, which round to `ray`'s (its
    /// own widened unless the query had an f64 ray, see `Ray64::for_ray`): a
    /// primitive that computes in f64 solves for it, so a ray that grazes it
    /// is hit or missed as the f64 ray is, not as its rounding is.
    fn intersect(&self, ray: &Ray, exact: &Ray64) -> Option<UserHit>;
    /// Whether any hit lies in [ray.tnear, ray.tfar).
    fn occluded(&self, ray: &Ray) -> bool;
}

/// How far a BVH grows each of `boxes` (on every side): 32 ulps of the
/// largest coordinate of them all. A BVH traverses the f32 ray, which may
/// lie an ulp or so off its f64 ray (`Ray64`) or, axis-parallel, exactly in
/// a box's face, where a slab test gives t = 0 × ∞; a shape whose surface
/// touches its box there (a torus's top) is then grazed by the f64 ray while
/// the f32 ray passes just outside the box. The padding puts every face
/// clear of that, at no cost in culling.
pub fn padding(boxes: impl Iterator<Item = Bounds>) -> f32 {
    let all = boxes.fold(Bounds::EMPTY, |a, b| a.union(b));
    32.0 * f32::EPSILON * all.min.abs().max(all.max.abs()).max_element()
}

/// The box Embree holds for a primitive whose bounds are `b`: grown by
/// `pad` (near f32's limit, where that overflows, as it is); an empty or
/// infinite box, which Embree's builder would refuse, is the point at the
/// origin.
pub fn held(b: Bounds, pad: f32) -> Bounds {
    let finite = |b: &Bounds| !b.is_empty() && b.min.is_finite() && b.max.is_finite();
    if !finite(&b) {
        return Bounds {
            min: Vec3::ZERO,
            max: Vec3::ZERO,
        };
    }
    Some(b.grown(pad)).filter(finite).unwrap_or(b)
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
    exact: &Ray64,
    mut visit: impl FnMut(&UserHit) -> bool,
) -> Option<UserHit> {
    let mut rest = *ray;
    for _ in 0..MAX_CROSSINGS {
        let hit = prim
            .intersect(&rest, exact)
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
