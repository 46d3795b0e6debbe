//! The sturmray command line. Exit codes: 0 success, 2 bad input or usage,
//! 1 an internal error.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context;
use clap::{Parser, Subcommand, ValueEnum};

use sturmray::accel::{Accel, Backend};
use sturmray::error::Error;
use sturmray::io;
use sturmray::render::{RayKind, RenderOptions, render};
use sturmray::report::bench;
use sturmray::scene::Scene;

#[derive(Parser)]
#[command(
    name = "sturmray",
    version,
    about = "Ray tracing meshes and exact analytic surfaces on Embree"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, ValueEnum)]
enum BackendArg {
    Embree,
}

impl From<BackendArg> for Backend {
    fn from(b: BackendArg) -> Backend {
        match b {
            BackendArg::Embree => Backend::Embree,
        }
    }
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene (.toml or a bare .obj) to an EXR with a PNG preview beside it.
    Render {
        scene: PathBuf,
        /// Output EXR (default: out/<scene name>.exr).
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Samples per pixel (overrides the scene's).
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
        spp: Option<u32>,
        #[arg(long, value_enum, default_value = "embree")]
        backend: BackendArg,
        /// Worker threads (default: all cores).
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
        threads: Option<u32>,
        /// Write ray counts and time as JSON.
        #[arg(long)]
        stats: Option<PathBuf>,
        /// Spawn every kind of ray, whatever the scene calls for (to measure what
        /// the render plan saves).
        #[arg(long)]
        all_effects: bool,
    },
    /// Print the Embree version in use, the objects, triangle count, lights and settings.
    Info { scene: PathBuf },
    /// Print the ray tree of one pixel sample: each ray's kind, what it hit, t,
    /// the material, its weight and the radiance it brings back.
    Explain {
        scene: PathBuf,
        /// The pixel, from the top-left corner.
        #[arg(long, value_parser = parse_pixel)]
        pixel: (usize, usize),
        /// Which of the pixel's samples (0 = the first).
        #[arg(long, default_value_t = 0)]
        sample: u32,
        /// As `render --all-effects`.
        #[arg(long)]
        all_effects: bool,
    },
    /// Trace rays from a .npy file and write the hits as a structured .npy.
    Trace {
        scene: PathBuf,
        /// float32 (N, 6) origin + direction, or (N, 8) with tnear, tfar.
        #[arg(long)]
        rays: PathBuf,
        #[arg(long)]
        out: PathBuf,
        #[arg(long, value_enum, default_value = "embree")]
        backend: BackendArg,
    },
    /// Find polynomial roots: JSON lines {"coeffs": [c0, c1, ...], "interval": [a, b],
    /// "method": "..."} on stdin, one JSON line out per line.
    Roots {
        /// Also print the Sturm sequence and its sign table at a and b.
        #[arg(long)]
        sturm: bool,
    },
    /// Measure Mrays/s of camera, incoherent and shadow rays, on one thread and on all.
    Bench {
        /// Fewer rays and repetitions: a run of seconds.
        #[arg(long)]
        quick: bool,
        /// Write the records as JSON.
        #[arg(long)]
        json: Option<PathBuf>,
        /// Scenes to measure (default: scenes/knot.toml).
        #[arg(long = "scene")]
        scenes: Vec<PathBuf>,
    },
}

fn parse_pixel(text: &str) -> Result<(usize, usize), String> {
    let (x, y) = text
        .split_once(',')
        .ok_or_else(|| format!("expected X,Y, found {text:?}"))?;
    let number = |s: &str| {
        s.trim()
            .parse::<usize>()
            .map_err(|_| format!("expected X,Y with whole numbers, found {text:?}"))
    };
    Ok((number(x)?, number(y)?))
}

fn triple(v: [f32; 3]) -> String {
    format!("[{:.4}, {:.4}, {:.4}]", v[0], v[1], v[2])
}

fn main() -> ExitCode {
    sturmray::accel::embree::enable_flush_to_zero();
    let cli = Cli::parse();
    match run(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            // The chain without repeats: an error's own text often includes its source's.
            let mut message = String::new();
            for cause in err.chain() {
                let text = cause.to_string();
                if !message.contains(&text) {
                    if !message.is_empty() {
                        message += ": ";
                    }
                    message += &text;
                }
            }
            eprintln!("sturmray: {message}");
            let bad_input = err.chain().any(|cause| {
                cause
                    .downcast_ref::<Error>()
                    .is_some_and(Error::is_bad_input)
            });
            ExitCode::from(if bad_input { 2 } else { 1 })
        }
    }
}

/// Creates the parent folder of an output file, so `out/` need not exist, and
/// makes sure the file can be written before any work is done, so a long
/// render is not lost at the end: an existing file is opened for writing
/// (not truncated), a new one is created and removed again.
fn prepare_output(path: &Path) -> Result<(), Error> {
    if let Some(dir) = path.parent()
        && !dir.as_os_str().is_empty()
    {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    }
    let existed = path.exists();
    std::fs::OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(false)
        .open(path)
        .map_err(|e| Error::io(path, e))?;
    if !existed {
        std::fs::remove_file(path).map_err(|e| Error::io(path, e))?;
    }
    Ok(())
}

