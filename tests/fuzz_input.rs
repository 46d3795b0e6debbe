//! Fuzzing (proptest, stable Rust) of the scene loader: TOML scene files and
//! OBJ/MTL files. Whatever the bytes, loading returns a scene or a bad-input
//! error naming the file; it never panics. `cargo test` runs a fixed set of
//! cases; `make fuzz` runs many fresh ones (see tests/fuzz_common).

mod fuzz_common;

use proptest::prelude::*;
use sturmray::accel::{Accel, Backend};
use sturmray::error::Error;
use sturmray::render::{RenderOptions, render};
use sturmray::scene::{Scene, load_obj};

fn fail(e: Error) -> TestCaseError {
    TestCaseError::fail(e.to_string())
}

/// A scratch folder per case, removed when the case ends.
fn scratch(name: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("sturmray-fuzz-{name}-"))
        .tempdir()
        .unwrap()
}

/// Checks what every load must give: a scene whose indices and bounds are
/// sound, or a bad-input error that names one of `files`.
fn check_load(result: Result<Scene, Error>, files: &[&str]) -> Result<(), TestCaseError> {
    match result {
        Ok(scene) => {
            let materials = scene.materials.len() as u32;
            for mesh in &scene.meshes {
                prop_assert_eq!(mesh.materials.len(), mesh.triangles.len());
                prop_assert!(mesh.materials.iter().all(|&m| m < materials));
                let n = mesh.positions.len() as u32;
                prop_assert!(mesh.triangles.iter().flatten().all(|&i| i < n));
                prop_assert!(mesh.positions.iter().all(|p| p.is_finite()));
            }
            let bounds = scene.bounds();
            prop_assert!(bounds.is_empty() || (bounds.min.is_finite() && bounds.max.is_finite()));
            prop_assert!(scene.camera.width > 0 && scene.camera.height > 0);
        }
        Err(e) => {
            let text = e.to_string();
            prop_assert!(e.is_bad_input(), "not bad input: {text}");
            prop_assert!(
                files.iter().any(|f| text.contains(f)),
                "no file named: {text}"
            );
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------
// Scene files: a valid scene using every table, mutated.

const SCENE: &str = r#"background = [0.1, 0.1, 0.1]
[constants]
R = 1.0
r = 0.25
[camera]
eye = [0, 2, 6]
look_at = [0, 0, 0]
up = [0, 1, 0]
fov = 40
width = 16
height = 12
[render]
spp = 2
max_depth = 4
seed = 3
filter = "tent"
integrator = "path"
adaptive = { max_spp = 8, threshold = 0.05 }
[materials.red]
type = "plastic"
albedo = [0.8, 0.1, 0.1]
[materials.glass]
type = "dielectric"
ior = 1.5
[[objects]]
type = "mesh"
file = "m.obj"
material = "red"
transform = { translate = [0, -1, 0], rotate = [0, 45, 0], scale = 2 }
[[objects]]
type = "torus"
major = 1.0
minor = 0.25
material = "glass"
[[objects]]
type = "algebraic"
expr = "(x^2 + y^2 + z^2 + R^2 - r^2)^2 - 4*R^2*(x^2 + y^2)"
clip = { min = [-2, -2, -1], max = [2, 2, 1] }
[[objects]]
type = "quadric"
a = [[1, 0, 0], [0, 1, 0], [0, 0, -1]]
c = -1
clip = { min = [-2, -2, -1], max = [2, 2, 1] }
[[objects]]
type = "ellipsoid"
radii = [1, 2, 3]
[[lights]]
type = "quad"
corner = [-1, 3, -1]
edge1 = [2, 0, 0]
edge2 = [0, 0, 2]
radiance = [5, 5, 5]
[[lights]]
type = "sphere"
center = [0, 4, 0]
radius = 0.5
radiance = [1, 1, 1]
[[lights]]
type = "point"
position = [0, 5, 0]
intensity = [10, 10, 10]
"#;

const MESH: &str = "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nf 1 2 3 4\n";

/// Text that breaks or bends TOML and the scene's rules.
fn fragment() -> impl Strategy<Value = &'static str> {
    prop::sample::select(vec![
        "[",
        "]",
        "{",
        "}",
        "=",
        ",",
        "\"",
        "'",
        "\n",
        "#",
        ".",
        "nan",
        "-inf",
        "-1",
        "0",
        "1e30",
        "1e400",
        "4294967296",
        "-0.0",
        "true",
        "\"\"",
        "[[objects]]",
        "[camera]",
        "type = \"torus\"\n",
        "radius = -1\n",
        "expr = \"x^17\"\n",
        "[materials.red]\n",
        "[[lights]]\ntype = \"sphere\"\n",
        "file = \"none.obj\"\n",
        "\u{0}",
        "é",
    ])
}

/// One edit at a place given as a fraction of the text's length.
#[derive(Clone, Debug)]
enum Edit {
    Delete(f64, usize),
    Insert(f64, &'static str),
    /// Replace the number starting at or after the place.
    Number(f64, &'static str),
}

fn edit() -> impl Strategy<Value = Edit> {
    let at = 0.0..1.0f64;
    prop_oneof![
        (at.clone(), 1usize..20).prop_map(|(a, n)| Edit::Delete(a, n)),
        (at.clone(), fragment()).prop_map(|(a, f)| Edit::Insert(a, f)),
        (at, fragment()).prop_map(|(a, f)| Edit::Number(a, f)),
    ]
}

/// The byte index at fraction `at` of `text`, moved back to a char boundary.
fn index(text: &str, at: f64) -> usize {
    let mut i = (at * text.len() as f64) as usize;
    while !text.is_char_boundary(i) {
        i -= 1;
    }
    i
}

fn apply(text: &mut String, edit: &Edit) {
    match *edit {
        Edit::Delete(at, n) => {
            let start = index(text, at);
            let end = text[start..]
                .char_indices()
                .nth(n)
                .map_or(text.len(), |(i, _)| start + i);
            text.replace_range(start..end, "");
        }
        Edit::Insert(at, f) => text.insert_str(index(text, at), f),
        Edit::Number(at, f) => {
            let start = index(text, at);
            if let Some(offset) = text[start..].find(|c: char| c.is_ascii_digit()) {
                let begin = start + offset;
                let len = text[begin..]
                    .find(|c: char| !(c.is_ascii_digit() || c == '.'))
                    .unwrap_or(text.len() - begin);
                text.replace_range(begin..begin + len, f);
            }
        }
    }
}

proptest! {
    #![proptest_config(fuzz_common::config(300))]

    /// A small scene that loads also builds and renders (on one thread, every
    /// effect on): values the loader accepts must not break Embree or the
    /// integrators.
    #[test]
    fn fuzz_scene_parser(edits in prop::collection::vec(edit(), 0..6)) {
        let scratch = scratch("scene");
        let dir = scratch.path();
        std::fs::write(dir.join("m.obj"), MESH).unwrap();
        let mut text = SCENE.to_owned();
        for e in &edits {
            apply(&mut text, e);
        }
        let path = dir.join("s.toml");
        std::fs::write(&path, &text).unwrap();
        let loaded = Scene::load(&path);
        let scene = loaded.as_ref().ok().cloned();
        check_load(loaded, &["s.toml", "m.obj", "none.obj"])?;
        // Small enough to take milliseconds.
        let small = |s: &Scene| {
            let samples = s.render.adaptive.as_ref().map_or(s.render.spp, |a| a.max_spp);
            u64::from(s.camera.width) * u64::from(s.camera.height) * u64::from(samples) <= 64 * 64 * 8
        };
        if let Some(scene) = scene.filter(small) {
            let accel = Accel::build(&scene, Backend::Embree, Some(1)).map_err(fail)?;
            let options = RenderOptions { threads: Some(1), all_effects: true, ..RenderOptions::default() };
            let out = render(&scene, &accel, &options).map_err(fail)?;
            prop_assert!(out.film.pixels.iter().all(|p| p.radiance.iter().all(|c| c.is_finite())));
        }
    }
}

// ---------------------------------------------------------------------------
// OBJ and MTL files, line by line.

fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => (-3i32..4).prop_map(|i| i.to_string()),
        2 => (-10.0..10.0f64).prop_map(|x| x.to_string()),
        1 => prop::sample::select(vec!["nan", "inf", "-inf", "1e30", "1e-40", "x", "", "1e", "0x1"])
            .prop_map(str::to_owned),
    ]
}

fn obj_line() -> impl Strategy<Value = String> {
    let index = (-6i32..8).prop_map(|i| i.to_string());
    let corner = (index, 0usize..4).prop_map(|(i, form)| match form {
        0 => i,
        1 => format!("{i}/1"),
        2 => format!("{i}//1"),
        _ => format!("{i}/1/1"),
    });
    prop_oneof![
        6 => prop::collection::vec(number(), 2..5).prop_map(|v| format!("v {}", v.join(" "))),
        6 => prop::collection::vec(corner, 0..6).prop_map(|c| format!("f {}", c.join(" "))),
        1 => prop::sample::select(vec![
            "o a", "g b", "o", "usemtl red", "usemtl ghost", "usemtl", "mtllib m.mtl",
            "mtllib missing.mtl", "mtllib", "vn 0 0 1", "vt 0 0", "s off", "# c", "", "   ",
            "l 1 2", "f 1 2 3 # tail", "\u{feff}v 0 0 0",
        ])
        .prop_map(str::to_owned),
        1 => "\\PC{0,12}",
    ]
}

fn mtl_line() -> impl Strategy<Value = String> {
    let keyword = prop::sample::select(vec![
        "newmtl", "Ka", "Kd", "Ks", "Ke", "Ns", "Ni", "d", "Tr", "illum", "Pr", "Pm", "map_Kd",
        "bump", "#",
    ]);
    prop_oneof![
        8 => (keyword, prop::collection::vec(number(), 0..5))
            .prop_map(|(k, v)| format!("{k} {}", v.join(" "))),
        1 => Just("newmtl red".to_owned()),
        1 => "\\PC{0,12}",
    ]
}

/// How many triangles the faces of `obj` fan into.
fn triangles_in(obj: &str) -> usize {
    obj.lines()
        .map(|l| l.split('#').next().unwrap_or("").trim())
        .filter(|l| l.split_whitespace().next() == Some("f"))
        .map(|l| l.split_whitespace().count() - 1 - 2)
        .sum()
}

proptest! {
    #![proptest_config(fuzz_common::config(300))]

    #[test]
    fn fuzz_obj_loader(
        obj in prop::collection::vec(obj_line(), 0..30),
        mtl in prop::collection::vec(mtl_line(), 0..12),
    ) {
        let scratch = scratch("obj");
        let dir = scratch.path();
        let (obj, mtl) = (obj.join("\n"), mtl.join("\n"));
        std::fs::write(dir.join("m.mtl"), &mtl).unwrap();
        let path = dir.join("o.obj");
        std::fs::write(&path, &obj).unwrap();
        let files = ["o.obj", "m.mtl", "missing.mtl"];
        if let Ok(loaded) = load_obj(&path) {
            let count: usize = loaded.meshes.iter().map(|m| m.triangles.len()).sum();
            prop_assert_eq!(count, triangles_in(&obj), "{}", obj);
            prop_assert!(loaded.degenerate <= count);
        }
        check_load(Scene::load(&path), &files)?;
        if let Err(Error::Mesh { path: file, line, .. }) = Scene::load(&path) {
            let text = if file.ends_with("m.mtl") { &mtl } else { &obj };
            prop_assert!(line <= text.lines().count(), "line {} of {}", line, file.display());
        }
    }
}

// ---------------------------------------------------------------------------
// POV-Ray scenes: Debian's own examples (`povray-examples`, which `make setup`
// installs for the comparisons against POV-Ray), mutated word by word. A
// mutation fuzz of them found a panic in the reader (a word that is not an
// object where objects stand), two stack overflows (a loop wrapping an object
// in itself on every pass; a declaration whose value holds the loop's
// `#end`) and a panic in a callback (a line touching a capped cylinder's
// box at one point of its rim).

const POV_EXAMPLES: &str = "/usr/share/doc/povray/examples";

/// Every `.pov` file under `dir`, sorted.
fn pov_files(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| {
            panic!(
                "{}: {e} (`make setup` installs povray-examples)",
                dir.display()
            )
        })
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            pov_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "pov") {
            out.push(path);
        }
    }
}

