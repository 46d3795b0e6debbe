//! Every kind of bad input the CLI meets exits with code 2 and a message that
//! names the file and the line (or column) at fault; none panics.

mod common;

use std::path::Path;

use common::{SQUARE, plane_scene, scratch, sturmray};

/// One bad input: the files it needs beside `square.obj`, the command line,
/// and the parts its message must contain.
struct Case {
    name: &'static str,
    files: Vec<(&'static str, Vec<u8>)>,
    args: &'static [&'static str],
    expected: &'static [&'static str],
}

/// `plane_scene` (lines 1-20, the mesh's `file` on line 15) with `from`
/// replaced by `to`, as the file `s.toml`.
fn scene_with(from: &str, to: &str) -> Vec<(&'static str, Vec<u8>)> {
    let text = plane_scene("");
    assert!(text.contains(from), "{from:?}");
    vec![("s.toml", text.replace(from, to).into_bytes())]
}

/// `plane_scene` with `extra` appended from line 21, as `s.toml`.
fn scene_plus(extra: &str) -> Vec<(&'static str, Vec<u8>)> {
    vec![("s.toml", plane_scene(extra).into_bytes())]
}

/// A square whose OBJ names `bad.mtl` with `mtl` as its text, used by `m.toml`.
fn with_mtl(mtl: &str) -> Vec<(&'static str, Vec<u8>)> {
    vec![
        ("m.obj", format!("mtllib bad.mtl\n{SQUARE}").into_bytes()),
        ("bad.mtl", mtl.as_bytes().to_vec()),
    ]
}

const RENDER: &[&str] = &["render", "s.toml", "-o", "out.exr"];
const RENDER_M: &[&str] = &["render", "m.obj", "-o", "out.exr"];

