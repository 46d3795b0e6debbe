//! Filter functions: the all-hits query, whose filter records every
//! candidate hit and rejects it so traversal goes on; the cut-out filter of
//! triangle geometries with alpha masks; and the protocol by which the
//! user-geometry callback offers each crossing to the filters.
//!
//! The query's filter rides in the query (Embree 3: the intersect context's
//! `filter`, with the scene flag `RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION`;
//! Embree 4: the intersect arguments' `filter`, with
//! `RTC_SCENE_FLAG_FILTER_FUNCTION_IN_ARGUMENTS`), and finds its hit list
//! through the context, which is the first field of a `Collector`.

use std::mem::MaybeUninit;
use std::sync::Arc;

#[cfg(embree4)]
use super::query::Context;
use super::query::{self, Coherence, Exact, Query};
use super::scene::CommittedScene;
use super::sys;
use super::user::{
    GEOM_ID, HIT_FIELDS, INST_ID, MAX_LANES, NG_X, PRIM_ID, Packet, RAY_FIELDS, TFAR, U, V,
    write_hit,
};
use crate::accel::cutout::Cutout;
use crate::accel::panics::PanicSlot;
use crate::accel::primitive::UserHit;
use crate::math::{Hit, Ray, Vec3};

/// The scene flag that lets a query carry its own filter function.
#[cfg(embree3)]
pub(super) const SCENE_FLAG: sys::RTCSceneFlags =
    sys::RTCSceneFlags_RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION;
#[cfg(embree4)]
pub(super) const SCENE_FLAG: sys::RTCSceneFlags =
    sys::RTCSceneFlags_RTC_SCENE_FLAG_FILTER_FUNCTION_IN_ARGUMENTS;

#[cfg(embree4)]
thread_local! {
    /// The context of the all-hits query running on this thread, if any.
    /// Embree 4 never calls a query's argument filter for user geometry
    /// (embree/embree#478: `rtcInvokeIntersectFilterFromGeometry` runs only
    /// the geometry's own), so `offer` hands a crossing to `collect` itself
    /// when the query it serves is this one.
    static COLLECTING: std::cell::Cell<*const Context> =
        const { std::cell::Cell::new(std::ptr::null()) };
}

/// Marks the all-hits query on this thread for as long as it lives.
#[cfg(embree4)]
struct Collecting;

#[cfg(embree4)]
impl Collecting {
    fn start(context: *const Context) -> Collecting {
        COLLECTING.with(|c| c.set(context));
        Collecting
    }
}

#[cfg(embree4)]
impl Drop for Collecting {
    fn drop(&mut self) {
        COLLECTING.with(|c| c.set(std::ptr::null()));
    }
}

/// An all-hits query's context: the intersect queries' own first (Embree's
/// context, then no f64 ray), so the filter finds the rest from the context
/// pointer it is given.
#[repr(C)]
struct Collector<'a> {
    query: Query<'a>,
    hits: *mut Vec<Hit>,
    panics: &'a PanicSlot,
}

