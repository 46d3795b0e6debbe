//! The scene hash: what changes it, what does not, and its golden values.

use std::path::Path;

use crate::scene::Scene;
use crate::scene::tests::{scratch, write};

fn load(dir: &Path, text: &str) -> Scene {
    Scene::load(&write(dir, "s.toml", text)).unwrap()
}

const SCENE: &str = "[render]\nspp = 4\n[[objects]]\ntype = \"sphere\"\nradius = 1\n";

#[test]
fn equal_scenes_hash_equal_and_changes_show() {
    let scratch = scratch("hash");
    let dir = scratch.path();
    let a = load(dir, SCENE).content_hash();
    assert_eq!(a.len(), 64);
    assert_eq!(a, load(dir, SCENE).content_hash());
    // More samples or another seed: the same scene.
    let more = SCENE.replace("spp = 4", "spp = 64\nseed = 3");
    assert_eq!(a, load(dir, &more).content_hash());
    // A different radius, or depth: another scene.
    assert_ne!(
        a,
        load(dir, &SCENE.replace("radius = 1", "radius = 2")).content_hash()
    );
    assert_ne!(
        a,
        load(dir, &SCENE.replace("spp = 4", "spp = 4\nmax_depth = 2")).content_hash()
    );
    // Another sampler takes other samples: a render resumed or tiled across
    // samplers would be no single render's image.
    let independent = SCENE.replace("spp = 4", "spp = 4\nsampler = \"independent\"");
    assert_ne!(a, load(dir, &independent).content_hash());
    let sobol = SCENE.replace("spp = 4", "spp = 4\nsampler = \"sobol\"");
    assert_eq!(a, load(dir, &sobol).content_hash());
    // The camera's optics: each of lens, fov axis and projection is another
    // scene, and spelling out the defaults is the same one.
    let camera = |extra: &str| {
        let text = format!(
            "{SCENE}[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nwidth = 8\nheight = 6\n{extra}\n"
        );
        load(dir, &text).content_hash()
    };
    let pinhole = camera("fov = 40");
    let variants = [
        camera("fov = 40\naperture = 0.1\nfocus_distance = 5"),
        camera("fov = 40\naperture = 0.1\nfocus_distance = 4"),
        camera("fov = 40\nfov_axis = \"x\""),
        camera("type = \"orthographic\"\nview_width = 3"),
    ];
    for (i, v) in variants.iter().enumerate() {
        assert_ne!(&pinhole, v, "variant {i}");
        assert!(variants[i + 1..].iter().all(|w| w != v), "variant {i}");
    }
    assert_eq!(
        pinhole,
        camera("fov = 40\nfov_axis = \"y\"\ntype = \"perspective\"")
    );
}

/// A scene whose every part is written out (no framing camera, no headlight),
/// so its hash depends on the loader and the serialisation alone.
const FIXED: &str = r#"
background = [0.1, 0.2, 0.3]

[camera]
eye = [0, 1, 5]
look_at = [0, 0, 0]
fov = 40
width = 64
height = 48

[render]
spp = 8
max_depth = 3
method = "sturm-bisect"

[materials.gold]
type = "plastic"
albedo = [0.9, 0.7, 0.2]

[[objects]]
type = "sphere"
radius = 0.5
material = "gold"
transform = { translate = [1, 0, 0] }

[[objects]]
type = "torus"
major = 1.0
minor = 0.25

[[lights]]
type = "point"
position = [0, 5, 0]
intensity = [10, 10, 10]
"#;

/// The golden hashes below are the point of these tests: the hash is a file
/// format contract, written into EXR attributes and film states, and `merge`
/// and `--resume` combine pieces only when it matches, so pieces rendered by
/// one build must merge with another's. It may change only when what a scene
/// renders changes (a new field in a hashed type, a loader that builds a
/// different scene), and then on purpose, with the new constant and a note.
/// Changed when `render.sampler` joined the hashed settings: the default
/// sampler became Sobol's, so every render takes other samples than the
/// builds before, and a piece or state of theirs must not merge or resume
/// with one of this build.
#[test]
fn the_hash_of_a_fixed_scene_is_golden() {
    let scratch = scratch("hash-golden");
    let dir = scratch.path();
    assert_eq!(
        load(dir, FIXED).content_hash(),
        "4700e936a972957aadfd7428f062d1eab049826fdb9eeb49ff9b3739877e3165"
    );
}

/// The same contract for a scene with an OBJ mesh (see above).
#[test]
fn the_hash_of_a_scene_with_a_mesh_is_golden() {
    let scratch = scratch("hash-golden-obj");
    let dir = scratch.path();
    write(
        dir,
        "tri.obj",
        "o tri\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n",
    );
    let text = FIXED.replace(
        "[[lights]]",
        "[[objects]]\ntype = \"mesh\"\nfile = \"tri.obj\"\nmaterial = \"gold\"\n\n[[lights]]",
    );
    assert_eq!(
        load(dir, &text).content_hash(),
        "f120d51ff659ed87cefd90d0def4b665cbfc3c2916e553086ec11449d5da0859"
    );
}

#[test]
fn fogs_and_the_hollow_shapes_they_fill_change_the_hash_and_nothing_else_does() {
    let scratch = scratch("hash-fog");
    let pov = |body: &str| {
        let text = format!("camera {{ location <0, 0, -5> look_at 0 }}\n{body}");
        Scene::load(&write(scratch.path(), "s.pov", &text))
            .unwrap()
            .content_hash()
    };
    let ball = "sphere { 0, 1 }";
    let hollow = "sphere { 0, 1 hollow }";
    let fog = "fog { distance 5 color rgb 1 }";
    // Without a fog, `hollow` changes no pixel, and no hash.
    assert_eq!(pov(ball), pov(hollow));
    // A fog changes the image, and with one, so does `hollow`.
    let fogged = pov(&format!("{ball}\n{fog}"));
    assert_ne!(pov(ball), fogged);
    assert_ne!(fogged, pov(&format!("{hollow}\n{fog}")));
    assert_ne!(fogged, pov(&format!("{ball}\n{}", fog.replace('5', "6"))));
}
