//! The shading point of a hit: where it is, how far it may be off, which way
//! the surface faces and what it is made of.

use super::{Instance, Scene};
use crate::geometry::{Mesh, Shape};
use crate::math::{Frame, Hit, Ray, Vec2, Vec3, gamma};
use crate::shading::{Material, Surface};

/// The least cosine between the viewer and a shading normal: an
/// interpolated normal the viewer is behind is bent towards the viewer until
/// this is met, so a smooth mesh's silhouette has no black seams.
const MIN_VIEW_COS: f32 = 0.01;

pub struct Interaction {
    pub p: Vec3,
    /// A bound on the error of `p`, per axis, for offsetting spawned rays.
    pub error: Vec3,
    /// Unit geometric normal, facing the side the ray came from: spawned
    /// rays leave by it, and it decides which side a direction is on.
    pub n: Vec3,
    /// Unit shading normal, on `n`'s side and never with the viewer behind
    /// it: the interpolated vertex normal of a smooth mesh, `n` elsewhere.
    /// The BSDF's frame and cosines use it.
    pub ns: Vec3,
    /// The texture coordinates of a mesh that has them.
    pub uv: Option<Vec2>,
    /// The interpolated vertex colour of a mesh that has colours: the
    /// albedo there, in place of the material's.
    pub colour: Option<Vec3>,
    /// Whether the ray hit the side the surface's own normal points to (the
    /// outside of a closed analytic shape, the counter-clockwise side of a triangle).
    pub front: bool,
    pub material: u32,
}

impl Scene {
    /// The meshes and shapes whose ids `hit` names (the scene's own, or the
    /// prototype's of the instance it is on), and that instance.
    pub fn hit_geometry(&self, hit: &Hit) -> (&[Mesh], &[Shape], Option<&Instance>) {
        match self.instances.get(hit.inst_id as usize) {
            Some(instance) => {
                let prototype = &self.prototypes[instance.prototype as usize];
                (&prototype.meshes, &prototype.shapes, Some(instance))
            }
            None => (&self.meshes, &self.shapes, None),
        }
    }

    /// Whether what `hit` found casts shadows (a shape may not: POV-Ray's
    /// `no_shadow`), as occlusion queries see it.
    pub fn casts_shadow(&self, hit: &Hit) -> bool {
        let (meshes, shapes, _) = self.hit_geometry(hit);
        hit.geom_id as usize != meshes.len() || shapes[hit.prim_id as usize].casts_shadow()
    }

    /// Whether the ray that made `hit` on the inside of what it hit came
    /// through that object's inside, not through air: true for an analytic
    /// shape that is not `hollow`; never for a mesh, to which POV-Ray gives
    /// no inside. A fog fills only the air.
    pub fn came_through_solid(&self, hit: &Hit, front: bool) -> bool {
        let (meshes, shapes, _) = self.hit_geometry(hit);
        !front && hit.geom_id as usize == meshes.len() && !shapes[hit.prim_id as usize].hollow()
    }

    /// The material `hit` found, which must be a hit in this scene: what
    /// `interaction` says, without the work of finding the point and normal.
    pub fn material_of(&self, hit: &Hit) -> u32 {
        let (meshes, shapes, instance) = self.hit_geometry(hit);
        let own = instance.and_then(|i| i.material);
        if hit.geom_id as usize == meshes.len() {
            // A shape's hit carries its CSG part in u (see accel::analytic).
            let m = own.unwrap_or_else(|| shapes[hit.prim_id as usize].material_of(hit.u as u32));
            instance.map_or(m, |i| i.shape_material(m))
        } else {
            own.unwrap_or(meshes[hit.geom_id as usize].materials[hit.prim_id as usize])
        }
    }

