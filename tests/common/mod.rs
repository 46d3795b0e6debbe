//! Helpers shared by the integration tests.
#![allow(dead_code)] // each test crate uses a different subset

pub mod analytic;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A fresh scratch directory for one test, removed with everything in it
/// when the value is dropped (at the end of the test, pass or fail), so test
/// runs do not fill the temporary folder.
pub struct Scratch(tempfile::TempDir);

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        self.0.path()
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        self.0.path()
    }
}

pub fn scratch(name: &str) -> Scratch {
    let dir = tempfile::Builder::new()
        .prefix(&format!("sturmray-it-{name}-"))
        .tempdir()
        .expect("a scratch directory in the temporary folder");
    Scratch(dir)
}

/// The width and height of a PNG, from its IHDR chunk (bytes 16..24, big-endian).
pub fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap();
    let word = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
    (word(16), word(20))
}

pub fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// Loads `text` as the scene file `s.toml` in `dir`, expecting an error
/// that names the file and contains every part of `expected`.
pub fn refused_scene(dir: &Path, text: &str, expected: &[&str]) {
    let err = sturmray::scene::Scene::load(&write(dir, "s.toml", text))
        .unwrap_err()
        .to_string();
    assert!(err.contains("s.toml"), "{err}");
    for part in expected {
        assert!(err.contains(part), "{part:?} not in {err}");
    }
}

/// Runs the sturmray binary in `dir`.
pub fn sturmray(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sturmray"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the sturmray binary runs")
}

/// Sends SIGINT to a running child, as Ctrl-C would.
pub fn interrupt(child: &std::process::Child) {
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
}

/// A square [-1, 1]² in the plane z = 0 (two triangles), as OBJ text.
pub const SQUARE: &str = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n";

/// A scene looking straight down -z at SQUARE with a directional light along -z.
pub fn plane_scene(extra: &str) -> String {
    format!(
        r#"background = [0.1, 0.2, 0.3]
[camera]
eye = [0, 0, 4]
look_at = [0, 0, 0]
fov = 40
width = 32
height = 24
[render]
spp = 1
[materials.paint]
type = "diffuse"
albedo = [0.5, 0.25, 0.125]
[[objects]]
type = "mesh"
file = "square.obj"
material = "paint"
[[lights]]
type = "directional"
direction = [0, 0, -1]
irradiance = [2, 2, 2]
{extra}"#
    )
}

/// An 8-bit PNG of `width` × `height` texels of `colour`, rows from the top.
pub fn png_bytes(width: u32, height: u32, colour: png::ColorType, data: &[u8]) -> Vec<u8> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, width, height);
    encoder.set_color(colour);
    encoder.set_depth(png::BitDepth::Eight);
    encoder
        .write_header()
        .unwrap()
        .write_image_data(data)
        .unwrap();
    bytes
}

/// Compiles the C program `source` with `cc` into `out`, every warning an
/// error, linked against the Embree 3 sturmray was built with (ffi/build.rs
/// reads the same EMBREE_DIR); panics with the compiler's message if it fails.
pub fn compile_embree3_c(source: &Path, out: &Path) {
    let mut cc = Command::new("cc");
    cc.args(["-O2", "-std=c11", "-Wall", "-Wextra", "-Werror"])
        .arg(source);
    if let Some(embree) = std::env::var_os("EMBREE_DIR") {
        let embree = Path::new(&embree);
        let lib = embree.join("lib");
        cc.arg(format!("-I{}", embree.join("include").display()))
            .arg(format!("-L{}", lib.display()))
            .arg(format!("-Wl,-rpath,{}", lib.display()));
    }
    let built = cc
        .args(["-lembree3", "-lm", "-o"])
        .arg(out)
        .output()
        .expect("cc runs");
    assert!(
        built.status.success(),
        "{}",
        String::from_utf8_lossy(&built.stderr)
    );
}

/// The beauty layer of `scene` rendered on `backend` with two threads.
pub fn beauty(scene: &sturmray::scene::Scene, backend: sturmray::accel::Backend) -> Vec<[f32; 3]> {
    let accel = sturmray::accel::Accel::build(scene, backend, None).unwrap();
    let options = sturmray::render::RenderOptions {
        threads: Some(2),
        ..sturmray::render::RenderOptions::default()
    };
    sturmray::render::render(scene, &accel, &options)
        .unwrap()
        .film
        .layers()
        .beauty
}