fn pov_examples() -> &'static [std::path::PathBuf] {
    static FILES: std::sync::OnceLock<Vec<std::path::PathBuf>> = std::sync::OnceLock::new();
    FILES.get_or_init(|| {
        let mut files = Vec::new();
        pov_files(std::path::Path::new(POV_EXAMPLES), &mut files);
        assert!(
            files.len() > 300,
            "{} examples in {POV_EXAMPLES}",
            files.len()
        );
        files
    })
}

/// Words that start or end what the reader nests, and values at its limits.
#[rustfmt::skip]
const POV_WORDS: &[&str] = &[
    "#declare", "#local", "#macro", "#end", "#while", "#for", "#if", "#else", "#switch",
    "#case", "#break", "#undef", "#ifdef", "{", "}", "<", ">", "(", ")", "[", "]", ",", ";",
    "=", "+", "-", "*", "/", "0", "-1", "1e308", "1e-308", "2147483648", "union", "difference",
    "intersection", "merge", "object", "sphere", "box", "cylinder", "quartic", "plane",
    "texture", "pigment", "color_map", "array", "rand", "bounded_by", "clipped_by", "inverse",
    "rotate", "scale", "translate", "clock", "orthographic", "mesh", "\"",
];

#[derive(Clone, Debug)]
enum PovEdit {
    Delete(f64),
    Insert(f64, usize),
    Double(f64),
    Cut(f64, usize),
}

