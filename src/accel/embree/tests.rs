//! The wrapper against the real Embree library: layouts, a canary after the hit
//! record, hits and misses on known geometry, errors from the device callback.

use super::*;
use crate::accel::ftz::enable_flush_to_zero;
use crate::accel::primitive::{UserHit, UserPrimitive};
use crate::error::Error;
use crate::math::{Hit, Ray, Ray64, Vec3};

const LEVELS: usize = sys::RTC_MAX_INSTANCE_LEVEL_COUNT as usize;

/// One triangle in the z = 0 plane: (0,0,0), (1,0,0), (0,1,0).
fn triangle_scene() -> CommittedScene {
    let device = Device::new().unwrap();
    let mut builder = SceneBuilder::new(&device, SceneOptions::default()).unwrap();
    let positions = [Vec3::ZERO, Vec3::X, Vec3::Y];
    builder
        .add_triangles(0, &positions, &[[0, 1, 2]], None)
        .unwrap();
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
        .add_triangles(0, &[Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 3]], None)
        .unwrap_err();
    assert!(matches!(err, Error::Input(_)), "{err}");
}

#[test]
fn embree_errors_arrive_through_the_device_callback() {
    let device = Device::new().unwrap();
    let mut builder = SceneBuilder::new(&device, SceneOptions::default()).unwrap();
    let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
    builder.add_triangles(7, &tri, &[[0, 1, 2]], None).unwrap();
    // Embree refuses a geometry ID that is already in use.
    let err = builder
        .add_triangles(7, &tri, &[[0, 1, 2]], None)
        .unwrap_err();
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

/// A unit-radius sphere as user geometry, intersected in the test itself;
/// `panic_below` makes rays with origin.x below it panic inside the callback.
struct TestSphere {
    center: Vec3,
    panic_below: f32,
}

impl TestSphere {
    fn roots(&self, ray: &Ray) -> Option<(f32, f32)> {
        if ray.origin.x < self.panic_below {
            panic!("test panic inside a callback");
        }
        let oc = ray.origin - self.center;
        let (a, b, c) = (ray.dir.dot(ray.dir), oc.dot(ray.dir), oc.dot(oc) - 1.0);
        let disc = b * b - a * c;
        (disc >= 0.0).then(|| ((-b - disc.sqrt()) / a, (-b + disc.sqrt()) / a))
    }
}

impl UserPrimitive for TestSphere {
    fn bounds(&self) -> crate::math::Bounds {
        crate::math::Bounds {
            min: self.center - Vec3::ONE,
            max: self.center + Vec3::ONE,
        }
    }

    fn intersect(&self, ray: &Ray, _: &Ray64) -> Option<UserHit> {
        let (t0, t1) = self.roots(ray)?;
        let t = if t0 >= ray.tnear { t0 } else { t1 };
        (t >= ray.tnear && t < ray.tfar).then(|| UserHit {
            t,
            ng: ray.at(t) - self.center,
            u: 0.0,
            v: 0.0,
        })
    }

    fn occluded(&self, ray: &Ray) -> bool {
        self.intersect(ray, &Ray64::of(ray)).is_some()
    }
}

/// Two spheres (prim 0 at z = 0, prim 1 at z = −4) as geometry 1, behind the triangle (geometry 0)
/// which sits at z = 0 … but over x, y ∈ [0, 1] only.
fn mixed_scene(panic_below: f32) -> CommittedScene {
    let device = Device::new().unwrap();
    let mut builder = SceneBuilder::new(&device, SceneOptions::default()).unwrap();
    builder
        .add_triangles(
            0,
            &[
                Vec3::new(0.0, 0.0, 3.0),
                Vec3::new(1.0, 0.0, 3.0),
                Vec3::new(0.0, 1.0, 3.0),
            ],
            &[[0, 1, 2]],
            None,
        )
        .unwrap();
    let spheres = vec![
        TestSphere {
            center: Vec3::ZERO,
            panic_below,
        },
        TestSphere {
            center: Vec3::new(0.0, 0.0, -4.0),
            panic_below,
        },
    ];
    builder.add_user(1, spheres).unwrap();
    builder.commit().unwrap()
}

#[test]
fn user_geometry_hits_report_t_ids_and_normal() {
    let scene = mixed_scene(f32::NEG_INFINITY);
    // Down the axis from z = 10: the triangle at z = 3 is missed (x = -0.5), the sphere hit at z = 1.
    let ray = Ray::new(Vec3::new(-0.5, 0.0, 10.0), -Vec3::Z);
    let hit = scene.intersect(&ray);
    assert_eq!((hit.geom_id, hit.prim_id), (1, 0));
    let expected_t = 10.0 - (1.0f32 - 0.25).sqrt();
    assert!((hit.t - expected_t).abs() < 1e-5, "{}", hit.t);
    assert!((hit.ng - Vec3::new(-0.5, 0.0, 0.75f32.sqrt())).length() < 1e-5);
    // Through the triangle first: the triangle wins.
    let ray = Ray::new(Vec3::new(0.1, 0.1, 10.0), -Vec3::Z);
    assert_eq!(scene.intersect(&ray).geom_id, 0);
    // Starting between the spheres, looking down: the second sphere (prim 1).
    let ray = Ray::new(Vec3::new(0.0, 0.0, -2.0), -Vec3::Z);
    let hit = scene.intersect(&ray);
    assert_eq!((hit.geom_id, hit.prim_id, hit.t), (1, 1, 1.0));
    // tfar stops short of it.
    let short = Ray { tfar: 0.5, ..ray };
    assert_eq!(scene.intersect(&short), Hit::MISS);
    assert!(scene.occluded(&ray) && !scene.occluded(&short));
    scene.check().unwrap();
}

#[test]
fn user_geometry_batches_agree_with_single_rays() {
    let scene = mixed_scene(f32::NEG_INFINITY);
    let rays: Vec<Ray> = (0..2000)
        .map(|i| {
            let x = (i % 50) as f32 / 20.0 - 1.25;
            let y = (i / 50) as f32 / 16.0 - 1.25;
            Ray::new(Vec3::new(x, y, 10.0), -Vec3::Z)
        })
        .collect();
    let mut hits = vec![Hit::MISS; rays.len()];
    for coherent in [true, false] {
        scene.intersect_batch(&rays, &mut hits, coherent).unwrap();
        let mut counts = [0usize; 3];
        for (ray, hit) in rays.iter().zip(&hits) {
            assert_eq!(*hit, scene.intersect(ray));
            counts[(hit.geom_id.wrapping_add(1)).min(2) as usize] += 1;
        }
        assert!(
            counts.iter().all(|&c| c > 50),
            "misses, triangle and sphere hits: {counts:?}"
        );
    }
}

#[test]
fn canary_survives_a_user_geometry_hit() {
    #[repr(C)]
    struct Guarded {
        record: sys::RTCRayHit,
        canary: [u32; 8],
    }
    let scene = mixed_scene(f32::NEG_INFINITY);
    let mut guarded = Guarded {
        record: query::rayhit_record(&Ray::new(Vec3::new(-0.5, 0.0, 10.0), -Vec3::Z)),
        canary: [0xDEAD_BEEF; 8],
    };
    scene.intersect_raw(&mut guarded.record);
    assert_eq!(
        guarded.record.hit.geomID, 1,
        "the guarded ray must hit the sphere"
    );
    assert_eq!(guarded.canary, [0xDEAD_BEEF; 8]);
}

#[test]
fn a_panicking_callback_is_a_miss_and_an_error_not_an_abort() {
    let scene = mixed_scene(0.0);
    let ray = Ray::new(Vec3::new(-0.5, 0.0, 10.0), -Vec3::Z);
    assert_eq!(scene.intersect(&ray), Hit::MISS);
    assert!(!scene.occluded(&ray));
    assert!(scene.panics().happened(), "visible before the check");
    let err = scene.check().unwrap_err();
    assert!(
        matches!(err, Error::Internal(_)) && err.to_string().contains("test panic"),
        "{err}"
    );
    // Reported once; rays that do not panic still work.
    scene.check().unwrap();
    assert!(
        scene
            .intersect(&Ray::new(Vec3::new(0.5, 0.0, 10.0), -Vec3::Z))
            .is_hit()
    );
    scene.check().unwrap();
}

#[test]
fn the_library_writes_the_hit_record_exactly_where_the_bindings_put_it() {
    // Fill the instance fields with a pattern; on a triangle hit Embree overwrites
    // them from the query context (all invalid). The last field the library writes
    // must be the last field of the bindings' RTCHit, and nothing after the record.
    #[repr(C)]
    struct Guarded {
        record: sys::RTCRayHit,
        canary: [u32; 8],
    }
    const PATTERN: u32 = 0x1234_5678;
    let scene = triangle_scene();
    let mut guarded = Guarded {
        record: query::rayhit_record(&down_at(0.25, 0.25)),
        canary: [PATTERN; 8],
    };
    guarded.record.hit.instID = [PATTERN; LEVELS];
    #[cfg(embree_inst_prim_id)]
    {
        guarded.record.hit.instPrimID = [PATTERN; LEVELS];
    }
    scene.intersect_raw(&mut guarded.record);
    assert_eq!(guarded.record.hit.geomID, 0);
    assert_eq!(
        guarded.record.hit.instID,
        [sys::RTC_INVALID_GEOMETRY_ID; LEVELS]
    );
    #[cfg(embree_inst_prim_id)]
    assert_eq!(
        guarded.record.hit.instPrimID,
        [sys::RTC_INVALID_GEOMETRY_ID; LEVELS]
    );
    assert_eq!(
        guarded.canary, [PATTERN; 8],
        "the library wrote past the record"
    );
}

/// Hits every ray at t = 1 and reports, in u, how far its f64 ray's origin
/// is from the lane's f32 one (in units of 2^-40): which f64 ray the
/// callback was handed.
struct ExactProbe;

impl UserPrimitive for ExactProbe {
    fn bounds(&self) -> crate::math::Bounds {
        crate::math::Bounds {
            min: Vec3::splat(-4.0),
            max: Vec3::splat(4.0),
        }
    }

    fn intersect(&self, ray: &Ray, exact: &Ray64) -> Option<UserHit> {
        let offset = (exact.origin.x - f64::from(ray.origin.x)) * 2f64.powi(40);
        (ray.tnear <= 1.0 && 1.0 < ray.tfar).then_some(UserHit {
            t: 1.0,
            ng: Vec3::Z,
            u: offset as f32,
            v: 0.0,
        })
    }

    fn occluded(&self, ray: &Ray) -> bool {
        self.intersect(ray, &Ray64::of(ray)).is_some()
    }
}

/// `intersect_exact_batch` gives each ray the bits `intersect_exact` gives
/// it alone, whatever rays share its stream, where no two primitives tie
/// (a tie, at a shared edge, a packet may break otherwise: see the
/// method). On 1,500 random triangles (Embree's packet kernels and its
/// single-ray ones must agree), and on user geometry that reports the f64
/// ray it was handed (each lane must get its own).
#[test]
fn streams_answer_as_single_rays() {
    enable_flush_to_zero();
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut uniform = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let device = Device::new().unwrap();
    let mut builder = SceneBuilder::new(&device, SceneOptions::default()).unwrap();
    let mut positions = Vec::new();
    for _ in 0..1500 {
        let centre = [uniform(), uniform(), uniform()].map(|c| 4.0 * c - 2.0);
        for _ in 0..3 {
            let p: [f64; 3] = std::array::from_fn(|a| centre[a] + 0.4 * (uniform() - 0.5));
            positions.push(Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32));
        }
    }
    let triangles: Vec<[u32; 3]> = (0..1500u32)
        .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    builder
        .add_triangles(0, &positions, &triangles, None)
        .unwrap();
    let mesh = builder.commit().unwrap();
    let mut builder = SceneBuilder::new(&device, SceneOptions::default()).unwrap();
    builder.add_user(0, vec![ExactProbe]).unwrap();
    let probe = builder.commit().unwrap();
    // Camera rays from a pinhole, then rays from random points in random
    // directions; origins off the f32 grid, as a camera's f64 rays are.
    let mut rays: Vec<Ray64> = (0..4000)
        .map(|i| {
            let (x, y) = ((i % 64) as f64 / 32.0 - 1.0, (i / 64) as f64 / 32.0 - 1.0);
            let origin = glam::DVec3::new(0.1 + 1e-9 * uniform(), 0.0, -6.0);
            Ray64 {
                origin,
                dir: glam::DVec3::new(x, y, 2.5).normalize(),
            }
        })
        .collect();
    rays.extend((0..4000).map(|_| {
        let origin = glam::DVec3::new(uniform(), uniform(), uniform()) * 4.0 - 2.0;
        let (z, phi) = (2.0 * uniform() - 1.0, std::f64::consts::TAU * uniform());
        let s = (1.0 - z * z).sqrt();
        Ray64 {
            origin,
            dir: glam::DVec3::new(s * phi.cos(), s * phi.sin(), z),
        }
    }));
    let bits = |h: &Hit| {
        [h.t, h.u, h.v, h.ng.x, h.ng.y, h.ng.z]
            .map(f32::to_bits)
            .into_iter()
            .chain([h.geom_id, h.prim_id, h.inst_id])
            .collect::<Vec<u32>>()
    };
    for scene in [&mesh, &probe] {
        let alone: Vec<Hit> = rays.iter().map(|r| scene.intersect_exact(r)).collect();
        assert!(alone.iter().filter(|h| h.is_hit()).count() > 2000);
        // Streams that start at different rays group every ray with others.
        for skip in [0, 37, 200] {
            let mut hits = vec![Hit::MISS; rays.len() - skip];
            scene.intersect_exact_batch(&rays[skip..], &mut hits);
            for (i, hit) in hits.iter().enumerate() {
                assert_eq!(bits(hit), bits(&alone[skip + i]), "ray {}", skip + i);
            }
        }
        scene.check().unwrap();
    }
    // The probe saw each ray's own f64 origin, not its neighbour's.
    let offsets: std::collections::HashSet<u32> = rays
        .iter()
        .map(|r| probe.intersect_exact(r).u.to_bits())
        .collect();
    assert!(offsets.len() > 3000, "{} distinct offsets", offsets.len());
}
