//! `sturmray bench --c-harness DIR`: the Rust side of the wrapper-overhead
//! measurement (issue #5). For each scene it writes the mesh and the camera
//! and incoherent rays as .npy files for the C program under
//! benches/c_harness, which calls Embree directly on them, then traces the
//! same rays through `Accel` on the calling thread, one call per ray and in
//! batches of `CHUNK` as `sturmray bench` does. Each measurement is one line
//! in the format the C program prints, with a checksum of the hits, so a
//! script can check that both sides did the same work and compare their speed.
//!
//! Both sides time each chunk of rays on its own and add up each chunk's best
//! time over `REPS` passes: on a machine shared with other jobs, a chunk of a
//! few milliseconds often runs undisturbed in some pass where a whole pass of
//! a second rarely does.

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use super::{CHUNK, Options, ray_sets, sizes, workload};
use crate::accel::ftz::enable_flush_to_zero;
use crate::accel::{Accel, Backend};
use crate::error::{Error, Result};
use crate::io::npy;
use crate::math::{Hit, Ray};

/// Passes over the rays; the C program's default is the same.
const REPS: usize = 10;

/// Writes the files into `dir` and one line per measurement to `out`:
/// `rust SCENE KIND API rays=N mrays=M hits=H tsum=S primsum=P`, where H is
/// the number of hits, S the sum of their t in ray order (in f64) and P the
/// sum of their primIDs.
pub fn run(options: &Options, dir: &Path, out: &mut impl Write) -> Result<()> {
    let (count, _) = sizes(options.quick);
    // As on every thread that traces (the C program sets both too).
    enable_flush_to_zero();
    let scenes = if options.scenes.is_empty() {
        // The knot and the largest generated mesh.
        let sizes = workload::mesh_sizes(options.quick);
        workload::scenes(
            &[options.scene_root.join("knot.toml")],
            &sizes[sizes.len() - 1..],
        )?
    } else {
        workload::scenes(&options.scenes, &[])?
    };
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    for scene in &scenes {
        // The C program builds one triangle geometry, ID 0, as Accel::build does for
        // a scene's only mesh; it cannot run Rust user-geometry callbacks.
        let [mesh] = &scene.meshes[..] else {
            return Err(Error::Input(format!(
                "{}: the C harness needs a scene of exactly one mesh, found {}",
                scene.name,
                scene.meshes.len()
            )));
        };
        if !scene.shapes.is_empty() {
            return Err(Error::Input(format!(
                "{}: the C harness cannot trace analytic shapes",
                scene.name
            )));
        }
        crate::io::console::note(format_args!(
            "bench: {} ({} triangles): building embree",
            scene.name,
            mesh.triangles.len()
        ));
        // Built on one thread, as the C program builds: no builder threads are left
        // spinning beside the traced one.
        let accel = Accel::build(scene, Backend::Embree, Some(1))?;
        let sets = ray_sets(scene, &accel, count);
        let file = |what: &str| dir.join(format!("{}.{what}.npy", scene.name));
        npy::write_mesh(
            &file("vertices"),
            &file("triangles"),
            &mesh.positions,
            &mesh.triangles,
        )?;
        for (kind, rays) in [("camera", &sets.camera), ("incoherent", &sets.incoherent)] {
            npy::write_rays(&file(kind), rays)?;
            for api in ["single", "batch"] {
                let mut hits = vec![Hit::MISS; rays.len()];
                let seconds = if api == "single" {
                    best_per_chunk(rays, &mut hits, |rays, hits| {
                        for (hit, ray) in hits.iter_mut().zip(rays) {
                            *hit = accel.intersect(ray);
                        }
                        Ok(())
                    })?
                } else {
                    best_per_chunk(rays, &mut hits, |rays, hits| {
                        accel.intersect_batch(rays, hits, kind == "camera")
                    })?
                };
                accel.check()?;
                let mrays = rays.len() as f64 / seconds / 1e6;
                let (count, tsum, primsum) = checksum(&hits);
                writeln!(
                    out,
                    "rust {} {kind} {api} rays={} mrays={mrays:.4} hits={count} tsum={tsum} \
                     primsum={primsum}",
                    scene.name,
                    rays.len()
                )
                .and_then(|()| out.flush())
                .map_err(|e| Error::Internal(format!("cannot write the results: {e}")))?;
            }
        }
    }
    Ok(())
}

/// The sum over chunks of `CHUNK` rays of each chunk's best time, in seconds,
/// of `REPS` passes of `trace` over all the rays.
fn best_per_chunk(
    rays: &[Ray],
    hits: &mut [Hit],
    mut trace: impl FnMut(&[Ray], &mut [Hit]) -> Result<()>,
) -> Result<f64> {
    let mut best = vec![f64::INFINITY; rays.len().div_ceil(CHUNK)];
    for _ in 0..REPS {
        for ((rays, hits), best) in rays
            .chunks(CHUNK)
            .zip(hits.chunks_mut(CHUNK))
            .zip(&mut best)
        {
            let start = Instant::now();
            trace(rays, hits)?;
            *best = best.min(start.elapsed().as_secs_f64());
        }
    }
    Ok(best.iter().sum())
}

/// The hits, the sum of their t in ray order and the sum of their primIDs:
/// the C program sums the same way, so equal work gives equal numbers.
fn checksum(hits: &[Hit]) -> (usize, f64, u64) {
    hits.iter()
        .filter(|h| h.is_hit())
        .fold((0, 0.0, 0), |(n, t, p), h| {
            (n + 1, t + f64::from(h.t), p + u64::from(h.prim_id))
        })
}
