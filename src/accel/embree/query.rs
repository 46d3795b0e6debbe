//! The Embree 3 ↔ 4 differences for queries, behind the version cfg, and the
//! conversions between sturmray's `Ray`/`Hit` and Embree's records.
//!
//! The `RTC_FORCEINLINE` initialisers (`rtcInitIntersectContext`,
//! `rtcInitRayQueryContext`, `rtcInitIntersectArguments`) have no symbol in the
//! library, so they are written here from the bound constants.

use super::sys;
use crate::math::{Hit, Ray, Ray64, Vec3};

const INVALID: u32 = sys::RTC_INVALID_GEOMETRY_ID;
const LEVELS: usize = sys::RTC_MAX_INSTANCE_LEVEL_COUNT as usize;

#[cfg(embree3)]
pub(super) type Context = sys::RTCIntersectContext;
#[cfg(embree4)]
pub(super) type Context = sys::RTCRayQueryContext;

/// The context of every intersect query: Embree's first, then the query's
/// f64 rays, if it has them (camera rays, `CommittedScene::intersect_exact`
/// and `intersect_exact_batch`). Embree hands the intersect callback the
/// context pointer it was given, so the callback reads the f64 ray from
/// there (`user::intersect_callback`). Every `rtcIntersect*` call must pass
/// a pointer made from a whole `Query` (or a struct that starts with one):
/// the callback reads it as one.
#[repr(C)]
pub(super) struct Query<'a> {
    pub(super) context: Context,
    pub(super) exact: Exact<'a>,
}

/// The f64 rays of a query: none, the one ray's, or one for each record of
/// a stream, found by the record's `id` (its index in the stream), which
/// Embree carries unchanged into every packet it forms.
#[derive(Clone, Copy)]
pub(super) enum Exact<'a> {
    None,
    One(&'a Ray64),
    Each(&'a [Ray64]),
}

impl Exact<'_> {
    /// What a shape is to solve for the lane ray `ray` whose record has
    /// `id`: its f64 ray where `ray` is that ray's rounding (see
    /// `Ray64::for_ray`), else `ray` itself widened.
    pub(super) fn for_lane(self, id: u32, ray: &Ray) -> Ray64 {
        let exact = match self {
            Exact::None => None,
            Exact::One(exact) => Some(exact),
            Exact::Each(rays) => rays.get(id as usize),
        };
        Ray64::for_ray(exact, ray)
    }
}

/// A ray record ready for Embree: the whole ray mask set, ids invalid.
pub(super) fn ray_record(ray: &Ray) -> sys::RTCRay {
    sys::RTCRay {
        org_x: ray.origin.x,
        org_y: ray.origin.y,
        org_z: ray.origin.z,
        tnear: ray.tnear,
        dir_x: ray.dir.x,
        dir_y: ray.dir.y,
        dir_z: ray.dir.z,
        time: 0.0,
        tfar: ray.tfar,
        // All ones: the ray sees every geometry whatever its mask (Embree 4's default
        // geometry mask is 0x1, Embree 3's is all ones).
        mask: u32::MAX,
        id: 0,
        flags: 0,
    }
}

/// A ray+hit record with geomID, primID and the instance stack invalid.
pub(super) fn rayhit_record(ray: &Ray) -> sys::RTCRayHit {
    sys::RTCRayHit {
        ray: ray_record(ray),
        hit: sys::RTCHit {
            primID: INVALID,
            geomID: INVALID,
            instID: [INVALID; LEVELS],
            #[cfg(embree_inst_prim_id)]
            instPrimID: [INVALID; LEVELS],
            ..Default::default()
        },
    }
}