fn cases() -> Vec<Case> {
    let case = |name, files, args, expected| Case {
        name,
        files,
        args,
        expected,
    };
    let obj = |name: &'static str, text: &[u8]| vec![(name, text.to_vec())];
    vec![
        case(
            "malformed TOML",
            scene_plus("[[objects]\n"),
            RENDER,
            &["s.toml", "line 21"],
        ),
        case(
            "unknown key",
            scene_with("fov", "fvo"),
            RENDER,
            &[
                "s.toml",
                "line 5",
                "unknown field `fvo`",
                "did you mean `fov`?",
            ],
        ),
        case(
            "missing OBJ named in TOML",
            scene_with("square.obj", "nope.obj"),
            RENDER,
            &["s.toml", "line 15, objects[0].file", "nope.obj"],
        ),
        case(
            "unreadable OBJ (a folder) named in TOML",
            scene_with("square.obj", "folder.obj"),
            RENDER,
            &["s.toml", "line 15, objects[0].file", "folder.obj"],
        ),
        case(
            "missing bare OBJ",
            vec![],
            &["render", "nope.obj"],
            &["nope.obj", "No such file"],
        ),
        case(
            "OBJ not UTF-8",
            obj("bin.obj", b"v 0 0 0\nv 1 0 \xff\n"),
            &["render", "bin.obj"],
            &["bin.obj:2", "not UTF-8"],
        ),
        case(
            "malformed OBJ",
            obj("bad.obj", b"v 0 0 0\nf 1 2 3\n"),
            &["render", "bad.obj"],
            &["bad.obj:2", "vertex index 2 out of range"],
        ),
        case(
            "usemtl without a name",
            obj("m.obj", b"v 0 0 0\nusemtl \n"),
            RENDER_M,
            &["m.obj:2", "expected a material name after `usemtl`"],
        ),
        case(
            "unreadable MTL (a folder)",
            obj("m.obj", b"mtllib folder.obj\n"),
            RENDER_M,
            &["m.obj:1", "folder.obj", "directory"],
        ),
        case(
            "mtllib without a file name",
            obj("m.obj", b"mtllib\n"),
            RENDER_M,
            &["m.obj:1", "expected a file name after `mtllib`"],
        ),
        case(
            "MTL colour of two numbers (tobj panics on it)",
            with_mtl("newmtl a\nKd 1 1\n"),
            RENDER_M,
            &["bad.mtl:2", "`Kd` expects 3 numbers, found `1 1`"],
        ),
        case(
            "MTL number that is not one",
            with_mtl("newmtl a\n\nNs shiny\n"),
            RENDER_M,
            &["bad.mtl:3", "`Ns` expects 1 number"],
        ),
        case(
            "MTL NaN colour",
            with_mtl("newmtl a\nKs nan 0 0\n"),
            RENDER_M,
            &["bad.mtl:2", "finite numbers >= 0"],
        ),
        case(
            "MTL IOR 0",
            with_mtl("newmtl a\nillum 7\nNi 0\n"),
            RENDER_M,
            &["bad.mtl:3", "`Ni` expects a finite number > 0"],
        ),
        case(
            "OBJ NaN vertex",
            obj("n.obj", b"v 0 0 0\nv nan 0 0\n"),
            &["render", "n.obj"],
            &["n.obj:2", "`nan` is not a finite number below 1e9"],
        ),
        case(
            "OBJ infinite vertex",
            obj("n.obj", b"v 0 -inf 0\n"),
            &["render", "n.obj"],
            &["n.obj:1", "`-inf` is not a finite number below 1e9"],
        ),
        case(
            "OBJ absurdly large vertex",
            obj("n.obj", b"v 0 0 0\nv 0 0 0\nv 0 0 2e18\n"),
            &["render", "n.obj"],
            &["n.obj:3", "`2e18` is not a finite number below 1e9"],
        ),
        case(
            "TOML NaN eye",
            scene_with("eye = [0, 0, 4]", "eye = [nan, 0, 4]"),
            RENDER,
            &["s.toml", "line 3, camera.eye", "at most 1e9"],
        ),
        case(
            "TOML infinite translation",
            scene_with(
                "material = \"paint\"",
                "material = \"paint\"\ntransform = { translate = [inf, 0, 0] }",
            ),
            RENDER,
            &["line 17, objects[0].transform.translate", "at most 1e9"],
        ),
        case(
            "TOML absurdly large light position",
            scene_plus(
                "[[lights]]\ntype = \"point\"\nposition = [0, 0, 1e30]\nintensity = [1, 1, 1]\n",
            ),
            RENDER,
            &["line 23, lights[1].position", "at most 1e9"],
        ),
        case(
            "TOML NaN clip box",
            scene_plus(
                "[[objects]]\ntype = \"sphere\"\nradius = 1\nclip = { min = [nan, 0, 0], max = [1, 1, 1] }\n",
            ),
            RENDER,
            &["line 24, objects[1].clip.min", "at most 1e9"],
        ),
        case(
            "TOML infinite quadric coefficient",
            scene_plus(
                "[[objects]]\ntype = \"quadric\"\na = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\nc = -inf\nclip = { min = [-1, -1, -1], max = [1, 1, 1] }\n",
            ),
            RENDER,
            &["line 24, objects[1].c", "finite"],
        ),
        case(
            "polynomial syntax error",
            scene_plus(
                "[[objects]]\ntype = \"algebraic\"\nexpr = \"x^2 + * y^2 - 1\"\nclip = { min = [-1, -1, -1], max = [1, 1, 1] }\n",
            ),
            RENDER,
            &["s.toml", "line 23, objects[1].expr: column 7"],
        ),
        case(
            "polynomial degree above the limit",
            scene_plus(
                "[[objects]]\ntype = \"algebraic\"\nexpr = \"x^36 - y\"\nclip = { min = [-1, -1, -1], max = [1, 1, 1] }\n",
            ),
            RENDER,
            &[
                "line 23, objects[1].expr: column 2",
                "above the limit of 35",
            ],
        ),
        case(
            "negative radius",
            scene_plus("[[objects]]\ntype = \"sphere\"\nradius = -1\n"),
            RENDER,
            &["line 23, objects[1].radius", "> 0"],
        ),
        case(
            "IOR 0",
            scene_plus("[materials.glass]\ntype = \"dielectric\"\nior = 0\n"),
            RENDER,
            &["line 23, materials.glass.ior", "> 0"],
        ),
        case(
            "negative IOR",
            scene_plus("[materials.glass]\ntype = \"dielectric\"\nior = -1.5\n"),
            RENDER,
            &["line 23, materials.glass.ior", "> 0"],
        ),
        case(
            "zero-area quad light",
            scene_plus(
                "[[lights]]\ntype = \"quad\"\ncorner = [0, 0, 1]\nedge1 = [1, 0, 0]\nedge2 = [2, 0, 0]\nradiance = [1, 1, 1]\n",
            ),
            RENDER,
            &["line 24, lights[1].edge1", "zero area"],
        ),
        case(
            "zero-radius sphere light",
            scene_plus(
                "[[lights]]\ntype = \"sphere\"\ncenter = [0, 0, 1]\nradius = 0\nradiance = [1, 1, 1]\n",
            ),
            RENDER,
            &["line 24, lights[1].radius", "> 0"],
        ),
        case(
            "absurdly large sphere light",
            scene_plus(
                "[[lights]]\ntype = \"sphere\"\ncenter = [0, 0, 1]\nradius = 3e38\nradiance = [1, 1, 1]\n",
            ),
            RENDER,
            &["line 24, lights[1].radius", "at most 1e9"],
        ),
        case(
            "spp = 0 in the scene",
            scene_with("spp = 1", "spp = 0"),
            RENDER,
            &["s.toml", "line 9, render.spp"],
        ),
        case(
            "spp = 0 on the command line",
            scene_plus(""),
            &["render", "s.toml", "--spp", "0"],
            &["--spp", "0"],
        ),
        case(
            "width 0",
            scene_with("width = 32", "width = 0"),
            RENDER,
            &["line 6, camera.width", "expected 1 to 65536 pixels"],
        ),
        case(
            "width above the limit",
            scene_with("width = 32", "width = 100000"),
            RENDER,
            &["line 6, camera.width", "expected 1 to 65536 pixels"],
        ),
        case(
            "negative width",
            scene_with("width = 32", "width = -32"),
            RENDER,
            &["s.toml", "line 6", "width"],
        ),
        case(
            "a film larger than the machine's memory",
            scene_with("width = 32\nheight = 24", "width = 65536\nheight = 65536"),
            RENDER,
            &["line 2, camera", "832.0 GiB", "208 bytes per pixel"],
        ),
        case(
            "an instance of an unknown prototype",
            scene_plus(
                "[[prototypes.tree.objects]]\ntype = \"sphere\"\nradius = 1\n\
                 [[objects]]\ntype = \"instance\"\nprototype = \"tre\"\n",
            ),
            RENDER,
            &[
                "line 26, objects[1].prototype",
                "no prototype named `tre`",
                "`tree`",
            ],
        ),
        case(
            "an instance inside a prototype (instancing is one level deep)",
            scene_plus("[[prototypes.a.objects]]\ntype = \"instance\"\nprototype = \"a\"\n"),
            RENDER,
            &["line 21, prototypes.a.objects[0]", "one level"],
        ),
        case(
            "an instance inside a csg",
            scene_plus(
                "[[prototypes.a.objects]]\ntype = \"sphere\"\nradius = 1\n[[objects]]\n\
                 type = \"csg\"\nop = \"union\"\n\
                 children = [{ type = \"instance\", prototype = \"a\" }]\n",
            ),
            RENDER,
            &["line 27, objects[1].children[0]", "csg"],
        ),
        case(
            "an unknown key in an instance",
            scene_plus(
                "[[prototypes.a.objects]]\ntype = \"sphere\"\nradius = 1\n\
                 [[objects]]\ntype = \"instance\"\nprototype = \"a\"\nmaterail = \"x\"\n",
            ),
            RENDER,
            &["s.toml", "materail", "material"],
        ),
        case(
            "an emissive prototype",
            scene_plus(
                "[materials.glow]\ntype = \"emissive\"\nradiance = [1, 1, 1]\n\
                 [[prototypes.lamp.objects]]\ntype = \"sphere\"\nradius = 1\n\
                 material = \"glow\"\n[[objects]]\ntype = \"instance\"\nprototype = \"lamp\"\n",
            ),
            RENDER,
            &["prototypes.lamp", "emissive geometry cannot be instanced"],
        ),
        case(
            "output under a file",
            scene_plus(""),
            &["render", "s.toml", "-o", "square.obj/x.exr"],
            &["square.obj"],
        ),
        case(
            "output that is a folder",
            scene_plus(""),
            &["render", "s.toml", "-o", "folder.obj"],
            &["folder.obj", "directory"],
        ),
    ]
}

