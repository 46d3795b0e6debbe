//! The sturmray command line. Exit codes: 0 success, 2 bad input or usage,
//! 1 an internal error.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use anyhow::Context;
use clap::{Parser, Subcommand, ValueEnum};

use sturmray::accel::{Accel, Backend};
use sturmray::error::Error;
use sturmray::film::Region;
use sturmray::io;
use sturmray::io::console::{note, print};
use sturmray::io::output::{Role, check_distinct, prepare, write_atomic};
use sturmray::render::job::{Job, Part, preview_path, state_path};
use sturmray::render::{RayKind, RenderOptions, merge};
use sturmray::report::bench;
use sturmray::scene::{PhotonSettings, Scene};

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
        /// Photons for caustics (overrides the scene's `render.photons.count`; 0: none).
        #[arg(long)]
        photons: Option<u32>,
        /// Spawn every kind of ray, whatever the scene calls for (to measure what
        /// the render plan saves).
        #[arg(long)]
        all_effects: bool,
        /// Render band I of N horizontal bands of whole rows (I from 0), with its
        /// film state beside the EXR, for `merge`.
        #[arg(long, value_parser = parse_tile, conflicts_with = "crop")]
        tile: Option<(usize, usize)>,
        /// Render only [x0, x1) x [y0, y1), with its film state beside the EXR.
        #[arg(long, value_parser = parse_crop)]
        crop: Option<Region>,
        /// The animation frame (cameras with `[[camera.keys]]`).
        #[arg(long, default_value_t = 0)]
        frame: u32,
        /// Continue an interrupted render from the film state beside the output.
        #[arg(long)]
        resume: bool,
    },
    /// Merge the EXRs of tiles or crops (their film states beside them) into
    /// the whole image; parts of one region with different seeds add up.
    Merge {
        /// The whole image to write.
        output: PathBuf,
        /// The parts (each with its .state beside it).
        #[arg(required = true)]
        parts: Vec<PathBuf>,
    },
    /// Print the backend in use, the objects, triangle count, lights and settings.
    Info {
        scene: PathBuf,
        #[arg(long, value_enum, default_value = "embree")]
        backend: BackendArg,
    },
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
        /// The animation frame, as `render --frame`.
        #[arg(long, default_value_t = 0)]
        frame: u32,
        #[arg(long, value_enum, default_value = "embree")]
        backend: BackendArg,
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
    /// Measure BVH build time, memory and Mrays/s of camera, incoherent and shadow
    /// rays per backend, on one thread and on all, on the same rays.
    Bench {
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
    },
    /// What accuracy costs in time: every root finder at tolerances 1e-2 to
    /// 1e-14 on the algebraic scenes and sets of hard polynomials, against the
    /// exact reference. Run from the repository (it reads scenes/).
    Accuracy {
        /// Fewer rays and passes: a run under a minute (release build).
        #[arg(long)]
        quick: bool,
        /// Write the records as JSON.
        #[arg(long)]
        json: Option<PathBuf>,
        /// Write the plot of time against error (SVG).
        #[arg(long)]
        plot: Option<PathBuf>,
    },
}

fn parse_tile(text: &str) -> Result<(usize, usize), String> {
    let parsed = text.split_once('/').and_then(|(i, n)| {
        Some((
            i.trim().parse::<usize>().ok()?,
            n.trim().parse::<usize>().ok()?,
        ))
    });
    parsed.ok_or_else(|| format!("expected I/N with whole numbers, found {text:?}"))
}

fn parse_crop(text: &str) -> Result<Region, String> {
    let numbers: Vec<usize> = text
        .split(',')
        .map(|s| s.trim().parse::<usize>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("expected x0,y0,x1,y1 with whole numbers, found {text:?}"))?;
    match numbers[..] {
        [x0, y0, x1, y1] => Ok(Region { x0, y0, x1, y1 }),
        _ => Err(format!("expected four numbers x0,y0,x1,y1, found {text:?}")),
    }
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
    // A panic is a bug, caught (in callbacks and backends) and reported as
    // exit 1 with its message: one line on stderr, not a backtrace hint.
    std::panic::set_hook(Box::new(|info| {
        note(format_args!("sturmray: internal error (a bug): {info}"));
    }));
    let cli = Cli::parse();
    // Not for `roots`: subnormal coefficients are ordinary numbers there, and
    // under DAZ even JSON parsing reads them as 0.
    if !matches!(cli.command, Command::Roots { .. }) {
        sturmray::accel::ftz::enable_flush_to_zero();
    }
    match run(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        // 128 + SIGINT, as shells report a process a Ctrl-C ended; the image and
        // film state so far are written.
        Err(err) if err.is::<Interrupted>() => ExitCode::from(130),
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
            note(format_args!("sturmray: {message}"));
            let bad_input = err.chain().any(|cause| {
                cause
                    .downcast_ref::<Error>()
                    .is_some_and(Error::is_bad_input)
            });
            ExitCode::from(if bad_input { 2 } else { 1 })
        }
    }
}

/// A render stopped by SIGINT or SIGTERM after writing what it had.
#[derive(Debug)]
struct Interrupted;

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("interrupted")
    }
}

