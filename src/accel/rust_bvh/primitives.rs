//! What the pure-Rust BVHs index: every mesh triangle and every analytic shape
//! of a scene in one list, each answering for itself with the ids Embree would
//! give it (mesh index and triangle index; `shapes_geom_id` and shape index).

use super::triangle;
use crate::accel::cutout::Cutout;
use crate::accel::primitive::{UserHit, UserPrimitive, crossings, padding};
use crate::error::{Error, Result};
use crate::geometry::Mesh;
use crate::geometry::Shape;
use crate::math::{Bounds, Hit, INVALID_ID, Ray, Ray64, Vec3, gamma};
use crate::scene::{Instance, Scene};

#[derive(Clone, Copy, Debug)]
enum Primitive {
    /// The corners are copied (in world space, an instance's moved there), so
    /// a test reads one record, not three vertices.
    Triangle {
        corners: [Vec3; 3],
        geom_id: u32,
        prim_id: u32,
        inst_id: u32,
    },
    /// `Primitives::shapes[index]`, with the ids Embree reports for it; on an
    /// instance, tested in its prototype's space.
    Shape {
        index: u32,
        geom_id: u32,
        prim_id: u32,
        inst_id: u32,
    },
}

/// The scene's primitives, in the order a BVH's leaves refer to them.
pub(super) struct Primitives {
    list: Vec<Primitive>,
    /// The scene's shapes, then each prototype's (once, however many
    /// instances place it).
    shapes: Box<[Shape]>,
    instances: Box<[Instance]>,
    /// The cut-outs of the scene's meshes, by geometry id, then of each
    /// prototype's meshes (an instance's triangles use its prototype's).
    cutouts: Box<[Option<Cutout>]>,
    prototype_cutouts: Box<[Box<[Option<Cutout>]>]>,
    /// Whether any mesh has a cut-out: without, a hit costs one branch more.
    any_cutout: bool,
}

impl Primitives {
    /// Every triangle that can be hit, then every shape, then each
    /// instance's. Instances are flattened: each instance's triangles are
    /// copied into world space (48 bytes a triangle a copy, and the BVH's
    /// nodes over them), its shapes are one record each that points at the
    /// prototype's. Embree drops triangles with a non-finite corner; a
    /// degenerate triangle (zero area) can never be hit. Leaving both out
    /// keeps the BVH free of them while the others keep their file-order
    /// `prim_id`. A vertex index out of range is an error, as in Embree's
    /// builder.
    pub(super) fn from_scene(scene: &Scene) -> Result<Primitives> {
        let count = scene.triangle_count()
            + scene.instanced_triangle_count()
            + scene.shapes.len()
            + scene.instances.len();
        let mut list = Vec::with_capacity(count);
        triangles(&mut list, &scene.meshes, None)?;
        let shapes_geom_id = scene.shapes_geom_id();
        list.extend((0..scene.shapes.len() as u32).map(|i| Primitive::Shape {
            index: i,
            geom_id: shapes_geom_id,
            prim_id: i,
            inst_id: INVALID_ID,
        }));
        let mut shapes = scene.shapes.clone();
        let mut first_shape = Vec::with_capacity(scene.prototypes.len());
        for prototype in &scene.prototypes {
            first_shape.push(shapes.len() as u32);
            shapes.extend(prototype.shapes.iter().cloned());
        }
        for (inst_id, instance) in scene.instances.iter().enumerate() {
            let inst_id = inst_id as u32;
            let p = instance.prototype as usize;
            let prototype = &scene.prototypes[p];
            triangles(&mut list, &prototype.meshes, Some((inst_id, instance)))?;
            list.extend(
                (0..prototype.shapes.len() as u32).map(|i| Primitive::Shape {
                    index: first_shape[p] + i,
                    geom_id: prototype.shapes_geom_id(),
                    prim_id: i,
                    inst_id,
                }),
            );
        }
        let cutouts = Cutout::of_meshes(&scene.meshes, &scene.materials, INVALID_ID, &[], 0);
        // A hit names instance i by i here.
        let prototype_cutouts: Box<[_]> = (scene.prototypes.iter().enumerate())
            .map(|(i, p)| {
                Cutout::of_meshes(&p.meshes, &scene.materials, i as u32, &scene.instances, 0)
            })
            .collect();
        let any_cutout = cutouts
            .iter()
            .chain(prototype_cutouts.iter().flatten())
            .any(Option::is_some);
        Ok(Primitives {
            list,
            shapes: shapes.into_boxed_slice(),
            instances: scene.instances.clone().into_boxed_slice(),
            cutouts,
            prototype_cutouts,
            any_cutout,
        })
    }

