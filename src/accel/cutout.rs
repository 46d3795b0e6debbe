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
//! An instance's own `material` decides its cut-outs, as pbrt's and
//! Mitsuba's instances take their material: with one, every triangle of the
//! prototype's meshes takes that material's mask (none if it has no
//! `map_d`); without, the meshes' own materials' masks. The prototype's
//! geometry is shared by its instances, so the cut-out of a prototype's mesh
//! holds each instance's choice, found by the instance id of the hit.

use crate::geometry::Mesh;
use crate::math::{INVALID_ID, Vec2};
use crate::scene::Instance;
use crate::shading::{Material, Texture};

/// Which masks an instance's hits on a prototype's mesh are cut by.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Pick {
    /// The triangles' own materials' (no instance, or no material of its own).
    Own,
    /// None: the instance's material has no mask.
    Opaque,
    /// The instance's material's, index into `masks`, for every triangle.
    Mask(u32),
}

/// One mesh's cut-out masks.
pub struct Cutout {
    /// Per triangle: its mask's index in `masks` (`INVALID_ID`: opaque) and
    /// its corners' uv. 28 bytes a triangle, only for meshes with a mask.
    triangles: Box<[(u32, [Vec2; 3])]>,
    masks: Box<[Texture]>,
    /// Per instance of the scene, by the id a hit names it with less
    /// `first`: its choice (empty for a mesh of the scene's own).
    picks: Box<[Pick]>,
    first: u32,
}

impl Cutout {
    /// The cut-out of `mesh`, whose material indices point into
    /// `materials`, as the scene's own mesh (`instances` empty) or as mesh
    /// of prototype `prototype`, placed by `instances`, whose hits name
    /// instance i by `first + i`. `None` if no triangle's material and no
    /// instance's own material has a mask, or the mesh has no texture
    /// coordinates (a mask, like a colour map, needs them).
    pub fn of(
        mesh: &Mesh,
        materials: &[Material],
        prototype: u32,
        instances: &[Instance],
        first: u32,
    ) -> Option<Cutout> {
        if mesh.uvs.is_empty() {
            return None;
        }
        // Per material of the scene, its mask's index here, on first use.
        let mut index: Vec<Option<u32>> = vec![None; materials.len()];
        let mut masks: Vec<Texture> = Vec::new();
        let mut mask_of = |m: u32| {
            let texture = materials.get(m as usize)?.maps.alpha.as_ref()?;
            Some(*index[m as usize].get_or_insert_with(|| {
                masks.push(texture.clone());
                masks.len() as u32 - 1
            }))
        };
        let picks: Box<[Pick]> = instances
            .iter()
            .map(|i| match i.material.filter(|_| i.prototype == prototype) {
                None => Pick::Own,
                Some(m) => mask_of(m).map_or(Pick::Opaque, Pick::Mask),
            })
            .collect();
        let triangles = mesh
            .triangles
            .iter()
            .zip(&mesh.materials)
            .map(|(corners, &m)| {
                let mask = mask_of(m).unwrap_or(INVALID_ID);
                let uv = corners.map(|i| mesh.uvs.get(i as usize).copied().unwrap_or_default());
                (mask, uv)
            })
            .collect();
        (!masks.is_empty()).then(|| Cutout {
            triangles,
            masks: masks.into_boxed_slice(),
            picks,
            first,
        })
    }

    /// The cut-outs of `meshes` (the scene's own, or prototype
    /// `prototype`'s as in [`Cutout::of`]), one entry per mesh (geometry id).
    pub fn of_meshes(
        meshes: &[Mesh],
        materials: &[Material],
        prototype: u32,
        instances: &[Instance],
        first: u32,
    ) -> Box<[Option<Cutout>]> {
        meshes
            .iter()
            .map(|m| Cutout::of(m, materials, prototype, instances, first))
            .collect()
    }

    /// Whether the hit at barycentrics (u, v) of triangle `prim`, through
    /// the instance a hit names by `inst` (`INVALID_ID`: none), is cut
    /// away: its mask's opacity there below [`Material::CUTOFF`]. The uv
    /// is interpolated as the shading point's is (`Mesh::uv`).
    pub fn skips(&self, prim: u32, u: f32, v: f32, inst: u32) -> bool {
        let Some(&(own, [t0, t1, t2])) = self.triangles.get(prim as usize) else {
            return false;
        };
        let pick = self.picks.get(inst.wrapping_sub(self.first) as usize);
        let mask = match pick.copied().unwrap_or(Pick::Own) {
            Pick::Own if own != INVALID_ID => own,
            Pick::Own | Pick::Opaque => return false,
            Pick::Mask(mask) => mask,
        };
        let uv = t0 * (1.0 - u - v) + t1 * u + t2 * v;
        self.masks[mask as usize].opacity(uv) < Material::CUTOFF
    }
}