fn pov_edit() -> impl Strategy<Value = PovEdit> {
    prop_oneof![
        (0.0..1.0f64).prop_map(PovEdit::Delete),
        (0.0..1.0f64, 0..POV_WORDS.len()).prop_map(|(at, w)| PovEdit::Insert(at, w)),
        (0.0..1.0f64).prop_map(PovEdit::Double),
        (0.0..1.0f64, 1usize..40).prop_map(|(at, n)| PovEdit::Cut(at, n)),
    ]
}

/// The text with the edits made, word by word (a word keeps the space or
/// bracket after it).
fn pov_mutated(text: &str, edits: &[PovEdit]) -> String {
    let mut words: Vec<String> = text
        .split_inclusive([' ', '\n', ',', '{', '}', '<', '>', '(', ')'])
        .map(str::to_owned)
        .collect();
    for edit in edits {
        if words.is_empty() {
            break;
        }
        let at = |f: f64| ((f * words.len() as f64) as usize).min(words.len() - 1);
        match *edit {
            PovEdit::Delete(f) => {
                words.remove(at(f));
            }
            PovEdit::Insert(f, w) => words.insert(at(f), format!("{} ", POV_WORDS[w])),
            PovEdit::Double(f) => {
                let i = at(f);
                let w = words[i].clone();
                words.insert(i, w);
            }
            PovEdit::Cut(f, n) => {
                let i = at(f);
                words.drain(i..(i + n).min(words.len()));
            }
        }
    }
    words.concat()
}

