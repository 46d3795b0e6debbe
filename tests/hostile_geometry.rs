//! Hostile rays, cameras and sizes (issue 14): rays Embree would assert on
//! are refused by index, cameras that would make such rays are refused by key,
//! every backend answers alike for any valid direction length, a panicking
//! builder is an error, and a scene at the coordinate limit renders as the
//! same scene at unit size does.

mod common;

use std::path::Path;

use common::{SQUARE, plane_scene, scratch, sturmray, write};
use sturmray::accel::{Accel, Backend};
use sturmray::geometry::Mesh;
use sturmray::math::{Ray, Vec3};
use sturmray::render::{RenderOptions, render};
use sturmray::scene::{Camera, Integrator, RenderSettings, Scene};
use sturmray::shading::Material;

const BACKENDS: [&str; 3] = ["embree", "obvhs", "bvh"];

/// The loaders' coordinate limit (`MAX_COORDINATE`), as the messages state it.
const LIMIT: f32 = 1e9;

/// Writes rays as a little-endian float32 .npy of shape (N, 6) or (N, 8).
fn write_rays(dir: &Path, name: &str, rows: &[Vec<f32>]) {
    let cols = rows[0].len();
    let mut header = format!(
        "{{'descr': '<f4', 'fortran_order': False, 'shape': ({}, {cols}), }}",
        rows.len()
    );
    while (header.len() + 11) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend((header.len() as u16).to_le_bytes());
    bytes.extend(header.as_bytes());
    for v in rows.iter().flatten() {
        bytes.extend(v.to_le_bytes());
    }
    std::fs::write(dir.join(name), bytes).unwrap();
}

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Exit code 2 (not a signal, not a panic) with every one of `words` in the message.
fn assert_refused(out: &std::process::Output, words: &[&str], what: &str) {
    let text = stderr(out);
    assert_eq!(out.status.code(), Some(2), "{what}: {text}");
    for word in words {
        assert!(text.contains(word), "{what}: {word:?} not in {text:?}");
    }
    assert!(!text.contains("panicked"), "{what}: {text}");
}

#[test]
fn trace_refuses_rays_beyond_embrees_limit_by_index_on_every_backend() {
    let dir = scratch("hostile-rays");
    write(&dir, "square.obj", SQUARE);
    write(&dir, "s.toml", &plane_scene(""));
    let good = vec![0.5, 0.5, 1.0, 0.0, 0.0, -1.0];
    let bad: [(&str, Vec<f32>); 4] = [
        ("origin", vec![0.0, 0.0, 2e18, 0.0, 0.0, -1.0]),
        ("origin", vec![-1.9e18, 0.0, 1.0, 1.0, 0.0, 0.0]),
        ("direction", vec![0.0, 0.0, 1.0, 0.0, 0.0, -2e18]),
        ("direction", vec![0.0, 0.0, 1.0, 1e-5, 1e-39, -3e38]),
    ];
    for backend in BACKENDS {
        let trace = || {
            let args = ["trace", "s.toml", "--rays", "r.npy", "--out", "h.npy"];
            sturmray(&dir, &[&args[..], &["--backend", backend]].concat())
        };
        for (i, (word, row)) in bad.iter().enumerate() {
            write_rays(&dir, "r.npy", &[good.clone(), good.clone(), row.clone()]);
            let _ = std::fs::remove_file(dir.join("h.npy"));
            let out = trace();
            let what = format!("{backend}, bad ray {i}");
            assert_refused(&out, &["r.npy", "ray 2", word, "1.844e18"], &what);
            assert!(!dir.join("h.npy").exists(), "{what}: an output was written");
        }
        // At Embree's limit itself every backend traces, and the first ray hits.
        let edge = vec![1.8e18, 0.0, 1.0, -1.8e18, 0.0, -1.8e18];
        write_rays(&dir, "r.npy", &[good.clone(), edge]);
        let out = trace();
        assert!(out.status.success(), "{backend}: {}", stderr(&out));
    }
}

/// The plane scene with its camera's eye and look_at lines replaced by
/// `view` (lines 3 and 4) and `keys` after its other camera lines (from line 8).
fn camera_scene(view: &str, keys: &str) -> String {
    plane_scene("")
        .replace(
            "eye = [0, 0, 4]\nlook_at = [0, 0, 0]\n",
            &format!("{view}\n"),
        )
        .replace("height = 24\n", &format!("height = 24\n{keys}\n"))
}

