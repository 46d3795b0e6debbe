//! `sturmray info`: what a scene holds and what will trace it.

use std::fmt::Write;
use std::path::PathBuf;

use sturmray::accel::Accel;
use sturmray::io::console::print;
use sturmray::lights::{Fade, Light, Shadowing};
use sturmray::math::Vec3;
use sturmray::render::Plan;
use sturmray::scene::Scene;
use sturmray::scene::{Projection, WorkingGamma};

use super::shared::{BackendArg, IncludeArgs, load};

/// Print the backend in use, the objects, triangle count, lights and settings.
#[derive(clap::Args)]
pub struct Args {
    scene: PathBuf,
    #[arg(long, value_enum, default_value = "embree")]
    backend: BackendArg,
    #[command(flatten)]
    include: IncludeArgs,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let scene = load(&args.scene, &args.include)?;
    let accel = Accel::build(&scene, args.backend.into(), None)?;
    print(&describe(&scene, &accel))?;
    Ok(())
}

fn v(x: Vec3) -> String {
    format!("[{}, {}, {}]", x.x, x.y, x.z)
}

/// How a POV-Ray light fades: not at all, or by its distance and power.
fn fading(fade: Option<&Fade>) -> String {
    match fade {
        None => "unfading".into(),
        Some(f) => format!(
            "fading (fade_distance {}, fade_power {}, from {})",
            f.distance,
            f.power,
            v(f.from)
        ),
    }
}

/// A POV-Ray light's `shadowless` and `media_attenuation`, where given.
fn shadows(shadowing: Shadowing) -> &'static str {
    match (shadowing.shadowless, shadowing.fogged) {
        (false, false) => "",
        (true, false) => ", shadowless",
        (false, true) => ", dimmed by the fog",
        (true, true) => ", shadowless, dimmed by the fog",
    }
}

