//! Fuzzing the command line end to end: generated scenes (with extreme
//! numbers, cameras, depths, photon counts and output names), ray files and
//! damaged film states, run through the real binary. Whatever the input, the
//! process exits 0, 2 or 130 (never a crash, a panic or an internal error),
//! changes no file but the outputs the command names, and writes no NaN into
//! an image. `cargo test` runs a fixed set of cases; `make fuzz` runs fresh
//! ones (see tests/fuzz_common). FUZZ_CLI_VERBOSE=1 prints each command with
//! its exit code and first line of stderr, to see what the cases reach.

mod fuzz_common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use proptest::prelude::*;
use sturmray::math::{Ray, Vec3};

/// Numbers that have broken renderers: zeros, signs, the coordinate limit
/// and around it, f32's edges, subnormals and non-numbers.
fn special() -> impl Strategy<Value = String> {
    prop::sample::select(vec![
        "0",
        "-0",
        "1",
        "-1",
        "1e-30",
        "-1e-30",
        "1e-45",
        "1e9",
        "-1e9",
        "1.0000001e9",
        "2e9",
        "1e17",
        "-1e17",
        "1e18",
        "-1e18",
        "1.8e18",
        "2e18",
        "1e30",
        "3.4e38",
        "1e300",
        "nan",
        "inf",
        "-inf",
    ])
    .prop_map(str::to_owned)
}

/// Mostly an ordinary number in `range`, now and then a special one: a
/// scene has dozens of numbers, and each special one alone decides its fate.
fn number(range: std::ops::Range<f64>) -> impl Strategy<Value = String> {
    prop_oneof![
        40 => range.prop_map(|x| format!("{x:.3}")),
        1 => special(),
    ]
}

fn vector(range: std::ops::Range<f64>) -> impl Strategy<Value = String> {
    let n = || number(range.clone());
    [n(), n(), n()].prop_map(|[x, y, z]| format!("[{x}, {y}, {z}]"))
}

fn position() -> impl Strategy<Value = String> {
    vector(-4.0..4.0)
}

fn colour() -> impl Strategy<Value = String> {
    vector(0.0..1.0)
}

/// Mostly `ordinary`, now and then one of `hostile`.
fn mostly<T: Clone + std::fmt::Debug + 'static>(
    ordinary: Vec<T>,
    hostile: Vec<T>,
) -> impl Strategy<Value = T> {
    prop_oneof![
        8 => prop::sample::select(ordinary),
        1 => prop::sample::select(hostile),
    ]
}

/// A camera: free, looking at its own eye, looking along `up`, or keyframed
/// (and then perhaps passing through its look-at point between keys).
fn camera() -> impl Strategy<Value = String> {
    let still = (position(), position()).prop_map(|(eye, look_at)| (eye, look_at, None));
    let hostile = prop_oneof![
        position().prop_map(|p| (p.clone(), p, None)),
        Just(("[0, 0, 0]".to_owned(), "[0, 5, 0]".to_owned(), None)),
        (position(), position(), position(), 1u32..4).prop_map(|(eye, look_at, eye2, frame)| {
            // The second key swaps eye and look-at: the eye meets it midway.
            let keys = (look_at.clone(), eye.clone(), frame);
            (eye, look_at, Some((keys, eye2)))
        }),
    ];
    prop_oneof![6 => still, 1 => hostile].prop_map(|(eye, look_at, keys)| {
        let keys = keys.map_or(String::new(), |((eye2, look2, frame), _)| {
            format!(
                "[[camera.keys]]\nframe = 0\neye = {eye}\nlook_at = {look_at}\n\
                 [[camera.keys]]\nframe = {}\neye = {eye2}\nlook_at = {look2}\n",
                2 * frame
            )
        });
        format!(
            "[camera]\neye = {eye}\nlook_at = {look_at}\nfov = 40\nwidth = 6\nheight = 4\n{keys}"
        )
    })
}

