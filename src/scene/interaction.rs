//! The shading point of a hit: where it is, how far it may be off, which way
//! the surface faces and what it is made of.

use super::Scene;
use crate::math::{Hit, Ray, Vec3, gamma};

pub struct Interaction {
    pub p: Vec3,
    /// A bound on the error of `p`, per axis, for offsetting spawned rays.
    pub error: Vec3,
    /// Unit geometric normal, facing the side the ray came from.
    pub n: Vec3,
    /// Whether the ray hit the side the surface's own normal points to (the
    /// outside of a closed analytic shape, the counter-clockwise side of a triangle).
    pub front: bool,
    pub material: u32,
}

impl Scene {
    /// The material `hit` found, which must be a hit in this scene: what
    /// `interaction` says, without the work of finding the point and normal.
    pub fn material_of(&self, hit: &Hit) -> u32 {
        if hit.geom_id == self.shapes_geom_id() {
            // A shape's hit carries its CSG part in u (see accel::analytic).
            self.shapes[hit.prim_id as usize].material_of(hit.u as u32)
        } else {
            self.meshes[hit.geom_id as usize].materials[hit.prim_id as usize]
        }
    }

    /// The shading point of `hit`, which must be a hit of `ray` in this scene.
    pub fn interaction(&self, ray: &Ray, hit: &Hit) -> Interaction {
        let (p, error) = if hit.geom_id == self.shapes_geom_id() {
            let p = ray.at(hit.t);
            // The root's own error bound, which a shape's hit carries in v
            // (see accel::analytic and `ShapeHit::error`), then t and o + t·d
            // rounded to f32.
            let t_error = hit.v + hit.t.abs() * f32::EPSILON;
            let error =
                t_error * ray.dir.abs() + gamma(3) * (ray.origin.abs() + (hit.t * ray.dir).abs());
            (p, error)
        } else {
            let mesh = &self.meshes[hit.geom_id as usize];
            let [p0, p1, p2] =
                mesh.triangles[hit.prim_id as usize].map(|i| mesh.positions[i as usize]);
            // From barycentrics the point is accurate to the triangle's own scale,
            // unlike o + t·d, whose error grows with the distance travelled.
            let (b1, b2) = (hit.u, hit.v);
            let b0 = 1.0 - b1 - b2;
            let p = b0 * p0 + b1 * p1 + b2 * p2;
            // pbrt bounds each axis by that axis's own terms, which is zero on an axis
            // plane such as x = 0. Embree's triangle test mixes the axes (it works
            // relative to the ray origin), so the bound uses the largest axis for all
            // three: the origin then always leaves the plane by more than Embree's own
            // rounding.
            let error = Vec3::splat(
                gamma(7) * ((b0 * p0).abs() + (b1 * p1).abs() + (b2 * p2).abs()).max_element(),
            );
            (p, error)
        };
        let outward = crate::math::unit(hit.ng);
        let front = outward.dot(ray.dir) <= 0.0;
        let n = if front { outward } else { -outward };
        Interaction {
            front,
            p,
            error,
            n,
            material: self.material_of(hit),
        }
    }
}
