//! What the pure-Rust BVHs index: every mesh triangle and every analytic shape
//! of a scene in one list, each answering for itself with the ids Embree would
//! give it (mesh index and triangle index; `shapes_geom_id` and shape index).

use super::triangle;
use crate::accel::primitive::{UserHit, UserPrimitive, crossings};
use crate::error::{Error, Result};
use crate::geometry::Shape;
use crate::math::{Bounds, Hit, Ray, Vec3};
use crate::scene::Scene;

#[derive(Clone, Copy, Debug)]
enum Primitive {
    /// The corners are copied, so a test reads one record, not three vertices.
    Triangle {
        corners: [Vec3; 3],
        geom_id: u32,
        prim_id: u32,
    },
    /// An index into `Primitives::shapes`, which is also its `prim_id`.
    Shape(u32),
}

/// The scene's primitives, in the order a BVH's leaves refer to them.
pub(super) struct Primitives {
    list: Vec<Primitive>,
    shapes: Box<[Shape]>,
    shapes_geom_id: u32,
}

impl Primitives {
    /// Every triangle that can be hit, then every shape. Embree drops
    /// triangles with a non-finite corner; a degenerate triangle (zero area)
    /// can never be hit. Leaving both out keeps the BVH free of them while the
    /// others keep their file-order `prim_id`. A vertex index out of range is
    /// an error, as in Embree's builder.
    pub(super) fn from_scene(scene: &Scene) -> Result<Primitives> {
        let mut list = Vec::with_capacity(scene.triangle_count() + scene.shapes.len());
        for (geom_id, mesh) in scene.meshes.iter().enumerate() {
            let count = mesh.positions.len();
            for (prim_id, triangle) in mesh.triangles.iter().enumerate() {
                if let Some(bad) = triangle.iter().find(|&&i| i as usize >= count) {
                    return Err(Error::Input(format!(
                        "geometry {geom_id}: vertex index {bad} out of range (the mesh has {count} vertices)"
                    )));
                }
                let corners = triangle.map(|i| mesh.positions[i as usize]);
                let [a, b, c] = corners;
                if !corners.iter().all(|p| p.is_finite()) || (b - a).cross(c - a) == Vec3::ZERO {
                    continue;
                }
                list.push(Primitive::Triangle {
                    corners,
                    geom_id: geom_id as u32,
                    prim_id: prim_id as u32,
                });
            }
        }
        list.extend((0..scene.shapes.len() as u32).map(Primitive::Shape));
        Ok(Primitives {
            list,
            shapes: scene.shapes.clone().into_boxed_slice(),
            shapes_geom_id: scene.shapes_geom_id(),
        })
    }

    pub(super) fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// Each primitive's box, grown by 32 ulps of the scene's largest
    /// coordinate. A ray lying exactly in a box's face (an axis-parallel ray
    /// through a vertex on the boundary) has a slab that ends at t = 0 give or
    /// take rounding, so the box may be missed though the vertex is hit: obvhs's
    /// quantised test cancels two terms to a few ulps of noise of the scene's
    /// size there, and a zero direction component puts the face at t = 0 ×
    /// ∞. The padding puts every face clear of that, at no cost in culling.
    pub(super) fn padded_bounds(&self) -> Vec<Bounds> {
        let boxes: Vec<Bounds> = self.list.iter().map(|p| self.bounds(p)).collect();
        let scene = boxes.iter().fold(Bounds::EMPTY, |a, &b| a.union(b));
        let largest = scene.min.abs().max(scene.max.abs()).max_element();
        let pad = Vec3::splat(32.0 * f32::EPSILON * largest);
        boxes
            .into_iter()
            .map(|b| Bounds {
                min: b.min - pad,
                max: b.max + pad,
            })
            .collect()
    }

    fn bounds(&self, primitive: &Primitive) -> Bounds {
        match *primitive {
            Primitive::Triangle { corners, .. } => {
                let mut b = Bounds::EMPTY;
                corners.into_iter().for_each(|p| b.grow(p));
                b
            }
            Primitive::Shape(i) => self.shapes[i as usize].bounds(),
        }
    }

    /// Puts the primitives in the order of `order` (old indices), so a BVH's
    /// leaf slots index the list directly.
    pub(super) fn reorder(&mut self, order: &[u32]) {
        self.list = order.iter().map(|&i| self.list[i as usize]).collect();
    }

    /// The hit of primitive `index` within [ray.tnear, ray.tfar], if any.
    #[inline]
    pub(super) fn intersect(&self, index: usize, ray: &Ray) -> Option<Hit> {
        match self.list[index] {
            Primitive::Triangle {
                corners,
                geom_id,
                prim_id,
            } => triangle::intersect(&corners, ray).map(|h| Hit {
                t: h.t,
                geom_id,
                prim_id,
                u: h.u,
                v: h.v,
                ng: h.ng,
            }),
            // As Embree's callback does: a hit only within [tnear, tfar) (the
            // f64 root rounded to f32 may land on tfar, which the shape excluded).
            Primitive::Shape(i) => {
                crossings(&self.shapes[i as usize], ray, |_| true).map(|h| self.shape_hit(i, &h))
            }
        }
    }

    fn shape_hit(&self, shape: u32, hit: &UserHit) -> Hit {
        Hit {
            t: hit.t,
            geom_id: self.shapes_geom_id,
            prim_id: shape,
            u: hit.u,
            v: hit.v,
            ng: hit.ng,
        }
    }

    /// Every hit of primitive `index` within [ray.tnear, ray.tfar), appended to `hits`.
    pub(super) fn intersect_every(&self, index: usize, ray: &Ray, hits: &mut Vec<Hit>) {
        match self.list[index] {
            Primitive::Triangle { .. } => hits.extend(self.intersect(index, ray)),
            Primitive::Shape(i) => {
                crossings(&self.shapes[i as usize], ray, |hit| {
                    hits.push(self.shape_hit(i, hit));
                    false
                });
            }
        }
    }

    /// Whether primitive `index` blocks the ray within its interval.
    #[inline]
    pub(super) fn occludes(&self, index: usize, ray: &Ray) -> bool {
        match self.list[index] {
            Primitive::Triangle { corners, .. } => triangle::intersect(&corners, ray).is_some(),
            Primitive::Shape(i) => UserPrimitive::occluded(&self.shapes[i as usize], ray),
        }
    }

    /// Bytes held: the primitive records plus the shapes' own records (their
    /// polynomials' heap storage, a few hundred bytes a shape, is not counted).
    pub(super) fn memory_bytes(&self) -> usize {
        self.list.capacity() * size_of::<Primitive>() + self.shapes.len() * size_of::<Shape>()
    }
}

/// The nearest hit found so far by a traversal, and the ray shortened to it.
pub(super) struct Closest {
    ray: Ray,
    hit: Hit,
}

impl Closest {
    pub(super) fn new(ray: &Ray) -> Closest {
        Closest {
            ray: *ray,
            hit: Hit::MISS,
        }
    }

    /// Tests primitive `index`; true if it is the nearest hit so far.
    #[inline]
    pub(super) fn test(&mut self, primitives: &Primitives, index: usize) -> bool {
        match primitives.intersect(index, &self.ray) {
            Some(hit) => {
                self.ray.tfar = hit.t;
                self.hit = hit;
                true
            }
            None => false,
        }
    }

    /// The current end of the ray: the nearest hit's t, or the ray's own tfar.
    pub(super) fn tfar(&self) -> f32 {
        self.ray.tfar
    }

    pub(super) fn hit(&self) -> Hit {
        self.hit
    }
}
