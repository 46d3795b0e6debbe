//! `sturmray trace`: rays from a .npy file in, their hits out as a .npy:
//! the nearest hit of each ray, every hit (`--all-hits`, with a second .npy
//! of per-ray offsets) or only whether anything blocks it (`--any-hit`).

use std::path::{Path, PathBuf};
use std::time::Instant;

use sturmray::accel::{Accel, check_rays};
use sturmray::io;
use sturmray::io::console::note;
use sturmray::io::output::Role;
use sturmray::render::{AllHits, all_hits_batch, thread_pool};

use super::shared::{BackendArg, IncludeArgs, check_outputs, load, scene_inputs};
use super::signals::Signals;

/// Trace rays from a .npy file and write the hits as a structured .npy.
#[derive(clap::Args)]
pub struct Args {
    scene: PathBuf,
    /// float32 (N, 6) origin + direction, or (N, 8) with tnear, tfar.
    #[arg(long)]
    rays: PathBuf,
    #[arg(long)]
    out: PathBuf,
    #[arg(long, value_enum, default_value = "embree")]
    backend: BackendArg,
    /// Every hit of each ray, nearest first, in --out; ray i's are rows
    /// offsets[i] to offsets[i+1], with the N+1 uint64 offsets written
    /// beside it as OUT.offsets.npy (h.npy: h.offsets.npy).
    #[arg(long, conflicts_with = "any_hit")]
    all_hits: bool,
    /// Only whether anything blocks each ray: --out is a bool array of N.
    #[arg(long)]
    any_hit: bool,
    #[command(flatten)]
    include: IncludeArgs,
}

/// Where `--all-hits` writes the offsets of the hits file `out`.
pub fn offsets_path(out: &Path) -> PathBuf {
    let stem = out.file_stem().unwrap_or_default().to_string_lossy();
    out.with_file_name(format!("{stem}.offsets.npy"))
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let scene = load(&args.scene, &args.include)?;
    let mut inputs = scene_inputs(&scene);
    inputs.push(Role::new("--rays", &args.rays));
    let offsets = offsets_path(&args.out);
    let mut outputs = vec![Role::new("--out", &args.out)];
    if args.all_hits {
        outputs.push(Role::new("the offsets of --all-hits", &offsets));
    }
    check_outputs(&inputs, &outputs)?;
    let signals = Signals::catch_at_once()?;
    let rays = io::npy::read_rays(&args.rays)?;
    let accel = Accel::build(&scene, args.backend.into(), None)?;
    // The trace alone is timed (not the reading, the BVH build or the
    // writing), so that tools/python_speed.py compares the module with it.
    let start = Instant::now();
    if args.any_hit {
        let blocked = sturmray::render::occluded_all(&accel, &rays, None)?;
        let seconds = start.elapsed().as_secs_f64();
        let _writing = signals.writing();
        io::npy::write_bools(&args.out, &blocked)?;
        wrote(&args.out, rays.len(), seconds);
    } else if args.all_hits {
        check_rays(&rays)?;
        let mut all = AllHits::default();
        thread_pool(None)?.install(|| all_hits_batch(&accel, &rays, None, &mut all))?;
        let seconds = start.elapsed().as_secs_f64();
        let _writing = signals.writing();
        io::npy::write_hits(&args.out, &all.hits)?;
        io::npy::write_offsets(&offsets, &all.offsets)?;
        wrote(&args.out, rays.len(), seconds);
    } else {
        let hits = sturmray::render::trace_all(&accel, &rays, None)?;
        let seconds = start.elapsed().as_secs_f64();
        let _writing = signals.writing();
        io::npy::write_hits(&args.out, &hits)?;
        wrote(&args.out, rays.len(), seconds);
    }
    Ok(())
}

/// The note after a trace: its rays, and the seconds of the trace alone.
fn wrote(out: &Path, rays: usize, seconds: f64) {
    note(format_args!(
        "wrote {} ({rays} rays traced in {seconds:.6} s, {:.2} Mrays/s)",
        out.display(),
        rays as f64 / seconds / 1e6
    ));
}