/// The all-hits filter: records each valid lane's candidate and rejects it.
extern "C" fn collect(args: *const sys::RTCFilterFunctionNArguments) {
    // SAFETY: Embree passes valid arguments for the duration of the call.
    let args = unsafe { &*args };
    let n = args.N as usize;
    if n > MAX_LANES {
        return;
    }
    // SAFETY: this filter is set only by `intersect_all`, whose context pointer is
    // that of a live `Collector` (repr(C), context first), made from the whole struct;
    // on Embree 4 `offer` also calls it, only with that same query's context.
    let collector = unsafe { &*args.context.cast::<Collector>() };
    // SAFETY: `ray` is a live RTCRayN of N lanes, its tfar the candidate's t, lent to
    // this call.
    let ray = unsafe { Packet::<u32>::new(args.ray.cast(), RAY_FIELDS, n) };
    // SAFETY: `hit` is a live RTCHitN of N lanes whose valid lanes are initialised (by
    // Embree, or by `offer` that zeroes its whole record), lent to this call.
    let hit = unsafe { Packet::<u32>::new(args.hit.cast(), INST_ID + 1, n) };
    collector.panics.guard((), || {
        // SAFETY: the list is the query's own, borrowed exclusively by `intersect_all`
        // for the query, and Embree calls this filter on the query's thread only.
        let hits = unsafe { &mut *collector.hits };
        for i in 0..n {
            // SAFETY: `valid` has N initialised, writable entries, lent to this call.
            let valid = unsafe { &mut *args.valid.wrapping_add(i) };
            if *valid != -1 {
                continue;
            }
            hits.push(Hit {
                t: ray.f32(TFAR, i),
                geom_id: hit.u32(GEOM_ID, i),
                prim_id: hit.u32(PRIM_ID, i),
                // Embree's id of the (first-level) instance; `intersect_all`
                // turns it into the instance's index.
                inst_id: hit.u32(INST_ID, i),
                u: hit.f32(U, i),
                v: hit.f32(V, i),
                ng: Vec3::new(hit.f32(NG_X, i), hit.f32(NG_X + 1, i), hit.f32(NG_X + 2, i)),
            });
            *valid = 0;
        }
    });
}

/// What a triangle geometry with cut-outs holds as its user pointer.
pub(super) struct CutoutData {
    pub(super) cutout: Cutout,
    pub(super) panics: Arc<PanicSlot>,
}

/// A triangle geometry's intersection and occlusion filter: rejects each
/// valid lane whose candidate hit its cut-out skips. Embree runs a
/// geometry's filter before the query's (the all-hits collector), so a
/// cut-away hit is never collected; on an instance it runs in the
/// prototype's scene, where primID, u and v are the prototype triangle's
/// and instID[0] (the instance's top-level geometry id) says whose
/// material decides.
pub(super) extern "C" fn cut_out(args: *const sys::RTCFilterFunctionNArguments) {
    // SAFETY: Embree passes valid arguments for the duration of the call.
    let args = unsafe { &*args };
    let n = args.N as usize;
    if n > MAX_LANES {
        return;
    }
    // SAFETY: this filter is set only by `add_triangles`, on a geometry whose user
    // pointer is a `CutoutData` the scene owns for as long as Embree may call it.
    let data = unsafe { &*args.geometryUserPtr.cast::<CutoutData>() };
    // SAFETY: `hit` is a live RTCHitN of N lanes whose valid lanes Embree initialised,
    // instance stack included, lent to this call; only read here.
    let hit = unsafe { Packet::<u32>::new(args.hit.cast(), INST_ID + 1, n) };
    data.panics.guard((), || {
        for i in 0..n {
            // SAFETY: `valid` has N initialised, writable entries, lent to this call.
            let valid = unsafe { &mut *args.valid.wrapping_add(i) };
            if *valid == -1
                && data.cutout.skips(
                    hit.u32(PRIM_ID, i),
                    hit.f32(U, i),
                    hit.f32(V, i),
                    hit.u32(INST_ID, i),
                )
            {
                *valid = 0;
            }
        }
    });
}

