//! Settings and inputs that once crashed sturmray, filled its memory or made
//! it deaf to Ctrl-C: each is now either honoured or refused with exit code 2
//! and a message naming the file and the line.

mod common;

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::{SQUARE, plane_scene, scratch, sturmray, write};

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Runs sturmray in `dir` and checks exit code 2 and that the message holds
/// every part of `expected`.
fn refused(dir: &Path, args: &[&str], expected: &[&str]) {
    let out = sturmray(dir, args);
    let message = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {message}");
    for part in expected {
        assert!(
            message.contains(part),
            "{args:?}: {part:?} not in {message}"
        );
    }
    assert!(!message.contains("panicked"), "{message}");
}

/// The camera inside a mirror sphere of reflectance 1: every ray of the tree
/// bounces to the depth limit, whatever `min_weight` it has.
fn hall_of_mirrors(max_depth: u32) -> String {
    format!(
        r#"[camera]
eye = [0, 0, 0]
look_at = [0.3, 0.2, 1]
fov = 40
width = 4
height = 3
[render]
spp = 1
max_depth = {max_depth}
min_weight = 0
[materials.silver]
type = "mirror"
albedo = [1, 1, 1]
[[objects]]
type = "sphere"
radius = 10
material = "silver"
"#
    )
}

#[test]
fn the_deepest_ray_tree_allowed_fits_every_stack() {
    let dir = scratch("depth");
    write(&dir, "deep.toml", &hall_of_mirrors(256));
    // Worker threads (render) and the main thread (explain) alike; this is a
    // debug build, whose frames are the largest.
    for threads in ["1", "2"] {
        let out = sturmray(
            &dir,
            &["render", "deep.toml", "-o", "d.exr", "--threads", threads],
        );
        assert!(out.status.success(), "{}", stderr(&out));
    }
    let out = sturmray(&dir, &["explain", "deep.toml", "--pixel", "1,1"]);
    assert!(out.status.success(), "{}", stderr(&out));
    // The camera ray and 256 reflections.
    let lines = String::from_utf8_lossy(&out.stdout).lines().count();
    assert_eq!(lines, 1 + 257);
}

#[test]
fn a_depth_past_the_limit_is_refused_by_line() {
    let dir = scratch("too-deep");
    for depth in [257, 3000, 100_000, u32::MAX] {
        write(&dir, "deep.toml", &hall_of_mirrors(depth));
        for command in [
            &["render", "deep.toml", "-o", "d.exr"][..],
            &["explain", "deep.toml", "--pixel", "0,0"],
        ] {
            refused(
                &dir,
                command,
                &["deep.toml", "line 9, render.max_depth", "at most 256"],
            );
        }
    }
}

#[test]
fn photon_counts_beyond_memory_are_refused() {
    let dir = scratch("photons");
    write(&dir, "square.obj", SQUARE);
    write(&dir, "s.toml", &plane_scene(""));
    let text = plane_scene("").replace("spp = 1", "spp = 1\nphotons = { count = 4000000000 }");
    write(&dir, "p.toml", &text);
    refused(
        &dir,
        &["render", "p.toml", "-o", "p.exr"],
        &[
            "p.toml",
            "render.photons.count",
            "at most 100000000 photons",
        ],
    );
    // The same limit for the command line's count, which the scene never
    // saw, with or without a photon pass in the plan.
    write(&dir, "g.toml", &plane_scene(GLASS_BALL));
    for scene in ["g.toml", "s.toml"] {
        refused(
            &dir,
            &["render", scene, "-o", "g.exr", "--photons", "4000000000"],
            &["--photons", "at most 100000000 photons"],
        );
    }
}

/// A glass ball above the square: the plan then asks for a photon pass.
const GLASS_BALL: &str = r#"
[materials.glass]
type = "dielectric"
ior = 1.5
[[objects]]
type = "sphere"
radius = 0.3
material = "glass"
transform = { translate = [0, 0, 1] }
[[lights]]
type = "point"
position = [0, 0, 3]
intensity = [10, 10, 10]
"#;

/// Starts a render, sends it SIGINT once it has run for `after`, and returns
/// its output and how long it took to stop after the signal.
fn interrupt(dir: &Path, args: &[&str], after: Duration) -> (Output, Duration) {
    let child = Command::new(env!("CARGO_BIN_EXE_sturmray"))
        .args(args)
        .current_dir(dir)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(after);
    let sent = Instant::now();
    common::interrupt(&child);
    let out = child.wait_with_output().unwrap();
    (out, sent.elapsed())
}

/// Not a speed target: without the checks inside passes these renders take
/// hours after the signal, so any bound far below that tells the two apart.
/// 20 s leaves room for a loaded 2-core machine and the debug build.
const PROMPTLY: Duration = Duration::from_secs(20);

#[test]
fn ctrl_c_stops_a_pass_of_billions_of_samples() {
    let dir = scratch("huge-spp");
    write(&dir, "square.obj", SQUARE);
    write(&dir, "s.toml", &plane_scene(""));
    let (out, waited) = interrupt(
        &dir,
        &["render", "s.toml", "-o", "s.exr", "--spp", "4000000000"],
        Duration::from_millis(1500),
    );
    assert_eq!(out.status.code(), Some(130), "{}", stderr(&out));
    assert!(waited < PROMPTLY, "stopped {waited:?} after the signal");
    // The first pass (one sample a pixel) is kept, the second dropped.
    let (header, film) = sturmray::io::state::read_state(&dir.join("s.state")).unwrap();
    assert_eq!(header.samples_done, 1);
    assert!(film.pixels.iter().all(|p| p.samples == 1));
}

