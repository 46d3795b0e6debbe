//! Acceleration structures: the BVH a scene is traced through. Every backend
//! answers the same queries for the same scene.

mod analytic;
pub mod cutout;
#[allow(unsafe_code)]
pub mod embree;
pub mod ftz;
mod panics;
pub mod primitive;
pub mod rust_bvh;

pub use rust_bvh::{LightBeams, ListBeams, ShapeSet};

use std::panic::{AssertUnwindSafe, catch_unwind};

use crate::error::{Error, Result};
use crate::geometry::{Mesh, Pinhole, Shape};
use crate::math::{DVec3, Hit, INVALID_ID, Ray, Ray64};
use crate::scene::{Instance, Scene};
use crate::shading::Material;

/// Which BVH traces the rays.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Backend {
    #[default]
    Embree,
    /// obvhs's compressed 8-wide BVH (pure Rust).
    Obvhs,
    /// The `bvh` crate's binary SAH BVH (pure Rust).
    Bvh,
}

impl Backend {
    pub const ALL: [Backend; 3] = [Backend::Embree, Backend::Obvhs, Backend::Bvh];

    /// The faster pure-Rust backend, measured with `sturmray bench`: obvhs
    /// traces several times as many rays a second as the `bvh` crate.
    pub const FASTEST_RUST: Backend = Backend::Obvhs;

    /// The name the CLI and the bench records use.
    pub fn name(self) -> &'static str {
        match self {
            Backend::Embree => "embree",
            Backend::Obvhs => "obvhs",
            Backend::Bvh => "bvh",
        }
    }
}

/// Refuses the first ray that a backend cannot trace (see `Ray::problem`),
/// naming its index. Every backend refuses the same rays, so the check runs
/// once, before tracing rays from outside (a ray file), not per ray: renders
/// make theirs from a checked camera inside a scene of bounded size.
pub fn check_rays(rays: &[Ray]) -> Result<()> {
    match rays
        .iter()
        .enumerate()
        .find_map(|(i, ray)| ray.problem().map(|p| (i, p)))
    {
        Some((i, problem)) => Err(Error::Input(format!("ray {i} (0-based row): {problem}"))),
        None => Ok(()),
    }
}

/// A scene's BVH, built by one backend.
pub enum Accel {
    /// Embree's scene and, for a scene of a few shapes alone, the list that
    /// answers a render's single rays without it (`rust_bvh::ListScene`).
    Embree(embree::CommittedScene, Option<rust_bvh::ListScene>),
    Obvhs(rust_bvh::CwbvhScene),
    Bvh(rust_bvh::SahScene),
}

/// Mesh i as Embree geometry i, with its cut-outs (its triangles'
/// materials are `materials`; for prototype `prototype`'s meshes, each of
/// `instances` may choose its own, see `cutout`), the shapes as one more
/// geometry after them.
fn add_geometry(
    builder: &mut embree::SceneBuilder,
    (meshes, shapes): (&[Mesh], &[Shape]),
    materials: &[Material],
    (prototype, instances, first): (u32, &[Instance], u32),
) -> Result<()> {
    for (id, mesh) in meshes.iter().enumerate() {
        let cutout = cutout::Cutout::of(mesh, materials, prototype, instances, first);
        builder.add_triangles(id as u32, &mesh.positions, &mesh.triangles, cutout)?;
    }
    builder.add_user(meshes.len() as u32, shapes.to_vec())
}