/// A scene with a camera, a render table and up to three objects and two
/// lights, any field of which may be extreme.
fn scene() -> impl Strategy<Value = String> {
    let render = (
        1u32..3,
        mostly(vec![0u32, 1, 2, 5], vec![256, 257, 3000, 100_000]),
        mostly(vec![0u64, 50], vec![4_000_000_000]),
        any::<bool>(),
    )
        .prop_map(|(spp, depth, photons, path)| {
            let integrator = if path { "path" } else { "whitted" };
            format!(
                "[render]\nspp = {spp}\nmax_depth = {depth}\nintegrator = \"{integrator}\"\n\
                 photons = {{ count = {photons} }}\n"
            )
        });
    let object = prop_oneof![
        (number(0.1..2.0), position()).prop_map(|(r, t)| format!(
            "[[objects]]\ntype = \"sphere\"\nradius = {r}\nmaterial = \"m\"\n\
             transform = {{ translate = {t} }}\n"
        )),
        (number(1.0..2.0), number(0.01..0.9)).prop_map(|(big, small)| format!(
            "[[objects]]\ntype = \"torus\"\nmajor = {big}\nminor = {small}\nmaterial = \"g\"\n"
        )),
        Just("[[objects]]\ntype = \"mesh\"\nfile = \"m.obj\"\n".to_owned()),
    ];
    let light = prop_oneof![
        (position(), vector(0.0..10.0)).prop_map(|(p, i)| format!(
            "[[lights]]\ntype = \"point\"\nposition = {p}\nintensity = {i}\n"
        )),
        (position(), colour()).prop_map(|(d, e)| format!(
            "[[lights]]\ntype = \"directional\"\ndirection = {d}\nirradiance = {e}\n"
        )),
    ];
    (
        camera(),
        render,
        colour(),
        prop::collection::vec(object, 0..3),
        prop::collection::vec(light, 0..2),
    )
        .prop_map(|(camera, render, albedo, objects, lights)| {
            format!(
                "{camera}{render}[materials.m]\ntype = \"mirror\"\nalbedo = {albedo}\n\
                 [materials.g]\ntype = \"dielectric\"\nior = 1.5\n{}{}",
                objects.concat(),
                lights.concat()
            )
        })
}

/// An OBJ of one or two triangles with extreme corners and an MTL whose
/// colour may be extreme too.
fn mesh() -> impl Strategy<Value = (String, String)> {
    (prop::collection::vec(position(), 3..5), colour()).prop_map(|(corners, colour)| {
        let mut obj = String::from("mtllib m.mtl\nusemtl hot\n");
        for c in &corners {
            let c = c.trim_matches(['[', ']']).replace(',', "");
            obj += &format!("v {c}\n");
        }
        obj += "f 1 2 3\n";
        if corners.len() == 4 {
            obj += "f 1 3 4\n";
        }
        let colour = colour.trim_matches(['[', ']']).replace(',', "");
        (obj, format!("newmtl hot\nKd {colour}\n"))
    })
}

/// Rays, extreme or not, written by the library's own writer as a float32
/// (N, 8) .npy (origin, direction, tnear, tfar).
fn rays() -> impl Strategy<Value = Vec<[f32; 8]>> {
    // Mostly ordinary, so that most ray files reach the trace.
    let component = prop_oneof![
        30 => -4.0f32..4.0,
        1 => prop::sample::select(vec![
            0.0, -0.0, 1e-30, 1e-45, 1e9, 2e9, 1e17, 1e18, 1.8e18, 2e18, 1e30, f32::MAX,
            f32::NAN, f32::INFINITY, f32::NEG_INFINITY,
        ]),
    ];
    let tnear =
        prop_oneof![12 => Just(0.0f32), 1 => prop::sample::select(vec![-1.0, 5.0, f32::NAN])];
    let tfar =
        prop_oneof![12 => Just(f32::INFINITY), 1 => prop::sample::select(vec![0.0, 1.0, f32::NAN])];
    let ray = (prop::collection::vec(component, 6), tnear, tfar)
        .prop_map(|(v, near, far)| [v[0], v[1], v[2], v[3], v[4], v[5], near, far]);
    prop::collection::vec(ray, 1..5)
}

