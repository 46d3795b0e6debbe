//! The wrapper against the real Embree library: layouts, a canary after the hit
//! record, hits and misses on known geometry, errors from the device callback.

use super::*;
use crate::error::Error;
use crate::math::{Hit, Ray, Vec3};

const LEVELS: usize = sys::RTC_MAX_INSTANCE_LEVEL_COUNT as usize;

/// One triangle in the z = 0 plane: (0,0,0), (1,0,0), (0,1,0).
fn triangle_scene() -> CommittedScene {
    let device = Device::new().unwrap();
    let mut builder = SceneBuilder::new(&device, SceneOptions::default()).unwrap();
    let positions = [Vec3::ZERO, Vec3::X, Vec3::Y];
    builder.add_triangles(0, &positions, &[[0, 1, 2]]).unwrap();
    builder.commit().unwrap()
}

fn down_at(x: f32, y: f32) -> Ray {
    Ray::new(Vec3::new(x, y, 2.0), Vec3::new(0.0, 0.0, -1.0))
}

#[test]
fn struct_layouts_match_the_header() {
    use std::mem::{align_of, size_of};
    // RTCRay: 12 four-byte fields, aligned to 16.
    assert_eq!(size_of::<sys::RTCRay>(), 48);
    assert_eq!(align_of::<sys::RTCRay>(), 16);
    // RTCHit: Ng (3), u, v, primID, geomID, instID[LEVELS], and instPrimID[LEVELS] when the
    // header has instance arrays (Embree 4.3+), rounded up to 16 bytes.
    let inst_words = if cfg!(embree_inst_prim_id) {
        2 * LEVELS
    } else {
        LEVELS
    };
    let hit_bytes = (7 + inst_words) * 4;
    assert_eq!(size_of::<sys::RTCHit>(), hit_bytes.next_multiple_of(16));
    assert_eq!(align_of::<sys::RTCRayHit>(), 16);
    assert_eq!(
        size_of::<sys::RTCRayHit>(),
        48 + hit_bytes.next_multiple_of(16)
    );
}

#[test]
fn library_version_matches_header_major() {
    let device = Device::new().unwrap();
    let library = device.library_version();
    assert_eq!(library.major(), HEADER_VERSION.major());
    assert!(library >= HEADER_VERSION, "{library} < {HEADER_VERSION}");
}

#[test]
fn canary_after_the_hit_record_survives_a_hit() {
    #[repr(C)]
    struct Guarded {
        record: sys::RTCRayHit,
        canary: [u32; 8],
    }
    const CANARY: u32 = 0xDEAD_BEEF;
    let scene = triangle_scene();
    let mut guarded = Guarded {
        record: query::rayhit_record(&down_at(0.25, 0.25)),
        canary: [CANARY; 8],
    };
    scene.intersect_raw(&mut guarded.record);
    assert_eq!(
        guarded.record.hit.geomID, 0,
        "the guarded ray must really hit"
    );
    assert_eq!(guarded.canary, [CANARY; 8]);
}

#[test]
fn hit_reports_t_ids_barycentrics_and_normal() {
    let scene = triangle_scene();
    let hit = scene.intersect(&down_at(0.25, 0.5));
    assert_eq!((hit.geom_id, hit.prim_id), (0, 0));
    assert!((hit.t - 2.0).abs() < 1e-6, "t = {}", hit.t);
    assert!((hit.u - 0.25).abs() < 1e-6 && (hit.v - 0.5).abs() < 1e-6);
    // Embree's Ng is (p1 - p0) × (p2 - p0) up to sign convention; it must be along z.
    assert!(hit.ng.x.abs() < 1e-6 && hit.ng.y.abs() < 1e-6 && hit.ng.z.abs() > 0.5);
}

#[test]
fn misses_and_interval_limits() {
    let scene = triangle_scene();
    assert_eq!(scene.intersect(&down_at(0.75, 0.75)), Hit::MISS);
    let mut short = down_at(0.25, 0.25);
    short.tfar = 1.5;
    assert_eq!(scene.intersect(&short), Hit::MISS);
    assert!(!scene.occluded(&short));
    short.tfar = 2.5;
    assert!(scene.occluded(&short));
    short.tnear = 2.1;
    assert!(!scene.occluded(&short));
}

#[test]
fn batch_agrees_with_single_rays() {
    let scene = triangle_scene();
    let rays: Vec<Ray> = (0..1000)
        .map(|i| down_at((i % 37) as f32 / 30.0, (i % 41) as f32 / 35.0))
        .collect();
    let mut hits = vec![Hit::MISS; rays.len()];
    scene.intersect_batch(&rays, &mut hits, false).unwrap();
    let mut some = 0;
    for (ray, hit) in rays.iter().zip(&hits) {
        assert_eq!(*hit, scene.intersect(ray));
        some += hit.is_hit() as usize;
    }
    assert!(
        some > 100 && some < 900,
        "{some} hits: the batch must mix hits and misses"
    );
}

#[test]
fn out_of_range_index_is_refused_before_embree_sees_it() {
    let device = Device::new().unwrap();
    let mut builder = SceneBuilder::new(&device, SceneOptions::default()).unwrap();
    let err = builder
        .add_triangles(0, &[Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 3]])
        .unwrap_err();
    assert!(matches!(err, Error::Input(_)), "{err}");
}

#[test]
fn embree_errors_arrive_through_the_device_callback() {
    let device = Device::new().unwrap();
    let mut builder = SceneBuilder::new(&device, SceneOptions::default()).unwrap();
    let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
    builder.add_triangles(7, &tri, &[[0, 1, 2]]).unwrap();
    // Embree refuses a geometry ID that is already in use.
    let err = builder.add_triangles(7, &tri, &[[0, 1, 2]]).unwrap_err();
    assert!(matches!(err, Error::Embree(_)), "{err}");
}

#[test]
fn committed_scene_is_shared_across_threads() {
    fn assert_send_sync<T: Send + Sync>() {}
    assert_send_sync::<CommittedScene>();
    let scene = triangle_scene();
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| {
                enable_flush_to_zero();
                assert!(scene.intersect(&down_at(0.1, 0.1)).is_hit());
            });
        }
    });
}

#[test]
fn bounds_cover_the_geometry() {
    let b = triangle_scene().bounds();
    assert_eq!((b.min, b.max), (Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0)));
}
