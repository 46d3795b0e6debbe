//! Instances trace and render as the flattened scene does, on every backend:
//! the same scene written once with `[prototypes.thing]` placed by three
//! instances (one mirrored, one with its own material, one scaled unevenly),
//! and once with each copy spelled out as objects of its own.

mod common;

use common::{scratch, write};
use sturmray::accel::{Accel, Backend};
use sturmray::math::{Hit, INVALID_ID, Ray, Vec3};
use sturmray::render::{RenderOptions, render};
use sturmray::scene::Scene;

/// A tetrahedron, closed, so a mirrored copy shows which way its normals
/// turn, with vertex normals, so its shading normals go through the
/// instance's transform too.
const TETRA: &str = "v 0 0.6 0\nv -0.5 -0.3 0.4\nv 0.5 -0.3 0.4\nv 0 -0.3 -0.5\n\
                     vn 0 1 0\nvn -0.5 -0.3 0.4\nvn 0.5 -0.3 0.4\nvn 0 -0.3 -0.5\n\
                     f 1//1 2//2 3//3\nf 1//1 3//3 4//4\nf 1//1 4//4 2//2\nf 2//2 4//4 3//3\n";

const HEAD: &str = r#"[camera]
eye = [0, 3, 9]
look_at = [0, 0, 0]
fov = 35
width = 64
height = 48
[render]
spp = 1
[materials.floor]
type = "diffuse"
albedo = [0.6, 0.6, 0.5]
[materials.red]
type = "plastic"
albedo = [0.8, 0.1, 0.1]
[[lights]]
type = "point"
position = [3, 6, 5]
intensity = [60, 60, 60]
[[lights]]
type = "directional"
direction = [-1, -2, -1]
irradiance = [0.5, 0.5, 0.5]
[[objects]]
type = "box"
min = [-6, -2, -6]
max = [6, -1.6, 6]
material = "floor"
"#;

/// The prototype's objects, each placed only by a translation along y,
/// which an instance's transform T·R·S moves to T + R·S·a = T + (0, s_y·a_y, 0)
/// when R turns about y: so the flattened copies can be written in TOML.
const PARTS: [(&str, f64); 3] = [
    (
        r#"type = "mesh"
file = "tetra.obj""#,
        0.0,
    ),
    (
        r#"type = "torus"
major = 0.6
minor = 0.2"#,
        1.2,
    ),
    (
        r#"type = "sphere"
radius = 0.3"#,
        -1.0,
    ),
];