    /// The shading normal of a mesh hit whose material has a bump or
    /// normal map and which has texture coordinates there, in the mesh's
    /// space: the interpolated normal (or the face's) bent by the map.
    fn mapped_normal(&self, mesh: &Mesh, hit: &Hit, uv: Option<Vec2>) -> Option<Vec3> {
        let uv = uv?;
        let maps = &self.materials.get(self.material_of(hit) as usize)?.maps;
        if !maps.bends() {
            return None;
        }
        let (dpdu, dpdv) = mesh.uv_derivatives(hit.prim_id)?;
        let ns = mesh
            .shading_normal(hit.prim_id, hit.u, hit.v)
            .unwrap_or_else(|| mesh.normal(hit.prim_id));
        Some(maps.shading_normal(ns, dpdu, dpdv, uv))
    }

    /// The shading point of `hit`, which must be a hit of `ray` in this scene.
    /// On an instance the point, its error and the shading normal are found
    /// in the prototype's space and moved to world space; the hit's own
    /// geometric normal is in world space already (every backend's contract).
    pub fn interaction(&self, ray: &Ray, hit: &Hit) -> Interaction {
        let (meshes, _, instance) = self.hit_geometry(hit);
        let mut shading = None;
        let mut uv = None;
        let mut colour = None;
        let (p, error) = if hit.geom_id as usize == meshes.len() {
            // t is the same in the prototype's space and the world's (the ray's
            // direction is transformed, not normalised), so o + t·d in world space.
            let p = ray.at(hit.t);
            // The root's own error bound, which a shape's hit carries in v
            // (see accel::analytic and `ShapeHit::error`), then t and o + t·d
            // rounded to f32.
            let t_error = hit.v + hit.t.abs() * f32::EPSILON;
            let error =
                t_error * ray.dir.abs() + gamma(3) * (ray.origin.abs() + (hit.t * ray.dir).abs());
            (p, error)
        } else {
            let mesh = &meshes[hit.geom_id as usize];
            let [p0, p1, p2] =
                mesh.triangles[hit.prim_id as usize].map(|i| mesh.positions[i as usize]);
            // From barycentrics the point is accurate to the triangle's own scale,
            // unlike o + t·d, whose error grows with the distance travelled.
            let (b1, b2) = (hit.u, hit.v);
            let b0 = 1.0 - b1 - b2;
            shading = mesh.shading_normal(hit.prim_id, b1, b2);
            uv = mesh.uv(hit.prim_id, b1, b2);
            shading = self.mapped_normal(mesh, hit, uv).or(shading);
            colour = mesh.colour(hit.prim_id, b1, b2);
            let p = b0 * p0 + b1 * p1 + b2 * p2;
            // pbrt bounds each axis by that axis's own terms, which is zero on an axis
            // plane such as x = 0. Embree's triangle test mixes the axes (it works
            // relative to the ray origin), so the bound uses the largest axis for all
            // three: the origin then always leaves the plane by more than Embree's own
            // rounding.
            let error = Vec3::splat(
                gamma(7) * ((b0 * p0).abs() + (b1 * p1).abs() + (b2 * p2).abs()).max_element(),
            );
            match instance {
                Some(instance) => {
                    shading = shading.and_then(|ns| {
                        let ns = crate::math::unit(instance.normal_to_world(ns));
                        (ns != Vec3::ZERO).then_some(ns)
                    });
                    instance.point_to_world(p, error)
                }
                None => (p, error),
            }
        };
        let outward = crate::math::unit(hit.ng);
        let front = outward.dot(ray.dir) <= 0.0;
        let n = if front { outward } else { -outward };
        let ns = shading.map_or(n, |ns| shading_normal(ns, n, -ray.dir));
        Interaction {
            front,
            p,
            error,
            n,
            ns,
            uv,
            colour,
            material: self.material_of(hit),
        }
    }
}

impl Interaction {
    /// Material `m`'s values here ([`Material::surface_at`]): looked up
    /// once a hit, as a texture's lookup is the costliest part of one.
    pub fn surface(&self, m: &Material) -> Surface {
        m.surface_at(self.p, self.error, self.uv, self.colour)
    }

