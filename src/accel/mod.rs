//! Acceleration structures: the BVH a scene is traced through. Every backend
//! answers the same queries for the same scene.

mod analytic;
#[allow(unsafe_code)]
pub mod embree;

use crate::error::Result;
use crate::math::{Hit, Ray};
use crate::scene::Scene;

/// Which BVH traces the rays.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Backend {
    #[default]
    Embree,
}

/// A scene's BVH, built by one backend.
pub enum Accel {
    Embree(embree::CommittedScene),
}

impl Accel {
    /// Builds the BVH of every mesh and shape: mesh i becomes geometry i, the
    /// shapes one more geometry after them (see `Scene::shapes_geom_id`).
    pub fn build(scene: &Scene, backend: Backend, threads: Option<usize>) -> Result<Accel> {
        match backend {
            Backend::Embree => {
                let config = threads.map_or(String::new(), |n| format!("threads={n}"));
                let device = embree::Device::with_config(&config)?;
                let mut builder =
                    embree::SceneBuilder::new(&device, embree::SceneOptions::default())?;
                for (id, mesh) in scene.meshes.iter().enumerate() {
                    builder.add_triangles(id as u32, &mesh.positions, &mesh.triangles)?;
                }
                builder.add_user(scene.shapes_geom_id(), scene.shapes.clone())?;
                Ok(Accel::Embree(builder.commit()?))
            }
        }
    }

    pub fn intersect(&self, ray: &Ray) -> Hit {
        match self {
            Accel::Embree(s) => s.intersect(ray),
        }
    }

    pub fn occluded(&self, ray: &Ray) -> bool {
        match self {
            Accel::Embree(s) => s.occluded(ray),
        }
    }

    /// Traces many rays; `coherent` says they are neighbouring camera rays.
    pub fn intersect_batch(&self, rays: &[Ray], hits: &mut [Hit], coherent: bool) -> Result<()> {
        match self {
            Accel::Embree(s) => s.intersect_batch(rays, hits, coherent),
        }
    }

    /// Reports errors the backend raised during queries since the last check.
    pub fn check(&self) -> Result<()> {
        match self {
            Accel::Embree(s) => s.check(),
        }
    }

    /// Bytes the backend holds for this scene's BVH and geometry.
    pub fn memory_bytes(&self) -> i64 {
        match self {
            Accel::Embree(s) => s.device().bytes_in_use(),
        }
    }

    /// The backend and its version, e.g. "Embree 3.13.5 (bindings from the 3.13.5 header)".
    pub fn describe(&self) -> String {
        match self {
            Accel::Embree(s) => format!(
                "Embree {} (bindings from the {} header)",
                s.device().library_version(),
                embree::HEADER_VERSION
            ),
        }
    }
}
