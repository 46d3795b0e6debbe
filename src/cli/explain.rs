//! `sturmray explain`: the ray tree of one pixel sample, printed one ray a
//! line (the tree itself is traced by `sturmray::render::explain`).

use std::fmt::Write as _;
use std::path::PathBuf;

use sturmray::accel::Accel;
use sturmray::io::console::print;
use sturmray::render::RayKind;

use super::shared::{BackendArg, IncludeArgs, SamplerArg, SizeArgs, load_sized};

/// Print the ray tree of one pixel sample: each ray's kind, what it hit, t,
/// the material, its weight and the radiance it brings back.
#[derive(clap::Args)]
pub struct Args {
    scene: PathBuf,
    /// The image size, as `render`'s: the pixel is the rendered image's.
    #[command(flatten)]
    size: SizeArgs,
    #[command(flatten)]
    include: IncludeArgs,
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
    /// As `render --sampler`: the sampler the sample's numbers come from.
    #[arg(long, value_enum)]
    sampler: Option<SamplerArg>,
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

pub fn run(args: Args) -> anyhow::Result<()> {
    let Args {
        scene,
        size,
        include,
        pixel,
        sample,
        all_effects,
        frame,
        backend,
        sampler,
    } = args;
    let mut scene = load_sized(&scene, &size, &include)?;
    if let Some(sampler) = sampler {
        scene.render.sampler = sampler.into();
    }
    scene.camera.go_to_frame(frame);
    let accel = Accel::build(&scene, backend.into(), None)?;
    let (result, ray, tree) =
        sturmray::render::explain(&scene, &accel, pixel, sample, all_effects)?;
    // The camera ray's origin shows the lens point (or an orthographic
    // camera's offset); its direction the pixel position and the focus.
    let mut text = format!(
        "pixel {},{} sample {sample}: radiance {}, camera ray from {} along {}\n",
        pixel.0,
        pixel.1,
        triple(result.radiance.to_array()),
        triple(ray.origin.to_array()),
        triple(ray.dir.to_array())
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
