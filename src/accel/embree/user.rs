//! Embree user geometry: primitives whose bounds, intersect and occluded
//! callbacks are Rust.
//!
//! The wrapper, not the primitive, owns the callback contract: it decodes
//! Embree's SoA ray packets, skips inactive lanes, accepts a hit only in
//! [tnear, tfar) of the lane, writes the whole hit record (t, Ng, u, v, primID,
//! geomID, the instance stack), sets tfar = −inf for occlusion, writes Embree
//! 4's `valid` flags, and catches every panic: a panicking primitive is a
//! miss, and the panic becomes an `Error` at the scene's next `check()`.
//! Each crossing goes through Embree's filter protocol (`filter::offer`),
//! nearest first, so the filter functions of a query (the all-hits
//! collector) and of a geometry see every crossing, not only the nearest.

use std::ffi::c_void;
use std::mem::MaybeUninit;

use super::filter;
use super::query::Query;
use super::sys;
use crate::accel::panics::PanicSlot;
use crate::accel::primitive::{UserHit, UserPrimitive, crossings, held};
use crate::math::{Bounds, Ray, Vec3};

/// What Embree's geometry user pointer points at: the primitives (primID
/// indexes them), how far their boxes are grown (`primitive::padding`) and
/// the scene's panic slot.
pub(super) struct UserData<T> {
    pub(super) prims: Box<[T]>,
    pub(super) pad: f32,
    pub(super) panics: std::sync::Arc<PanicSlot>,
}

/// An SoA record of N lanes seen as 4-byte words: field `f` of lane `i` is
/// word `f * N + i`. Embree's `RTCRayN_*`/`RTCHitN_*` accessors are
/// FORCEINLINE; this is their layout. `W` is `u32` for the ray fields, which
/// Embree fills, and `MaybeUninit<u32>` for the hit fields, which are only
/// written (Embree's own packets may leave them uninitialised).
pub(super) struct Packet<'a, W> {
    words: &'a mut [W],
    n: usize,
}

impl<'a, W> Packet<'a, W> {
    /// The first `fields` fields of the record at `base`, for `n` lanes.
    ///
    /// # Safety
    /// `base` must point at a live SoA record of `n` lanes with at least
    /// `fields` fields, writable, touched by nothing else for `'a`; `W` must
    /// be `u32`, with the fields initialised, or `MaybeUninit<u32>`.
    pub(super) unsafe fn new(base: *mut u32, fields: usize, n: usize) -> Packet<'a, W> {
        // SAFETY: guaranteed by the caller; `MaybeUninit<u32>` has the layout of `u32`.
        let words = unsafe { std::slice::from_raw_parts_mut(base.cast::<W>(), fields * n) };
        Packet { words, n }
    }

    fn word(&mut self, f: usize, i: usize) -> &mut W {
        &mut self.words[f * self.n + i]
    }
}

impl Packet<'_, u32> {
    pub(super) fn f32(&self, f: usize, i: usize) -> f32 {
        f32::from_bits(self.u32(f, i))
    }

    pub(super) fn u32(&self, f: usize, i: usize) -> u32 {
        self.words[f * self.n + i]
    }

    pub(super) fn set_f32(&mut self, f: usize, i: usize, v: f32) {
        *self.word(f, i) = v.to_bits();
    }

    /// Lane `i`: fields 0..9 of an RTCRayN are org xyz, tnear, dir xyz, time, tfar.
    fn ray(&self, i: usize) -> Ray {
        Ray {
            origin: Vec3::new(self.f32(0, i), self.f32(1, i), self.f32(2, i)),
            dir: Vec3::new(self.f32(4, i), self.f32(5, i), self.f32(6, i)),
            tnear: self.f32(3, i),
            tfar: self.f32(TFAR, i),
        }
    }
}

impl Packet<'_, MaybeUninit<u32>> {
    fn set_f32(&mut self, f: usize, i: usize, v: f32) {
        self.set_u32(f, i, v.to_bits());
    }

    fn set_u32(&mut self, f: usize, i: usize, v: u32) {
        self.word(f, i).write(v);
    }
}