impl std::error::Error for Interrupted {}

/// SIGINT and SIGTERM. During a render the first one stops the render (it
/// drops the pass under way), so the work so far is written; a second ends
/// the process at once. Commands that only write at their end (`trace`,
/// `merge`, `bench`, `accuracy`) end at the first. Never in the middle of
/// writing: the end waits for the files being written, so none is lost or
/// torn and no temporary is left behind.
struct Signals {
    interrupt: Arc<AtomicBool>,
    /// Set by a second signal.
    again: Arc<AtomicBool>,
    writing: Arc<Mutex<()>>,
}

impl Signals {
    /// For a render: the first signal asks it to stop.
    fn catch() -> Result<Signals, Error> {
        Self::catch_after(false)
    }

    /// For the other commands that write: the first signal ends the process.
    fn catch_at_once() -> Result<Signals, Error> {
        Self::catch_after(true)
    }

    /// `stopping`: as if a first signal had come already.
    fn catch_after(stopping: bool) -> Result<Signals, Error> {
        let interrupt = Arc::new(AtomicBool::new(stopping));
        let again = Arc::new(AtomicBool::new(false));
        let writing = Arc::new(Mutex::new(()));
        let (first, second, lock) = (interrupt.clone(), again.clone(), writing.clone());
        // ctrlc runs this on a thread of its own, so it may wait on a lock.
        ctrlc::set_handler(move || {
            if first.swap(true, Ordering::SeqCst) {
                // Recorded before waiting, so the writer sees it when done.
                second.store(true, Ordering::SeqCst);
                let _writes_done = lock.lock();
                std::process::exit(130);
            }
            note(format_args!(
                "\ninterrupted: stopping, then writing the image of the passes done"
            ));
        })
        .map_err(|e| Error::Internal(format!("cannot catch signals: {e}")))?;
        Ok(Signals {
            interrupt,
            again,
            writing,
        })
    }

    /// Held while files are written: a second signal waits for it.
    fn writing(&self) -> MutexGuard<'_, ()> {
        self.writing.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Whether a second signal came (while writing, it waits to end the
    /// process: ask before letting go of [`Signals::writing`]).
    fn twice(&self) -> bool {
        self.again.load(Ordering::SeqCst)
    }
}

/// Refuses outputs that would replace an input or each other, then makes
/// sure each can be written (see [`prepare`]), before any work is done.
fn check_outputs(inputs: &[Role], outputs: &[Role]) -> Result<(), Error> {
    check_distinct(inputs, outputs)?;
    outputs.iter().try_for_each(|o| prepare(o.path))
}

/// Writes a text output (JSON) atomically.
fn write_text(path: &Path, text: &str) -> Result<(), Error> {
    write_atomic(path, |w| {
        w.write_all(text.as_bytes()).map_err(|e| Error::io(path, e))
    })
}

/// Every file the scenes at `files` are read from (loading them).
fn sources_of(files: &[PathBuf]) -> Result<Vec<PathBuf>, Error> {
    let mut sources = Vec::new();
    for file in files {
        sources.extend(Scene::load(file)?.sources);
    }
    Ok(sources)
}

/// `paths` as inputs described by `what`.
fn roles<'a>(what: &str, paths: &'a [PathBuf]) -> Vec<Role<'a>> {
    paths.iter().map(|p| Role::new(what, p)).collect()
}

/// The files a scene was read from, as inputs no output may replace.
fn scene_inputs(scene: &Scene) -> Vec<Role<'_>> {
    let mut files = scene.sources.iter();
    let first = files.next().map(|s| Role::new("the scene", s));
    first
        .into_iter()
        .chain(files.map(|s| Role::new("the scene's file", s)))
        .collect()
}

