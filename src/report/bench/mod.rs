//! `sturmray bench`: Mrays/s per backend, ray kind and thread count, all on
//! the same rays in the same run, plus BVH build time and memory.

pub mod c_harness;
mod workload;

use std::path::PathBuf;
use std::time::Instant;

use rayon::prelude::*;
use serde::Serialize;

use crate::accel::{Accel, Backend};
use crate::error::Result;
use crate::math::{Bounds, Hit, Ray, Vec3, offset};
use crate::render::thread_pool;
use crate::sampling::Rng;
use crate::scene::Scene;

/// One measurement, in the JSON form ARCHITECTURE.md fixes (plus `api`).
#[derive(Clone, Debug, Serialize)]
pub struct Record {
    pub backend: String,
    pub scene: String,
    pub triangles: usize,
    /// "camera" | "incoherent" | "shadow".
    pub ray_kind: &'static str,
    /// How rays reach the backend: "single" (one call per ray) or "batch".
    pub api: &'static str,
    pub threads: usize,
    pub mrays_per_s: f64,
    pub build_ms: f64,
    pub bytes: i64,
}

/// The three ray sets of a scene: camera rays through pixel centres (row by
/// row, coherent), random rays in and around the bounds (incoherent), and
/// shadow rays from the camera rays' hits towards the first light.
struct RaySets {
    camera: Vec<Ray>,
    incoherent: Vec<Ray>,
    shadow: Vec<Ray>,
}

/// `count` rays from random points in `bounds` (grown by 10% each side) in
/// uniformly random directions, from the generator seeded by `seed`: the
/// benchmark's incoherent rays, and the backend tests' random rays.
pub fn incoherent_rays(bounds: Bounds, count: usize, seed: u64) -> Vec<Ray> {
    let (lo, size) = (
        bounds.min - 0.1 * bounds.diagonal(),
        1.2 * bounds.diagonal(),
    );
    let mut rng = Rng::for_sample(seed, 0, 0);
    (0..count)
        .map(|_| {
            let o = lo + size * Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            // Uniform on the sphere: z uniform in [-1, 1], angle uniform.
            let z = 2.0 * rng.next_f32() - 1.0;
            let phi = std::f32::consts::TAU * rng.next_f32();
            let r = (1.0 - z * z).max(0.0).sqrt();
            Ray::new(o, Vec3::new(r * phi.cos(), r * phi.sin(), z))
        })
        .collect()
}

fn ray_sets(scene: &Scene, accel: &Accel, count: usize) -> RaySets {
    let frame = scene.camera.frame();
    // A grid of `count` rays spread over the whole image, row by row: with fewer
    // rays than pixels, the top rows alone would mostly see background.
    let (w, h) = (scene.camera.width as f32, scene.camera.height as f32);
    let columns = ((count as f32 * w / h).sqrt().ceil() as usize).max(1);
    let rows = count.div_ceil(columns);
    let camera: Vec<Ray> = (0..count)
        .map(|i| {
            let (x, y) = ((i % columns) as f32 + 0.5, (i / columns) as f32 + 0.5);
            frame.ray(x * w / columns as f32, y * h / rows as f32)
        })
        .collect();

    let bounds = scene.bounds();
    let incoherent = incoherent_rays(bounds, count, 0x5eed);

    // Shadow rays go towards the first light, or straight up without one.
    let overhead = crate::lights::Incident {
        wi: Vec3::Y,
        distance: f32::INFINITY,
        irradiance: Vec3::ONE,
        pdf: 0.0,
    };
    let target = scene
        .lights
        .first()
        .and_then(|light| light.incident(bounds.center(), [0.5; 2]))
        .unwrap_or(overhead);
    let shadow = camera
        .iter()
        .filter_map(|ray| {
            let hit = accel.intersect(ray);
            hit.is_hit().then(|| {
                // Spawned as the renderer spawns its shadow rays.
                let it = scene.interaction(ray, &hit);
                let mut s = Ray::new(offset(it.p, it.error, it.n, target.wi), target.wi);
                s.tfar = target.distance;
                s
            })
        })
        .collect();
    RaySets {
        camera,
        incoherent,
        shadow,
    }
}