impl Accel {
    /// Builds the BVH of every mesh and shape: mesh i becomes geometry i, the
    /// shapes one more geometry after them (see `Scene::shapes_geom_id`); each
    /// instance's hits name it (`Hit::inst_id`) and its prototype's geometry,
    /// numbered the same way. Embree builds a two-level BVH (each prototype
    /// once); the pure-Rust backends copy each instance's geometry into one
    /// world-space BVH (`rust_bvh::primitives`).
    /// `threads` bounds the builder's threads (default: all cores).
    pub fn build(scene: &Scene, backend: Backend, threads: Option<usize>) -> Result<Accel> {
        match backend {
            Backend::Embree => {
                // First: the list finds its shapes' boxes (an algebraic
                // surface's takes milliseconds, `extent`) on the scene's own
                // shapes, so the copies Embree takes below have them too.
                let list = rust_bvh::ListScene::of(scene);
                let config = threads.map_or(String::new(), |n| format!("threads={n}"));
                let device = embree::Device::with_config(&config)?;
                let options = embree::SceneOptions::default();
                let mut builder = embree::SceneBuilder::new(&device, options)?;
                let own = (&scene.meshes[..], &scene.shapes[..]);
                add_geometry(&mut builder, own, &scene.materials, (INVALID_ID, &[], 0))?;
                if !scene.instances.is_empty() {
                    // Instance i is the geometry after the shapes' plus i.
                    let first = scene.shapes_geom_id() + 1;
                    let prototypes = (scene.prototypes.iter().enumerate())
                        .map(|(i, p)| {
                            let mut prototype = builder.prototype(options)?;
                            let placed = (i as u32, &scene.instances[..], first);
                            let geometry = (&p.meshes[..], &p.shapes[..]);
                            add_geometry(&mut prototype, geometry, &scene.materials, placed)?;
                            Ok((prototype.commit()?, p.shapes_geom_id()))
                        })
                        .collect::<Result<Vec<_>>>()?;
                    builder.add_instances(first, prototypes, &scene.instances)?;
                }
                Ok(Accel::Embree(builder.commit()?, list))
            }
            // The pure-Rust builders run on rayon: on a pool of `threads` if given.
            // A panic in a builder crate is an internal error, not a crash.
            Backend::Obvhs | Backend::Bvh => {
                let build = || {
                    catch_unwind(AssertUnwindSafe(|| match backend {
                        Backend::Obvhs => rust_bvh::CwbvhScene::build(scene).map(Accel::Obvhs),
                        _ => rust_bvh::SahScene::build(scene).map(Accel::Bvh),
                    }))
                    .unwrap_or_else(|payload| {
                        Err(Error::Internal(format!(
                            "the {} BVH builder panicked: {}",
                            backend.name(),
                            panics::describe(payload)
                        )))
                    })
                };
                match threads {
                    None => build(),
                    Some(n) => rayon::ThreadPoolBuilder::new()
                        .num_threads(n)
                        .build()
                        .map_err(|e| Error::Internal(format!("cannot start build threads: {e}")))?
                        .install(build),
                }
            }
        }
    }

    pub fn intersect(&self, ray: &Ray) -> Hit {
        self.intersect_among(ray, ShapeSet::ALL)
    }

    /// `intersect`, offered to the shapes of `among` only where the
    /// render's rays skip the BVH (as `occluded_among`).
    pub fn intersect_among(&self, ray: &Ray, among: ShapeSet) -> Hit {
        match self {
            Accel::Embree(s, Some(list)) => list.nearest(ray, &Ray64::of(ray), among, s.panics()),
            Accel::Embree(s, None) => s.intersect(ray),
            Accel::Obvhs(s) => s.intersect(ray),
            Accel::Bvh(s) => s.intersect(ray),
        }
    }

    /// The nearest hit of `exact`'s rounding over [0, inf), with the
    /// analytic shapes solving for `exact` itself (see `Ray64`): for camera
    /// rays, so a graze is decided as POV-Ray's double-precision ray decides it.
    pub fn intersect_exact(&self, exact: &Ray64) -> Hit {
        self.intersect_exact_among(exact, ShapeSet::ALL)
    }

    /// `intersect_exact` offered to the shapes of `among` only, where the
    /// render's rays skip the BVH (`rust_bvh::ListScene`): those of a
    /// `camera_beams` rectangle that some ray through it may hit. Elsewhere
    /// (the set is the list's) every primitive is offered.
    pub fn intersect_exact_among(&self, exact: &Ray64, among: ShapeSet) -> Hit {
        match self {
            Accel::Embree(s, Some(list)) => {
                list.nearest(&exact.rounded(), exact, among, s.panics())
            }
            Accel::Embree(s, None) => s.intersect_exact(exact),
            Accel::Obvhs(s) => s.intersect_exact(exact),
            Accel::Bvh(s) => s.intersect_exact(exact),
        }
    }