/// Offers the crossing `hit` of lane `i` to the filter functions of the
/// query and of the geometry, as Embree's own primitives do: the ray's tfar
/// set to the hit, the hit in a record of its own. Returns whether they
/// accepted it (with none, always); tfar is restored if not.
pub(super) fn offer(args: &sys::RTCIntersectFunctionNArguments, i: usize, hit: &UserHit) -> bool {
    let n = args.N as usize;
    // Zeroed whole, so a filter may read any lane of it.
    let mut candidate = [0u32; HIT_FIELDS * MAX_LANES];
    {
        // SAFETY: `candidate` holds HIT_FIELDS fields of n <= MAX_LANES lanes, owned here.
        let mut hits =
            unsafe { Packet::<MaybeUninit<u32>>::new(candidate.as_mut_ptr(), HIT_FIELDS, n) };
        // SAFETY: Embree passes the instance stack of the traversal, valid for the call.
        let context = unsafe { &*args.context };
        write_hit(&mut hits, i, hit, args.primID, args.geomID, context);
    }
    let base = args.rayhit.cast::<u32>();
    let before = {
        // SAFETY: `rayhit` is a live RTCRayHitN of N lanes lent to this call; the packet
        // lives only for this exchange, before the filters run.
        let mut rays = unsafe { Packet::<u32>::new(base, RAY_FIELDS, n) };
        let before = rays.f32(TFAR, i);
        rays.set_f32(TFAR, i, hit.t);
        before
    };
    let mut mask = [0i32; MAX_LANES];
    mask[i] = -1;
    let filter_args = sys::RTCFilterFunctionNArguments {
        valid: mask.as_mut_ptr(),
        geometryUserPtr: args.geometryUserPtr,
        context: args.context,
        ray: args.rayhit.cast(),
        hit: candidate.as_mut_ptr().cast(),
        N: args.N,
    };
    #[cfg(embree3)]
    // SAFETY: `args` are this callback's own arguments; `filter_args` points at the
    // mask, the candidate and the callback's ray, all live for the call.
    unsafe {
        sys::rtcFilterIntersection(args, &filter_args)
    };
    #[cfg(embree4)]
    {
        // SAFETY: as above.
        unsafe { sys::rtcInvokeIntersectFilterFromGeometry(args, &filter_args) };
        // The query's filter, which Embree 4 leaves out here (see `COLLECTING`):
        // only for the all-hits query whose context this is, so `collect` finds
        // its `Collector` there.
        if mask[i] == -1 && COLLECTING.with(|c| c.get()) == args.context.cast_const() {
            collect(&filter_args);
        }
    }
    let accepted = mask[i] == -1;
    if !accepted {
        // SAFETY: as above; the filters have returned.
        let mut rays = unsafe { Packet::<u32>::new(base, RAY_FIELDS, n) };
        rays.set_f32(TFAR, i, before);
    }
    accepted
}

impl CommittedScene {
    /// Every hit along `ray` in [tnear, tfar), appended to `hits` in the
    /// order traversal met them: two triangles hit at the same t (a shared
    /// edge) are both there, and every crossing of an analytic shape; on an
    /// instance with its index and its normal in world space, as `intersect`.
    pub fn intersect_all(&self, ray: &Ray, hits: &mut Vec<Hit>) {
        let first = hits.len();
        self.collect_all(ray, hits);
        for hit in &mut hits[first..] {
            *hit = self.instances.to_world(*hit);
        }
    }

    fn collect_all(&self, ray: &Ray, hits: &mut Vec<Hit>) {
        let mut record = query::rayhit_record(ray);
        #[cfg(embree3)]
        {
            let mut context = query::context(Coherence::Incoherent);
            context.filter = Some(collect);
            let mut collector = Collector {
                query: Query {
                    context,
                    exact: Exact::None,
                },
                hits,
                panics: self.panics(),
            };
            let whole: *mut Collector = &mut collector;
            // SAFETY: scene committed; the context starts `collector` (in its `Query`, as the
            // intersect callback reads it), whose pointer (made from the whole struct)
            // outlives the call, as does `record`.
            unsafe { sys::rtcIntersect1(self.raw(), whole.cast(), &mut record) };
        }
        #[cfg(embree4)]
        {
            let mut collector = Collector {
                query: Query {
                    context: query::context(),
                    exact: Exact::None,
                },
                hits,
                panics: self.panics(),
            };
            let mut args =
                query::intersect_arguments(Coherence::Incoherent, &mut collector.query.context);
            let whole: *mut Collector = &mut collector;
            args.context = whole.cast();
            args.filter = Some(collect);
            // Embree 4 calls an argument filter only when the query asks for it.
            args.flags |= sys::RTCRayQueryFlags_RTC_RAY_QUERY_FLAG_INVOKE_ARGUMENT_FILTER;
            let _collecting = Collecting::start(whole.cast_const().cast());
            // SAFETY: scene committed; `args` points at the context, the first field of
            // `collector`, made from the whole struct; all outlive the call.
            unsafe { sys::rtcIntersect1(self.raw(), &mut record, &mut args) };
        }
    }
}
