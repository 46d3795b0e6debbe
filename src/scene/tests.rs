//! Scene loading: OBJ triangulation and numbering, MTL mapping, TOML settings,
//! and the errors bad files produce.

use std::path::{Path, PathBuf};

use super::*;
use crate::math::Vec2;
use crate::shading::MaterialKind;

/// A fresh directory under the system temp dir for one test's files,
/// removed when the returned guard is dropped.
pub(super) fn scratch(test: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("sturmray-scene-{test}-"))
        .tempdir()
        .unwrap()
}

pub(super) fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn message(err: Error) -> String {
    err.to_string()
}

const QUAD_AND_PENTAGON: &str = "\
mtllib m.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0 0
vt 0 0
o first
usemtl red
f 1 2 3 4
usemtl shiny
f 2/1 5/1 3/1
o second # comments may follow a statement
f -1 -2 -3 -4 -5 # here too
";

const MTL: &str = "\
newmtl red
Kd 0.8 0.1 0.1
illum 1
newmtl shiny
Kd 0.5 0.5 0.5
Ks 0.04 0.04 0.04
Ns 100
illum 2
";

#[test]
fn objects_fans_and_materials() {
    let scratch = scratch("fans");
    let dir = scratch.path();
    write(dir, "m.mtl", MTL);
    let scene = Scene::load(&write(dir, "a.obj", QUAD_AND_PENTAGON)).unwrap();
    assert_eq!(scene.meshes.len(), 2);
    let [first, second] = &scene.meshes[..] else {
        unreachable!()
    };
    assert_eq!(first.name, "first");
    // The quad fans into (0,1,2), (0,2,3); `usemtl` does not start a new object.
    // The pentagon's corners carry a uv, so they are vertices of their own.
    assert_eq!(first.triangles, vec![[0, 1, 2], [0, 2, 3], [4, 5, 6]]);
    assert_eq!(first.positions[4], first.positions[1]);
    let kinds: Vec<_> = first
        .materials
        .iter()
        .map(|&m| scene.materials[m as usize].kind)
        .collect();
    assert_eq!(
        kinds,
        [
            MaterialKind::Diffuse,
            MaterialKind::Diffuse,
            MaterialKind::Plastic
        ]
    );
    assert_eq!(
        scene.materials[first.materials[0] as usize].albedo,
        Vec3::new(0.8, 0.1, 0.1)
    );
    // Negative indices count back: the pentagon is vertices 5, 4, 3, 2, 1 (file order).
    assert_eq!(second.name, "second");
    assert_eq!(second.triangles.len(), 3);
    assert_eq!(second.positions[0], Vec3::new(2.0, 0.0, 0.0));
    // Faces after `o second` have no usemtl... but materials persist across objects in
    // OBJ, so they keep `shiny`.
    assert_eq!(scene.materials[second.materials[0] as usize].name, "shiny");
}

#[test]
fn bare_obj_gets_camera_light_and_grey() {
    let scratch = scratch("bare");
    let dir = scratch.path();
    let path = write(dir, "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let scene = Scene::load(&path).unwrap();
    assert_eq!(scene.name, "tri");
    assert_eq!(scene.lights.len(), 1);
    assert_eq!(
        scene.materials[scene.meshes[0].materials[0] as usize],
        Material::default_grey()
    );
    let forward = (scene.camera.look_at - scene.camera.eye).normalize();
    assert!(
        forward.z < -0.5,
        "the camera looks at the mesh from the front"
    );
}

#[test]
fn degenerate_triangles_keep_their_index() {
    let scratch = scratch("degenerate");
    let dir = scratch.path();
    let path = write(
        dir,
        "d.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 1 2\nf 1 2 3\n",
    );
    let scene = Scene::load(&path).unwrap();
    assert_eq!(scene.meshes[0].triangles, vec![[0, 0, 1], [0, 1, 2]]);
    assert_eq!(load_obj(&path).unwrap().degenerate, 1);
    assert_eq!(scene.warnings.len(), 1, "{:?}", scene.warnings);
    assert!(scene.warnings[0].contains("d.obj: 1 degenerate triangle (zero area)"));
}

#[test]
fn obj_errors_name_the_line() {
    let scratch = scratch("objerr");
    let dir = scratch.path();
    let cases = [
        ("v 0 0\n", ":1: expected 3 coordinates"),
        (
            "v 0 0 0\nv 1 zero 0\n",
            ":2: expected a number, found `zero`",
        ),
        ("v 0 0 nan\n", ":1: coordinate `nan` is not a finite number"),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n",
            ":5: vertex index 4 out of range",
        ),
        ("v 0 0 0\nf 1 1\n", ":2: a face needs at least 3 vertices"),
        ("v 0 0 0\nf 1 a 1\n", ":2: expected a vertex index"),
        ("usemtl\n", ":1: expected a material name after `usemtl`"),
    ];
    for (text, expected) in cases {
        let path = write(dir, "bad.obj", text);
        let err = Scene::load(&path).unwrap_err();
        assert!(err.is_bad_input());
        let msg = message(err);
        assert!(
            msg.contains(expected) && msg.contains("bad.obj"),
            "{text:?} gave {msg}"
        );
    }
    let err = Scene::load(&dir.join("missing.obj")).unwrap_err();
    assert!(err.is_bad_input() && message(err).contains("missing.obj"));
}

