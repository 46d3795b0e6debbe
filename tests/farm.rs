//! Pieces of work: tiles and crops rendered in separate processes merge into
//! exactly the image one process renders; `merge` refuses pieces that do not
//! fit together; an interrupted render resumes to the identical image.

mod common;

use std::path::Path;
use std::process::{Command, Stdio};

use common::{SQUARE, scratch, sturmray, write};

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A small path-traced scene with a glass sphere (photons too), so pixels
/// differ and every integrator path runs.
fn scene(dir: &Path, spp: u32) {
    write(dir, "square.obj", SQUARE);
    let text = format!(
        "[camera]\neye = [0, -3, 2]\nlook_at = [0, 0, 0]\nfov = 45\nwidth = 40\nheight = 30\n\
         [render]\nspp = {spp}\nintegrator = \"path\"\nphotons = {{ count = 20000 }}\n\
         [materials.paint]\ntype = \"diffuse\"\nalbedo = [0.6, 0.5, 0.4]\n\
         [materials.glass]\ntype = \"dielectric\"\n\
         [[objects]]\ntype = \"mesh\"\nfile = \"square.obj\"\nmaterial = \"paint\"\n\
         [[objects]]\ntype = \"sphere\"\nradius = 0.4\nmaterial = \"glass\"\n\
         transform = {{ translate = [0, 0, 0.5] }}\n\
         [[lights]]\ntype = \"sphere\"\ncenter = [1, -1, 2]\nradius = 0.2\nradiance = [20, 20, 20]\n"
    );
    write(dir, "s.toml", &text);
}

fn ok(dir: &Path, args: &[&str]) {
    let out = sturmray(dir, args);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
}

#[test]
fn four_tiles_in_four_processes_merge_bit_identically() {
    let dir = scratch("tiles");
    scene(&dir, 4);
    ok(
        &dir,
        &["render", "s.toml", "-o", "whole.exr", "--threads", "2"],
    );
    let parts: Vec<String> = (0..4).map(|i| format!("part{i}.exr")).collect();
    for (i, part) in parts.iter().enumerate() {
        let tile = format!("{i}/4");
        ok(
            &dir,
            &[
                "render",
                "s.toml",
                "--tile",
                &tile,
                "-o",
                part,
                "--threads",
                "1",
            ],
        );
        assert!(dir.join(part).with_extension("state").is_file());
    }
    // Given in any order.
    let mut args = vec!["merge", "merged.exr"];
    args.extend(parts.iter().rev().map(String::as_str));
    ok(&dir, &args);
    let whole = std::fs::read(dir.join("whole.exr")).unwrap();
    let merged = std::fs::read(dir.join("merged.exr")).unwrap();
    assert!(
        whole == merged,
        "the merged EXR differs from the whole render"
    );

    // A crop is the same region of the whole render, too.
    ok(
        &dir,
        &["render", "s.toml", "--crop", "5,7,23,19", "-o", "crop.exr"],
    );
    let whole = sturmray::io::exr::read_exr(&dir.join("whole.exr")).unwrap();
    let crop = sturmray::io::exr::read_exr(&dir.join("crop.exr")).unwrap();
    assert_eq!((crop.0, crop.1), (18, 12));
    for ((name, all), (crop_name, part)) in whole.2.iter().zip(&crop.2) {
        assert_eq!(name, crop_name);
        for (i, v) in part.iter().enumerate() {
            let (x, y) = (5 + i % 18, 7 + i / 18);
            assert_eq!(v.to_bits(), all[y * 40 + x].to_bits(), "{name} at {x},{y}");
        }
    }
}