/// An instance: translation, rotation about y (degrees), scale, material.
type Place = ([f64; 3], f64, [f64; 3], Option<&'static str>);

const PLACES: [Place; 3] = [
    ([-2.5, 0.0, 0.0], 37.0, [0.8, 0.8, 0.8], None),
    ([0.0, 0.0, 0.0], -20.0, [-1.0, 1.0, 1.0], Some("red")),
    ([2.5, 0.5, -1.0], 0.0, [1.0, 0.5, 1.5], None),
];

fn material(m: Option<&str>) -> String {
    m.map_or(String::new(), |m| format!("material = \"{m}\"\n"))
}

fn instanced() -> String {
    let mut text = HEAD.to_owned();
    for (part, y) in PARTS {
        text += &format!(
            "[[prototypes.thing.objects]]\n{part}\ntransform = {{ translate = [0, {y}, 0] }}\n"
        );
    }
    for (t, r, s, m) in PLACES {
        text += &format!(
            "[[objects]]\ntype = \"instance\"\nprototype = \"thing\"\n{}\
             transform = {{ translate = {t:?}, rotate = [0, {r}, 0], scale = {s:?} }}\n",
            material(m)
        );
    }
    text
}

fn flattened() -> String {
    let mut text = HEAD.to_owned();
    for (t, r, s, m) in PLACES {
        for (part, y) in PARTS {
            let t = [t[0], t[1] + s[1] * y, t[2]];
            text += &format!(
                "[[objects]]\n{part}\n{}\
                 transform = {{ translate = {t:?}, rotate = [0, {r}, 0], scale = {s:?} }}\n",
                material(m)
            );
        }
    }
    text
}

fn scenes() -> (Scene, Scene) {
    let dir = scratch("instances");
    write(dir.as_ref(), "tetra.obj", TETRA);
    let load = |name: &str, text: &str| {
        Scene::load(&write(dir.as_ref(), name, text)).unwrap_or_else(|e| panic!("{name}: {e}"))
    };
    (load("i.toml", &instanced()), load("f.toml", &flattened()))
}

/// What an instanced hit should say, from the flattened scene's hit: the
/// instance, and the prototype's geometry and primitive. The flattened scene
/// has one mesh per copy (geometry k is copy k's tetrahedron) and its shapes
/// in the fourth geometry: the floor, then each copy's torus and sphere. The
/// instanced scene has no meshes of its own, so its floor is geometry 0;
/// the prototype's shapes are its geometry 1.
fn expected_ids(flat: &Hit) -> (u32, u32, u32) {
    match (flat.geom_id, flat.prim_id) {
        (g, p) if g < 3 => (g, 0, p),
        (3, 0) => (INVALID_ID, 0, 0),
        (3, p) => ((p - 1) / 2, 1, (p - 1) % 2),
        other => panic!("unexpected flattened hit {other:?}"),
    }
}

fn camera_rays(scene: &Scene) -> Vec<Ray> {
    let frame = scene.camera.frame();
    let (w, h) = (scene.camera.width, scene.camera.height);
    (0..w * h)
        .map(|i| frame.ray((i % w) as f32 + 0.5, (i / w) as f32 + 0.5))
        .collect()
}

fn build(scene: &Scene, backend: Backend) -> Accel {
    Accel::build(scene, backend, Some(2)).unwrap()
}

#[test]
fn instances_hit_as_the_flattened_copies_on_every_backend() {
    let (inst, flat) = scenes();
    assert_eq!((inst.instances.len(), inst.prototypes.len()), (3, 1));
    let rays = camera_rays(&inst);
    for backend in Backend::ALL {
        let (a, b) = (build(&inst, backend), build(&flat, backend));
        let (mut hits, mut on_instances, mut edges) = (0, [0; 3], 0);
        for (i, ray) in rays.iter().enumerate() {
            let (h, f) = (a.intersect(ray), b.intersect(ray));
            let what = format!(
                "{}: ray {i}: instanced {h:?}, flattened {f:?}",
                backend.name()
            );
            assert_eq!(a.occluded(ray), b.occluded(ray), "{what}");
            if h.is_hit() != f.is_hit() {
                // A ray that grazes a silhouette may pass on one side of the
                // rounding (the instance's ray is moved in f32) and not the
                // other: counted, and bounded below.
                edges += 1;
                continue;
            }
            if !h.is_hit() {
                continue;
            }
            hits += 1;
            let (n, m) = (h.ng.normalize(), f.ng.normalize());
            if (h.t - f.t).abs() > 1e-3 * f.t || n.dot(m) < 0.999 {
                edges += 1;
                continue;
            }
            assert_eq!(
                (h.inst_id, h.geom_id, h.prim_id),
                expected_ids(&f),
                "{what}"
            );
            assert_eq!(inst.material_of(&h), flat.material_of(&f), "{what}");
            if let Some(count) = on_instances.get_mut(h.inst_id as usize) {
                *count += 1;
            }
            let (p, q) = (inst.interaction(ray, &h), flat.interaction(ray, &f));
            assert!(p.p.distance(q.p) <= 1e-3 * q.p.length().max(1.0), "{what}");
            assert_eq!(p.front, q.front, "{what}: the mirrored winding");
            assert!(p.ns.dot(q.ns) > 0.999, "{what}: {} vs {}", p.ns, q.ns);
        }
        // Every instance is seen, by many rays.
        assert!(on_instances.iter().all(|&n| n > 40), "{on_instances:?}");
        assert!(hits > rays.len() / 2, "{hits} hits");
        // At most a few silhouette rays in 3072 (measured: none on any backend).
        assert!(edges <= 3, "{}: {edges} rays differ", backend.name());
        a.check().unwrap();
    }
}

#[test]
fn instances_render_as_the_flattened_scene_on_every_backend() {
    let (inst, flat) = scenes();
    let options = RenderOptions {
        threads: Some(2),
        ..RenderOptions::default()
    };
    for backend in Backend::ALL {
        let image = |scene: &Scene| {
            let out = render(scene, &build(scene, backend), &options).unwrap();
            out.film.layers().beauty
        };
        let (a, b) = (image(&inst), image(&flat));
        let mut differ = 0;
        for (x, y) in a.iter().zip(&b) {
            let d = x
                .iter()
                .zip(y)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f32::max);
            let scale = y.iter().copied().fold(1.0, f32::max);
            if d > 1e-3 * scale {
                differ += 1;
            }
        }
        // The same samples on the same surfaces: only pixels where a sample
        // grazes a silhouette (or a shadow's edge) may differ; measured: none
        // of the 3072 on any backend.
        assert!(
            differ <= 3,
            "{}: {differ} of {} pixels differ",
            backend.name(),
            a.len()
        );
        let lit = a.iter().filter(|p| p.iter().sum::<f32>() > 0.0).count();
        assert!(lit > a.len() / 2, "{lit} lit pixels");
    }
}