/// Blender's export of a model whose library was not copied along, with
/// faces that had no material (`usemtl None`).
const BLENDER_WITHOUT_LIBRARY: &str = "\
mtllib gone.mtl
v 0 0 0
v 1 0 0
v 0 1 0
usemtl Material.001
f 1 2 3
usemtl None
f 3 2 1
usemtl Material.001
f 1 3 2
";

#[test]
fn a_missing_library_and_undefined_names_warn_once_each_and_render_grey() {
    let scratch = scratch("blender");
    let dir = scratch.path();
    let scene = Scene::load(&write(dir, "b.obj", BLENDER_WITHOUT_LIBRARY)).unwrap();
    let grey = Material::default_grey();
    for &m in &scene.meshes[0].materials {
        assert_eq!(scene.materials[m as usize], grey);
    }
    let warnings = scene.warnings.join("\n");
    assert_eq!(scene.warnings.len(), 3, "{warnings}");
    assert!(
        warnings.contains("b.obj:1: material library") && warnings.contains("gone.mtl not found"),
        "{warnings}"
    );
    // One warning per name, at the line that first used it.
    assert!(
        warnings.contains("b.obj:5: material `Material.001` is not defined"),
        "{warnings}"
    );
    assert!(
        warnings.contains("b.obj:7: material `None` is not defined"),
        "{warnings}"
    );
}

#[test]
fn a_scene_material_replaces_the_obj_material_of_its_name() {
    let scratch = scratch("override");
    let dir = scratch.path();
    write(dir, "m.mtl", MTL);
    write(dir, "a.obj", QUAD_AND_PENTAGON);
    write(dir, "b.obj", BLENDER_WITHOUT_LIBRARY);
    let scene_text = |extra: &str| {
        format!(
            "[materials.red]\ntype = \"metal\"\nalbedo = [0.9, 0.2, 0.2]\nroughness = 0.1\n\
             [materials.None]\ntype = \"diffuse\"\nalbedo = [0.1, 0.2, 0.3]\n\
             [[objects]]\ntype = \"mesh\"\nfile = \"a.obj\"\n{extra}\
             [[objects]]\ntype = \"mesh\"\nfile = \"b.obj\"\n"
        )
    };
    let scene = Scene::load(&write(dir, "s.toml", &scene_text(""))).unwrap();
    let material = |mesh: usize, triangle: usize| {
        &scene.materials[scene.meshes[mesh].materials[triangle] as usize]
    };
    // a.obj's `red` faces take the scene's `red`; `shiny` keeps the MTL's.
    assert_eq!(
        (material(0, 0).name.as_str(), material(0, 0).kind),
        ("red", MaterialKind::Metal)
    );
    assert_eq!(material(0, 1).kind, MaterialKind::Metal);
    assert_eq!(
        (material(0, 2).name.as_str(), material(0, 2).kind),
        ("shiny", MaterialKind::Plastic)
    );
    // b.obj's `usemtl None` faces take the scene's `None`, with no warning for
    // it; `Material.001` is still undefined and grey.
    assert_eq!(material(2, 1).albedo, Vec3::new(0.1, 0.2, 0.3));
    assert_eq!(*material(2, 0), Material::default_grey());
    let warnings = scene.warnings.join("\n");
    assert!(!warnings.contains("`None`"), "{warnings}");
    assert!(warnings.contains("`Material.001`"), "{warnings}");
    // An object's own `material` still replaces every one of its faces', quietly.
    let forced = Scene::load(&write(
        dir,
        "f.toml",
        &scene_text("material = \"None\"\n").replace(
            "file = \"b.obj\"\n",
            "file = \"b.obj\"\nmaterial = \"red\"\n",
        ),
    ))
    .unwrap();
    let forced_material = |mesh: usize, triangle: usize| {
        &forced.materials[forced.meshes[mesh].materials[triangle] as usize]
    };
    assert_eq!(forced_material(0, 0).name, "None");
    assert_eq!(forced_material(0, 2).name, "None");
    assert_eq!(forced_material(2, 1).name, "red");
    // (a.obj's fan has a degenerate triangle, warned as such.)
    assert!(
        forced.warnings.iter().all(|w| !w.contains("material")),
        "{:?}",
        forced.warnings
    );
}