#[test]
fn ctrl_c_stops_a_long_first_pass_after_its_grace() {
    let dir = scratch("long-first-pass");
    // One sample a pixel, but 257 rays each over 120,000 pixels: the first
    // pass alone takes far longer than its second of grace.
    let text = hall_of_mirrors(256).replace("width = 4\nheight = 3", "width = 400\nheight = 300");
    write(&dir, "deep.toml", &text);
    let (out, waited) = interrupt(
        &dir,
        &["render", "deep.toml", "-o", "d.exr"],
        Duration::from_millis(1500),
    );
    assert_eq!(out.status.code(), Some(130), "{}", stderr(&out));
    assert!(waited < PROMPTLY, "stopped {waited:?} after the signal");
    let (header, film) = sturmray::io::state::read_state(&dir.join("d.state")).unwrap();
    assert_eq!(
        header.samples_done, 0,
        "the first pass was cut, not finished"
    );
    assert!(film.pixels.iter().all(|p| p.samples == 0));
}

#[test]
fn ctrl_c_stops_the_photon_pass() {
    let dir = scratch("huge-photons");
    write(&dir, "square.obj", SQUARE);
    write(&dir, "g.toml", &plane_scene(GLASS_BALL));
    let (out, waited) = interrupt(
        &dir,
        &["render", "g.toml", "-o", "g.exr", "--photons", "20000000"],
        Duration::from_millis(1500),
    );
    assert_eq!(out.status.code(), Some(130), "{}", stderr(&out));
    assert!(waited < PROMPTLY, "stopped {waited:?} after the signal");
    let (header, _) = sturmray::io::state::read_state(&dir.join("g.state")).unwrap();
    assert_eq!(
        header.samples_done, 0,
        "no pass runs without its photon map"
    );
}

#[test]
fn only_regular_files_are_read() {
    let dir = scratch("special-files");
    write(&dir, "square.obj", SQUARE);
    let fifo = dir.join("fifo.toml");
    let made = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    refused(
        &dir,
        &["render", "fifo.toml", "-o", "f.exr"],
        &["fifo.toml", "not a regular file (a FIFO)"],
    );
    std::os::unix::fs::symlink("/dev/zero", dir.join("zero.toml")).unwrap();
    refused(
        &dir,
        &["info", "zero.toml"],
        &["zero.toml", "not a regular file (a character device)"],
    );
    // A mesh and a material library that never end.
    write(
        &dir,
        "z.toml",
        &plane_scene("").replace("square.obj", "/dev/zero"),
    );
    refused(
        &dir,
        &["render", "z.toml", "-o", "z.exr"],
        &["/dev/zero", "character device"],
    );
    write(&dir, "m.obj", &format!("mtllib /dev/zero\n{SQUARE}"));
    refused(
        &dir,
        &["render", "m.obj", "-o", "m.exr"],
        &["/dev/zero", "character device"],
    );
    write(&dir, "p.obj", &format!("mtllib fifo.toml\n{SQUARE}"));
    refused(
        &dir,
        &["render", "p.obj", "-o", "p.exr"],
        &["fifo.toml", "FIFO"],
    );
}

#[test]
fn a_huge_sparse_file_costs_nothing_to_refuse() {
    let dir = scratch("sparse");
    // 64 GiB of holes after a real line: reading it whole would fill memory.
    let path = write(&dir, "sparse.obj", "v 0 0 0\n");
    std::fs::File::options()
        .write(true)
        .open(&path)
        .unwrap()
        .set_len(64 << 30)
        .unwrap();
    refused(
        &dir,
        &["render", "sparse.obj", "-o", "s.exr"],
        &["sparse.obj:2", "NUL byte"],
    );
    write(&dir, "m.obj", &format!("mtllib sparse.obj\n{SQUARE}"));
    refused(&dir, &["render", "m.obj", "-o", "m.exr"], &["sparse.obj:2"]);
    std::fs::rename(&path, dir.join("sparse.toml")).unwrap();
    refused(
        &dir,
        &["info", "sparse.toml"],
        &["sparse.toml:2", "NUL byte"],
    );
}

#[test]
fn colours_share_one_limit_in_mtl_and_toml() {
    let dir = scratch("colours");
    for (statement, value) in [("Kd", "1e30"), ("Ke", "1e38"), ("Ks", "2e18")] {
        write(
            &dir,
            "c.mtl",
            &format!("newmtl hot\n{statement} 0.5 {value} 0.5\n"),
        );
        write(
            &dir,
            "c.obj",
            &format!("mtllib c.mtl\nusemtl hot\n{SQUARE}"),
        );
        refused(
            &dir,
            &["render", "c.obj", "-o", "c.exr"],
            &["c.mtl:2", "at most 1e18"],
        );
    }
    write(&dir, "square.obj", SQUARE);
    let text = plane_scene("").replace("[0.5, 0.25, 0.125]", "[0.5, 1e30, 0.125]");
    write(&dir, "s.toml", &text);
    refused(
        &dir,
        &["render", "s.toml", "-o", "s.exr"],
        &["s.toml", "at most 1e18"],
    );
    // The limit itself is a colour.
    write(&dir, "c.mtl", "newmtl hot\nKe 1e18 1e18 1e18\n");
    write(
        &dir,
        "c.obj",
        &format!("mtllib c.mtl\nusemtl hot\n{SQUARE}"),
    );
    let out = sturmray(&dir, &["info", "c.obj"]);
    assert!(out.status.success(), "{}", stderr(&out));
}
