//! `sturmray bench`: Mrays/s per backend, ray kind and thread count, all on
//! the same rays in the same run, plus BVH build time and memory.

use std::path::PathBuf;
use std::time::Instant;

use rayon::prelude::*;
use serde::Serialize;

use crate::accel::{Accel, Backend};
use crate::error::Result;
use crate::math::{Hit, Ray, Vec3, offset};
use crate::render::thread_pool;
use crate::sampling::Rng;
use crate::scene::Scene;

/// One measurement, in the JSON form DESIGN.md fixes (plus `api`).
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

fn ray_sets(scene: &Scene, accel: &Accel, count: usize) -> RaySets {
    let frame = scene.camera.frame();
    let (w, h) = (scene.camera.width as usize, scene.camera.height as usize);
    let camera: Vec<Ray> = (0..count)
        .map(|i| {
            let p = i % (w * h);
            frame.ray((p % w) as f32 + 0.5, (p / w) as f32 + 0.5)
        })
        .collect();

    let bounds = scene.bounds();
    let (lo, size) = (
        bounds.min - 0.1 * bounds.diagonal(),
        1.2 * bounds.diagonal(),
    );
    let mut rng = Rng::for_sample(0x5eed, 0, 0);
    let incoherent = (0..count)
        .map(|_| {
            let o = lo + size * Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            // Uniform on the sphere: z uniform in [-1, 1], angle uniform.
            let z = 2.0 * rng.next_f32() - 1.0;
            let phi = std::f32::consts::TAU * rng.next_f32();
            let r = (1.0 - z * z).max(0.0).sqrt();
            Ray::new(o, Vec3::new(r * phi.cos(), r * phi.sin(), z))
        })
        .collect();

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

pub fn run(scenes: &[PathBuf], quick: bool) -> Result<Vec<Record>> {
    let (count, reps) = if quick { (200_000, 2) } else { (1_000_000, 5) };
    let all = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut thread_counts = vec![1];
    if all > 1 {
        thread_counts.push(all);
    }
    let mut records = Vec::new();
    for path in scenes {
        let scene = Scene::load(path)?;
        let start = Instant::now();
        let accel = Accel::build(&scene, Backend::Embree, None)?;
        let build_ms = start.elapsed().as_secs_f64() * 1e3;
        let bytes = accel.memory_bytes();
        let sets = ray_sets(&scene, &accel, count);
        let cases: [(&'static str, &'static str, &[Ray]); 5] = [
            ("camera", "single", &sets.camera),
            ("camera", "batch", &sets.camera),
            ("incoherent", "single", &sets.incoherent),
            ("incoherent", "batch", &sets.incoherent),
            ("shadow", "single", &sets.shadow),
        ];
        for &threads in &thread_counts {
            for (kind, api, rays) in cases {
                records.push(Record {
                    backend: "embree".into(),
                    scene: scene.name.clone(),
                    triangles: scene.triangle_count(),
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
    Ok(records)
}

/// The records as a plain-text table.
pub fn table(records: &[Record]) -> String {
    let mut s = format!(
        "{:<8} {:<12} {:>10} {:<11} {:<7} {:>7} {:>10} {:>9} {:>12}\n",
        "backend", "scene", "triangles", "rays", "api", "threads", "Mrays/s", "build ms", "bytes"
    );
    for r in records {
        s += &format!(
            "{:<8} {:<12} {:>10} {:<11} {:<7} {:>7} {:>10.2} {:>9.1} {:>12}\n",
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
