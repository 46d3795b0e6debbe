//! Alpha cut-outs (MTL's `map_d`): the triangles of a mesh whose material
//! has a mask, with their corners' texture coordinates, so a backend can
//! tell from a candidate hit's barycentrics whether the hit is cut away.
//!
//! Every backend asks the same question at the same point: Embree from a
//! geometry filter callback (`embree::filter`), the pure-Rust backends in
//! their triangle test (`rust_bvh::primitives`). A cut-away hit is as if
//! the triangle were not there, for the nearest hit, shadow rays and the
//! all-hits query alike. Only meshes with a mask and texture coordinates
//! get a `Cutout`; the others are traced as before, at no cost.
//!
//! An instance's own `material` does not change its prototype's cut-outs:
//! the masks are the prototype meshes' own materials', as Embree's filter
//! belongs to the prototype's geometry, shared by all its instances.

use crate::geometry::Mesh;
use crate::math::{INVALID_ID, Vec2};
use crate::shading::{Material, Texture};

/// One mesh's cut-out masks.
pub struct Cutout {
    /// Per triangle: its mask's index in `masks` (`INVALID_ID`: opaque) and
    /// its corners' uv. 28 bytes a triangle, only for meshes with a mask.
    triangles: Box<[(u32, [Vec2; 3])]>,
    masks: Box<[Texture]>,
}

impl Cutout {
    /// The cut-out of `mesh`, whose material indices point into
    /// `materials`; `None` if no triangle's material has a mask or the mesh
    /// has no texture coordinates (a mask, like a colour map, needs them).
    pub fn of(mesh: &Mesh, materials: &[Material]) -> Option<Cutout> {
        if mesh.uvs.is_empty() {
            return None;
        }
        // Per material of the scene, its mask's index here, on first use.
        let mut index: Vec<Option<u32>> = vec![None; materials.len()];
        let mut masks: Vec<Texture> = Vec::new();
        let triangles = mesh
            .triangles
            .iter()
            .zip(&mesh.materials)
            .map(|(corners, &m)| {
                let mask = match materials
                    .get(m as usize)
                    .and_then(|m| m.maps.alpha.as_ref())
                {
                    None => INVALID_ID,
                    Some(texture) => *index[m as usize].get_or_insert_with(|| {
                        masks.push(texture.clone());
                        masks.len() as u32 - 1
                    }),
                };
                let uv = corners.map(|i| mesh.uvs.get(i as usize).copied().unwrap_or_default());
                (mask, uv)
            })
            .collect();
        (!masks.is_empty()).then(|| Cutout {
            triangles,
            masks: masks.into_boxed_slice(),
        })
    }

    /// The cut-outs of `meshes`, one entry per mesh (geometry id).
    pub fn of_meshes(meshes: &[Mesh], materials: &[Material]) -> Box<[Option<Cutout>]> {
        meshes.iter().map(|m| Cutout::of(m, materials)).collect()
    }

    /// Whether the hit at barycentrics (u, v) of triangle `prim` is cut
    /// away: its mask's opacity there below [`Material::CUTOFF`]. The uv
    /// is interpolated as the shading point's is (`Mesh::uv`).
    pub fn skips(&self, prim: u32, u: f32, v: f32) -> bool {
        let Some(&(mask, [t0, t1, t2])) = self.triangles.get(prim as usize) else {
            return false;
        };
        if mask == INVALID_ID {
            return false;
        }
        let uv = t0 * (1.0 - u - v) + t1 * u + t2 * v;
        self.masks[mask as usize].opacity(uv) < Material::CUTOFF
    }
}
