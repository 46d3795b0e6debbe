//! `sturmray merge`: the EXRs of tiles or crops into the whole image.

use std::path::PathBuf;

use sturmray::io::console::note;
use sturmray::io::output::Role;
use sturmray::render::job::{preview_path, state_path};
use sturmray::render::merge;

use super::shared::check_outputs;
use super::signals::Signals;

/// Merge the EXRs of tiles or crops (their film states beside them) into
/// the whole image; parts of one region with different seeds add up.
#[derive(clap::Args)]
pub struct Args {
    /// The whole image to write.
    output: PathBuf,
    /// The parts (each with its .state beside it).
    #[arg(required = true)]
    parts: Vec<PathBuf>,
}

pub fn run(Args { output, parts }: Args) -> anyhow::Result<()> {
    let states: Vec<PathBuf> = parts.iter().map(|p| state_path(p)).collect();
    let inputs: Vec<Role> = parts
        .iter()
        .map(|p| Role::new("the part", p))
        .chain(states.iter().map(|s| Role::new("the part's film state", s)))
        .collect();
    let preview = preview_path(&output);
    check_outputs(
        &inputs,
        &[
            Role::new("the image", &output),
            Role::new("its PNG preview", &preview),
        ],
    )?;
    // Held while merge reads and writes: a signal waits for the files.
    let signals = Signals::catch_at_once()?;
    let writing = signals.writing();
    let summary = merge::merge(&output, &parts)?;
    drop(writing);
    note(format_args!("wrote {}: {summary}", output.display()));
    Ok(())
}
