//! Edge cases of the pure-Rust backends, each checked against Embree.

use crate::accel::{Accel, Backend};
use crate::geometry::Mesh;
use crate::math::{Hit, Ray, Vec3};
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