proptest! {
    #![proptest_config(fuzz_common::config(1000))]

    /// A mutated example loads, or fails as bad input naming a file; what
    /// loads renders (8×6, one thread) to finite pixels.
    #[test]
    fn fuzz_pov_examples(pick in any::<prop::sample::Index>(), edits in prop::collection::vec(pov_edit(), 1..5)) {
        let seed = pick.get(pov_examples());
        let text = String::from_utf8_lossy(&std::fs::read(seed).unwrap()).into_owned();
        let scratch = scratch("pov");
        let path = scratch.path().join("s.pov");
        std::fs::write(&path, pov_mutated(&text, &edits)).unwrap();
        let options = sturmray::scene::LoadOptions {
            size: Some((8, 6)),
            pov_include: vec![seed.parent().unwrap().to_owned()],
        };
        let loaded = Scene::load_with(&path, &options);
        let scene = loaded.as_ref().ok().cloned();
        check_load(loaded, &[".pov", ".inc"])?;
        if let Some(scene) = scene {
            let accel = Accel::build(&scene, Backend::Embree, Some(1)).map_err(fail)?;
            let options = RenderOptions { threads: Some(1), ..RenderOptions::default() };
            let out = render(&scene, &accel, &options).map_err(fail)?;
            prop_assert!(out.film.pixels.iter().all(|p| p.radiance.iter().all(|c| c.is_finite())));
        }
    }
}