    /// The BSDF's frame: around the shading normal, out of the material
    /// (the BSDF tells inside from outside by the surface's own normal).
    pub fn frame(&self) -> Frame {
        Frame::from_normal(self.outward())
    }

    /// The shading normal pointing out of the material.
    pub fn outward(&self) -> Vec3 {
        if self.front { self.ns } else { -self.ns }
    }

    /// Whether a scattered direction `wi` leaves on the side its lobe says:
    /// the viewer's side for a reflection, the other for a transmission. A
    /// shading normal can tilt a lobe past the true surface; such directions
    /// are dropped, so no light leaks through a smooth mesh (pbrt-v3's rule).
    pub fn leaves_as(&self, wi: Vec3, transmission: bool) -> bool {
        let towards_viewer = wi.dot(self.n) > 0.0;
        towards_viewer != transmission
    }
}

/// An interpolated normal `ns`, turned to the side of the geometric normal
/// `n` (which faces the viewer `wo`) as pbrt-v4 does when the geometric side
/// is authoritative, then, where the viewer is still behind it (the
/// silhouette of a coarse mesh), bent towards the viewer: otherwise the BSDF
/// would see the viewer below its horizon and return black.
fn shading_normal(ns: Vec3, n: Vec3, wo: Vec3) -> Vec3 {
    let ns = if ns.dot(n) < 0.0 { -ns } else { ns };
    let cos = ns.dot(wo);
    if cos >= MIN_VIEW_COS {
        return ns;
    }
    // ns + k·wo with k chosen so that its dot with wo is MIN_VIEW_COS before
    // normalising: still positive after.
    (ns + (MIN_VIEW_COS - cos) * wo).normalize_or(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn it(ns: Vec3) -> Interaction {
        Interaction {
            p: Vec3::ZERO,
            error: Vec3::ZERO,
            n: Vec3::Z,
            ns,
            uv: None,
            colour: None,
            front: true,
            material: 0,
        }
    }

    #[test]
    fn a_shading_normal_the_viewer_is_behind_is_bent_towards_the_viewer() {
        let n = Vec3::Z;
        // Grazing view from +x; the interpolated normal leans away to -x.
        let wo = Vec3::new(1.0, 0.0, 0.1).normalize();
        let leaning = Vec3::new(-0.5, 0.0, 1.0).normalize();
        assert!(leaning.dot(wo) < 0.0);
        let ns = shading_normal(leaning, n, wo);
        assert!((ns.length() - 1.0).abs() < 1e-6);
        // Just above the horizon: bent no further than it takes.
        assert!(
            ns.dot(wo) >= MIN_VIEW_COS && ns.dot(wo) < 2.0 * MIN_VIEW_COS,
            "{ns}"
        );
        // One facing the viewer well is kept; one on the other side of the
        // surface is turned to the geometric normal's side first.
        let fine = Vec3::new(0.2, 0.0, 1.0).normalize();
        assert_eq!(shading_normal(fine, n, wo), fine);
        assert_eq!(shading_normal(-fine, n, wo), fine);
    }

    #[test]
    fn directions_that_cross_the_true_surface_are_dropped() {
        let tilted = it(Vec3::new(0.6, 0.0, 0.8));
        // Above the shading normal's horizon but below the surface: a reflection
        // there would leak light through it.
        let below = Vec3::new(0.9, 0.0, -0.1).normalize();
        assert!(tilted.ns.dot(below) > 0.0);
        assert!(!tilted.leaves_as(below, false));
        assert!(tilted.leaves_as(below, true));
        assert!(tilted.leaves_as(Vec3::Z, false));
        // The frame and outward normal follow the shading normal, out of the material.
        assert_eq!(tilted.frame().n, tilted.ns);
        let back = Interaction {
            front: false,
            ..it(Vec3::Z)
        };
        assert_eq!(back.outward(), -Vec3::Z);
    }
}