/// One command line, with the outputs it names (which it may change).
#[derive(Clone, Debug)]
enum Run {
    /// `render s.toml -o OUTPUT` plus options; OUTPUT may collide with an input.
    Render {
        output: &'static str,
        extra: Vec<&'static str>,
    },
    Info,
    Explain,
    Trace {
        out: &'static str,
    },
    /// Render a tile, damage its state at `byte` (xor `flip`), then merge it
    /// with the other tile and resume it.
    DamagedState {
        byte: usize,
        flip: u8,
    },
}

fn run() -> impl Strategy<Value = Run> {
    let outputs = prop::sample::select(vec![
        "o.exr",
        "s.toml",
        "m.obj",
        "o.png",
        "o.state",
        "m.mtl",
        "./sub/../o.exr",
        "rays.npy",
    ]);
    let extra = prop::sample::select(vec![
        vec![],
        vec!["--stats", "o.exr"],
        vec!["--stats", "o.json"],
        vec!["--tile", "0/2"],
        vec!["--backend", "obvhs"],
        vec!["--backend", "bvh"],
        vec!["--frame", "2"],
        vec!["--photons", "4000000000"],
    ]);
    prop_oneof![
        3 => (outputs.clone(), extra).prop_map(|(output, extra)| Run::Render { output, extra }),
        1 => Just(Run::Info),
        1 => Just(Run::Explain),
        1 => prop::sample::select(vec!["hits.npy", "rays.npy", "s.toml"])
            .prop_map(|out| Run::Trace { out }),
        1 => (any::<usize>(), 1u8..=255).prop_map(|(byte, flip)| Run::DamagedState { byte, flip }),
    ]
}

/// Every file under `dir` with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut files = BTreeMap::new();
    let mut stack = vec![dir.to_owned()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else {
                files.insert(path.clone(), std::fs::read(&path).unwrap_or_default());
            }
        }
    }
    files
}

/// A wall-clock limit per process: a hang is a failure too. Generous, for
/// the debug build on a loaded 2-core machine; the scenes are 6×4 pixels.
const LIMIT: Duration = Duration::from_secs(60);

