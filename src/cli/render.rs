//! `sturmray render`: a scene (whole, a tile or a crop) to an EXR with its
//! PNG preview and film state, and the `--stats` JSON.

use std::path::PathBuf;

use sturmray::accel::Accel;
use sturmray::error::Error;
use sturmray::film::Region;
use sturmray::io::console::note;
use sturmray::io::output::Role;
use sturmray::render::RenderOptions;
use sturmray::render::job::{Job, Part, Written, preview_path, state_path};
use sturmray::scene::{PhotonSettings, Scene};

use super::shared::{
    BackendArg, IncludeArgs, SamplerArg, SizeArgs, check_outputs, load_sized, scene_inputs,
    write_text,
};
use super::signals::{Interrupted, Signals};

/// Render a scene (.toml, a bare .obj or .ply, or .pov) to an EXR with a PNG preview beside it.
#[derive(clap::Args)]
pub struct Args {
    scene: PathBuf,
    #[command(flatten)]
    size: SizeArgs,
    #[command(flatten)]
    include: IncludeArgs,
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
    /// Where samples draw their numbers from (overrides the scene's `render.sampler`).
    #[arg(long, value_enum)]
    sampler: Option<SamplerArg>,
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

pub fn run(args: Args) -> anyhow::Result<()> {
    // Caught from the start: the first signal stops the render, even
    // while it loads (see `Signals`).
    let signals = Signals::catch()?;
    let mut scene = load_sized(&args.scene, &args.size, &args.include)?;
    if let Some(count) = args.photons {
        // Refused even where the plan has no photon pass: a typo either way.
        PhotonSettings::check_count(count).map_err(|e| Error::Input(format!("--photons: {e}")))?;
        scene.render.photons.count = count;
    }
    if let Some(sampler) = args.sampler {
        scene.render.sampler = sampler.into();
    }
    scene.camera.go_to_frame(args.frame);
    let output = args
        .output
        .unwrap_or_else(|| PathBuf::from(format!("out/{}.exr", scene.name)));
    let (preview, state) = (preview_path(&output), state_path(&output));
    // The state is written by pieces and interrupted renders, so it is
    // always reserved; with --resume it is read first, then replaced.
    let mut outputs = vec![
        Role::new("the image", &output),
        Role::new("its PNG preview", &preview),
        Role::new("its film state", &state),
    ];
    outputs.extend(args.stats.as_deref().map(|p| Role::new("--stats", p)));
    check_outputs(&scene_inputs(&scene), &outputs)?;
    let threads = args.threads.map(|n| n as usize);
    let accel = Accel::build(&scene, args.backend.into(), threads)?;
    let options = RenderOptions {
        threads,
        spp: args.spp,
        progress: true,
        all_effects: args.all_effects,
        interrupt: Some(signals.interrupt.clone()),
        ..RenderOptions::default()
    };
    let job = Job {
        scene: &scene,
        accel: &accel,
        backend: args.backend.into(),
        part: match (args.tile, args.crop) {
            (Some((index, count)), _) => Part::Tile { index, count },
            (None, Some(region)) => Part::Crop(region),
            (None, None) => Part::Whole,
        },
        frame: args.frame,
        resume: args.resume,
        output: &output,
    };
    let rendered = job.render(options)?;
    let writing = signals.writing();
    let written = rendered.write()?;
    if let Some(path) = args.stats {
        write_text(&path, &format!("{:#}\n", stats(&scene, &written)))?;
    }
    let result = &written.output;
    // Asked even when the render is incomplete: a yes means this thread,
    // not the signal handler, ends the process.
    let twice = signals.twice();
    let stop = !result.complete || twice;
    drop(writing);
    if result.nonfinite > 0 {
        note(format_args!(
            "warning: {} samples had NaN or infinite radiance and were counted as black",
            result.nonfinite
        ));
    }
    let r = result.film.region;
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

/// The `--stats` record: ray counts by kind and depth, time, size, samples,
/// and the scene's instances (how many, of how many prototypes, and the
/// triangles they place, which the BVH holds once per prototype on Embree).
fn stats(scene: &Scene, written: &Written) -> serde_json::Value {
    let result = &written.output;
    let r = result.film.region;
    serde_json::json!({
        "instances": {
            "count": scene.instances.len(),
            "prototypes": scene.prototypes.len(),
            "triangles": scene.instanced_triangle_count(),
        },
        "rays": result.stats,
        "seconds": result.seconds,
        "width": r.width(),
        "height": r.height(),
        "spp": written.spp,
        "nonfinite_samples": result.nonfinite,
    })
}
