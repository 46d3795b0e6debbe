//! `make embree-modes` (tools/peers/embree_modes.c) compiles here with `cc`
//! and runs on a few rays of the Cornell box without timing anything that is
//! checked: every query mode (robust or not; one ray a call, packets of 8,
//! streams of 256) must find the primitive the robust single-ray query finds
//! on all but 0.1% of the rays, or the tool exits 1. Embree 3 only: the tool
//! uses the Embree 3 API.
#![cfg(embree3)]

mod common;

use std::path::Path;
use std::process::Command;

#[test]
fn every_embree_mode_finds_the_same_hits() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = common::scratch("embree-modes");
    let tool = dir.join("embree_modes");
    common::compile_embree3_c(&root.join("tools/peers/embree_modes.c"), &tool);

    let run = Command::new(&tool)
        .arg(root.join("scenes/cornell/cornell.obj"))
        .args(["20000", "1"])
        .output()
        .expect("the tool runs");
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&run.stderr)
    );
    // The OBJ's 16 quads, each a fan of two triangles.
    assert!(
        stdout.contains(": 32 triangles, 20000 rays a kind"),
        "{stdout}"
    );
    // Three ray kinds by three APIs, each with two positive times.
    let rows: Vec<&str> = stdout
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| rays"))
        .collect();
    assert_eq!(rows.len(), 9, "{stdout}");
    for row in rows {
        let cells: Vec<&str> = row.split('|').map(str::trim).collect();
        for ns in &cells[3..5] {
            let ns: f64 = ns.parse().unwrap_or_else(|_| panic!("{row}"));
            assert!(ns > 0.0 && ns.is_finite(), "{row}");
        }
    }

    // A mesh that is no mesh is an error, not a crash.
    let empty = dir.join("empty.obj");
    std::fs::write(&empty, "v 0 0 0\n").unwrap();
    let refused = Command::new(&tool).arg(&empty).output().unwrap();
    assert_eq!(refused.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("no faces"));
}