#[test]
fn every_bad_input_exits_with_2_and_names_file_and_line() {
    let mut failures = Vec::new();
    for (i, case) in cases().into_iter().enumerate() {
        let dir = scratch(&format!("bad-{i}"));
        std::fs::write(dir.join("square.obj"), SQUARE).unwrap();
        std::fs::create_dir(dir.join("folder.obj")).unwrap();
        for (name, bytes) in &case.files {
            std::fs::write(dir.join(name), bytes).unwrap();
        }
        let out = sturmray(&dir, case.args);
        let err = String::from_utf8_lossy(&out.stderr);
        let missing: Vec<_> = case.expected.iter().filter(|e| !err.contains(*e)).collect();
        if out.status.code() != Some(2) || !missing.is_empty() || err.contains("panicked") {
            failures.push(format!(
                "{}: exit {:?}, missing {missing:?} in: {err}",
                case.name,
                out.status.code()
            ));
        }
        // Nothing is rendered: every case fails before the first pixel.
        assert!(!dir.join("out.exr").exists(), "{}", case.name);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// An output that cannot be written is found before rendering, so no work is
/// lost: the EXR beside an unwritable preview or stats file is never written.
#[test]
fn unwritable_outputs_are_found_before_rendering() {
    let dir = scratch("unwritable");
    std::fs::write(dir.join("square.obj"), SQUARE).unwrap();
    std::fs::write(dir.join("s.toml"), plane_scene("")).unwrap();
    std::fs::create_dir(dir.join("image.png")).unwrap();
    std::fs::create_dir(dir.join("stats")).unwrap();
    for (args, named) in [
        (&["render", "s.toml", "-o", "image.exr"][..], "image.png"),
        (
            &["render", "s.toml", "-o", "other.exr", "--stats", "stats"],
            "stats",
        ),
    ] {
        let out = sturmray(&dir, args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(named), "{args:?}: {err}");
        let exr = Path::new(args[3]);
        assert!(!dir.join(exr).exists(), "{args:?} rendered {exr:?}");
    }
    // The check leaves no empty file behind when the render succeeds or fails.
    assert!(!dir.join("other.png").exists());
}

#[test]
fn degenerate_triangles_are_counted_in_one_warning() {
    let dir = scratch("degenerate");
    // One good triangle, one with a repeated corner, one of collinear corners.
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\nf 1 2 4\n";
    std::fs::write(dir.join("d.obj"), obj).unwrap();
    let out = sturmray(&dir, &["info", "d.obj"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert_eq!(
        err.matches("warning").count(),
        1,
        "one warning for the file: {err}"
    );
    assert!(
        err.contains("d.obj: 2 degenerate triangles (zero area) skipped"),
        "{err}"
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("triangles  3"), "all three kept: {text}");
}