#[test]
fn camera_paths_that_look_along_up_or_through_the_eye_are_refused_by_key() {
    let dir = scratch("hostile-keys");
    write(&dir, "square.obj", SQUARE);
    // Keys are interpolated linearly: between these two the view direction
    // (1, 1, 0) → (−1, 1, 0) passes (0, 1, 0) = up, at frame 1; with frame 3 it
    // passes between frames 1 and 2, which is refused all the same.
    let view = "eye = [0, 0, 4]\nlook_at = [0, 0, 0]";
    let along_up = "[[camera.keys]]\nframe = 0\neye = [-1, -1, 0]\nlook_at = [0, 0, 0]\n\
        [[camera.keys]]\nframe = LAST\neye = [1, -1, 0]\nlook_at = [0, 0, 0]";
    // The eye and look_at swap places: at frame 1 they coincide.
    let through = "[[camera.keys]]\nframe = 0\neye = [0, 0, -1]\nlook_at = [0, 0, 1]\n\
        [[camera.keys]]\nframe = LAST\neye = [0, 0, 1]\nlook_at = [0, 0, -1]";
    for (keys, word) in [(along_up, "camera.up"), (through, "eye and look_at")] {
        for last in ["2", "3"] {
            write(
                &dir,
                "s.toml",
                &camera_scene(view, &keys.replace("LAST", last)),
            );
            for command in [
                &["render", "s.toml", "--frame", "1"][..],
                &["info", "s.toml"],
            ] {
                let out = sturmray(&dir, command);
                let what = format!("{word}, last frame {last}, {command:?}");
                assert_refused(&out, &["s.toml", "line 12, camera.keys[1]", word], &what);
            }
        }
    }
}

#[test]
fn a_camera_a_hair_from_its_target_renders_or_is_refused_never_aborts() {
    let dir = scratch("hostile-eye");
    write(&dir, "square.obj", SQUARE);
    // 1e-20 away: the view direction's squared length underflows f32, which
    // made NaN rays; the direction is well defined, so the render goes on.
    write(
        &dir,
        "s.toml",
        &camera_scene("eye = [0, 0, 1e-20]\nlook_at = [0, 0, 0]", ""),
    );
    let out = sturmray(&dir, &["render", "s.toml", "-o", "a.exr"]);
    assert!(out.status.success(), "{}", stderr(&out));
    // One float apart at 1: the view direction would be rounding noise.
    write(
        &dir,
        "s.toml",
        &camera_scene("eye = [1, 1, 1]\nlook_at = [1, 1, 1.0000001]", ""),
    );
    let out = sturmray(&dir, &["render", "s.toml", "-o", "b.exr"]);
    assert_refused(
        &out,
        &["s.toml", "line 4, camera.look_at"],
        "one float apart",
    );
}

/// The unit square (two triangles) in z = 0 as a scene of its own.
fn square_scene(half: f32) -> Scene {
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    Scene {
        name: "square".into(),
        camera: Camera::default(),
        render: RenderSettings::default(),
        background: Vec3::ZERO,
        environment: None,
        fogs: Vec::new(),
        materials: vec![Material::default_grey()],
        meshes: vec![Mesh {
            name: "square".into(),
            positions: corners
                .iter()
                .map(|&(x, y)| Vec3::new(x * half, y * half, 0.0))
                .collect(),
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            materials: vec![0, 0],
            ..Mesh::default()
        }],
        shapes: Vec::new(),
        prototypes: Vec::new(),
        instances: Vec::new(),
        lights: Vec::new(),
        light_picker: Default::default(),
        warnings: Vec::new(),
        sources: Vec::new(),
        import: None,
    }
}

