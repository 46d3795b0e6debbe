//! `.pov` scenes through the CLI: rendered at POV-Ray's default size or the
//! asked one, `#include` through `--pov-include`, warnings naming the line of
//! what is skipped, syntax errors with exit code 2, `info` listing what was
//! read, and the included files protected as the scene's inputs.

mod common;

use common::{png_size, scratch, sturmray, write};

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn stdout(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// A red sphere under a white light, its radius declared in `radius.inc`.
const SCENE: &str = "#version 3.7;
#include \"radius.inc\"
camera { location <0, 0, -5> look_at <0, 0, 0> angle 40 right x*image_width/image_height }
light_source { <10, 10, -10> color rgb 1 }
sphere { 0, Radius pigment { rgb <1, 0, 0> } finish { phong 0.5 } }
blob { threshold 0.5 sphere { 0, 1, 1 } }
background { color rgb 0.1 }
";

#[test]
fn a_pov_scene_renders_at_povrays_size_or_the_asked_one() {
    let dir = scratch("pov-render");
    let includes = dir.join("lib");
    std::fs::create_dir_all(&includes).unwrap();
    write(&includes, "radius.inc", "#declare Radius = 1.5;\n");
    write(&dir, "ball.pov", SCENE);
    // Without the folder, the include is not found: exit 2, naming the line.
    let out = sturmray(&dir, &["render", "ball.pov", "-o", "a.exr"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("ball.pov:2:1: cannot find the include file \"radius.inc\""),
        "{}",
        stderr(&out)
    );
    let out = sturmray(
        &dir,
        &[
            "render",
            "ball.pov",
            "--pov-include",
            "lib",
            "--width",
            "40",
            "-o",
            "b.exr",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    // The height follows POV-Ray's 4:3.
    assert_eq!(png_size(&dir.join("b.png")), (40, 30));
    // What is outside the subset is a warning with its place, and the rest renders.
    assert!(
        stderr(&out).contains("ball.pov:6:1: `blob` is not supported"),
        "{}",
        stderr(&out)
    );
    let out = sturmray(
        &dir,
        &[
            "render",
            "ball.pov",
            "--pov-include",
            "lib",
            "--spp",
            "1",
            "-o",
            "c.exr",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(png_size(&dir.join("c.png")), (800, 600));
}

#[test]
fn info_lists_what_was_read_and_skipped() {
    let dir = scratch("pov-info");
    write(&dir, "radius.inc", "#declare Radius = 1.5;\n");
    write(&dir, "ball.pov", SCENE);
    let out = sturmray(&dir, &["info", "ball.pov"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(
        text.contains("read       #include, background, camera, light_source, sphere"),
        "{text}"
    );
    assert!(
        text.contains("skipped    blob (outside the POV-Ray subset"),
        "{text}"
    );
    assert!(text.contains("unfading point (POV-Ray's)"), "{text}");
    // A fading light says how it fades, and from where.
    let faded = SCENE.replace(
        "color rgb 1 }",
        "color rgb 1 fade_distance 4 fade_power 2 }",
    );
    write(&dir, "faded.pov", &faded);
    let out = sturmray(&dir, &["info", "faded.pov"]);
    let text = stdout(&out);
    assert!(
        text.contains("fading (fade_distance 4, fade_power 2, from [10, 10, -10]) point"),
        "{text}"
    );
}

#[test]
fn syntax_errors_are_bad_input_with_their_line_and_column() {
    let dir = scratch("pov-syntax");
    for (text, place) in [
        (
            "sphere { <0, 0, 0> 1\n",
            "bad.pov:1:20: this object is never closed",
        ),
        (
            "camera { location <0, 0, -5> look_at 0 }\nsphere { 0, 1 } }\n",
            "bad.pov:2:17: expected an object",
        ),
        (
            "#declare A = 1;\n#if (A)\nsphere { 0, 1 }\n",
            "bad.pov:3:15: this file ends inside an `#if`",
        ),
        (
            "/* never closed\n",
            "bad.pov:1:1: this comment is never closed",
        ),
        ("sphere { 0, \"one\" }\n", "bad.pov:1:13: expected a number"),
    ] {
        write(&dir, "bad.pov", text);
        let out = sturmray(&dir, &["render", "bad.pov", "-o", "x.exr"]);
        assert_eq!(out.status.code(), Some(2), "{text}: {}", stderr(&out));
        assert!(stderr(&out).contains(place), "{text}: {}", stderr(&out));
        assert!(!stderr(&out).contains("panicked"), "{}", stderr(&out));
    }
}

#[test]
fn an_included_file_is_an_input_no_output_may_replace() {
    let dir = scratch("pov-inputs");
    write(&dir, "radius.inc", "#declare Radius = 1.5;\n");
    write(&dir, "ball.pov", SCENE);
    let before = std::fs::read(dir.join("radius.inc")).unwrap();
    let out = sturmray(
        &dir,
        &[
            "render",
            "ball.pov",
            "--width",
            "8",
            "-o",
            "x.exr",
            "--stats",
            "radius.inc",
        ],
    );
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert_eq!(std::fs::read(dir.join("radius.inc")).unwrap(), before);
}
