//! `--width` and `--height`: the size of the rendered image for every scene
//! kind, one side alone keeping the scene's aspect ratio, bad sizes refused
//! with the flag's name, and pieces, states and `merge` at the new size.

mod common;

use std::path::Path;

use common::{SQUARE, plane_scene, png_size, scratch, sturmray, write};

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn ok(dir: &Path, args: &[&str]) {
    let out = sturmray(dir, args);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
}

/// Exit 2 with every one of `needles` in the message.
fn refused(dir: &Path, args: &[&str], needles: &[&str]) {
    let out = sturmray(dir, args);
    let text = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {text}");
    for needle in needles {
        assert!(
            text.contains(needle),
            "{args:?}: expected {needle:?} in {text}"
        );
    }
}

/// The size of a whole render's EXR and of its preview.
fn rendered_size(dir: &Path, exr: &str) -> (u32, u32) {
    let (width, height, _) = sturmray::io::exr::read_exr(&dir.join(exr)).unwrap();
    let png = png_size(&dir.join(exr).with_extension("png"));
    let exr = (width as u32, height as u32);
    assert_eq!(exr, png, "{exr:?}: the EXR and its preview disagree");
    exr
}

/// The 32×24 scene of `common::plane_scene`, with its square.
fn toml_scene(dir: &Path) {
    write(dir, "square.obj", SQUARE);
    write(dir, "s.toml", &plane_scene(""));
}

#[test]
fn a_toml_scene_renders_at_the_size_asked_for() {
    let dir = scratch("size-toml");
    toml_scene(&dir);
    // Both sides, then each alone: 32×24 is 4:3, so 16 wide is 12 high and
    // 6 high is 8 wide; 10 wide is 7.5 high, rounded up to 8.
    for (args, size) in [
        (&["--width", "20", "--height", "9"][..], (20, 9)),
        (&["--width", "16"], (16, 12)),
        (&["--height", "6"], (8, 6)),
        (&["--width", "10"], (10, 8)),
        (&["--height", "1"], (1, 1)),
        (&[], (32, 24)),
    ] {
        let mut command = vec!["render", "s.toml", "-o", "a.exr"];
        command.extend(args);
        ok(&dir, &command);
        assert_eq!(rendered_size(&dir, "a.exr"), size, "{args:?}");
    }
}

#[test]
fn the_size_flags_render_what_the_same_size_in_the_file_renders() {
    // The camera keeps its vertical field of view, and the scene hash changes
    // as the file's own width and height change it: the EXRs, hash attribute
    // and all, are the same bytes.
    let dir = scratch("size-same");
    toml_scene(&dir);
    let edited = plane_scene("").replace("width = 32\nheight = 24", "width = 20\nheight = 30");
    assert_ne!(edited, plane_scene(""));
    write(&dir, "edited.toml", &edited);
    ok(&dir, &["render", "edited.toml", "-o", "file.exr"]);
    ok(
        &dir,
        &[
            "render",
            "s.toml",
            "--width",
            "20",
            "--height",
            "30",
            "-o",
            "flags.exr",
        ],
    );
    let file = std::fs::read(dir.join("file.exr")).unwrap();
    let flags = std::fs::read(dir.join("flags.exr")).unwrap();
    assert!(
        file == flags,
        "--width/--height differ from the size in the file"
    );
}

#[test]
fn a_bare_obj_renders_at_the_size_asked_for() {
    let dir = scratch("size-obj");
    write(&dir, "square.obj", SQUARE);
    // The OBJ's own camera is 640×480: 64 wide is 48 high, 10 high is 13.3
    // wide, rounded to 13.
    for (args, size) in [
        (&["--width", "64"][..], (64, 48)),
        (&["--height", "10"], (13, 10)),
        (&["--width", "30", "--height", "40"], (30, 40)),
    ] {
        let mut command = vec!["render", "square.obj", "-o", "o.exr", "--spp", "1"];
        command.extend(args);
        ok(&dir, &command);
        assert_eq!(rendered_size(&dir, "o.exr"), size, "{args:?}");
    }
}

#[test]
fn a_bad_size_is_refused_with_the_flag_s_name() {
    let dir = scratch("size-bad");
    toml_scene(&dir);
    write(&dir, "square.obj", SQUARE);
    let sides = "expected 1 to 65536 pixels";
    for (args, needles) in [
        (&["--width", "0"][..], &["--width: ", sides, "found 0"][..]),
        (
            &["--height", "0", "--width", "5"],
            &["--height: ", "found 0"],
        ),
        (&["--width", "65537"], &["--width: ", sides, "found 65537"]),
        // The film-memory check: 832 GiB and 523 GiB of film, beyond any
        // machine these tests run on. In the second, the width is fine alone:
        // the film is too large with the height that follows from it.
        (
            &["--width", "65536", "--height", "65536"],
            &["--width and --height: ", "GiB for its film", "65536x65536"],
        ),
        (
            &["--width", "60000"],
            &[
                "--width 60000 (the height 45000 follows",
                "GiB for its film",
            ],
        ),
        (&["--width=-3"], &["--width <WIDTH>"]),
        (&["--height", "wide"], &["--height <HEIGHT>"]),
    ] {
        for scene in ["s.toml", "square.obj"] {
            let mut command = vec!["render", scene, "-o", "bad.exr"];
            command.extend(args);
            refused(&dir, &command, needles);
        }
    }
    assert!(!dir.join("bad.exr").exists());
    // The same check for explain, whose pixels are the rendered image's.
    refused(
        &dir,
        &["explain", "s.toml", "--pixel", "0,0", "--width", "0"],
        &["--width: ", sides],
    );
}