/// Runs the binary in `dir`; the exit code (None if a signal ended it).
fn sturmray(dir: &Path, args: &[&str]) -> Result<(Option<i32>, String), TestCaseError> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_sturmray"))
        .args(args)
        .current_dir(dir)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut message = String::new();
            use std::io::Read;
            child
                .stderr
                .take()
                .unwrap()
                .read_to_string(&mut message)
                .unwrap();
            return Ok((status.code(), message));
        }
        if start.elapsed() > LIMIT {
            let _ = child.kill();
            return Err(TestCaseError::fail(format!(
                "{args:?} still running after {LIMIT:?}"
            )));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// What every run must give: exit 0, 2 or 130, with no panic on stderr.
fn check_exit(args: &[&str], code: Option<i32>, message: &str) -> Result<(), TestCaseError> {
    prop_assert!(
        matches!(code, Some(0 | 2 | 130)),
        "{args:?} exited with {code:?}: {message}"
    );
    prop_assert!(!message.contains("panicked"), "{args:?}: {message}");
    Ok(())
}

/// No NaN in any EXR or .npy the run left.
fn check_outputs(files: &BTreeMap<PathBuf, Vec<u8>>) -> Result<(), TestCaseError> {
    for path in files.keys() {
        if path.extension().is_some_and(|e| e == "exr") {
            let Ok((_, _, channels)) = sturmray::io::exr::read_exr(path) else {
                // `--stats o.exr` writes JSON under that name, as asked.
                continue;
            };
            for (name, values) in channels {
                prop_assert!(
                    values.iter().all(|v| !v.is_nan()),
                    "NaN in channel {name} of {}",
                    path.display()
                );
            }
        }
    }
    Ok(())
}

fn case(
    scene: &str,
    (obj, mtl): &(String, String),
    rays: &[[f32; 8]],
    run: &Run,
) -> Result<(), TestCaseError> {
    // A fresh folder per case, removed when the case ends.
    let scratch = tempfile::Builder::new()
        .prefix("sturmray-fuzz-cli-")
        .tempdir()
        .unwrap();
    let dir = scratch.path();
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    std::fs::write(dir.join("s.toml"), scene).unwrap();
    std::fs::write(dir.join("m.obj"), obj).unwrap();
    std::fs::write(dir.join("m.mtl"), mtl).unwrap();
    let rays: Vec<Ray> = rays
        .iter()
        .map(|r| Ray {
            origin: Vec3::new(r[0], r[1], r[2]),
            dir: Vec3::new(r[3], r[4], r[5]),
            tnear: r[6],
            tfar: r[7],
        })
        .collect();
    sturmray::io::npy::write_rays(&dir.join("rays.npy"), &rays).unwrap();
    let before = snapshot(dir);
    let mut commands: Vec<(Vec<String>, Vec<String>)> = Vec::new();
    let owned = |args: &[&str]| args.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    match run {
        Run::Render { output, extra } => {
            let mut args = owned(&["render", "s.toml", "-o", output]);
            args.extend(owned(extra));
            let mut outs = owned(&[output]);
            for beside in ["png", "state"] {
                let path = Path::new(output).with_extension(beside);
                outs.push(path.to_string_lossy().into_owned());
            }
            if let Some(i) = extra.iter().position(|a| *a == "--stats") {
                outs.push(extra[i + 1].to_owned());
            }
            commands.push((args, outs));
        }
        Run::Info => commands.push((owned(&["info", "s.toml"]), vec![])),
        Run::Explain => commands.push((owned(&["explain", "s.toml", "--pixel", "1,1"]), vec![])),
        Run::Trace { out } => commands.push((
            owned(&["trace", "s.toml", "--rays", "rays.npy", "--out", out]),
            owned(&[out]),
        )),
        Run::DamagedState { .. } => {
            for tile in ["0/2", "1/2"] {
                let name = if tile == "0/2" { "a.exr" } else { "b.exr" };
                commands.push((
                    owned(&["render", "s.toml", "--tile", tile, "-o", name]),
                    owned(&[name, "a.png", "b.png", "a.state", "b.state"]),
                ));
            }
        }
    }
    let mut allowed: Vec<PathBuf> = Vec::new();
    for (args, outs) in &commands {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let (code, message) = sturmray(dir, &args)?;
        if std::env::var_os("FUZZ_CLI_VERBOSE").is_some() {
            eprintln!(
                "{args:?} -> {code:?} {}",
                message.lines().next().unwrap_or("")
            );
        }
        check_exit(&args, code, &message)?;
        allowed.extend(outs.iter().map(|o| normal(&dir.join(o))));
    }
    if let Run::DamagedState { byte, flip } = run
        && let Ok(mut bytes) = std::fs::read(dir.join("a.state"))
    {
        let at = byte % bytes.len();
        bytes[at] ^= flip;
        std::fs::write(dir.join("a.state"), &bytes).unwrap();
        let damaged = snapshot(dir);
        for args in [
            &["merge", "m.exr", "a.exr", "b.exr"][..],
            &[
                "render", "s.toml", "--tile", "0/2", "-o", "a.exr", "--resume",
            ],
        ] {
            let (code, message) = sturmray(dir, args)?;
            check_exit(args, code, &message)?;
            // A damaged state is refused, never merged or resumed.
            prop_assert_eq!(code, Some(2), "{:?} accepted a damaged state", args);
        }
        prop_assert!(snapshot(dir) == damaged, "a refused run changed files");
        return check_outputs(&damaged);
    }
    let after = snapshot(dir);
    for (path, bytes) in &after {
        if before.get(path) != Some(bytes) {
            prop_assert!(
                allowed.contains(&normal(path)),
                "{} changed, not an output of {run:?}",
                path.display()
            );
        }
    }
    check_outputs(&after)
}

/// `dir/./sub/../o.exr` as `dir/o.exr`.
fn normal(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for part in path.components() {
        match part {
            std::path::Component::ParentDir => {
                out.pop();
            }
            std::path::Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

proptest! {
    #![proptest_config(fuzz_common::config(24))]

    #[test]
    fn fuzz_cli_end_to_end(scene in scene(), mesh in mesh(), rays in rays(), run in run()) {
        case(&scene, &mesh, &rays, &run)?;
    }
}
