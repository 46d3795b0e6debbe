//! What several subcommands share: the `--backend` and `--sampler` choices, the image size
//! (`--width`, `--height`), loading a scene, and the checks that no output replaces an input or another output.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use clap::ValueEnum;

use sturmray::accel::Backend;
use sturmray::error::Error;
use sturmray::io::console::note;
use sturmray::io::output::{Role, check_distinct, prepare, write_atomic};
use sturmray::sampling::SamplerKind;
use sturmray::scene::{Scene, SizeRequest};

// `--backend`: the doc comments of the values are their help text.
#[derive(Clone, Copy, ValueEnum)]
pub enum BackendArg {
    Embree,
    /// obvhs's compressed wide BVH (pure Rust).
    Obvhs,
    /// The bvh crate's binary SAH BVH (pure Rust).
    Bvh,
    /// The faster of the pure-Rust backends (obvhs).
    RustBvh,
}

impl From<BackendArg> for Backend {
    fn from(b: BackendArg) -> Backend {
        match b {
            BackendArg::Embree => Backend::Embree,
            BackendArg::Obvhs => Backend::Obvhs,
            BackendArg::Bvh => Backend::Bvh,
            BackendArg::RustBvh => Backend::FASTEST_RUST,
        }
    }
}

// `--sampler`: the doc comments of the values are their help text.
#[derive(Clone, Copy, ValueEnum)]
pub enum SamplerArg {
    /// Owen-scrambled Sobol points, stratified in every dimension (the default).
    Sobol,
    /// Independent random numbers, stratified in the pixel only.
    Independent,
}

impl From<SamplerArg> for SamplerKind {
    fn from(s: SamplerArg) -> SamplerKind {
        match s {
            SamplerArg::Sobol => SamplerKind::Sobol,
            SamplerArg::Independent => SamplerKind::Independent,
        }
    }
}

/// Refuses outputs that would replace an input or each other, then makes
/// sure each can be written (see [`prepare`]), before any work is done.
pub fn check_outputs(inputs: &[Role], outputs: &[Role]) -> Result<(), Error> {
    check_distinct(inputs, outputs)?;
    outputs.iter().try_for_each(|o| prepare(o.path))
}

/// Writes a text output (JSON) atomically.
pub fn write_text(path: &Path, text: &str) -> Result<(), Error> {
    write_atomic(path, |w| {
        w.write_all(text.as_bytes()).map_err(|e| Error::io(path, e))
    })
}

/// Every file the scenes at `files` are read from (loading them).
pub fn sources_of(files: &[PathBuf]) -> Result<Vec<PathBuf>, Error> {
    let mut sources = Vec::new();
    for file in files {
        sources.extend(Scene::load(file)?.sources);
    }
    Ok(sources)
}

/// `paths` as inputs described by `what`.
pub fn roles<'a>(what: &str, paths: &'a [PathBuf]) -> Vec<Role<'a>> {
    paths.iter().map(|p| Role::new(what, p)).collect()
}

/// The files a scene was read from, as inputs no output may replace.
pub fn scene_inputs(scene: &Scene) -> Vec<Role<'_>> {
    let mut files = scene.sources.iter();
    let first = files.next().map(|s| Role::new("the scene", s));
    first
        .into_iter()
        .chain(files.map(|s| Role::new("the scene's file", s)))
        .collect()
}

/// `--width` and `--height`, for the commands whose pixels are the rendered
/// image's. The doc comments are their help text.
#[derive(clap::Args, Default)]
pub struct SizeArgs {
    /// Image width in pixels, replacing the scene's (a .pov scene's: 800). Alone,
    /// the height follows the scene's aspect ratio. A TOML or OBJ camera keeps
    /// its vertical field of view.
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels, replacing the scene's (a .pov scene's: 600).
    /// Alone, the width follows the scene's aspect ratio.
    #[arg(long)]
    height: Option<u32>,
}

/// `--pov-include DIR`, for every command that loads a scene.
#[derive(clap::Args, Default)]
pub struct IncludeArgs {
    /// A folder where a .pov scene's `#include` looks for files, after the
    /// including file's own folder and before POV-Ray's installed includes
    /// (/usr/share/povray-3.7/include); may be given more than once.
    #[arg(long = "pov-include", value_name = "DIR")]
    pov_include: Vec<PathBuf>,
}

/// Loads a scene and prints its warnings, once per command.
pub fn load(path: &Path, include: &IncludeArgs) -> Result<Scene, Error> {
    load_sized(path, &SizeArgs::default(), include)
}

/// Loads a scene at the size `--width`/`--height` ask for, and prints its
/// warnings, once per command.
pub fn load_sized(path: &Path, size: &SizeArgs, include: &IncludeArgs) -> Result<Scene, Error> {
    let request = SizeRequest {
        width: size.width,
        height: size.height,
    };
    let scene = Scene::load_sized(path, request, include.pov_include.clone())?;
    for warning in &scene.warnings {
        note(format_args!("sturmray: warning: {warning}"));
    }
    Ok(scene)
}