/// Loads a scene and prints its warnings, once per command.
fn load(path: &Path) -> Result<Scene, Error> {
    let scene = Scene::load(path)?;
    for warning in &scene.warnings {
        note(format_args!("sturmray: warning: {warning}"));
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
            photons,
            all_effects,
            tile,
            crop,
            frame,
            resume,
        } => {
            // Caught from the start: the first signal stops the render, even
            // while it loads (see `Signals`).
            let signals = Signals::catch()?;
            let scene_path = scene;
            let mut scene = load(&scene_path)?;
            if let Some(count) = photons {
                // Refused even where the plan has no photon pass: a typo either way.
                PhotonSettings::check_count(count)
                    .map_err(|e| Error::Input(format!("--photons: {e}")))?;
                scene.render.photons.count = count;
            }
            scene.camera.go_to_frame(frame);
            let output = output.unwrap_or_else(|| PathBuf::from(format!("out/{}.exr", scene.name)));
            let (preview, state) = (preview_path(&output), state_path(&output));
            // The state is written by pieces and interrupted renders, so it is
            // always reserved; with --resume it is read first, then replaced.
            let mut outputs = vec![
                Role::new("the image", &output),
                Role::new("its PNG preview", &preview),
                Role::new("its film state", &state),
            ];
            outputs.extend(stats.as_deref().map(|p| Role::new("--stats", p)));
            check_outputs(&scene_inputs(&scene), &outputs)?;
            let threads = threads.map(|n| n as usize);
            let accel = Accel::build(&scene, backend.into(), threads)?;
            let options = RenderOptions {
                threads,
                spp,
                progress: true,
                all_effects,
                interrupt: Some(signals.interrupt.clone()),
                ..RenderOptions::default()
            };
            let job = Job {
                scene: &scene,
                accel: &accel,
                backend: backend.into(),
                part: match (tile, crop) {
                    (Some((index, count)), _) => Part::Tile { index, count },
                    (None, Some(region)) => Part::Crop(region),
                    (None, None) => Part::Whole,
                },
                frame,
                resume,
                output: &output,
            };
            let rendered = job.render(options)?;
            let writing = signals.writing();
            let written = rendered.write()?;
            let result = &written.output;
            let r = result.film.region;
            if let Some(path) = stats {
                let json = serde_json::json!({
                    "rays": result.stats,
                    "seconds": result.seconds,
                    "width": r.width(),
                    "height": r.height(),
                    "spp": written.spp,
                    "nonfinite_samples": result.nonfinite,
                });
                write_text(&path, &format!("{json:#}\n"))?;
            }
            let stop = !result.complete || signals.twice();
            drop(writing);
            if result.nonfinite > 0 {
                note(format_args!(
                    "warning: {} samples had NaN or infinite radiance and were counted as black",
                    result.nonfinite
                ));
            }
            let state = written
                .state
                .as_ref()
                .map_or(String::new(), |p| format!(", film state {}", p.display()));
            note(format_args!(
                "wrote {} and {}{state} ({}x{}, {} of {} spp, {:.2} s, {:.2} Mrays/s)",
                output.display(),
                written.preview.display(),
                r.width(),
                r.height(),
                result.samples_done,
                written.spp,
                result.seconds,
                result.stats.total() as f64 / result.seconds / 1e6
            ));
            if !result.complete {
                note(format_args!(
                    "interrupted: continue with the same command and --resume"
                ));
            }
            if stop {
                return Err(Interrupted.into());
            }
            Ok(())
        }
        Command::Merge { output, parts } => {
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
        Command::Info {
            scene: path,
            backend,
        } => {
            let scene = load(&path)?;
            let accel = Accel::build(&scene, backend.into(), None)?;
            print(&sturmray::report::info::describe(&scene, &accel))?;
            Ok(())
        }
        Command::Explain {
            scene,
            pixel,
            sample,
            all_effects,
            backend,
            frame,
        } => {
            let mut scene = load(&scene)?;
            scene.camera.go_to_frame(frame);
            let accel = Accel::build(&scene, backend.into(), None)?;
            let (result, tree) =
                sturmray::render::explain(&scene, &accel, pixel, sample, all_effects)?;
            let mut text = format!(
                "pixel {},{} sample {sample}: radiance {}\n",
                pixel.0,
                pixel.1,
                triple(result.radiance.to_array())
            );
            for node in tree {
                // Shadow rays belong to the hit they leave from: one level deeper.
                let level = node.depth as usize + usize::from(node.kind == RayKind::Shadow);
                let kind = format!("{:?}", node.kind).to_lowercase();
                // Writing to a String cannot fail.
                let _ = writeln!(
                    text,
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
            print(&text)?;
            Ok(())
        }
        Command::Trace {
            scene,
            rays,
            out,
            backend,
        } => {
            let scene = load(&scene)?;
            let mut inputs = scene_inputs(&scene);
            inputs.push(Role::new("--rays", &rays));
            check_outputs(&inputs, &[Role::new("--out", &out)])?;
            let signals = Signals::catch_at_once()?;
            let rays = io::npy::read_rays(&rays)?;
            let accel = Accel::build(&scene, backend.into(), None)?;
            let hits = sturmray::render::trace_all(&accel, &rays, None)?;
            let _writing = signals.writing();
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
            backends,
            c_harness,
        } => {
            let options = bench::Options {
                quick,
                scenes,
                scene_root: PathBuf::from("scenes"),
                backends: backends.into_iter().map(Backend::from).collect(),
            };
            let signals = Signals::catch_at_once()?;
            if let Some(path) = &json {
                let sources = sources_of(&bench::scene_files(&options))?;
                check_outputs(
                    &roles("a bench scene's file", &sources),
                    &[Role::new("--json", path)],
                )?;
            }
            if let Some(dir) = c_harness {
                return bench::c_harness::run(&options, &dir, &mut std::io::stdout().lock())
                    .context("benchmark failed");
            }
            let records = bench::run(&options).context("benchmark failed")?;
            if let Some(path) = json {
                let _writing = signals.writing();
                write_text(&path, &(serde_json::to_string_pretty(&records)? + "\n"))?;
            }
            print(&(bench::table(&records) + &bench::incoherent_ratios(&records)))?;
            Ok(())
        }
        Command::Accuracy { quick, json, plot } => {
            use sturmray::report::accuracy;
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
            Ok(print(&accuracy::table(&records))?)
        }
    }
}
