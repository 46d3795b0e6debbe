//! Every scene shipped in `scenes/` loads, builds and renders (small, few
//! samples) to a finite image that is not black.

use std::path::{Path, PathBuf};

use sturmray::accel::{Accel, Backend};
use sturmray::render::{RenderOptions, render};
use sturmray::scene::Scene;

fn scene_files(dir: &Path, found: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            scene_files(&path, found);
        } else if path.extension().is_some_and(|e| e == "toml") {
            found.push(path);
        }
    }
}

#[test]
fn every_shipped_scene_renders_a_finite_image() {
    let mut files = Vec::new();
    scene_files(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes"),
        &mut files,
    );
    files.sort();
    assert!(files.len() >= 10, "{files:?}");
    for file in files {
        let mut scene = Scene::load(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        // A thumbnail keeps the whole set quick; the aspect ratio stays.
        let (w, h) = (scene.camera.width, scene.camera.height);
        scene.camera.width = 32;
        scene.camera.height = (32 * h / w).max(1);
        scene.render.adaptive = None;
        let accel = Accel::build(&scene, Backend::Embree, None).unwrap();
        let options = RenderOptions {
            spp: Some(2),
            ..RenderOptions::default()
        };
        let out = render(&scene, &accel, &options).unwrap();
        let beauty = out.film.layers().beauty;
        let name = file.display();
        assert!(
            beauty.iter().flatten().all(|c| c.is_finite() && *c >= 0.0),
            "{name}"
        );
        assert!(beauty.iter().flatten().any(|&c| c > 0.0), "{name} is black");
    }
}