/// Reads a finished query back into a `Hit`; `inst_id` is still Embree's
/// (the instance geometry's id in the top-level scene), and the normal in the
/// space of the geometry hit (see `instance::Instances::to_world`).
pub(super) fn hit_from_record(record: &sys::RTCRayHit) -> Hit {
    if record.hit.geomID == INVALID {
        return Hit::MISS;
    }
    Hit {
        t: record.ray.tfar,
        geom_id: record.hit.geomID,
        prim_id: record.hit.primID,
        inst_id: record.hit.instID[0],
        u: record.hit.u,
        v: record.hit.v,
        ng: Vec3::new(record.hit.Ng_x, record.hit.Ng_y, record.hit.Ng_z),
    }
}

/// After `rtcOccluded1`, Embree sets tfar to -inf when it found a hit.
pub(super) fn occluded_from_record(ray: &sys::RTCRay) -> bool {
    ray.tfar == f32::NEG_INFINITY
}

/// How coherent the rays of a query are; Embree picks its traversal from it.
#[derive(Clone, Copy)]
pub(super) enum Coherence {
    Coherent,
    Incoherent,
}

#[cfg(embree3)]
mod version {
    use super::*;

    /// Embree 3's `rtcInitIntersectContext`. The struct update covers
    /// `minWidthDistanceFactor`, present only in Embree builds with curve minimum width.
    #[allow(clippy::needless_update)]
    pub(in super::super) fn context(coherence: Coherence) -> sys::RTCIntersectContext {
        sys::RTCIntersectContext {
            flags: match coherence {
                Coherence::Coherent => {
                    sys::RTCIntersectContextFlags_RTC_INTERSECT_CONTEXT_FLAG_COHERENT
                }
                Coherence::Incoherent => {
                    sys::RTCIntersectContextFlags_RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT
                }
            },
            filter: None,
            instID: [INVALID; LEVELS],
            ..Default::default()
        }
    }
}

#[cfg(embree4)]
mod version {
    use super::*;

    /// Embree 4's `rtcInitRayQueryContext`. The struct update covers `instStackSize`,
    /// present only when Embree is built with more than one instance level.
    #[allow(clippy::needless_update)]
    pub(in super::super) fn context() -> sys::RTCRayQueryContext {
        sys::RTCRayQueryContext {
            instID: [INVALID; LEVELS],
            #[cfg(embree_inst_prim_id)]
            instPrimID: [INVALID; LEVELS],
            ..Default::default()
        }
    }

    fn flags(coherence: Coherence) -> sys::RTCRayQueryFlags {
        match coherence {
            Coherence::Coherent => sys::RTCRayQueryFlags_RTC_RAY_QUERY_FLAG_COHERENT,
            Coherence::Incoherent => sys::RTCRayQueryFlags_RTC_RAY_QUERY_FLAG_INCOHERENT,
        }
    }

    /// Embree 4's `rtcInitIntersectArguments`, pointing at `context`. The struct update
    /// covers `minWidthDistanceFactor`, present only with curve minimum width.
    #[allow(clippy::needless_update)]
    pub(in super::super) fn intersect_arguments(
        coherence: Coherence,
        context: &mut sys::RTCRayQueryContext,
    ) -> sys::RTCIntersectArguments {
        sys::RTCIntersectArguments {
            flags: flags(coherence),
            feature_mask: sys::RTCFeatureFlags_RTC_FEATURE_FLAG_ALL,
            context,
            filter: None,
            intersect: None,
            ..Default::default()
        }
    }

    /// Embree 4's `rtcInitOccludedArguments`, pointing at `context`. The struct update
    /// covers `minWidthDistanceFactor`, present only with curve minimum width.
    #[allow(clippy::needless_update)]
    pub(in super::super) fn occluded_arguments(
        coherence: Coherence,
        context: &mut sys::RTCRayQueryContext,
    ) -> sys::RTCOccludedArguments {
        sys::RTCOccludedArguments {
            flags: flags(coherence),
            feature_mask: sys::RTCFeatureFlags_RTC_FEATURE_FLAG_ALL,
            context,
            filter: None,
            occluded: None,
            ..Default::default()
        }
    }
}

pub(super) use version::*;