/// Word offsets in RTCRayN and, after the 12 ray words, in RTCHitN.
pub(super) const TFAR: usize = 8;
/// The ray's `id`, after its mask.
const ID: usize = 10;
const RAY_WORDS: usize = 12;
pub(super) const NG_X: usize = 0;
pub(super) const U: usize = 3;
pub(super) const V: usize = 4;
pub(super) const PRIM_ID: usize = 5;
pub(super) const GEOM_ID: usize = 6;
pub(super) const INST_ID: usize = 7;
const LEVELS: usize = sys::RTC_MAX_INSTANCE_LEVEL_COUNT as usize;
/// The widest ray packet Embree hands a callback (AVX-512: 16 lanes).
pub(super) const MAX_LANES: usize = 16;
/// The ray fields the callbacks read or write: up to tfar.
pub(super) const RAY_FIELDS: usize = TFAR + 1;
/// The hit fields the intersect callback writes: all of RTCHitN.
pub(super) const HIT_FIELDS: usize = if cfg!(embree_inst_prim_id) {
    INST_ID + 2 * LEVELS
} else {
    INST_ID + LEVELS
};

/// The primitive and its data behind a callback's user pointer.
///
/// # Safety
/// `user_ptr` must be the `UserData<T>` registered with the geometry, alive
/// for the call (the committed scene owns it and releases Embree's scene first).
unsafe fn primitive<'a, T>(
    user_ptr: *mut c_void,
    prim_id: u32,
) -> (&'a UserData<T>, Option<&'a T>) {
    // SAFETY: guaranteed by the caller; only shared references are formed.
    let data = unsafe { &*(user_ptr as *const UserData<T>) };
    (data, data.prims.get(prim_id as usize))
}

pub(super) extern "C" fn bounds_callback<T: UserPrimitive>(
    args: *const sys::RTCBoundsFunctionArguments,
) {
    // SAFETY: Embree passes valid arguments for the duration of the call.
    let args = unsafe { &*args };
    // SAFETY: the user pointer is our UserData<T> (set in `add_user`).
    let (data, prim) = unsafe { primitive::<T>(args.geometryUserPtr, args.primID) };
    let bounds = data.panics.guard(None, || prim.map(T::bounds));
    let bounds = held(bounds.unwrap_or(Bounds::EMPTY), data.pad);
    // SAFETY: bounds_o points at one writable RTCBounds.
    let out = unsafe { &mut *args.bounds_o };
    (out.lower_x, out.lower_y, out.lower_z) = (bounds.min.x, bounds.min.y, bounds.min.z);
    (out.upper_x, out.upper_y, out.upper_z) = (bounds.max.x, bounds.max.y, bounds.max.z);
}

