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
//!
//! The traversal ray's direction is first scaled by a power of two so that
//! its largest component lies in [1, 2): t' then measures distance, not
//! multiples of the caller's direction. Without it a direction 1e-30 long
//! puts its hits at t' = 2^40 · 1e30, beyond f32, and a long one pushes the
//! cut-off out to real hits.

use std::time::Duration;

use glam::Vec3A;
use obvhs::BvhBuildParams;
use obvhs::aabb::Aabb;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh;
use obvhs::ray::{RayHit, safe_inverse};

use super::primitives::{Closest, Primitives};
use crate::accel::panics::PanicSlot;
use crate::error::{Error, Result};
use crate::math::{Bounds, Hit, Ray, Ray64};
use crate::scene::Scene;

/// 2^40: large enough to push obvhs's cut-off below any t a float scene
/// produces, small enough that scaled inverse directions (at most 2^40 /
/// f32::EPSILON ≈ 1e19) and scaled distances stay far from f32 overflow.
const T_SCALE: f32 = (1u64 << 40) as f32;

pub struct CwbvhScene {
    bvh: CwBvh,
    /// In the BVH's leaf order: leaf slot i tests primitive i.
    primitives: Primitives,
    panics: PanicSlot,
}

impl CwbvhScene {
    pub fn build(scene: &Scene) -> Result<CwbvhScene> {
        let mut primitives = Primitives::from_scene(scene)?;
        let bounds = primitives.padded_bounds();
        check_size(&bounds)?;
        let boxes: Vec<Aabb> = bounds
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
        Ok(CwbvhScene {
            bvh,
            primitives,
            panics: PanicSlot::default(),
        })
    }

    /// The nearest hit; a panic in the traversal or a primitive is a miss
    /// and an error at the next `check`.
    pub fn intersect(&self, ray: &Ray) -> Hit {
        self.nearest(ray, None)
    }

    /// The nearest hit of `exact`'s rounding, the shapes solving for `exact`.
    pub fn intersect_exact(&self, exact: &Ray64) -> Hit {
        self.nearest(&exact.rounded(), Some(exact))
    }

    fn nearest(&self, ray: &Ray, exact: Option<&Ray64>) -> Hit {
        if self.primitives.is_empty() {
            return Hit::MISS;
        }
        self.panics.guard(Hit::MISS, || {
            let mut closest = Closest::new(ray, exact);
            let (traversal, k) = traversal_ray(ray);
            self.bvh
                .ray_traverse(traversal, &mut RayHit::none(), |_, slot| {
                    if closest.test(&self.primitives, slot) {
                        closest.tfar() * k
                    } else {
                        f32::INFINITY
                    }
                });
            closest.hit()
        })
    }

    /// Any hit ends the traversal. A panic counts as no hit, as in `intersect`.
    /// Every hit in [tnear, tfar), appended to `hits`: no hit shortens the ray.
    pub fn intersect_all(&self, ray: &Ray, hits: &mut Vec<Hit>) {
        if self.primitives.is_empty() {
            return;
        }
        self.panics.guard((), || {
            let (traversal, _) = traversal_ray(ray);
            self.bvh
                .ray_traverse(traversal, &mut RayHit::none(), |_, slot| {
                    self.primitives.intersect_every(slot, ray, hits);
                    f32::INFINITY
                });
        })
    }

    pub fn occluded(&self, ray: &Ray) -> bool {
        if self.primitives.is_empty() {
            return false;
        }
        self.panics.guard(false, || {
            // ray_traverse_miss stops at the first t below tmax: −∞ for a blocker.
            !self.bvh.ray_traverse_miss(traversal_ray(ray).0, |_, slot| {
                if self.primitives.occludes(slot, ray) {
                    f32::NEG_INFINITY
                } else {
                    f32::INFINITY
                }
            })
        })
    }

    /// The slot that records panics caught in this BVH's queries.
    pub(crate) fn panics(&self) -> &PanicSlot {
        &self.panics
    }

    /// A panic caught in a query since the last check.
    pub fn check(&self) -> Result<()> {
        self.panics.check("the obvhs traversal")
    }

    /// The nodes (80 bytes each), the leaf-to-primitive indices and the primitives.
    pub fn memory_bytes(&self) -> usize {
        self.bvh.nodes.capacity() * size_of::<obvhs::cwbvh::node::CwBvhNode>()
            + self.bvh.primitive_indices.capacity() * size_of::<u32>()
            + self.primitives.memory_bytes()
    }
}

/// Refuses a scene whose SAH costs overflow f32 in obvhs's builder, which
/// then panics (an index out of bounds) instead of building: a cost is a box's
/// surface area times a primitive count, summed over the tree. The bound
/// allows 64 times the root's area times the count, a wide margin over
/// obvhs's cost constants and sums. Scenes within the loaders' coordinate
/// limit are far inside it.
fn check_size(boxes: &[Bounds]) -> Result<()> {
    let scene = boxes.iter().fold(Bounds::EMPTY, |a, &b| a.union(b));
    if scene.is_empty() {
        return Ok(());
    }
    let d = scene.diagonal().as_dvec3();
    let area = d.x * d.y + d.y * d.z + d.z * d.x;
    let cost = 64.0 * area * boxes.len() as f64;
    if cost <= f64::from(f32::MAX) {
        return Ok(());
    }
    let largest = scene.min.abs().max(scene.max.abs()).max_element();
    Err(Error::Input(format!(
        "the obvhs backend cannot build this scene: with {} primitives reaching a coordinate \
         of {largest:e}, its float32 costs (box area × primitive count × 64 must stay below \
         {:e}) overflow; use --backend embree or bvh, or a smaller scene",
        boxes.len(),
        f32::MAX
    )))
}

/// The ray obvhs traverses, and k: its parameter is t' = k·t. The direction
/// is scaled by 2^-e, which brings its largest component into [1, 2)
/// exactly, and t' stretched by T_SCALE: k = T_SCALE · 2^e. obvhs reads only
/// the signs of `direction` (for the child order), the origin, the inverse
/// direction and tmax.
fn traversal_ray(ray: &Ray) -> (obvhs::ray::Ray, f32) {
    // −0 + 0 = +0: obvhs takes the sign from `direction < 0` but the inverse's
    // sign from signum, which disagree on −0 and would flip that axis's slab.
    let dir = Vec3A::from(ray.dir) + Vec3A::ZERO;
    // The unbiased exponent of the largest component, kept where 2^±e and k are
    // normal f32 (validated rays lie well inside).
    let e = ((dir.abs().max_element().to_bits() >> 23) as i32 - 127).clamp(-100, 80);
    let dir = dir * pow2(-e);
    let k = T_SCALE * pow2(e);
    let traversal = obvhs::ray::Ray {
        origin: ray.origin.into(),
        direction: dir,
        inv_direction: T_SCALE * dir.map(safe_inverse),
        tmin: ray.tnear * k,
        tmax: ray.tfar * k,
    };
    (traversal, k)
}

/// 2^e, exactly, for e in the normal range [−126, 127]: the bits of its exponent.
fn pow2(e: i32) -> f32 {
    f32::from_bits(((e + 127) as u32) << 23)
}