#[test]
fn every_backend_hits_alike_for_tiny_and_huge_directions() {
    let scene = square_scene(1.0);
    let accels: Vec<Accel> = Backend::ALL
        .iter()
        .map(|&b| Accel::build(&scene, b, Some(1)).unwrap())
        .collect();
    // Straight down onto triangle 0, and obliquely onto triangle 1, from 2 away.
    let paths = [
        (Vec3::new(0.5, -0.25, 2.0), Vec3::new(0.0, 0.0, -1.0), 0),
        (
            Vec3::new(-0.5, 1.0, 2.0),
            Vec3::new(0.1, -0.5, -2.0).normalize(),
            1,
        ),
    ];
    for (origin, unit_dir, prim) in paths {
        let distance = origin.z / -unit_dir.z;
        for length in [1e-30f32, 1e-20, 1e-10, 1.0, 1e10] {
            let ray = Ray::new(origin, unit_dir * length);
            assert_eq!(ray.problem(), None);
            for accel in &accels {
                let what = format!("{} at length {length:e}", accel.describe());
                let hit = accel.intersect(&ray);
                assert_eq!((hit.geom_id, hit.prim_id), (0, prim), "{what}: {hit:?}");
                let t = hit.t * length;
                assert!(
                    (t - distance).abs() <= 1e-5 * distance,
                    "{what}: t·|d| = {t}, expected {distance}"
                );
                assert!(accel.occluded(&ray), "{what}: not occluded");
                let short = Ray {
                    tfar: 0.99 * distance / length,
                    ..ray
                };
                assert!(!accel.intersect(&short).is_hit(), "{what}: hit before tfar");
                assert!(!accel.occluded(&short), "{what}: occluded before tfar");
                accel.check().unwrap();
            }
        }
    }
}

#[test]
fn obvhs_refuses_a_scene_too_large_for_it_instead_of_panicking() {
    // obvhs's builder overflows its f32 costs and panics (index out of bounds)
    // on a scene 2e19 across; scenes from files cannot get there, a library
    // caller can.
    let scene = square_scene(1e19);
    let error = Accel::build(&scene, Backend::Obvhs, Some(1)).err().unwrap();
    assert!(error.is_bad_input(), "{error}");
    assert!(error.to_string().contains("obvhs"), "{error}");
    // The other two build it (their arithmetic does not overflow there).
    for backend in [Backend::Embree, Backend::Bvh] {
        Accel::build(&scene, backend, Some(1)).unwrap();
    }
}

