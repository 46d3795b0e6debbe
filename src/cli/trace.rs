//! `sturmray trace`: rays from a .npy file in, their hits out as a .npy.

use std::path::PathBuf;

use sturmray::accel::Accel;
use sturmray::io;
use sturmray::io::output::Role;

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
    #[command(flatten)]
    include: IncludeArgs,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let scene = load(&args.scene, &args.include)?;
    let mut inputs = scene_inputs(&scene);
    inputs.push(Role::new("--rays", &args.rays));
    check_outputs(&inputs, &[Role::new("--out", &args.out)])?;
    let signals = Signals::catch_at_once()?;
    let rays = io::npy::read_rays(&args.rays)?;
    let accel = Accel::build(&scene, args.backend.into(), None)?;
    let hits = sturmray::render::trace_all(&accel, &rays, None)?;
    let _writing = signals.writing();
    io::npy::write_hits(&args.out, &hits)?;
    Ok(())
}