pub(super) extern "C" fn intersect_callback<T: UserPrimitive>(
    args: *const sys::RTCIntersectFunctionNArguments,
) {
    // SAFETY: Embree passes valid arguments for the duration of the call.
    let args = unsafe { &*args };
    // SAFETY: the user pointer is our UserData<T>.
    let (data, prim) = unsafe { primitive::<T>(args.geometryUserPtr, args.primID) };
    let n = args.N as usize;
    if n > MAX_LANES {
        return;
    }
    // SAFETY: every intersect query passes a pointer made from a whole `Query` (Embree's
    // context first), live for the query; Embree hands it on unchanged. Only the f64
    // ray is read (Embree writes the instance stack before it), and no reference to
    // the context is kept.
    let exact = unsafe { (*args.context.cast::<Query>()).exact };
    let base = args.rayhit.cast::<u32>();
    for i in 0..n {
        // SAFETY: `valid` has N initialised entries, lent to this call; no reference to
        // it is held across the filter calls below.
        let active = unsafe { *args.valid.wrapping_add(i) } == -1;
        if !active {
            continue;
        }
        // SAFETY: `rayhit` is a live RTCRayHitN of N lanes (12 ray words each, the id
        // the 11th) that Embree filled with the rays and lends to this call; the packet
        // lives only for these reads.
        let lanes = unsafe { Packet::<u32>::new(base, ID + 1, n) };
        let (ray, id) = (lanes.ray(i), lanes.u32(ID, i));
        // The query's f64 ray, where this lane's ray is its rounding: not in an
        // instance's space, where the lane holds the ray moved there.
        let exact = exact.for_lane(id, &ray);
        // Each crossing is offered to the filter functions (a query's all-hits
        // collector, a geometry's own), nearest first, until one is accepted.
        let found = data.panics.guard(None, || {
            prim.and_then(|p| crossings(p, &ray, &exact, |hit| filter::offer(args, i, hit)))
        });
        if let Some(hit) = found {
            // SAFETY: as above; the packets live only for these writes, after the filters ran.
            let mut rays = unsafe { Packet::<u32>::new(base, RAY_FIELDS, n) };
            rays.set_f32(TFAR, i, hit.t);
            // SAFETY: the hit part of that RTCRayHitN starts after the 12 ray words of N
            // lanes; the pointer stays inside the record.
            let hit_base = unsafe { base.add(RAY_WORDS * n) };
            // SAFETY: RTCHitN has HIT_FIELDS fields of N lanes, writable, lent to this call
            // and disjoint from `rays`; it is only written, so may be uninitialised.
            let mut hits = unsafe { Packet::<MaybeUninit<u32>>::new(hit_base, HIT_FIELDS, n) };
            // SAFETY: Embree passes the instance stack of the traversal, valid for the call.
            let context = unsafe { &*args.context };
            write_hit(&mut hits, i, &hit, args.primID, args.geomID, context);
        }
        // Embree 4 asks for -1 on an accepted hit and 0 on a miss; Embree 3 wants the
        // lane left alone.
        #[cfg(embree4)]
        {
            // SAFETY: as for `active`.
            unsafe { *args.valid.wrapping_add(i) = if found.is_some() { -1 } else { 0 } };
        }
    }
}

/// Writes lane `i` of an RTCHitN: Ng, u, v, the ids and the instance stack.
pub(super) fn write_hit(
    hits: &mut Packet<'_, MaybeUninit<u32>>,
    i: usize,
    hit: &UserHit,
    prim_id: u32,
    geom_id: u32,
    #[cfg(embree3)] context: &sys::RTCIntersectContext,
    #[cfg(embree4)] context: &sys::RTCRayQueryContext,
) {
    hits.set_f32(NG_X, i, hit.ng.x);
    hits.set_f32(NG_X + 1, i, hit.ng.y);
    hits.set_f32(NG_X + 2, i, hit.ng.z);
    hits.set_f32(U, i, hit.u);
    hits.set_f32(V, i, hit.v);
    hits.set_u32(PRIM_ID, i, prim_id);
    hits.set_u32(GEOM_ID, i, geom_id);
    for level in 0..LEVELS {
        hits.set_u32(INST_ID + level, i, context.instID[level]);
        #[cfg(embree_inst_prim_id)]
        hits.set_u32(INST_ID + LEVELS + level, i, context.instPrimID[level]);
    }
}

pub(super) extern "C" fn occluded_callback<T: UserPrimitive>(
    args: *const sys::RTCOccludedFunctionNArguments,
) {
    // SAFETY: Embree passes valid arguments for the duration of the call.
    let args = unsafe { &*args };
    // SAFETY: the user pointer is our UserData<T>.
    let (data, prim) = unsafe { primitive::<T>(args.geometryUserPtr, args.primID) };
    let n = args.N as usize;
    // SAFETY: `ray` is a live, writable RTCRayN of N lanes that Embree filled and lends to
    // this call.
    let mut rays = unsafe { Packet::<u32>::new(args.ray.cast(), RAY_FIELDS, n) };
    // SAFETY: `valid` has N initialised, writable entries, lent to this call.
    let valid = unsafe { std::slice::from_raw_parts_mut(args.valid, n) };
    for (i, valid) in valid.iter_mut().enumerate() {
        if *valid != -1 {
            continue;
        }
        let ray = rays.ray(i);
        let blocked = data
            .panics
            .guard(false, || prim.is_some_and(|p| p.occluded(&ray)));
        if blocked {
            rays.set_f32(TFAR, i, f32::NEG_INFINITY);
        }
        #[cfg(embree4)]
        {
            *valid = if blocked { -1 } else { 0 };
        }
    }
}