    /// Whether the hit at barycentrics (u, v) of triangle `prim_id` of mesh
    /// `geom_id` (of the scene, or of instance `inst_id`'s prototype) is cut
    /// away, as Embree's cut-out filter decides.
    #[inline]
    fn cut(&self, [geom_id, prim_id, inst_id]: [u32; 3], u: f32, v: f32) -> bool {
        if !self.any_cutout {
            return false;
        }
        let meshes = match self.instances.get(inst_id as usize) {
            Some(instance) => &self.prototype_cutouts[instance.prototype as usize],
            None => &self.cutouts,
        };
        meshes
            .get(geom_id as usize)
            .and_then(Option::as_ref)
            .is_some_and(|c| c.skips(prim_id, u, v, inst_id))
    }

    pub(super) fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// Each primitive's box, grown by 32 ulps of the scene's largest
    /// coordinate (`primitive::padding`). A ray lying exactly in a box's face
    /// (an axis-parallel ray through a vertex on the boundary) has a slab that
    /// ends at t = 0 give or take rounding, so the box may be missed though the
    /// vertex is hit: obvhs's quantised test cancels two terms to a few ulps of
    /// noise of the scene's size there.
    pub(super) fn padded_bounds(&self) -> Vec<Bounds> {
        let boxes: Vec<Bounds> = self.list.iter().map(|p| self.bounds(p)).collect();
        let pad = padding(boxes.iter().copied());
        boxes.into_iter().map(|b| b.grown(pad)).collect()
    }

    fn bounds(&self, primitive: &Primitive) -> Bounds {
        match *primitive {
            Primitive::Triangle { corners, .. } => {
                let mut b = Bounds::EMPTY;
                corners.into_iter().for_each(|p| b.grow(p));
                b
            }
            Primitive::Shape { index, inst_id, .. } => {
                let bounds = self.shapes[index as usize].bounds();
                match self.instances.get(inst_id as usize) {
                    Some(instance) => instance.bounds_to_world(bounds),
                    None => bounds,
                }
            }
        }
    }

    /// Puts the primitives in the order of `order` (old indices), so a BVH's
    /// leaf slots index the list directly.
    pub(super) fn reorder(&mut self, order: &[u32]) {
        self.list = order.iter().map(|&i| self.list[i as usize]).collect();
    }

    /// The hit of primitive `index` within [ray.tnear, ray.tfar], if any;
    /// a shape solves for `exact` where `ray` is its rounding (see `Ray64`).
    #[inline]
    pub(super) fn intersect(&self, index: usize, ray: &Ray, exact: Option<&Ray64>) -> Option<Hit> {
        match self.list[index] {
            Primitive::Triangle {
                corners,
                geom_id,
                prim_id,
                inst_id,
            } => triangle::intersect(&corners, ray)
                .filter(|h| !self.cut([geom_id, prim_id, inst_id], h.u, h.v))
                .map(|h| Hit {
                    t: h.t,
                    geom_id,
                    prim_id,
                    inst_id,
                    u: h.u,
                    v: h.v,
                    ng: h.ng,
                }),
            // As Embree's callback does: a hit only within [tnear, tfar) (the
            // f64 root rounded to f32 may land on tfar, which the shape excluded).
            Primitive::Shape {
                index,
                geom_id,
                prim_id,
                inst_id,
            } => {
                let local = self.local(inst_id, ray);
                let exact = Ray64::for_ray(exact, &local);
                crossings(&self.shapes[index as usize], &local, &exact, |_| true)
                    .map(|h| self.shape_hit([geom_id, prim_id, inst_id], &h))
            }
        }
    }

    /// The ray in its shape's space: the prototype's for an instanced shape.
    fn local(&self, inst_id: u32, ray: &Ray) -> Ray {
        self.instances
            .get(inst_id as usize)
            .map_or(*ray, |i| i.ray_to_prototype(ray))
    }

    /// A shape's hit with its ids, its normal in world space (t is the same
    /// in both spaces: the direction is transformed, not normalised).
    fn shape_hit(&self, [geom_id, prim_id, inst_id]: [u32; 3], hit: &UserHit) -> Hit {
        let instance = self.instances.get(inst_id as usize);
        Hit {
            t: hit.t,
            geom_id,
            prim_id,
            inst_id,
            u: hit.u,
            v: hit.v,
            ng: instance.map_or(hit.ng, |i| i.ng_to_world(hit.ng, false)),
        }
    }

    /// Every hit of primitive `index` within [ray.tnear, ray.tfar), appended to `hits`.
    pub(super) fn intersect_every(&self, index: usize, ray: &Ray, hits: &mut Vec<Hit>) {
        match self.list[index] {
            Primitive::Triangle { .. } => hits.extend(self.intersect(index, ray, None)),
            Primitive::Shape {
                index,
                geom_id,
                prim_id,
                inst_id,
            } => {
                let local = self.local(inst_id, ray);
                crossings(
                    &self.shapes[index as usize],
                    &local,
                    &Ray64::of(&local),
                    |hit| {
                        hits.push(self.shape_hit([geom_id, prim_id, inst_id], hit));
                        false
                    },
                );
            }
        }
    }

