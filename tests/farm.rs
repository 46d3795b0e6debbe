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
    crop_matches(&dir, [5, 7, 23, 19]);
}

/// Renders `crop` = [x0, y0, x1, y1] of s.toml and checks every channel
/// against whole.exr, bit for bit.
fn crop_matches(dir: &Path, crop: [usize; 4]) {
    let [x0, y0, x1, y1] = crop;
    let region = format!("{x0},{y0},{x1},{y1}");
    ok(
        dir,
        &["render", "s.toml", "--crop", &region, "-o", "crop.exr"],
    );
    let whole = sturmray::io::exr::read_exr(&dir.join("whole.exr")).unwrap();
    let part = sturmray::io::exr::read_exr(&dir.join("crop.exr")).unwrap();
    assert_eq!((part.0, part.1), (x1 - x0, y1 - y0));
    for ((name, all), (part_name, values)) in whole.2.iter().zip(&part.2) {
        assert_eq!(name, part_name);
        for (i, v) in values.iter().enumerate() {
            let (x, y) = (x0 + i % part.0, y0 + i / part.0);
            let at = all[y * whole.0 + x];
            assert_eq!(
                v.to_bits(),
                at.to_bits(),
                "{name} at {x},{y}, crop {region}"
            );
        }
    }
}

/// Camera rays are traced in streams, whose packets may break a tie
/// between two triangles hit at the same t otherwise than one ray would
/// (render::batch): a crop must still have the whole image's pixels. A
/// grid of triangles with smooth normals, seen head-on from above a grid
/// line through an odd number of pixels, so a row and a column of rays
/// meet edges exactly and the triangle reported shows in the normal's
/// last bits (three pixels' normals differ from single-ray queries'). In
/// Debian's Embree 3.13.5 a camera ray's tie did not change with the rays
/// streamed beside it, so this passes with a crop's own streams too; the
/// whole grid tile's stream is what keeps it so if another Embree differs.
#[test]
fn crops_keep_the_whole_renders_ties_between_triangles() {
    let dir = scratch("ties");
    let n = 20;
    let mut obj = String::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (
                i as f64 / n as f64 * 2.0 - 1.0,
                j as f64 / n as f64 * 2.0 - 1.0,
            );
            let l = (x * x + y * y + 1.0).sqrt();
            obj += &format!("v {x} {y} 0\nvn {} {} {}\n", x / l, y / l, 1.0 / l);
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i + 1;
            let (b, c, d) = (a + 1, a + n + 1, a + n + 2);
            obj += &format!("f {a}//{a} {b}//{b} {d}//{d}\nf {a}//{a} {d}//{d} {c}//{c}\n");
        }
    }
    write(&dir, "grid.obj", &obj);
    write(
        &dir,
        "s.toml",
        "[camera]\neye = [0, 0, 3]\nlook_at = [0, 0, 0]\nfov = 45\nwidth = 41\nheight = 31\n\
         [render]\nspp = 1\nintegrator = \"path\"\n\
         [[objects]]\ntype = \"mesh\"\nfile = \"grid.obj\"\n\
         [[lights]]\ntype = \"point\"\nposition = [0.3, 0.2, 2]\nintensity = [5, 5, 5]\n",
    );
    ok(
        &dir,
        &["render", "s.toml", "-o", "whole.exr", "--threads", "2"],
    );
    for crop in [
        [3, 2, 30, 25],
        [17, 9, 41, 31],
        [0, 0, 21, 16],
        [20, 1, 22, 30],
    ] {
        crop_matches(&dir, crop);
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
    common::interrupt(&child);
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

/// docs/farm.md's Slurm recipe without a cluster: the array task script run
/// with SLURM_ARRAY_TASK_ID set in a loop, then the merge script, gives the
/// image a single render gives.
#[test]
fn the_slurm_recipe_tiles_and_merges_to_the_whole_image() {
    let dir = scratch("slurm");
    scene(&dir, 2);
    ok(&dir, &["render", "s.toml", "-o", "whole.exr"]);
    let tools = Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/farm");
    let run = |script: &str, task: Option<usize>| {
        let mut command = Command::new("bash");
        command
            .arg(tools.join(script))
            .current_dir(&dir)
            .env("STURMRAY", env!("CARGO_BIN_EXE_sturmray"))
            .env("SCENE", "s.toml")
            .env("TILES", "3")
            .env("OUT", "parts")
            .env("IMAGE", "merged.exr")
            .env("SLURM_CPUS_PER_TASK", "1");
        if let Some(task) = task {
            command.env("SLURM_ARRAY_TASK_ID", task.to_string());
        }
        let out = command.output().unwrap();
        assert!(out.status.success(), "{script} {task:?}: {}", stderr(&out));
    };
    for task in 0..3 {
        run("slurm_render.sh", Some(task));
    }
    // A requeued task (its state exists) resumes and rewrites the same part.
    let before = std::fs::read(dir.join("parts/part-1.exr")).unwrap();
    run("slurm_render.sh", Some(1));
    assert!(std::fs::read(dir.join("parts/part-1.exr")).unwrap() == before);
    run("slurm_merge.sh", None);
    let whole = std::fs::read(dir.join("whole.exr")).unwrap();
    let merged = std::fs::read(dir.join("merged.exr")).unwrap();
    assert!(
        whole == merged,
        "the Slurm recipe's image differs from the whole render"
    );
}

#[test]
fn frames_of_a_camera_path_differ_and_are_recorded() {
    let dir = scratch("frames");
    scene(&dir, 1);
    let text = std::fs::read_to_string(dir.join("s.toml")).unwrap();
    let keys = "[[camera.keys]]\nframe = 0\neye = [0, -3, 2]\nlook_at = [0, 0, 0]\n\
                [[camera.keys]]\nframe = 10\neye = [3, 0, 2]\nlook_at = [0, 0, 0]\n";
    write(
        &dir,
        "s.toml",
        &text.replace("[render]", &format!("{keys}[render]")),
    );
    for frame in ["0", "5"] {
        let out = format!("f{frame}.exr");
        ok(
            &dir,
            &[
                "render", "s.toml", "--frame", frame, "-o", &out, "--tile", "0/1",
            ],
        );
    }
    let attributes = |f: &str| sturmray::io::exr::read_exr_attributes(&dir.join(f)).unwrap();
    assert!(attributes("f5.exr").contains(&("sturmray.frame".into(), "5".into())));
    let hash = |f: &str| {
        attributes(f)
            .into_iter()
            .find(|(k, _)| k == "sturmray.scene_hash")
            .unwrap()
            .1
    };
    assert_ne!(hash("f0.exr"), hash("f5.exr"), "the camera moved");
    let beauty = |f: &str| sturmray::io::exr::read_exr(&dir.join(f)).unwrap().2;
    assert_ne!(beauty("f0.exr"), beauty("f5.exr"));
    // Frames do not merge with each other.
    let out = sturmray(&dir, &["merge", "m.exr", "f0.exr", "f5.exr"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
}

#[test]
fn one_thread_and_many_give_the_same_bytes() {
    let dir = scratch("threads");
    scene(&dir, 4);
    // Adaptive sampling too: its decisions are each pixel's own.
    let text = std::fs::read_to_string(dir.join("s.toml")).unwrap();
    write(
        &dir,
        "a.toml",
        &text.replace(
            "spp = 4",
            "spp = 4\nadaptive = { max_spp = 16, threshold = 0.05 }",
        ),
    );
    for scene in ["s.toml", "a.toml"] {
        // The default sampler (Sobol's) and the independent one.
        let mut by_sampler = Vec::new();
        for sampler in [&[][..], &["--sampler", "independent"]] {
            let mut images = Vec::new();
            for threads in ["1", "2", "3"] {
                let mut args = vec!["render", scene, "-o", "t.exr", "--threads", threads];
                args.extend(sampler);
                ok(&dir, &args);
                images.push(std::fs::read(dir.join("t.exr")).unwrap());
            }
            assert!(
                images.iter().all(|i| *i == images[0]),
                "{scene} {sampler:?}: 1, 2 and 3 threads differ"
            );
            by_sampler.push(images.swap_remove(0));
        }
        assert!(
            by_sampler[0] != by_sampler[1],
            "{scene}: the samplers agree"
        );
    }
}