const TOML: &str = r#"
background = [0.1, 0.2, 0.3]

[camera]
eye = [0, 0, 5]
look_at = [0, 0, 0]
fov = 30
width = 32
height = 16

[render]
spp = 3
seed = 9

[materials.gold]
type = "plastic"
albedo = [0.9, 0.7, 0.2]

[[objects]]
type = "mesh"
file = "tri.obj"
material = "gold"
transform = { translate = [1, 0, 0], rotate = [0, 0, 90], scale = 2 }

[[lights]]
type = "directional"
direction = [0, 0, -1]
irradiance = [1, 1, 1]
"#;

#[test]
fn toml_scene_settings_and_transforms() {
    let scratch = scratch("toml");
    let dir = scratch.path();
    write(dir, "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let scene = Scene::load(&write(dir, "s.toml", TOML)).unwrap();
    assert_eq!(scene.name, "s");
    assert_eq!(
        (scene.camera.width, scene.camera.height, scene.camera.fov),
        (32, 16, 30.0)
    );
    assert_eq!(
        scene.render,
        RenderSettings {
            spp: 3,
            max_depth: 5,
            seed: 9,
            min_weight: 1e-3,
            filter: crate::sampling::Filter::BOX,
            sampler: SamplerKind::Sobol,
            integrator: Integrator::Whitted,
            adaptive: None,
            photons: super::PhotonSettings::default(),
            working_gamma: super::WorkingGamma::Linear,
        }
    );
    let independent = TOML.replace("seed = 9", "seed = 9\nsampler = \"independent\"");
    let scene_b = Scene::load(&write(dir, "b.toml", &independent)).unwrap();
    assert_eq!(scene_b.render.sampler, SamplerKind::Independent);
    assert_eq!(scene.background, Vec3::new(0.1, 0.2, 0.3));
    let mesh = &scene.meshes[0];
    assert_eq!(scene.materials[mesh.materials[0] as usize].name, "gold");
    // Scale 2, rotate 90° about z, then translate by x: (1,0,0) → (0,2,0) → (1,2,0).
    assert!((mesh.positions[1] - Vec3::new(1.0, 2.0, 0.0)).length() < 1e-5);
    assert_eq!(scene.lights.len(), 1);
}

#[test]
fn toml_errors_name_line_and_suggest() {
    let scratch = scratch("tomlerr");
    let dir = scratch.path();
    write(dir, "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let cases = [
        (
            TOML.replace("fov = 30", "fvo = 30"),
            vec!["line 7", "unknown field `fvo`", "did you mean `fov`?"],
        ),
        (
            TOML.replace("spp = 3", "spp = 3\nspp = 4"),
            vec!["line 13", "duplicate key"],
        ),
        (
            TOML.replace("type = \"directional\"", "type = \"directonal\""),
            vec!["did you mean `directional`?"],
        ),
        (
            TOML.replace("spp = 3", "spp = 0"),
            vec!["line 12, render.spp"],
        ),
        (
            TOML.replace("spp = 3", "spp = 3\nsampler = \"sobl\""),
            vec![
                "line 13",
                "unknown variant `sobl`, expected `sobol` or `independent`",
                "did you mean `sobol`?",
            ],
        ),
        (
            TOML.replace(
                "spp = 3",
                "spp = 1\nadaptive = { max_spp = 8, threshold = 0.1 }",
            ),
            vec!["render.adaptive.max_spp", "at least 2"],
        ),
        (
            TOML.replace(
                "spp = 3",
                "spp = 3\nadaptive = { max_spp = 8, threshold = 0 }",
            ),
            vec!["render.adaptive.threshold", "> 0"],
        ),
        (
            TOML.replace(
                "spp = 3",
                "spp = 3\nadaptive = { max_spp = 8, treshold = 0.1 }",
            ),
            vec!["unknown field `treshold`", "did you mean `threshold`?"],
        ),
        (
            TOML.replace("fov = 30", "fov = 180"),
            vec!["line 7, camera.fov", "(0, 180)"],
        ),
        (
            TOML.replace("fov = 30", "fov = 30\naperture = 0.1"),
            vec!["camera.aperture", "focus_distance"],
        ),
        (
            TOML.replace("fov = 30", "fov = 30\naperture = -1\nfocus_distance = 2"),
            vec!["camera.aperture", "at least 0"],
        ),
        (
            TOML.replace("fov = 30", "type = \"orthographic\""),
            vec!["camera", "missing view_width"],
        ),
        (
            TOML.replace(
                "fov = 30",
                "fov = 30\ntype = \"orthographic\"\nview_width = 2",
            ),
            vec!["camera.fov", "view_width instead"],
        ),
        (
            TOML.replace("fov = 30", "fov = 30\nfov_axis = \"z\""),
            vec!["line 8", "unknown variant `z`, expected `x` or `y`"],
        ),
        (
            TOML.replace("fov = 30", "view_width = 3"),
            vec!["camera", "missing fov"],
        ),
        (
            format!(
                "{TOML}\n[[lights]]\ntype = \"spot\"\nposition = [0, 0, 1]\ndirection = [0, 0, -1]\nintensity = [1, 1, 1]\ncone_angle = 0\n"
            ),
            vec!["lights[1].cone_angle", "(0, 180]"],
        ),
        (
            format!(
                "{TOML}\n[[lights]]\ntype = \"spot\"\nposition = [0, 0, 1]\ndirection = [0, 0, -1]\nintensity = [1, 1, 1]\ncone_angle = 20\nfalloff = 25\n"
            ),
            vec!["lights[1].falloff", "cone_angle (20)"],
        ),
        (
            TOML.replace("width = 32", "width = 0"),
            vec!["camera.width"],
        ),
        (
            TOML.replace("material = \"gold\"", "material = \"gld\""),
            vec!["objects[0].material", "did you mean `gold`?"],
        ),
        (TOML.replace("tri.obj", "nope.obj"), vec!["nope.obj"]),
        (
            TOML.replace("width = 32", "width = \"wide\""),
            vec!["line 8", "invalid type"],
        ),
        (
            TOML.replace("irradiance = [1, 1, 1]", "irradiance = [1, -1, 1]"),
            vec!["lights[0].irradiance", ">= 0"],
        ),
    ];
    for (text, expected) in cases {
        let err = Scene::load(&write(dir, "bad.toml", &text)).unwrap_err();
        assert!(err.is_bad_input(), "{err}");
        let msg = message(err);
        for part in expected {
            assert!(msg.contains(part), "expected {part:?} in: {msg}");
        }
    }
    let err = Scene::load(&write(dir, "scene.txt", "")).unwrap_err();
    assert!(message(err).contains("expected a scene file ending in .toml, .obj, .ply or .pov"));
}

const SHAPES: &str = r#"
[constants]
R = 1.0

[[objects]]
type = "torus"
major = 1.0
minor = 0.25

[[objects]]
type = "algebraic"
expr = "x^2 + y^2 + z^2 - R^2"
clip = { min = [-2, -2, -2], max = [2, 2, 2] }
transform = { translate = [3, 0, 0] }
"#;

#[test]
fn analytic_objects_load_as_one_geometry_after_the_meshes() {
    let scratch = scratch("shapes");
    let dir = scratch.path();
    let scene = Scene::load(&write(dir, "s.toml", SHAPES)).unwrap();
    assert_eq!(scene.shapes.len(), 2);
    assert_eq!(
        scene.shapes_geom_id(),
        0,
        "no meshes: the shapes are geometry 0"
    );
    // Framed automatically: the bounds hold both shapes, the algebraic
    // sphere's by its own points (to x = 4), not its clip box (to x = 5).
    let b = scene.bounds();
    assert!(b.min.x <= -1.25 && b.max.x >= 4.0 && b.max.x < 4.1, "{b:?}");
}

#[test]
fn analytic_object_errors_name_line_key_and_column() {
    let scratch = scratch("shapeerr");
    let dir = scratch.path();
    let cases = [
        (
            SHAPES.replace("x^2 + y^2", "x^2 + * y^2"),
            vec!["line 12, objects[1].expr: column 7"],
        ),
        (
            SHAPES.replace("minor = 0.25", "minor = -0.25"),
            vec!["objects[0]", "minor", "> 0"],
        ),
        (
            SHAPES.replace("minor = 0.25", "minor = 0.25\nradius = 2"),
            vec!["`radius` does not apply"],
        ),
        (
            SHAPES.replace("clip = { min = [-2, -2, -2], max = [2, 2, 2] }\n", ""),
            vec!["needs a clip box"],
        ),
        (SHAPES.replace("R^2", "Q^2"), vec!["unknown name 'Q'"]),
        (
            SHAPES.replace("\"torus\"", "\"torsu\""),
            vec!["did you mean `torus`?"],
        ),
        (
            SHAPES.replace("major = 1.0", "majr = 1.0"),
            vec!["did you mean `major`?"],
        ),
    ];
    for (text, expected) in cases {
        let err = Scene::load(&write(dir, "bad.toml", &text)).unwrap_err();
        assert!(err.is_bad_input(), "{err}");
        let msg = message(err);
        for part in expected {
            assert!(msg.contains(part), "expected {part:?} in: {msg}");
        }
    }
}

const LIT: &str = r#"
[materials.brushed]
type = "metal"
albedo = [0.9, 0.6, 0.3]
roughness = 0.5

[materials.glow]
type = "emissive"
radiance = [2, 2, 2]

[[objects]]
type = "sphere"
radius = 0.5
material = "glow"
transform = { translate = [0, 2, 0], scale = 2 }

[[objects]]
type = "sphere"
radius = 0.5
material = "glow"
clip = { min = [-1, -1, 0], max = [1, 1, 1] }

[[objects]]
type = "torus"
major = 1.0
minor = 0.1
material = "glow"

[[objects]]
type = "sphere"
radius = 0.5
material = "brushed"
transform = { translate = [3, 0, 0] }

[[lights]]
type = "quad"
corner = [0, 3, 0]
edge1 = [1, 0, 0]
edge2 = [0, 0, 1]
radiance = [1, 1, 1]

[[lights]]
type = "point"
position = [0, 5, 0]
intensity = [1, 1, 1]
"#;

#[test]
fn emissive_geometry_becomes_sampled_lights() {
    let scratch = scratch("lit");
    let dir = scratch.path();
    let scene = Scene::load(&write(dir, "s.toml", LIT)).unwrap();
    let metal = scene
        .materials
        .iter()
        .find(|m| m.name == "brushed")
        .unwrap();
    assert_eq!((metal.kind, metal.roughness), (MaterialKind::Metal, 0.5));
    // The point light first, then the quad's two triangles, then the one whole
    // sphere (scaled by 2: radius 1). The clipped sphere and the torus emit but
    // have no area sampling.
    assert!(matches!(scene.lights[0], Light::Point { .. }));
    assert!(matches!(scene.lights[1], Light::Triangle { .. }));
    assert!(matches!(scene.lights[2], Light::Triangle { .. }));
    match scene.lights[3] {
        Light::Sphere { center, radius, .. } => {
            assert!((center - Vec3::new(0.0, 2.0, 0.0)).length() < 1e-6);
            assert!((radius - 1.0).abs() < 1e-6);
        }
        ref other => panic!("{other:?}"),
    }
    assert_eq!(scene.lights.len(), 4);
    assert_eq!(scene.unsampled_emitters(), 2);
    // Hits on light geometry find their light.
    let quad_mesh = scene.meshes.len() as u32 - 1;
    assert_eq!(scene.light_picker.light_of(quad_mesh, 1).unwrap().0, 2);
    assert_eq!(
        scene
            .light_picker
            .light_of(scene.shapes_geom_id(), 0)
            .unwrap()
            .0,
        3
    );
    assert_eq!(scene.light_picker.light_of(scene.shapes_geom_id(), 1), None);

    let bad = LIT.replace("roughness = 0.5", "roughness = 1.5");
    let msg = message(Scene::load(&write(dir, "bad.toml", &bad)).unwrap_err());
    assert!(msg.contains("materials.brushed.roughness"), "{msg}");
}

#[test]
fn normals_and_texture_coordinates_follow_each_corner() {
    let scratch = scratch("attributes");
    let dir = scratch.path();
    // Two triangles sharing the edge 2-3: the same positions, but the second
    // has its own normal at vertex 2 (a crease) and no uv anywhere; a third
    // triangle has neither.
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n\
                vn 0 0 1\nvn 0 0 2\nvt 0 0\nvt 1 0 0.5\nvt 0.25\n\
                f 1/1/1 2/2/1 3/3/1\nf 2//2 4//1 3//1\nf 1 2 4\n";
    let mesh = &load_obj(&write(dir, "a.obj", text)).unwrap().meshes[0];
    // Nine distinct (v, vt, vn) triples, so nine vertices: a position with
    // another normal or uv, or with none, is another vertex.
    assert_eq!(mesh.positions.len(), 9);
    assert_eq!(mesh.normals.len(), 9);
    assert_eq!(mesh.uvs.len(), 9);
    assert_eq!(mesh.triangles, vec![[0, 1, 2], [3, 4, 5], [6, 7, 8]]);
    assert_eq!(
        mesh.uvs[..3],
        [
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(0.25, 0.0)
        ]
    );
    assert_eq!(mesh.normals[3], Vec3::new(0.0, 0.0, 2.0));
    // Interpolated: unit length; flat (None) where a corner has no normal.
    assert_eq!(mesh.shading_normal(1, 0.3, 0.3), Some(Vec3::Z));
    assert_eq!(mesh.shading_normal(2, 0.3, 0.3), None);
    assert_eq!(mesh.uv(0, 0.5, 0.5), Some(Vec2::new(0.625, 0.0)));
    // A transform moves normals by the inverse transpose: a stretch along x
    // tilts a 45° normal towards x less.
    let mut tilted = Mesh {
        normals: vec![Vec3::new(1.0, 0.0, 1.0)],
        positions: vec![Vec3::ZERO],
        ..Mesh::default()
    };
    tilted.transform(&crate::math::Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0)));
    assert_eq!(tilted.normals[0], Vec3::new(0.5, 0.0, 1.0));
}

#[test]
fn bad_normal_and_texture_references_name_the_line() {
    let scratch = scratch("attrerr");
    let dir = scratch.path();
    for (text, expected) in [
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n",
            ":4: normal index 1 out of range",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/2 2/1 3/1\n",
            ":5: texture coordinate index 2",
        ),
        (
            "vn 0 nan 1\n",
            ":1: coordinate `nan` is not a finite number",
        ),
        ("vn 0 1\n", ":1: expected 3 coordinates after `vn`, found 2"),
        ("vt\n", ":1: expected 1 coordinates after `vt`, found 0"),
        ("v 0 0 0\nf 1/1/1/1 1 1\n", ":2: expected a face corner"),
        (
            "v 0 0 0\nf 1/x 1 1\n",
            ":2: expected a texture coordinate index in face",
        ),
    ] {
        let err = Scene::load(&write(dir, "bad.obj", text)).unwrap_err();
        assert!(err.is_bad_input());
        let msg = message(err);
        assert!(msg.contains(expected), "{text:?} gave {msg}");
    }
}
