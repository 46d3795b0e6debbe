//! The obvhs backend: a compressed 8-wide BVH (CWBVH), built by PLOC with
//! reinsertion, traversed four child boxes at a time with SSE.
//!
//! obvhs clamps every node's entry distance to a fixed 1e-4 (`EPSILON` in its
//! node test), so a node that the ray leaves before t = 1e-4 is skipped: in a
//! scene a millimetre across, or for a ray spawned next to a surface, real
//! hits vanish. The traversal here runs in a stretched parameter t' = T_SCALE·t
//! (the inverse direction and tfar scaled by a power of two, which is exact),
//! so that cut-off lies at t = 1e-4 / 2^40 ≈ 1e-16 instead. Primitive tests
//! use the caller's own ray and t.

use std::time::Duration;

use glam::Vec3A;
use obvhs::BvhBuildParams;
use obvhs::aabb::Aabb;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh;
use obvhs::ray::{RayHit, safe_inverse};

use super::primitives::{Closest, Primitives};
use crate::error::Result;
use crate::math::{Hit, Ray};
use crate::scene::Scene;

/// 2^40: large enough to push obvhs's cut-off below any t a float scene
/// produces, small enough that scaled inverse directions (at most 2^40 /
/// f32::EPSILON ≈ 1e19) and scaled distances stay far from f32 overflow.
const T_SCALE: f32 = (1u64 << 40) as f32;

pub struct CwbvhScene {
    bvh: CwBvh,
    /// In the BVH's leaf order: leaf slot i tests primitive i.
    primitives: Primitives,
}

impl CwbvhScene {
    pub fn build(scene: &Scene) -> Result<CwbvhScene> {
        let mut primitives = Primitives::from_scene(scene)?;
        let boxes: Vec<Aabb> = primitives
            .padded_bounds()
            .iter()
            .map(|b| Aabb::new(b.min.into(), b.max.into()))
            .collect();
        let bvh = if boxes.is_empty() {
            CwBvh::default()
        } else {
            build_cwbvh(
                &boxes,
                BvhBuildParams::medium_build(),
                &mut Duration::default(),
            )
        };
        primitives.reorder(&bvh.primitive_indices);
        Ok(CwbvhScene { bvh, primitives })
    }

    pub fn intersect(&self, ray: &Ray) -> Hit {
        if self.primitives.is_empty() {
            return Hit::MISS;
        }
        let mut closest = Closest::new(ray);
        self.bvh
            .ray_traverse(traversal_ray(ray), &mut RayHit::none(), |_, slot| {
                if closest.test(&self.primitives, slot) {
                    closest.tfar() * T_SCALE
                } else {
                    f32::INFINITY
                }
            });
        closest.hit()
    }

    /// Any hit ends the traversal.
    pub fn occluded(&self, ray: &Ray) -> bool {
        if self.primitives.is_empty() {
            return false;
        }
        // ray_traverse_miss stops at the first t below tmax: −∞ for a blocker.
        !self.bvh.ray_traverse_miss(traversal_ray(ray), |_, slot| {
            if self.primitives.occludes(slot, ray) {
                f32::NEG_INFINITY
            } else {
                f32::INFINITY
            }
        })
    }

    /// The nodes (80 bytes each), the leaf-to-primitive indices and the primitives.
    pub fn memory_bytes(&self) -> usize {
        self.bvh.nodes.capacity() * size_of::<obvhs::cwbvh::node::CwBvhNode>()
            + self.bvh.primitive_indices.capacity() * size_of::<u32>()
            + self.primitives.memory_bytes()
    }
}

/// The ray obvhs traverses, in the stretched parameter t' = T_SCALE·t.
/// obvhs reads only the signs of `direction` (for the child order), the
/// origin, the inverse direction and tmax.
fn traversal_ray(ray: &Ray) -> obvhs::ray::Ray {
    // −0 + 0 = +0: obvhs takes the sign from `direction < 0` but the inverse's
    // sign from signum, which disagree on −0 and would flip that axis's slab.
    let dir = Vec3A::from(ray.dir) + Vec3A::ZERO;
    obvhs::ray::Ray {
        origin: ray.origin.into(),
        direction: dir,
        inv_direction: T_SCALE * dir.map(safe_inverse),
        tmin: ray.tnear * T_SCALE,
        tmax: ray.tfar * T_SCALE,
    }
}