/// Loads a scene and prints its warnings, once per command.
fn load(path: &Path) -> Result<Scene, Error> {
    let scene = Scene::load(path)?;
    for warning in &scene.warnings {
        eprintln!("sturmray: warning: {warning}");
    }
    Ok(scene)
}

fn run(command: Command) -> anyhow::Result<()> {
    match command {
        Command::Render {
            scene,
            output,
            spp,
            backend,
            threads,
            stats,
            all_effects,
        } => {
            let scene = load(&scene)?;
            let output = output.unwrap_or_else(|| PathBuf::from(format!("out/{}.exr", scene.name)));
            let preview = output.with_extension("png");
            for path in [Some(&output), Some(&preview), stats.as_ref()]
                .into_iter()
                .flatten()
            {
                prepare_output(path)?;
            }
            let threads = threads.map(|n| n as usize);
            let accel = Accel::build(&scene, backend.into(), threads)?;
            let options = RenderOptions {
                threads,
                spp,
                progress: true,
                all_effects,
            };
            let result = render(&scene, &accel, &options)?;
            let layers = result.film.layers();
            let (width, height) = (result.film.width, result.film.height);
            let image = io::exr::ImageLayers {
                width,
                height,
                beauty: &layers.beauty,
                depth: &layers.depth,
                normal: &layers.normal,
                albedo: &layers.albedo,
            };
            let spp = spp.unwrap_or(scene.render.spp);
            let attributes = [
                ("sturmray.spp", spp.to_string()),
                ("sturmray.seed", scene.render.seed.to_string()),
            ];
            io::exr::write_exr(&output, &image, &attributes)?;
            io::png::write_png_preview(&preview, width, height, &layers.beauty)?;
            if let Some(path) = stats {
                let json = serde_json::json!({
                    "rays": result.stats,
                    "seconds": result.seconds,
                    "width": width,
                    "height": height,
                    "spp": spp,
                });
                std::fs::write(&path, format!("{json:#}\n")).map_err(|e| Error::io(&path, e))?;
            }
            eprintln!(
                "wrote {} and {} ({width}x{height}, {spp} spp, {:.2} s, {:.2} Mrays/s)",
                output.display(),
                preview.display(),
                result.seconds,
                result.stats.total() as f64 / result.seconds / 1e6
            );
            Ok(())
        }
        Command::Info { scene: path } => {
            let scene = load(&path)?;
            let accel = Accel::build(&scene, Backend::Embree, None)?;
            print!("{}", sturmray::report::info::describe(&scene, &accel));
            Ok(())
        }
        Command::Explain {
            scene,
            pixel,
            sample,
            all_effects,
        } => {
            let scene = load(&scene)?;
            let accel = Accel::build(&scene, Backend::Embree, None)?;
            let (result, tree) =
                sturmray::render::explain(&scene, &accel, pixel, sample, all_effects)?;
            println!(
                "pixel {},{} sample {sample}: radiance {}",
                pixel.0,
                pixel.1,
                triple(result.radiance.to_array())
            );
            for node in tree {
                // Shadow rays belong to the hit they leave from: one level deeper.
                let level = node.depth as usize + usize::from(node.kind == RayKind::Shadow);
                let kind = format!("{:?}", node.kind).to_lowercase();
                println!(
                    "{:indent$}{kind:<10} t={:<10.6} {} {} weight {} radiance {}",
                    "",
                    node.t,
                    node.hit,
                    node.material
                        .map_or(String::new(), |m| format!("material {m}")),
                    triple(node.weight),
                    triple(node.radiance),
                    indent = 2 * level
                );
            }
            Ok(())
        }
        Command::Trace {
            scene,
            rays,
            out,
            backend,
        } => {
            let scene = load(&scene)?;
            let rays = io::npy::read_rays(&rays)?;
            prepare_output(&out)?;
            let accel = Accel::build(&scene, backend.into(), None)?;
            let hits = sturmray::render::trace_all(&accel, &rays, None)?;
            io::npy::write_hits(&out, &hits)?;
            Ok(())
        }
        Command::Roots { sturm } => {
            let any_bad = sturmray::report::roots::run(
                std::io::stdin().lock(),
                std::io::stdout().lock(),
                sturm,
            )?;
            if any_bad {
                let message = "some lines were not understood (see their error lines)";
                return Err(Error::Input(message.into()).into());
            }
            Ok(())
        }
        Command::Bench {
            quick,
            json,
            scenes,
        } => {
            let scenes = if scenes.is_empty() {
                vec![PathBuf::from("scenes/knot.toml")]
            } else {
                scenes
            };
            let records = bench::run(&scenes, quick).context("benchmark failed")?;
            print!("{}", bench::table(&records));
            if let Some(path) = json {
                prepare_output(&path)?;
                let text = serde_json::to_string_pretty(&records)?;
                std::fs::write(&path, text + "\n").map_err(|e| Error::io(&path, e))?;
            }
            Ok(())
        }
    }
}
