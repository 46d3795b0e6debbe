//! `sturmray bench`: runs the benchmark study (`sturmray::report::bench`)
//! and prints its table, or writes the C harness's inputs.

use std::path::PathBuf;

use anyhow::Context;

use sturmray::accel::Backend;
use sturmray::io::console::print;
use sturmray::io::output::Role;
use sturmray::report::bench;

use super::shared::{BackendArg, check_outputs, roles, sources_of, write_text};
use super::signals::Signals;

/// Measure BVH build time, memory and Mrays/s of camera, incoherent and shadow
/// rays per backend, on one thread and on all, on the same rays.
#[derive(clap::Args)]
pub struct Args {
    /// Smaller meshes, fewer rays and repetitions: under a minute.
    #[arg(long)]
    quick: bool,
    /// Write the records as JSON.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Scenes to measure (default: generated meshes of 10k to 1M triangles,
    /// scenes/knot.toml and scenes/gallery/*.toml).
    #[arg(long = "scene")]
    scenes: Vec<PathBuf>,
    /// Backends to measure (repeatable; default: all).
    #[arg(long = "backend", value_enum)]
    backends: Vec<BackendArg>,
    /// Instead: write each scene's mesh and rays into DIR for the C harness
    /// (benches/c_harness) and print Embree's Mrays/s through the wrapper on
    /// one thread, with a checksum of the hits (default scenes: the knot and
    /// the largest generated mesh).
    #[arg(long, value_name = "DIR", conflicts_with_all = ["json", "backends"])]
    c_harness: Option<PathBuf>,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let options = bench::Options {
        quick: args.quick,
        scenes: args.scenes,
        scene_root: PathBuf::from("scenes"),
        backends: args.backends.into_iter().map(Backend::from).collect(),
    };
    let signals = Signals::catch_at_once()?;
    if let Some(path) = &args.json {
        let sources = sources_of(&bench::scene_files(&options))?;
        check_outputs(
            &roles("a bench scene's file", &sources),
            &[Role::new("--json", path)],
        )?;
    }
    if let Some(dir) = args.c_harness {
        return bench::c_harness::run(&options, &dir, &mut std::io::stdout().lock())
            .context("benchmark failed");
    }
    let records = bench::run(&options).context("benchmark failed")?;
    if let Some(path) = args.json {
        let _writing = signals.writing();
        write_text(&path, &(serde_json::to_string_pretty(&records)? + "\n"))?;
    }
    print(&(bench::table(&records) + &bench::incoherent_ratios(&records)))?;
    Ok(())
}