    /// The shapes along a pinhole camera's rays, where the render's rays
    /// skip the BVH and some shape can be proven missed by a rectangle of
    /// them (`ListBeams`); None elsewhere.
    pub fn camera_beams(&self, pinhole: &Pinhole) -> Option<ListBeams<'_>> {
        match self {
            Accel::Embree(_, Some(list)) => list.beams(pinhole),
            _ => None,
        }
    }

    /// The shapes along a point light's rays, where the render's rays skip
    /// the BVH and a shape's own lit points can be proven to cast no
    /// shadow on themselves (`LightBeams`); None elsewhere.
    pub fn light_beams(&self, light: DVec3) -> Option<LightBeams<'_>> {
        match self {
            Accel::Embree(_, Some(list)) => list.light_beams(light),
            _ => None,
        }
    }

    /// Whether `intersect_exact_batch` traces its rays together (Embree's
    /// stream API), and so is worth gathering them for: elsewhere it asks
    /// one ray at a time, and gathering only costs.
    pub fn streams(&self) -> bool {
        matches!(self, Accel::Embree(_, None))
    }

    /// `intersect_exact` of each of many neighbouring rays: on Embree 3 as
    /// one coherent stream (`CommittedScene::intersect_exact_batch`, whose
    /// hits are the same bits but where two primitives tie); a scene that
    /// skips the BVH, and the pure-Rust backends, one ray at a time. A panic
    /// caught in a query leaves a miss, as in `intersect_exact`, for the
    /// render's `check` to report.
    pub fn intersect_exact_batch(&self, rays: &[Ray64], hits: &mut [Hit]) {
        match self {
            Accel::Embree(s, None) => s.intersect_exact_batch(rays, hits),
            _ => {
                for (hit, ray) in hits.iter_mut().zip(rays) {
                    *hit = self.intersect_exact(ray);
                }
            }
        }
    }

    pub fn occluded(&self, ray: &Ray) -> bool {
        self.occluded_among(ray, ShapeSet::ALL)
    }

    /// `occluded`, asking only the shapes of `among` where the render's
    /// rays skip the BVH (`rust_bvh::ListScene`): those that some
    /// `light_beams` proof leaves. Elsewhere every primitive is asked.
    pub fn occluded_among(&self, ray: &Ray, among: ShapeSet) -> bool {
        match self {
            Accel::Embree(s, Some(list)) => list.occluded(ray, among, s.panics()),
            Accel::Embree(s, None) => s.occluded(ray),
            Accel::Obvhs(s) => s.occluded(ray),
            Accel::Bvh(s) => s.occluded(ray),
        }
    }

    /// Every hit along `ray` in [tnear, tfar), appended to `hits`, nearest
    /// first (equal t: by geometry, then primitive): two triangles hit at
    /// the same t, as at a shared edge, are both there, and every crossing
    /// of an analytic shape (a tangent double root is one hit).
    pub fn intersect_all(&self, ray: &Ray, hits: &mut Vec<Hit>) {
        let first = hits.len();
        match self {
            Accel::Embree(s, _) => s.intersect_all(ray, hits),
            Accel::Obvhs(s) => s.intersect_all(ray, hits),
            Accel::Bvh(s) => s.intersect_all(ray, hits),
        }
        hits[first..].sort_unstable_by(|a, b| {
            a.t.total_cmp(&b.t)
                .then(a.geom_id.cmp(&b.geom_id))
                .then(a.prim_id.cmp(&b.prim_id))
        });
    }

    /// Traces many rays; `coherent` says they are neighbouring camera rays.
    pub fn intersect_batch(&self, rays: &[Ray], hits: &mut [Hit], coherent: bool) -> Result<()> {
        assert_eq!(rays.len(), hits.len(), "one hit record per ray");
        match self {
            Accel::Embree(s, _) => s.intersect_batch(rays, hits, coherent),
            // No packet traversal in the pure-Rust backends: one ray at a time.
            Accel::Obvhs(_) | Accel::Bvh(_) => {
                for (hit, ray) in hits.iter_mut().zip(rays) {
                    *hit = self.intersect(ray);
                }
                // A panic caught in a query left a miss behind: say so now,
                // as Embree's batch does, before anyone reads the hits.
                self.check()
            }
        }
    }

    /// Whether a query has panicked since the last `check` (which reports
    /// it): one atomic load, for loops that should stop at once.
    pub fn panicked(&self) -> bool {
        match self {
            Accel::Embree(s, _) => s.panics().happened(),
            Accel::Obvhs(s) => s.panics().happened(),
            Accel::Bvh(s) => s.panics().happened(),
        }
    }

    /// Reports errors the backend raised during queries since the last
    /// check, and panics caught in them.
    pub fn check(&self) -> Result<()> {
        match self {
            Accel::Embree(s, _) => s.check(),
            Accel::Obvhs(s) => s.check(),
            Accel::Bvh(s) => s.check(),
        }
    }

    /// Bytes the backend holds for this scene's BVH and geometry: Embree's own
    /// count of its allocations; for the pure-Rust backends, the capacity of
    /// each of their vectors times its element size.
    pub fn memory_bytes(&self) -> i64 {
        match self {
            Accel::Embree(s, _) => s.device().bytes_in_use(),
            Accel::Obvhs(s) => s.memory_bytes() as i64,
            Accel::Bvh(s) => s.memory_bytes() as i64,
        }
    }

    /// The backend and its version, e.g. "Embree 3.13.5 (bindings from the
    /// 3.13.5 header)", and whether a render's rays skip its BVH.
    pub fn describe(&self) -> String {
        match self {
            Accel::Embree(s, list) => format!(
                "Embree {} (bindings from the {} header){}",
                s.device().library_version(),
                embree::HEADER_VERSION,
                list.as_ref()
                    .map_or(String::new(), |l| match l.shape_count() {
                        1 => "; a render's rays go to its one shape directly, without a BVH".into(),
                        n => format!(
                            "; a render's rays go to its {n} shapes directly, without a BVH"
                        ),
                    })
            ),
            Accel::Obvhs(_) => "obvhs 0.4 CWBVH (pure Rust)".into(),
            Accel::Bvh(_) => "bvh 0.13 binary SAH BVH (pure Rust)".into(),
        }
    }
}