#[test]
fn geometry_beyond_the_limit_in_world_space_is_refused_by_object() {
    let dir = scratch("hostile-bounds");
    // Each coordinate is within the limit, scaled it is not.
    write(
        &dir,
        "square.obj",
        "v -1e9 -1e9 0\nv 1e9 -1e9 0\nv 1e9 1e9 0\nv -1e9 1e9 0\nf 1 2 3 4\n",
    );
    let scaled = plane_scene("").replace(
        "material = \"paint\"\n[[lights]]",
        "material = \"paint\"\ntransform = { scale = 2 }\n[[lights]]",
    );
    write(&dir, "s.toml", &scaled);
    let out = sturmray(&dir, &["render", "s.toml"]);
    assert_refused(&out, &["s.toml", "objects[0]", "2e9", "1e9"], "scaled mesh");
    let sphere = plane_scene(
        "[[objects]]\ntype = \"sphere\"\nradius = 1e9\ntransform = { translate = [1e9, 0, 0] }\n",
    );
    write(&dir, "s.toml", &sphere);
    let out = sturmray(&dir, &["render", "s.toml"]);
    assert_refused(&out, &["s.toml", "objects[1]", "1e9"], "moved sphere");
    // A bare OBJ past the limit is refused; at it, the framing camera sees it
    // with finite distances (t = inf hits came from f32 overflow beyond 1e12).
    write(
        &dir,
        "big.obj",
        "v -1e13 -1e13 0\nv 1e13 -1e13 0\nv 1e13 1e13 0\nf 1 2 3\n",
    );
    let out = sturmray(&dir, &["explain", "big.obj", "--pixel", "320,240"]);
    assert_refused(&out, &["big.obj:1", "1e9"], "a bare OBJ 1e13 across");
    let out = sturmray(&dir, &["explain", "square.obj", "--pixel", "320,240"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(text.contains("camera") && text.contains("mesh"), "{text}");
    assert!(!text.contains("inf") && !text.contains("NaN"), "{text}");
}

/// A diffuse ground square with a sphere on it (a unit sphere, scaled: one
/// written with `radius = 8e7` vanishes today, as the analytic intersector
/// trims Q(s)'s s² term against its constant term, a bug of that code), a smaller mirror square
/// floating over it that shades part of it, a quad light facing down, a point
/// light and a directional light, all scaled by `s`: radiance and irradiance
/// do not change with scale (the point light's intensity grows by s²), so
/// neither should the image.
fn shadow_scene(dir: &Path, s: f32, integrator: &str) -> Scene {
    let p = |v: [f32; 3]| format!("[{:e}, {:e}, {:e}]", v[0] * s, v[1] * s, v[2] * s);
    let obj = |name: &str, half: f32, z: f32| {
        let text: String = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .iter()
            .map(|&(x, y)| format!("v {:e} {:e} {:e}\n", x * half * s, y * half * s, z * s))
            .collect();
        write(dir, name, &format!("{text}f 1 2 3 4\n"));
    };
    obj("ground.obj", 0.5, 0.0);
    obj("blocker.obj", 0.1, 0.2);
    let toml = format!(
        r#"background = [0.1, 0.2, 0.3]
[camera]
eye = {}
look_at = [0, 0, 0]
fov = 50
width = 24
height = 24
[render]
spp = 2
max_depth = 3
integrator = "{integrator}"
photons = {{ count = 0 }}
[materials.paint]
type = "diffuse"
albedo = [0.6, 0.5, 0.4]
[materials.mirror]
type = "mirror"
albedo = [0.9, 0.9, 0.9]
[[objects]]
type = "mesh"
file = "ground.obj"
material = "paint"
[[objects]]
type = "mesh"
file = "blocker.obj"
material = "mirror"
[[objects]]
type = "sphere"
radius = 1
transform = {{ scale = {:e}, translate = {} }}
material = "paint"
# Written at scene size, not scaled from unit size: the ray polynomial's
# terms then differ by s^2, which must not make any of them negligible.
[[objects]]
type = "sphere"
radius = {:e}
transform = {{ translate = {} }}
material = "paint"
[[objects]]
type = "torus"
major = {:e}
minor = {:e}
transform = {{ translate = {} }}
material = "paint"
[[lights]]
type = "point"
position = {}
intensity = [{:e}, {:e}, {:e}]
[[lights]]
type = "quad"
corner = {}
edge1 = {}
edge2 = {}
radiance = [20, 20, 20]
[[lights]]
type = "directional"
direction = [0.2, 0.1, -1]
irradiance = [0.5, 0.5, 0.5]
"#,
        p([0.1, -0.3, 1.0]),
        0.08 * s,
        p([-0.25, 0.2, 0.08]),
        0.06 * s,
        p([0.25, 0.2, 0.06]),
        0.07 * s,
        0.02 * s,
        p([0.2, -0.25, 0.02]),
        p([-0.3, -0.2, 0.5]),
        0.1 * s * s,
        0.1 * s * s,
        0.1 * s * s,
        p([0.0, 0.05, 0.6]),
        p([0.0, 0.1, 0.0]),
        p([0.1, 0.0, 0.0]),
    );
    let path = write(dir, "s.toml", &toml);
    Scene::load(&path).unwrap()
}

#[test]
fn a_scene_at_the_coordinate_limit_renders_as_at_unit_size() {
    let options = RenderOptions {
        threads: Some(2),
        ..RenderOptions::default()
    };
    for integrator in ["whitted", "path"] {
        let dir = scratch(&format!("hostile-limit-{integrator}"));
        let image = |s: f32, backend| {
            let scene = shadow_scene(&dir, s, integrator);
            assert_eq!(
                scene.render.integrator == Integrator::Path,
                integrator == "path"
            );
            let accel = Accel::build(&scene, backend, Some(2)).unwrap();
            let out = render(&scene, &accel, &options).unwrap();
            assert_eq!(out.nonfinite, 0);
            out.film.layers().beauty
        };
        let reference = image(1.0, Backend::Embree);
        let values: Vec<f32> = reference.iter().map(|p| p[0]).collect();
        let (dark, bright) = values.iter().fold((f32::INFINITY, 0.0f32), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
        assert!(
            bright > 3.0 * dark.max(0.05),
            "no contrast: {dark}..{bright}"
        );
        for s in [LIMIT, 0.999 * LIMIT] {
            for backend in Backend::ALL {
                let other = image(s, backend);
                let mut off = 0;
                for (a, b) in reference.iter().zip(&other) {
                    let (a, b) = (Vec3::from(*a), Vec3::from(*b));
                    assert!(b.is_finite(), "{integrator} at {s:e}, {backend:?}: {b}");
                    let bad = (a - b).abs().max_element() > 1e-3 * a.max_element().max(1.0);
                    off += usize::from(bad);
                }
                // Paths are random walks: a hit point rounded differently at a different
                // scale may take another branch of Russian roulette in a pixel or two.
                let allowed = if integrator == "path" {
                    reference.len() / 50
                } else {
                    0
                };
                assert!(
                    off <= allowed,
                    "{integrator} at {s:e}, {}: {off} pixels differ from the unit scene",
                    backend.name()
                );
            }
        }
    }
}
