//! `sturmray accuracy`: runs the accuracy study
//! (`sturmray::report::accuracy`) and prints its table, with its JSON and
//! plot when asked.

use std::path::{Path, PathBuf};

use anyhow::Context;

use sturmray::io::console::print;
use sturmray::io::output::Role;
use sturmray::report::accuracy;

use super::shared::{check_outputs, roles, sources_of};
use super::signals::Signals;

/// What accuracy costs in time: every root finder at tolerances 1e-2 to
/// 1e-14 on the algebraic scenes and sets of hard polynomials, against the
/// exact reference; then, per degree 17 to 35, how often the f64 answer
/// fails its exact certificate. Run from the repository (it reads scenes/).
#[derive(clap::Args)]
pub struct Args {
    /// Fewer rays and passes: a run under a minute (release build).
    #[arg(long)]
    quick: bool,
    /// Write the records as JSON.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Write the plot of time against error (SVG).
    #[arg(long)]
    plot: Option<PathBuf>,
}

pub fn run(Args { quick, json, plot }: Args) -> anyhow::Result<()> {
    let signals = Signals::catch_at_once()?;
    let mut outputs: Vec<Role> = json.iter().map(|p| Role::new("--json", p)).collect();
    outputs.extend(plot.iter().map(|p| Role::new("--plot", p)));
    let sources = sources_of(&accuracy::scene_files(Path::new(".")))?;
    check_outputs(&roles("a study scene's file", &sources), &outputs)?;
    let records = accuracy::command(quick).context("accuracy study failed")?;
    {
        let _writing = signals.writing();
        if let Some(path) = &json {
            accuracy::write_json(path, &records)?;
        }
        if let Some(path) = &plot {
            accuracy::plot::write_svg(path, &records)?;
        }
    }
    let per_degree = if quick { 6 } else { 24 };
    let certified = accuracy::certified::run(per_degree);
    Ok(print(&format!(
        "{}{}",
        accuracy::table(&records),
        accuracy::certified::table(&certified)
    ))?)
}