#[test]
fn embree_holds_a_prototype_once_however_many_instances_place_it() {
    // A 2,000-triangle grid placed 100 times, against the 100 copies flattened.
    let dir = scratch("instances-memory");
    let mut obj = String::new();
    for j in 0..=20 {
        for i in 0..=50 {
            obj += &format!(
                "v {} {} {}\n",
                i as f32 * 0.02,
                j as f32 * 0.05,
                (i * j % 7) as f32 * 0.01
            );
        }
    }
    for j in 0..20 {
        for i in 0..50 {
            let a = j * 51 + i + 1;
            obj += &format!("f {} {} {} {}\n", a, a + 1, a + 52, a + 51);
        }
    }
    write(dir.as_ref(), "grid.obj", &obj);
    let place = |k: usize| {
        format!(
            "transform = {{ translate = [{}, {}, 0] }}\n",
            k % 10,
            k / 10
        )
    };
    let mut inst = "[[prototypes.grid.objects]]\ntype = \"mesh\"\nfile = \"grid.obj\"\n".to_owned();
    let mut flat = String::new();
    for k in 0..100 {
        inst += &format!(
            "[[objects]]\ntype = \"instance\"\nprototype = \"grid\"\n{}",
            place(k)
        );
        flat += &format!(
            "[[objects]]\ntype = \"mesh\"\nfile = \"grid.obj\"\n{}",
            place(k)
        );
    }
    let bytes = |name: &str, text: &str| {
        let scene = Scene::load(&write(dir.as_ref(), name, text)).unwrap();
        build(&scene, Backend::Embree).memory_bytes()
    };
    let (inst, flat) = (bytes("i.toml", &inst), bytes("f.toml", &flat));
    // One copy and 100 small records against 100 copies: measured 0.012
    // (176,248 against 15,044,320 bytes).
    assert!(
        (inst as f64) < 0.05 * flat as f64,
        "instanced {inst} bytes, flattened {flat} bytes"
    );
}

#[test]
fn each_instances_checker_moves_with_it_on_every_backend() {
    // A checkered sphere, moved inside its prototype, placed three times:
    // at the origin, shifted, and turned a quarter about z and shifted.
    // Each shows the checker in its own space (the same colour at the
    // same place on it), not the world's; the fourth, with its own
    // checkered material, shows that in the prototype's space.
    let dir = scratch("instance_checker");
    let toml = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nfov = 40\nwidth = 8\nheight = 8\n\
                [materials.c]\ntype = \"diffuse\"\n\
                albedo = { checker = [[1, 0, 0], [0, 0, 1]], scale = 0.3 }\n\
                [materials.d]\ntype = \"diffuse\"\n\
                albedo = { checker = [[0, 1, 0], [1, 1, 1]], scale = 0.4 }\n\
                [[prototypes.ball.objects]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"c\"\n\
                transform = { translate = [0.2, 0.1, 0] }\n\
                [[objects]]\ntype = \"instance\"\nprototype = \"ball\"\n\
                [[objects]]\ntype = \"instance\"\nprototype = \"ball\"\n\
                transform = { translate = [7.31, 0.43, -0.2] }\n\
                [[objects]]\ntype = \"instance\"\nprototype = \"ball\"\n\
                transform = { rotate = [0, 0, 90], translate = [0, 7, 0] }\n\
                [[objects]]\ntype = \"instance\"\nprototype = \"ball\"\nmaterial = \"d\"\n\
                transform = { translate = [0, -7, 0] }\n";
    let scene = Scene::load(&write(&dir, "c.toml", toml)).unwrap();
    let turn = |v: Vec3| Vec3::new(-v.y, v.x, v.z);
    let shift = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    for backend in Backend::ALL {
        let accel = build(&scene, backend);
        let albedo = |ray: &Ray| {
            let hit = accel.intersect(ray);
            assert!(hit.is_hit(), "{backend:?}: {ray:?}");
            let it = scene.interaction(ray, &hit);
            (
                it.surface(&scene.materials[it.material as usize]).albedo,
                it.p,
                hit.inst_id,
            )
        };
        let (mut world_differs, mut colours) = (0, std::collections::BTreeSet::new());
        for k in 0..100 {
            let (x, y) = ((k % 10) as f32 * 0.14 - 0.43, (k / 10) as f32 * 0.14 - 0.52);
            let ray = Ray::new(shift(x, y, 5.0), shift(0.0, 0.0, -1.0));
            let (a, _, inst) = albedo(&ray);
            assert_eq!(inst, 0);
            colours.insert(format!("{a}"));
            let moved = Ray::new(ray.origin + shift(7.31, 0.43, -0.2), ray.dir);
            let (b, p, inst) = albedo(&moved);
            assert_eq!((a, inst), (b, 1), "{backend:?}: shifted, {ray:?}");
            // The checker unplaced by the instance would lie where the
            // shape alone puts it, whatever the instance.
            let unplaced = scene.materials[scene.prototypes[0].shapes[0].material as usize]
                .albedo_at(p, Vec3::ZERO, None);
            world_differs += usize::from(unplaced != b);
            let turned = Ray::new(turn(ray.origin) + shift(0.0, 7.0, 0.0), turn(ray.dir));
            let (c, _, inst) = albedo(&turned);
            assert_eq!((a, inst), (c, 2), "{backend:?}: turned, {ray:?}");
            // Its own material: the checker in the prototype's space.
            let own = Ray::new(ray.origin + shift(0.0, -7.0, 0.0), ray.dir);
            let (d, p, inst) = albedo(&own);
            let material_d = &scene.materials[1];
            assert_eq!(inst, 3);
            assert_eq!(
                d,
                material_d.albedo_at(p + shift(0.0, 7.0, 0.0), Vec3::ZERO, None),
                "{backend:?}"
            );
        }
        // So the test can fail: both colours are seen, and in world space
        // the pattern would not follow the instance.
        assert_eq!(colours.len(), 2, "{colours:?}");
        assert!(world_differs > 10, "{backend:?}: {world_differs}");
    }
}