/// Best of `reps` timings of `f`, in seconds.
fn best_of(reps: usize, mut f: impl FnMut()) -> f64 {
    (0..reps)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

const CHUNK: usize = 4096;

fn measure(
    accel: &Accel,
    rays: &[Ray],
    kind: &'static str,
    api: &'static str,
    threads: usize,
    reps: usize,
) -> Result<f64> {
    let pool = thread_pool(Some(threads))?;
    let mut hits = vec![Hit::MISS; rays.len()];
    let mut failure = None;
    let seconds = pool.install(|| {
        best_of(reps, || {
            let outcome = match (kind, api) {
                ("shadow", _) => {
                    let blocked: usize = rays
                        .par_chunks(CHUNK)
                        .map(|c| c.iter().filter(|r| accel.occluded(r)).count())
                        .sum();
                    std::hint::black_box(blocked);
                    Ok(())
                }
                (_, "single") => {
                    rays.par_chunks(CHUNK)
                        .zip(hits.par_chunks_mut(CHUNK))
                        .for_each(|(r, h)| {
                            for (ray, hit) in r.iter().zip(h) {
                                *hit = accel.intersect(ray);
                            }
                        });
                    Ok(())
                }
                _ => rays
                    .par_chunks(CHUNK)
                    .zip(hits.par_chunks_mut(CHUNK))
                    .try_for_each(|(r, h)| accel.intersect_batch(r, h, kind == "camera")),
            };
            if let Err(e) = outcome {
                failure = Some(e);
            }
        })
    });
    match failure {
        Some(e) => Err(e),
        None => Ok(rays.len() as f64 / seconds / 1e6),
    }
}

/// What to measure.
pub struct Options {
    /// Fewer rays and repetitions, smaller meshes: under a minute on 2 cores.
    pub quick: bool,
    /// Scene files to measure instead of the default workload (see `workload`).
    pub scenes: Vec<PathBuf>,
    /// Where the default workload's scene files live.
    pub scene_root: PathBuf,
    /// Which backends (default: all).
    pub backends: Vec<Backend>,
}

/// Rays per set and repetitions per measurement.
fn sizes(quick: bool) -> (usize, usize) {
    if quick { (100_000, 3) } else { (500_000, 3) }
}

/// The scene files a run reads: those asked for, or the standard set.
pub fn scene_files(options: &Options) -> Vec<PathBuf> {
    if options.scenes.is_empty() {
        workload::scene_files(&options.scene_root)
    } else {
        options.scenes.clone()
    }
}

pub fn run(options: &Options) -> Result<Vec<Record>> {
    let (count, reps) = sizes(options.quick);
    // The generated meshes join the standard set only.
    let sizes = if options.scenes.is_empty() {
        workload::mesh_sizes(options.quick)
    } else {
        &[]
    };
    let scenes = workload::scenes(&scene_files(options), sizes)?;
    let backends = if options.backends.is_empty() {
        Backend::ALL.to_vec()
    } else {
        options.backends.clone()
    };
    let all = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut thread_counts = vec![1];
    if all > 1 {
        thread_counts.push(all);
    }
    let mut records = Vec::new();
    for scene in &scenes {
        let triangles = scene.triangle_count();
        let mut sets = None;
        for &backend in &backends {
            crate::io::console::note(format_args!(
                "bench: {} ({triangles} triangles): building {}",
                scene.name,
                backend.name()
            ));
            let start = Instant::now();
            let accel = Accel::build(scene, backend, None)?;
            let build_ms = start.elapsed().as_secs_f64() * 1e3;
            let bytes = accel.memory_bytes();
            // The same rays for every backend: made once, with the first backend's
            // hits for the shadow rays' origins.
            let sets = sets.get_or_insert_with(|| ray_sets(scene, &accel, count));
            // Only Embree has a batch API of its own; the others loop.
            let apis: &[&'static str] = if backend == Backend::Embree {
                &["single", "batch"]
            } else {
                &["single"]
            };
            for &threads in &thread_counts {
                let cases = [
                    ("camera", &sets.camera),
                    ("incoherent", &sets.incoherent),
                    ("shadow", &sets.shadow),
                ];
                for (kind, rays) in cases {
                    // Shadow rays go through `occluded`, which has no batch form.
                    let kind_apis = if kind == "shadow" { &apis[..1] } else { apis };
                    for &api in kind_apis {
                        records.push(Record {
                            backend: backend.name().into(),
                            scene: scene.name.clone(),
                            triangles,
                            ray_kind: kind,
                            api,
                            threads,
                            mrays_per_s: measure(&accel, rays, kind, api, threads, reps)?,
                            build_ms,
                            bytes,
                        });
                    }
                }
            }
        }
    }
    Ok(records)
}

/// "Embree / fastest pure-Rust backend" on incoherent rays on the scene with
/// the most triangles, per thread count: the target is at least 1.5
/// on the 1M mesh. Each backend counts with its fastest API. Empty if Embree
/// or every pure-Rust backend was left out.
pub fn incoherent_ratios(records: &[Record]) -> String {
    let Some(largest) = records.iter().max_by_key(|r| r.triangles) else {
        return String::new();
    };
    let mut threads: Vec<usize> = records.iter().map(|r| r.threads).collect();
    threads.sort_unstable();
    threads.dedup();
    let mut s = String::new();
    for t in threads {
        let best = |backend: &str| {
            records
                .iter()
                .filter(|r| {
                    r.scene == largest.scene
                        && r.ray_kind == "incoherent"
                        && r.threads == t
                        && r.backend == backend
                })
                .map(|r| r.mrays_per_s)
                .fold(None, |a: Option<f64>, x| Some(a.map_or(x, |a| a.max(x))))
        };
        let rust = [Backend::Obvhs, Backend::Bvh]
            .into_iter()
            .filter_map(|b| best(b.name()).map(|m| (b.name(), m)))
            .max_by(|a, b| a.1.total_cmp(&b.1));
        if let (Some(embree), Some((name, fastest))) = (best("embree"), rust) {
            s += &format!(
                "embree / fastest rust ({name}), incoherent rays, {} ({} triangles), {t} thread(s): {:.2}\n",
                largest.scene,
                largest.triangles,
                embree / fastest
            );
        }
    }
    s
}

/// The records as a plain-text table.
pub fn table(records: &[Record]) -> String {
    let mut s = format!(
        "{:<8} {:<14} {:>10} {:<11} {:<7} {:>7} {:>10} {:>9} {:>12}\n",
        "backend", "scene", "triangles", "rays", "api", "threads", "Mrays/s", "build ms", "bytes"
    );
    for r in records {
        s += &format!(
            "{:<8} {:<14} {:>10} {:<11} {:<7} {:>7} {:>10.2} {:>9.1} {:>12}\n",
            r.backend,
            r.scene,
            r.triangles,
            r.ray_kind,
            r.api,
            r.threads,
            r.mrays_per_s,
            r.build_ms,
            r.bytes
        );
    }
    s
}