    /// Whether primitive `index` blocks the ray within its interval.
    #[inline]
    pub(super) fn occludes(&self, index: usize, ray: &Ray) -> bool {
        match self.list[index] {
            Primitive::Triangle { .. } => self.intersect(index, ray, None).is_some(),
            Primitive::Shape { index, inst_id, .. } => {
                UserPrimitive::occluded(&self.shapes[index as usize], &self.local(inst_id, ray))
            }
        }
    }

    /// Bytes held: the primitive records plus the shapes' own records (their
    /// polynomials' heap storage, a few hundred bytes a shape, is not counted).
    pub(super) fn memory_bytes(&self) -> usize {
        self.list.capacity() * size_of::<Primitive>()
            + self.shapes.len() * size_of::<Shape>()
            + self.instances.len() * size_of::<Instance>()
    }
}

/// Appends the triangles of `meshes` that can be hit, mesh i as geometry i;
/// an instance's moved to world space and named by it.
fn triangles(
    list: &mut Vec<Primitive>,
    meshes: &[Mesh],
    instance: Option<(u32, &Instance)>,
) -> Result<()> {
    for (geom_id, mesh) in meshes.iter().enumerate() {
        let count = mesh.positions.len();
        for (prim_id, triangle) in mesh.triangles.iter().enumerate() {
            if let Some(bad) = triangle.iter().find(|&&i| i as usize >= count) {
                return Err(Error::Input(format!(
                    "geometry {geom_id}: vertex index {bad} out of range (the mesh has {count} vertices)"
                )));
            }
            let corners = triangle.map(|i| {
                let p = mesh.positions[i as usize];
                instance.map_or(p, |(_, inst)| inst.to_world.transform_point3(p))
            });
            let [a, b, c] = corners;
            if !corners.iter().all(|p| p.is_finite()) || (b - a).cross(c - a) == Vec3::ZERO {
                continue;
            }
            list.push(Primitive::Triangle {
                corners,
                geom_id: geom_id as u32,
                prim_id: prim_id as u32,
                inst_id: instance.map_or(INVALID_ID, |(id, _)| id),
            });
        }
    }
    Ok(())
}

/// The nearest hit found so far by a traversal, and the ray shortened to it.
pub(super) struct Closest<'a> {
    ray: Ray,
    exact: Option<&'a Ray64>,
    hit: Hit,
}

impl<'a> Closest<'a> {
    /// The search along `ray`; the shapes solve for `exact`, when given,
    /// which `ray` must be the rounding of.
    pub(super) fn new(ray: &Ray, exact: Option<&'a Ray64>) -> Closest<'a> {
        Closest {
            ray: *ray,
            exact,
            hit: Hit::MISS,
        }
    }

    /// Tests primitive `index`; true if it is the nearest hit so far.
    #[inline]
    pub(super) fn test(&mut self, primitives: &Primitives, index: usize) -> bool {
        match primitives.intersect(index, &self.ray, self.exact) {
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

/// A ray's slab test against boxes: its origin and its direction's
/// reciprocal, clamped to finite values, so (box − origin) · inv_dir is
/// never 0 · ∞ = NaN: a zero component gives ±∞ slab ends (or 0 on the
/// box's face).
pub(super) struct Slabs {
    origin: Vec3,
    inv_dir: Vec3,
}

impl Slabs {
    pub(super) fn new(ray: &Ray) -> Slabs {
        Slabs {
            origin: ray.origin,
            inv_dir: ray
                .dir
                .recip()
                .clamp(Vec3::splat(-f32::MAX), Vec3::splat(f32::MAX)),
        }
    }

    /// Whether the ray meets `b` with t in [tnear, tfar]. The far end is
    /// rounded up by 1 + 2γ(3) (pbrt), so a rounding error never drops a
    /// box the ray touches, flat ones included. Compared, not `f32::min`
    /// and `max` (see `math::larger`): with a finite reciprocal and origin,
    /// no slab end is NaN.
    #[inline]
    pub(super) fn meet(&self, b: &Bounds, tnear: f32, tfar: f32) -> bool {
        let round_up = 1.0 + 2.0 * gamma(3);
        let (mut near, mut far) = (tnear, tfar);
        for axis in 0..3 {
            let t0 = (b.min[axis] - self.origin[axis]) * self.inv_dir[axis];
            let t1 = (b.max[axis] - self.origin[axis]) * self.inv_dir[axis];
            let (t0, t1) = if t0 < t1 { (t0, t1) } else { (t1, t0) };
            if t0 > near {
                near = t0;
            }
            if t1 * round_up < far {
                far = t1 * round_up;
            }
        }
        near <= far
    }
}