#[test]
fn the_same_bytes_whatever_the_thread_count() {
    let dir = scratch("size-threads");
    toml_scene(&dir);
    let mut images = Vec::new();
    for threads in ["1", "3"] {
        let out = format!("t{threads}.exr");
        ok(
            &dir,
            &[
                "render",
                "s.toml",
                "--width",
                "27",
                "--height",
                "19",
                "--spp",
                "3",
                "--threads",
                threads,
                "-o",
                &out,
            ],
        );
        assert_eq!(rendered_size(&dir, &out), (27, 19));
        images.push(std::fs::read(dir.join(&out)).unwrap());
    }
    assert!(images[0] == images[1], "one thread and three differ");
}

#[test]
fn tiles_crops_states_and_merge_keep_the_size_asked_for() {
    let dir = scratch("size-pieces");
    toml_scene(&dir);
    let size = ["--width", "16", "--height", "12"];
    let render = |extra: &[&str]| {
        let mut command = vec!["render", "s.toml"];
        command.extend(size);
        command.extend(extra);
        command.into_iter().map(String::from).collect::<Vec<_>>()
    };
    let run = |args: Vec<String>| {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        ok(&dir, &args);
    };
    run(render(&["-o", "whole.exr"]));
    run(render(&["--tile", "0/2", "-o", "t0.exr"]));
    run(render(&["--tile", "1/2", "-o", "t1.exr"]));
    ok(&dir, &["merge", "merged.exr", "t0.exr", "t1.exr"]);
    let whole = std::fs::read(dir.join("whole.exr")).unwrap();
    let merged = std::fs::read(dir.join("merged.exr")).unwrap();
    assert!(
        whole == merged,
        "the merged EXR differs from the whole render"
    );

    // A crop is checked against the size asked for, not the scene's 32×24.
    let mut beyond = vec!["render", "s.toml", "--crop", "0,0,20,5", "-o", "c.exr"];
    beyond.extend(size);
    refused(&dir, &beyond, &["--crop 0,0,20,5", "x1 <= 16"]);
    run(render(&["--crop", "0,0,16,5", "-o", "c.exr"]));

    // The state of a 16×12 piece resumes at 16×12, and is refused by a render
    // at the scene's own size or any other, by its header.
    run(render(&["--tile", "0/2", "-o", "t0.exr", "--resume"]));
    refused(
        &dir,
        &[
            "render", "s.toml", "--tile", "0/2", "-o", "t0.exr", "--resume",
        ],
        &["--resume", "t0.state", "another render", "16x12", "32x24"],
    );
    refused(
        &dir,
        &[
            "render", "s.toml", "--width", "16", "--tile", "0/2", "-o", "t0.exr", "--resume",
            "--height", "13",
        ],
        &["another render", "16x12", "16x13"],
    );
    // Nor do pieces of two sizes merge.
    ok(
        &dir,
        &[
            "render", "s.toml", "--tile", "1/2", "-o", "own.exr", "--width", "16", "--height", "13",
        ],
    );
    refused(&dir, &["merge", "m.exr", "t0.exr", "own.exr"], &["own.exr"]);
}

#[test]
fn explain_takes_pixels_of_the_image_asked_for() {
    let dir = scratch("size-explain");
    toml_scene(&dir);
    // (20, 5) lies in the scene's own 32×24 image, not in a 16×12 one.
    ok(&dir, &["explain", "s.toml", "--pixel", "20,5"]);
    refused(
        &dir,
        &[
            "explain", "s.toml", "--pixel", "20,5", "--width", "16", "--height", "12",
        ],
        &["--pixel 20,5 is outside the 16x12 image"],
    );
    // Near the image's centre, either size sees the square, 4 from the eye:
    // pixel centres are at most a pixel, 0.06 in tangent at 16×12, off the
    // axis, so t is below 4·√(1 + 2·0.06²) < 4.03.
    for (pixel, size) in [("16,12", &[][..]), ("8,6", &["--width", "16"][..])] {
        let mut command = vec!["explain", "s.toml", "--pixel", pixel];
        command.extend(size);
        let out = sturmray(&dir, &command);
        assert!(out.status.success(), "{}", stderr(&out));
        let text = String::from_utf8(out.stdout).unwrap();
        // The camera ray's node (the first line names the camera ray too).
        let camera = text.lines().find(|l| l.starts_with("camera ")).unwrap();
        assert!(
            camera.contains("t=4.00") || camera.contains("t=4.01") || camera.contains("t=4.02"),
            "{pixel}: {text}"
        );
    }
}

#[test]
fn a_pov_scene_takes_the_size_flags_too() {
    let dir = scratch("size-pov");
    write(&dir, "s.pov", "sphere { 0, 1 }\n");
    // The size is checked before the file is read, against POV-Ray's 800×600
    // when one side is given.
    refused(&dir, &["render", "s.pov", "--width", "0"], &["--width: "]);
    refused(
        &dir,
        &["render", "S.POV", "--height", "60000"],
        &["--height 60000 (the width 80000 follows", "found 80000"],
    );
    // One side alone keeps POV-Ray's 4:3.
    ok(&dir, &["render", "s.pov", "--width", "40", "-o", "s.exr"]);
    assert_eq!(png_size(&dir.join("s.png")), (40, 30));
}
