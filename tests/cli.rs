//! The command line: outputs, exit codes (0 ok, 2 bad input), messages.

mod common;

use common::{SQUARE, plane_scene, scratch, sturmray, write};
use sturmray::io::npy;
use sturmray::math::{Ray, Vec3};

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn render_bare_obj_to_default_output_with_stats() {
    let dir = scratch("bare");
    write(&dir, "square.obj", SQUARE);
    let out = sturmray(
        &dir,
        &[
            "render",
            "square.obj",
            "--spp",
            "2",
            "--stats",
            "stats.json",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(dir.join("out/square.exr").is_file());
    assert!(dir.join("out/square.png").is_file());
    let stats: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("stats.json")).unwrap()).unwrap();
    // The automatic camera is 640×480; two samples each.
    assert_eq!(stats["rays"]["camera"], 640 * 480 * 2);
    for kind in ["reflection", "refraction", "diffuse", "photon"] {
        assert_eq!(stats["rays"][kind], 0, "{kind}");
    }
    assert!(stats["rays"]["shadow"].as_u64().unwrap() > 0);
    assert!(stats["seconds"].as_f64().unwrap() > 0.0);
}

#[test]
fn info_names_embree_objects_and_lights() {
    let dir = scratch("info");
    write(&dir, "square.obj", SQUARE);
    write(&dir, "s.toml", &plane_scene(""));
    let out = sturmray(&dir, &["info", "s.toml"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8(out.stdout).unwrap();
    for part in ["Embree 3.", "Embree 4."] {
        if text.contains(part) {
            return assert!(
                text.contains("triangles  2") && text.contains("directional"),
                "{text}"
            );
        }
    }
    panic!("no Embree version in: {text}");
}

/// A scratch folder with SQUARE and rays.npy of rays straight down from z = 1 at `xy`.
fn square_and_rays(name: &str, xy: &[(f32, f32)]) -> common::Scratch {
    let dir = scratch(name);
    write(&dir, "square.obj", SQUARE);
    let rays: Vec<Ray> = xy
        .iter()
        .map(|&(x, y)| Ray::new(Vec3::new(x, y, 1.0), -Vec3::Z))
        .collect();
    npy::write_rays(&dir.join("rays.npy"), &rays).unwrap();
    dir
}

/// A hit record of `trace`'s .npy: t, geom_id, prim_id, inst_id, u, v, ng.
const HIT_RECORD_BYTES: usize = 36;

#[test]
fn trace_writes_one_hit_per_ray() {
    let dir = square_and_rays("trace", &[(0.5, 0.5), (5.0, 0.5)]);
    let out = sturmray(
        &dir,
        &[
            "trace",
            "square.obj",
            "--rays",
            "rays.npy",
            "--out",
            "hits.npy",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    // The trace's own time, which tools/python_speed.py reads.
    assert!(
        stderr(&out).contains("(2 rays traced in "),
        "{}",
        stderr(&out)
    );
    // A version 1.0 header (its length at bytes 8..10) then 2 records;
    // numpy's reading of the records is checked in tests/test_embreex.py.
    let bytes = std::fs::read(dir.join("hits.npy")).unwrap();
    assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00");
    let header = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    assert_eq!(bytes.len(), 10 + header + 2 * HIT_RECORD_BYTES);
    assert_eq!((10 + header) % 64, 0, "data start 64-byte aligned");
}

/// The values of a 1-D .npy the CLI wrote: its header's length, then `size`-byte values.
fn npy_values(path: &std::path::Path, size: usize) -> Vec<u64> {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00");
    let header = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    bytes[10 + header..]
        .chunks(size)
        .map(|c| c.iter().rev().fold(0u64, |v, &b| (v << 8) | u64::from(b)))
        .collect()
}

#[test]
fn trace_all_hits_and_any_hit() {
    // Inside one triangle, beside the square, and on the diagonal both triangles share.
    let dir = square_and_rays("trace-all", &[(0.25, 0.75), (5.0, 0.5), (0.5, 0.5)]);
    for backend in ["embree", "bvh", "obvhs"] {
        let args = [
            "trace",
            "square.obj",
            "--rays",
            "rays.npy",
            "--backend",
            backend,
        ];
        let out = sturmray(
            &dir,
            &[&args[..], &["--out", "h.npy", "--all-hits"]].concat(),
        );
        assert!(out.status.success(), "{}", stderr(&out));
        assert_eq!(
            npy_values(&dir.join("h.offsets.npy"), 8),
            [0, 1, 1, 3],
            "{backend}"
        );
        let hits = std::fs::read(dir.join("h.npy")).unwrap();
        let header = u16::from_le_bytes([hits[8], hits[9]]) as usize;
        assert_eq!(hits.len(), 10 + header + 3 * HIT_RECORD_BYTES, "{backend}");
        let out = sturmray(
            &dir,
            &[&args[..], &["--out", "any.npy", "--any-hit"]].concat(),
        );
        assert!(out.status.success(), "{}", stderr(&out));
        assert_eq!(npy_values(&dir.join("any.npy"), 1), [1, 0, 1], "{backend}");
    }
    let out = sturmray(
        &dir,
        &[
            "trace",
            "square.obj",
            "--rays",
            "rays.npy",
            "--out",
            "h.npy",
            "--all-hits",
            "--any-hit",
        ],
    );
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
}

#[test]
fn bad_input_exits_with_2_and_names_the_problem() {
    let dir = scratch("bad");
    write(&dir, "square.obj", SQUARE);
    write(&dir, "s.toml", &plane_scene(""));
    write(&dir, "typo.toml", &plane_scene("").replace("fov", "fvo"));
    write(&dir, "broken.obj", "v 0 0 0\nf 1 2 3\n");
    write(
        &dir,
        "broken.ply",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\nzero\n",
    );
    write(&dir, "rays.npy", "not a numpy file");
    write(&dir, "file", "");
    let cases: [(&[&str], &str); 10] = [
        (&["render", "missing.toml"], "missing.toml"),
        (
            &["render", "s.toml", "--sampler", "sobl"],
            "a similar value exists: 'sobol'",
        ),
        (&["render", "typo.toml"], "did you mean `fov`?"),
        (&["render", "broken.obj"], "broken.obj:2"),
        (
            &["render", "broken.ply"],
            "broken.ply:6: vertex 0: expected the numbers of x, found `zero`",
        ),
        (&["render", "s.toml", "-o", "file/x.exr"], "file"),
        (&["render", "s.toml", "--spp", "0"], "spp"),
        (
            &["trace", "s.toml", "--rays", "rays.npy", "--out", "h.npy"],
            "rays.npy",
        ),
        (
            &["info", "scene.txt"],
            "expected a scene file ending in .toml, .obj, .ply or .pov",
        ),
        (&["frobnicate"], "unrecognized subcommand"),
    ];
    for (args, expected) in cases {
        let out = sturmray(&dir, args);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains(expected),
            "{args:?}: expected {expected:?} in {err}"
        );
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

#[test]
fn explain_takes_the_sampler_as_render_does() {
    let dir = scratch("explain-sampler");
    write(&dir, "square.obj", SQUARE);
    write(
        &dir,
        "s.toml",
        &plane_scene("").replace("spp = 1", "spp = 4"),
    );
    let tree = |extra: &[&str]| {
        let mut args = vec!["explain", "s.toml", "--pixel", "20,15", "--sample", "1"];
        args.extend(extra);
        let out = sturmray(&dir, &args);
        assert!(out.status.success(), "{}", stderr(&out));
        String::from_utf8(out.stdout).unwrap()
    };
    // Sobol's is the default; the independent sampler puts the sample
    // elsewhere in the pixel, so the camera ray meets the square at another t.
    let default = tree(&[]);
    assert_eq!(default, tree(&["--sampler", "sobol"]));
    assert_ne!(default, tree(&["--sampler", "independent"]), "{default}");
}

#[test]
fn explain_prints_the_ray_tree_of_one_sample() {
    let dir = scratch("explain");
    write(&dir, "square.obj", SQUARE);
    write(&dir, "s.toml", &plane_scene(""));
    // The centre pixel sees the lit square: a camera ray and its shadow ray.
    let out = sturmray(&dir, &["explain", "s.toml", "--pixel", "16,12"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert!(
        lines[0].starts_with("pixel 16,12 sample 0: radiance"),
        "{text}"
    );
    // One sample a pixel: the ray through the pixel's centre, from the eye.
    assert!(
        lines[0].contains("camera ray from [0.0000, 0.0000, 4.0000] along [0.0"),
        "{text}"
    );
    assert!(
        lines[1].starts_with("camera") && lines[1].contains("material paint"),
        "{text}"
    );
    assert!(
        lines[2].trim_start().starts_with("shadow") && lines[2].contains("visible"),
        "{text}"
    );
    for (args, expected) in [
        (
            &["explain", "s.toml", "--pixel", "99,0"][..],
            "outside the 32x24 image",
        ),
        (
            &["explain", "s.toml", "--pixel", "1,1", "--sample", "3"],
            "samples per pixel",
        ),
        (&["explain", "s.toml", "--pixel", "1;1"], "expected X,Y"),
    ] {
        let out = sturmray(&dir, args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(
            stderr(&out).contains(expected),
            "{args:?}: {}",
            stderr(&out)
        );
    }
}
