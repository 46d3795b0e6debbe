//! The C harness of the wrapper-overhead measurement (benches/c_harness) does
//! the same work as sturmray: compiled here with `cc` (the C compiler cargo
//! links with), it traces the mesh and rays `sturmray bench --c-harness`
//! writes, and both sides must report the same hits, t sum and primID sum for
//! every ray kind and API. Nothing is timed. Embree 3 only: the harness uses
//! the Embree 3 API (rtcIntersect1M has no Embree 4 form).
#![cfg(embree3)]

mod common;

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

/// rays, hits, the sum of their t and of their primIDs.
type Checksum = (usize, usize, f64, u64);

/// Each line's "SCENE KIND API" and its checksum, leaving out the speed.
fn checksums(side: &str, stdout: &[u8]) -> BTreeMap<String, Checksum> {
    let text = String::from_utf8(stdout.to_vec()).unwrap();
    text.lines()
        .map(|line| {
            let fields: Vec<&str> = line.split_whitespace().collect();
            assert_eq!(fields[0], side, "{line}");
            let value = |key: &str| {
                let prefix = format!("{key}=");
                fields.iter().find_map(|f| f.strip_prefix(&prefix)).unwrap()
            };
            // tsum is printed to round-trip on both sides (C's %.17g, Rust's
            // shortest form): compared as a number, bit for bit.
            let check = (
                value("rays").parse().unwrap(),
                value("hits").parse().unwrap(),
                value("tsum").parse().unwrap(),
                value("primsum").parse().unwrap(),
            );
            (fields[1..4].join(" "), check)
        })
        .collect()
}

#[test]
fn c_and_rust_report_the_same_hits() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = common::scratch("c-harness");
    let harness = dir.join("c_harness");
    common::compile_embree3_c(&root.join("benches/c_harness/c_harness.c"), &harness);

    // The small knot (3,240 triangles) under the knot scene's camera.
    let knot = root.join("scenes/meshes/knot_small.obj");
    let scene = format!(
        "[camera]\neye = [0.0, 0.9, 3.2]\nlook_at = [0.0, 0.0, 0.0]\nfov = 40.0\n\
         width = 64\nheight = 64\n[materials.m]\ntype = \"diffuse\"\n\
         [[objects]]\ntype = \"mesh\"\nfile = {:?}\nmaterial = \"m\"\n",
        knot.display().to_string()
    );
    common::write(&dir, "knot_small.toml", &scene);
    let rust = common::sturmray(
        &dir,
        &[
            "bench",
            "--quick",
            "--c-harness",
            "files",
            "--scene",
            "knot_small.toml",
        ],
    );
    assert!(
        rust.status.success(),
        "{}",
        String::from_utf8_lossy(&rust.stderr)
    );
    let c = Command::new(&harness)
        .args(["files", "knot_small", "1"])
        .current_dir(&dir)
        .output()
        .expect("the C harness runs");
    assert!(c.status.success(), "{}", String::from_utf8_lossy(&c.stderr));

    let (rust, c) = (checksums("rust", &rust.stdout), checksums("c", &c.stdout));
    assert_eq!(rust.len(), 4, "{rust:?}");
    assert_eq!(rust, c);
    // Both ray kinds hit the knot and miss it.
    for &(rays, hits, _, _) in rust.values() {
        assert!(0 < hits && hits < rays, "{rust:?}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
