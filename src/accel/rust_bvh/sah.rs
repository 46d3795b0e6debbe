//! The `bvh` crate backend (svenstaro's): a binary BVH split by binned SAH,
//! one primitive a leaf, walked with the crate's allocation-free
//! `traverse_iterator`. The crate's own `Ray` knows no interval and its
//! front-to-back iterator allocates a heap per ray, so the query here is a
//! ray segment whose far end shrinks to the nearest hit found so far: boxes
//! behind it are skipped, as in any closest-hit traversal.

use std::cell::Cell;

use bvh::aabb::{Aabb, Bounded, IntersectsAabb};
use bvh::bounding_hierarchy::{BHShape, BoundingHierarchy};
use bvh::bvh::{Bvh, BvhNode};

use super::primitives::{Closest, Primitives, Slabs};
use crate::accel::panics::PanicSlot;
use crate::error::Result;
use crate::math::{Bounds, Hit, Ray, Ray64, Vec3};

/// A leaf of the crate's BVH: the primitive's box and where the builder put it.
struct Leaf {
    aabb: Aabb<f32, 3>,
    /// Index into `Primitives`.
    primitive: u32,
    node: usize,
}

impl Bounded<f32, 3> for Leaf {
    fn aabb(&self) -> Aabb<f32, 3> {
        self.aabb
    }
}

impl BHShape<f32, 3> for Leaf {
    fn set_bh_node_index(&mut self, index: usize) {
        self.node = index;
    }

    fn bh_node_index(&self) -> usize {
        self.node
    }
}

pub struct SahScene {
    bvh: Bvh<f32, 3>,
    leaves: Vec<Leaf>,
    primitives: Primitives,
    panics: PanicSlot,
}

impl SahScene {
    pub fn build(scene: &crate::scene::Scene) -> Result<SahScene> {
        let primitives = Primitives::from_scene(scene)?;
        let mut leaves: Vec<Leaf> = primitives
            .padded_bounds()
            .iter()
            .enumerate()
            .map(|(i, b)| {
                // Filled by axis: the crate's points are nalgebra's, which we need not name.
                let mut aabb = Aabb::empty();
                for axis in 0..3 {
                    (aabb.min[axis], aabb.max[axis]) = (b.min[axis], b.max[axis]);
                }
                Leaf {
                    aabb,
                    primitive: i as u32,
                    node: 0,
                }
            })
            .collect();
        let bvh = Bvh::build_par(&mut leaves);
        Ok(SahScene {
            bvh,
            leaves,
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
        self.panics.guard(Hit::MISS, || {
            let segment = Segment::new(ray);
            let mut closest = Closest::new(ray, exact);
            for leaf in self.bvh.traverse_iterator(&segment, &self.leaves) {
                if closest.test(&self.primitives, leaf.primitive as usize) {
                    segment.tfar.set(closest.tfar());
                }
            }
            closest.hit()
        })
    }

    /// Every hit in [tnear, tfar), appended to `hits`: no hit shortens the segment.
    pub fn intersect_all(&self, ray: &Ray, hits: &mut Vec<Hit>) {
        self.panics.guard((), || {
            let segment = Segment::new(ray);
            for leaf in self.bvh.traverse_iterator(&segment, &self.leaves) {
                self.primitives
                    .intersect_every(leaf.primitive as usize, ray, hits);
            }
        })
    }

    /// Any hit ends the traversal. A panic counts as no hit, as in `intersect`.
    pub fn occluded(&self, ray: &Ray) -> bool {
        self.panics.guard(false, || {
            let segment = Segment::new(ray);
            self.bvh
                .traverse_iterator(&segment, &self.leaves)
                .any(|leaf| self.primitives.occludes(leaf.primitive as usize, ray))
        })
    }

    /// The slot that records panics caught in this BVH's queries.
    pub(crate) fn panics(&self) -> &PanicSlot {
        &self.panics
    }

    /// A panic caught in a query since the last check.
    pub fn check(&self) -> Result<()> {
        self.panics.check("the bvh traversal")
    }

    /// The nodes, the leaf records and the primitives.
    pub fn memory_bytes(&self) -> usize {
        self.bvh.nodes.capacity() * size_of::<BvhNode<f32, 3>>()
            + self.leaves.capacity() * size_of::<Leaf>()
            + self.primitives.memory_bytes()
    }
}

/// A ray segment [tnear, tfar] as the crate's box query. `tfar` is a `Cell`
/// because the iterator holds the query by shared reference while the
/// traversal shortens it.
struct Segment {
    slabs: Slabs,
    tnear: f32,
    tfar: Cell<f32>,
}

impl Segment {
    fn new(ray: &Ray) -> Segment {
        Segment {
            slabs: Slabs::new(ray),
            tnear: ray.tnear,
            tfar: Cell::new(ray.tfar),
        }
    }
}

impl IntersectsAabb<f32, 3> for Segment {
    fn intersects_aabb(&self, aabb: &Aabb<f32, 3>) -> bool {
        let bounds = Bounds {
            min: Vec3::from_array(std::array::from_fn(|axis| aabb.min[axis])),
            max: Vec3::from_array(std::array::from_fn(|axis| aabb.max[axis])),
        };
        self.slabs.meet(&bounds, self.tnear, self.tfar.get())
    }
}
