//! Embree instances, a two-level BVH: each prototype is an Embree scene of its
//! own, committed once, and each instance an `RTC_GEOMETRY_TYPE_INSTANCE`
//! geometry of the top-level scene that points at it with its transform, so
//! a thousand instances of a mesh hold one copy of its triangles and BVH.
//!
//! Embree traces an instance in the prototype's space: the ray is moved by
//! the inverse transform (its direction not normalised, so t is the same in
//! both spaces) before the prototype's BVH, so triangle tests and the user
//! geometry callbacks of analytic shapes see it there, and the hit's Ng comes
//! back in that space too. Embree keeps the instance stack in the query
//! context; its triangles copy it into the hit, and so do our user callbacks
//! (`user.rs`, on Embree 3 and 4 alike, with `instPrimID` where the header has
//! it). [`Instances::to_world`] then turns Embree's instance geometry id into
//! the instance's index and the normal into world space.

use std::sync::Arc;

use glam::Mat4;

use super::scene::{CommittedScene, SceneBuilder, SceneOptions};
use super::sys;
use crate::error::{Error, Result};
use crate::math::{Hit, INVALID_ID};
use crate::scene::Instance;

/// What a top-level scene keeps for its instances.
#[derive(Default)]
pub(super) struct Instances {
    /// The prototypes' committed scenes, which the instance geometries point
    /// into: released after the top-level scene (field order in the owners).
    _prototypes: Vec<CommittedScene>,
    /// The top-level geometry id of instance 0.
    first: u32,
    /// Per instance, its record (for its normals) and its prototype's
    /// shapes' geometry id (to tell triangles from shapes).
    records: Vec<(Instance, u32)>,
}

impl Instances {
    /// A finished query's hit with the instance's index for Embree's id and
    /// its normal in world space; a hit on the top-level scene's own geometry
    /// as it is.
    pub(super) fn to_world(&self, mut hit: Hit) -> Hit {
        let index = hit.inst_id.wrapping_sub(self.first);
        if let (true, Some((instance, shapes))) =
            (hit.inst_id != INVALID_ID, self.records.get(index as usize))
        {
            hit.inst_id = index;
            hit.ng = instance.ng_to_world(hit.ng, hit.geom_id != *shapes);
        }
        hit
    }
}

impl SceneBuilder {
    /// A builder for a prototype's scene, on this builder's device: panics in
    /// its callbacks are recorded in this scene's slot, so the top-level
    /// scene's `check` reports them.
    pub fn prototype(&self, options: SceneOptions) -> Result<SceneBuilder> {
        let mut builder = SceneBuilder::new(&self.device, options)?;
        builder.panics = Arc::clone(&self.panics);
        Ok(builder)
    }

    /// Adds instance i as top-level geometry `first + i`, placing
    /// `prototypes[instances[i].prototype]` (a committed scene and the
    /// geometry id of its shapes) by its transform. The scene keeps the
    /// prototypes alive for as long as it is.
    pub fn add_instances(
        &mut self,
        first: u32,
        prototypes: Vec<(CommittedScene, u32)>,
        instances: &[Instance],
    ) -> Result<()> {
        let mut records = Vec::with_capacity(instances.len());
        for (i, instance) in instances.iter().enumerate() {
            let Some((prototype, shapes)) = prototypes.get(instance.prototype as usize) else {
                return Err(Error::Input(format!(
                    "instance {i}: prototype {} does not exist",
                    instance.prototype
                )));
            };
            let geom_id = u32::try_from(i)
                .ok()
                .and_then(|i| first.checked_add(i))
                .filter(|&id| id != INVALID_ID)
                .ok_or_else(|| Error::Input(format!("instance {i}: too many instances")))?;
            let geometry = self.new_geometry(sys::RTCGeometryType_RTC_GEOMETRY_TYPE_INSTANCE)?;
            let g = geometry.0.as_ptr();
            // SAFETY: `g` is a new, unshared instance geometry; the prototype's scene is
            // committed and is kept alive by `self.instances` until after the top-level
            // scene is released.
            unsafe { sys::rtcSetGeometryInstancedScene(g, prototype.scene.0.as_ptr()) };
            let matrix = Mat4::from(instance.to_world).to_cols_array();
            // SAFETY: `g` as above; `matrix` holds the 16 floats of a column-major 4×4
            // matrix, which Embree copies during the call.
            unsafe {
                sys::rtcSetGeometryTransform(
                    g,
                    0,
                    sys::RTCFormat_RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR,
                    matrix.as_ptr().cast(),
                )
            };
            self.attach(geometry, geom_id)?;
            records.push((instance.clone(), *shapes));
        }
        self.instances = Instances {
            _prototypes: prototypes.into_iter().map(|(p, _)| p).collect(),
            first,
            records,
        };
        Ok(())
    }
}