fn describe(scene: &Scene, accel: &Accel) -> String {
    let mut s = String::new();
    let c = &scene.camera;
    let r = &scene.render;
    // Writing to a String cannot fail.
    let _ = writeln!(s, "scene      {}", scene.name);
    let _ = writeln!(s, "backend    {}", accel.describe());
    if let Some(import) = &scene.import {
        let list = |m: &std::collections::BTreeMap<String, usize>| {
            m.iter()
                .map(|(k, n)| {
                    if *n == 1 {
                        k.clone()
                    } else {
                        format!("{k} ×{n}")
                    }
                })
                .collect::<Vec<_>>()
                .join(", ")
        };
        let _ = writeln!(s, "read       {}", list(&import.read));
        if !import.skipped.is_empty() {
            let _ = writeln!(
                s,
                "skipped    {} (outside the POV-Ray subset; see the warnings)",
                list(&import.skipped)
            );
        }
    }
    let view = match c.optics.projection {
        Projection::Perspective => format!("fov {}°", c.fov),
        Projection::PerspectiveX => format!("fov {}° across", c.fov),
        Projection::Orthographic { view_width } => format!("orthographic, {view_width} wide"),
    };
    let lens = c.optics.lens.map_or(String::new(), |l| {
        format!(
            ", lens radius {} focused at {}",
            l.aperture, l.focus_distance
        )
    });
    let _ = writeln!(
        s,
        "camera     eye {} look_at {} up {} {view}{lens}, {}x{}",
        v(c.eye),
        v(c.look_at),
        v(c.up),
        c.width,
        c.height
    );
    let _ = writeln!(
        s,
        "render     {} spp, max depth {}, seed {}, sampler {}",
        r.spp,
        r.max_depth,
        r.seed,
        r.sampler.name()
    );
    // Only POV-Ray's gamma rules make colours other than linear.
    let gamma = match r.working_gamma {
        WorkingGamma::Linear => None,
        WorkingGamma::Power(g) => Some(format!("assumed_gamma {g}: radiance v is the light v^{g}")),
        WorkingGamma::Srgb => Some(
            "sRGB-encoded (POV-Ray's gamma rules for a scene before 3.7 without assumed_gamma)"
                .to_string(),
        ),
    };
    if let Some(gamma) = gamma {
        let _ = writeln!(s, "colours    {gamma}");
    }
    match &scene.environment {
        Some(e) => {
            let what = match (&e.source.file, e.source.radiance) {
                (Some(file), _) => format!("map {}", file.display()),
                (None, Some(radiance)) => format!("constant radiance {}", v(Vec3::from(radiance))),
                (None, None) => "none".to_string(),
            };
            let _ = writeln!(
                s,
                "environment {what}, scale {}, rotation {}°, picked with p = {:.3}",
                e.source.scale,
                e.source.rotation,
                scene.light_picker.environment().unwrap_or(0.0)
            );
        }
        None => {
            let _ = writeln!(s, "background {}", v(scene.background));
        }
    }
    for fog in &scene.fogs {
        let ground = fog.ground.map_or(String::new(), |g| {
            format!(
                ", ground: offset {} alt {} up {}",
                g.offset,
                g.alt,
                v(g.up.as_vec3())
            )
        });
        let _ = writeln!(
            s,
            "fog        distance {}, colour {} filter {} transmit {}{ground}",
            fog.distance,
            v(fog.colour),
            fog.filter,
            fog.transmit
        );
    }
    let _ = writeln!(s, "plan       {}", Plan::for_scene(scene));
    let _ = writeln!(s, "meshes     {}", scene.meshes.len());
    for (id, mesh) in scene.meshes.iter().enumerate() {
        let mut names: Vec<&str> = mesh
            .materials
            .iter()
            .map(|&m| scene.materials[m as usize].name.as_str())
            .collect();
        names.dedup();
        names.sort_unstable();
        names.dedup();
        let _ = writeln!(
            s,
            "  {id:>3} {:<20} {:>9} triangles  {} vertices  material {}",
            mesh.name,
            mesh.triangles.len(),
            mesh.positions.len(),
            names.join(", ")
        );
    }
    let _ = writeln!(s, "triangles  {}", scene.triangle_count());
    if !scene.shapes.is_empty() {
        let _ = writeln!(
            s,
            "shapes     {} (geometry {}, prim_id = the index below)",
            scene.shapes.len(),
            scene.shapes_geom_id()
        );
        for (i, shape) in scene.shapes.iter().enumerate() {
            let material = &scene.materials[shape.material as usize].name;
            let _ = writeln!(s, "  {i:>3} {:<40} material {material}", shape.describe());
        }
    }
    if !scene.instances.is_empty() {
        let _ = writeln!(
            s,
            "instances  {} of {} prototypes ({} triangles placed)",
            scene.instances.len(),
            scene.prototypes.len(),
            scene.instanced_triangle_count()
        );
        for (i, prototype) in scene.prototypes.iter().enumerate() {
            let count = scene
                .instances
                .iter()
                .filter(|inst| inst.prototype as usize == i)
                .count();
            let _ = writeln!(
                s,
                "  {:<24} {} meshes ({} triangles), {} shapes, {count} instances",
                prototype.name,
                prototype.meshes.len(),
                prototype.triangle_count(),
                prototype.shapes.len()
            );
        }
    }
    let bounds = scene.bounds();
    if !bounds.is_empty() {
        let _ = writeln!(s, "bounds     {} to {}", v(bounds.min), v(bounds.max));
    }
    let triangles = scene
        .lights
        .iter()
        .filter(|l| matches!(l, Light::Triangle { .. }))
        .count();
    let _ = writeln!(
        s,
        "lights     {} ({} emissive triangles, sampled one per shading point by power)",
        scene.lights.len(),
        triangles
    );
    for light in &scene.lights {
        let _ = match light {
            Light::Point {
                position,
                intensity,
            } => writeln!(s, "  point at {} intensity {}", v(*position), v(*intensity)),
            Light::Spot {
                position,
                direction,
                intensity,
                cos_end,
                cos_start,
            } => writeln!(
                s,
                "  spot at {} along {} intensity {}, cone {:.4}° (full to {:.4}°)",
                v(*position),
                v(*direction),
                v(*intensity),
                cos_end.acos().to_degrees(),
                cos_start.acos().to_degrees()
            ),
            Light::PovPoint {
                position,
                irradiance,
                fade,
                shadowing,
            } => writeln!(
                s,
                "  {} point (POV-Ray's) at {} irradiance {}{}",
                fading(fade.as_ref()),
                v(*position),
                v(*irradiance),
                shadows(*shadowing)
            ),
            Light::PovBeam(light) => writeln!(
                s,
                "  {} {:?}{} (POV-Ray's) at {} along {} irradiance {}{}",
                fading(light.fade.as_ref()),
                light.beam,
                if light.parallel { ", parallel" } else { "" },
                v(light.position),
                v(light.direction),
                v(light.irradiance),
                shadows(light.shadowing)
            ),
            Light::Directional {
                direction,
                irradiance,
            } => writeln!(
                s,
                "  directional towards {} irradiance {}",
                v(*direction),
                v(*irradiance)
            ),
            Light::Sphere {
                center,
                radius,
                radiance,
            } => writeln!(
                s,
                "  sphere at {} radius {radius} radiance {}",
                v(*center),
                v(*radiance)
            ),
            Light::Triangle { .. } => Ok(()),
        };
    }
    let unsampled = scene.unsampled_emitters();
    if unsampled > 0 {
        let _ = writeln!(
            s,
            "  {unsampled} emissive shapes that are not spheres: found by bounces only"
        );
    }
    s
}
