//! Edge cases of the pure-Rust backends, each checked against Embree.

use crate::accel::{Accel, Backend};
use crate::geometry::Mesh;
use crate::math::{Hit, Ray, Ray64, Vec3};
use crate::scene::{Camera, RenderSettings, Scene};
use crate::shading::Material;

/// A scene of one mesh made of `triangles` over `positions`.
fn mesh_scene(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Scene {
    Scene {
        name: "test".into(),
        camera: Camera::default(),
        render: RenderSettings::default(),
        background: Vec3::ZERO,
        environment: None,
        fogs: Vec::new(),
        materials: vec![Material::default_grey()],
        meshes: vec![Mesh {
            name: "mesh".into(),
            materials: vec![0; triangles.len()],
            positions,
            triangles,
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

/// The unit square in z = 0 (triangles 0 and 1) after two degenerate triangles
/// (2: a repeated corner, 3: collinear corners) that lie across it.
fn square_with_degenerates() -> Scene {
    let positions = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ];
    mesh_scene(positions, vec![[0, 1, 2], [0, 2, 3], [0, 0, 2], [0, 2, 0]])
}

fn every_backend(scene: &Scene) -> Vec<Accel> {
    Backend::ALL
        .iter()
        .map(|&b| Accel::build(scene, b, Some(1)).unwrap())
        .collect()
}

/// Whether t is `want` or one of its f32 neighbours. Embree's t comes from
/// a reciprocal whose rounding depends on the instruction set it picks at
/// run time: this machine's AMD EPYC gives 0.99999994 where others gave 1.
fn within_an_ulp(t: f32, want: f32) -> bool {
    [want.next_down(), want, want.next_up()].contains(&t)
}

fn down(x: f32, y: f32) -> Ray {
    Ray::new(Vec3::new(x, y, 1.0), Vec3::new(0.0, 0.0, -1.0))
}

#[test]
fn hits_carry_embrees_ids_barycentrics_and_normal() {
    let scene = square_with_degenerates();
    for accel in every_backend(&scene) {
        let hit = accel.intersect(&down(0.75, 0.25));
        assert_eq!((hit.geom_id, hit.prim_id), (0, 0), "{}", accel.describe());
        assert!(
            within_an_ulp(hit.t, 1.0),
            "{}: t {}",
            accel.describe(),
            hit.t
        );
        assert!((hit.u - 0.5).abs() < 1e-6 && (hit.v - 0.25).abs() < 1e-6);
        assert_eq!(hit.ng, Vec3::Z);
        assert_eq!(accel.intersect(&down(0.25, 0.75)).prim_id, 1);
    }
}

#[test]
fn degenerate_triangles_are_never_hit() {
    let scene = square_with_degenerates();
    for accel in every_backend(&scene) {
        // Along the diagonal, where both degenerate triangles lie.
        for i in 0..=20 {
            let s = i as f32 / 20.0;
            let hit = accel.intersect(&down(s, s));
            assert!(hit.prim_id < 2, "{} at {s}: {hit:?}", accel.describe());
        }
    }
}

#[test]
fn the_ray_interval_is_respected() {
    let scene = square_with_degenerates();
    for accel in every_backend(&scene) {
        let mut ray = down(0.5, 0.25);
        ray.tfar = 0.999;
        assert_eq!(accel.intersect(&ray), Hit::MISS);
        assert!(!accel.occluded(&ray));
        ray.tnear = 1.001;
        ray.tfar = f32::INFINITY;
        assert_eq!(accel.intersect(&ray), Hit::MISS);
        assert!(!accel.occluded(&ray));
        ray.tnear = 0.5;
        assert!(accel.intersect(&ray).is_hit() && accel.occluded(&ray));
    }
}

#[test]
fn negative_zero_direction_components_still_hit() {
    // obvhs orders children by `dir < 0` but inverts with signum: they disagree on −0.
    let scene = square_with_degenerates();
    for accel in every_backend(&scene) {
        let ray = Ray::new(Vec3::new(0.3, 0.6, 1.0), Vec3::new(-0.0, -0.0, -1.0));
        let t = accel.intersect(&ray).t;
        assert!(within_an_ulp(t, 1.0), "{}: t {t}", accel.describe());
    }
}

#[test]
fn hits_a_billionth_of_a_unit_away_are_found() {
    let scene = square_with_degenerates();
    for accel in every_backend(&scene) {
        let ray = Ray::new(Vec3::new(0.5, 0.25, 1e-9), Vec3::new(0.0, 0.0, -1.0));
        assert_eq!(accel.intersect(&ray).prim_id, 0, "{}", accel.describe());
        assert!(accel.occluded(&ray));
    }
}

#[test]
fn an_empty_scene_is_all_misses_and_a_bad_index_an_error() {
    let empty = mesh_scene(Vec::new(), Vec::new());
    for accel in every_backend(&empty) {
        assert_eq!(accel.intersect(&down(0.5, 0.5)), Hit::MISS);
        assert!(!accel.occluded(&down(0.5, 0.5)));
    }
    let bad = mesh_scene(vec![Vec3::ZERO; 3], vec![[0, 1, 3]]);
    for backend in Backend::ALL {
        let error = Accel::build(&bad, backend, None).err().unwrap();
        assert!(error.to_string().contains("out of range"), "{error}");
    }
}

/// A torus whose top is grazed by an f64 ray whose f32 rounding passes just
/// above it: centre (0, 0, 3), axis z, R = 1, and r just below 1/4, so the
/// top z = 3 + r lies 1e-9 below the f32 value 3.25. The ray runs along x at
/// y = R and z₀ = 3.25 − 1.1e-7, δ = 1.09e-7 below the top (9e-8 of the
/// torus's size). There the tube's top is r − x⁴/8r + …, so the ray crosses
/// it at x = ±(8rδ)^¼ = ±0.0216, t = 5 ∓ 0.0216. Its f32 rounding has
/// z₀ = 3.25, 1e-9 above the top, and misses; it also lies in the top face
/// of the torus's f32 box, which the BVHs must not cull (`padding`).
fn grazed_torus() -> (Scene, Ray64) {
    use glam::{DAffine3, DVec3};

    use crate::geometry::{Shape, Surface};
    use crate::poly::solve::Solver;

    let top = 3.25 - 1e-9;
    let torus = Shape::new(
        Surface::Torus {
            major: 1.0,
            minor: top - 3.0,
        },
        DAffine3::from_translation(DVec3::new(0.0, 0.0, 3.0)),
        None,
        0,
        Solver::default(),
    )
    .unwrap();
    let mut scene = mesh_scene(Vec::new(), Vec::new());
    scene.meshes.clear();
    scene.shapes.push(torus);
    let ray = Ray64 {
        origin: DVec3::new(-5.0, 1.0, 3.25 - 1.1e-7),
        dir: DVec3::X,
    };
    (scene, ray)
}

#[test]
fn a_camera_ray_is_traced_in_f64_where_its_f32_rounding_misses() {
    let (scene, exact) = grazed_torus();
    let rounded = exact.rounded();
    assert_eq!(rounded.origin.z, 3.25, "the f32 ray passes above the top");
    for accel in every_backend(&scene) {
        let name = accel.describe();
        assert!(
            !accel.intersect(&rounded).is_hit(),
            "{name}: the f32 ray misses"
        );
        let hit = accel.intersect_exact(&exact);
        assert!(hit.is_hit(), "{name}: the f64 ray grazes the torus");
        let depth = (3.25 - 1e-9) - exact.origin.z;
        let nearer = 5.0 - (8.0 * 0.25 * depth).powf(0.25);
        assert!(
            (f64::from(hit.t) - nearer).abs() < 1e-4,
            "{name}: t = {}",
            hit.t
        );
        // The same ray as f32 values in a ray of its own is only its rounding.
        let widened = Ray64::of(&rounded);
        assert!(!accel.intersect_exact(&widened).is_hit(), "{name}");
        accel.check().unwrap();
    }
}