#[test]
fn merge_names_the_parts_that_do_not_fit() {
    let dir = scratch("merge-bad");
    scene(&dir, 2);
    for i in 0..3 {
        let (tile, out) = (format!("{i}/3"), format!("t{i}.exr"));
        ok(&dir, &["render", "s.toml", "--tile", &tile, "-o", &out]);
    }
    // Another scene (a different albedo) for one part.
    let other = scratch("merge-bad-other");
    scene(&other, 2);
    let text = std::fs::read_to_string(other.join("s.toml")).unwrap();
    write(
        &other,
        "s.toml",
        &text.replace("0.6, 0.5, 0.4", "0.6, 0.5, 0.5"),
    );
    ok(
        &other,
        &["render", "s.toml", "--tile", "2/3", "-o", "t2.exr"],
    );
    let foreign = other.join("t2.exr").display().to_string();
    ok(
        &dir,
        &[
            "render",
            "s.toml",
            "--crop",
            "0,0,40,12",
            "-o",
            "overlap.exr",
        ],
    );
    write(&dir, "lonely.exr", "");
    let cases: [(&[&str], &str); 5] = [
        (
            &["merge", "m.exr", "t0.exr", "t1.exr"],
            "rows from 20 on are missing",
        ),
        (
            &["merge", "m.exr", "t0.exr", "t1.exr", &foreign],
            "another scene",
        ),
        (
            &[
                "merge",
                "m.exr",
                "t0.exr",
                "t1.exr",
                "t2.exr",
                "overlap.exr",
            ],
            "overlap",
        ),
        (
            &["merge", "m.exr", "t0.exr", "t0.exr", "t1.exr", "t2.exr"],
            "same seed",
        ),
        (&["merge", "m.exr", "t0.exr", "lonely.exr"], "no film state"),
    ];
    for (args, expected) in cases {
        let out = sturmray(&dir, args);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(
            stderr(&out).contains(expected),
            "{args:?}: {}",
            stderr(&out)
        );
    }
}

#[test]
fn parts_of_one_region_with_other_seeds_add_up() {
    let dir = scratch("merge-seeds");
    scene(&dir, 2);
    let text = std::fs::read_to_string(dir.join("s.toml")).unwrap();
    write(
        &dir,
        "more.toml",
        &text.replace("spp = 2", "spp = 6\nseed = 7"),
    );
    ok(
        &dir,
        &["render", "s.toml", "--crop", "0,0,40,30", "-o", "a.exr"],
    );
    ok(
        &dir,
        &["render", "more.toml", "--crop", "0,0,40,30", "-o", "b.exr"],
    );
    ok(&dir, &["merge", "m.exr", "a.exr", "b.exr"]);
    let attributes = sturmray::io::exr::read_exr_attributes(&dir.join("m.exr")).unwrap();
    assert!(
        attributes.contains(&("sturmray.spp".into(), "8".into())),
        "{attributes:?}"
    );
    // Each pixel is the sample-weighted mean of the two (box filter: weight 1 each).
    let read = |f: &str| {
        sturmray::io::exr::read_exr(&dir.join(f)).unwrap().2[0]
            .1
            .clone()
    };
    let (a, b, m) = (read("a.exr"), read("b.exr"), read("m.exr"));
    for i in 0..a.len() {
        let expected = (2.0 * a[i] + 6.0 * b[i]) / 8.0;
        assert!(
            (m[i] - expected).abs() <= 1e-5 * expected.abs().max(1.0),
            "{i}"
        );
    }
}

#[test]
fn an_interrupted_render_resumes_to_the_identical_image() {
    let dir = scratch("resume");
    scene(&dir, 64);
    // Bigger, so the render lasts long enough to be stopped midway.
    let text = std::fs::read_to_string(dir.join("s.toml")).unwrap();
    write(
        &dir,
        "s.toml",
        &text.replace("width = 40\nheight = 30", "width = 160\nheight = 120"),
    );
    let child = Command::new(env!("CARGO_BIN_EXE_sturmray"))
        .args(["render", "s.toml", "-o", "cut.exr", "--threads", "2"])
        .current_dir(&dir)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The render catches signals from its start and stops after the pass it is
    // in, so this lands midway unless the whole render takes under 0.2 s.
    std::thread::sleep(std::time::Duration::from_millis(200));
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(130), "{}", stderr(&out));
    let (header, _) = sturmray::io::state::read_state(&dir.join("cut.state")).unwrap();
    assert!(
        header.samples_done > 0 && header.samples_done < 64,
        "stopped after {} of 64 samples",
        header.samples_done
    );
    assert!(dir.join("cut.exr").is_file(), "the image so far is written");

    ok(
        &dir,
        &[
            "render",
            "s.toml",
            "-o",
            "cut.exr",
            "--threads",
            "1",
            "--resume",
        ],
    );
    ok(
        &dir,
        &["render", "s.toml", "-o", "whole.exr", "--threads", "2"],
    );
    let cut = std::fs::read(dir.join("cut.exr")).unwrap();
    let whole = std::fs::read(dir.join("whole.exr")).unwrap();
    assert!(
        cut == whole,
        "the resumed render differs from the uninterrupted one"
    );

    // Resuming with other settings is refused, naming the state.
    let out = sturmray(
        &dir,
        &[
            "render", "s.toml", "-o", "cut.exr", "--spp", "32", "--resume",
        ],
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("cut.state"), "{}", stderr(&out));
}
