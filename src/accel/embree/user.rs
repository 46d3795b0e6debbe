//! Embree user geometry: primitives whose bounds, intersect and occluded
//! callbacks are Rust.
//!
//! The wrapper, not the primitive, owns the callback contract: it decodes
//! Embree's SoA ray packets, skips inactive lanes, accepts a hit only in
//! [tnear, tfar) of the lane, writes the whole hit record (t, Ng, u, v, primID,
//! geomID, the instance stack), sets tfar = −inf for occlusion, writes Embree
//! 4's `valid` flags, and catches every panic: a panicking primitive is a
//! miss, and the panic becomes an `Error` at the scene's next `check()`.
//! No filter functions are registered anywhere in sturmray, so there are none
//! to invoke from the callbacks.

use std::ffi::c_void;

use super::sys;
use crate::accel::panics::PanicSlot;
use crate::accel::primitive::UserPrimitive;
use crate::math::{Bounds, Ray, Vec3};

/// What Embree's geometry user pointer points at: the primitives (primID
/// indexes them) and the scene's panic slot.
pub(super) struct UserData<T> {
    pub(super) prims: Box<[T]>,
    pub(super) panics: std::sync::Arc<PanicSlot>,
}

/// Lane `i` of an SoA packet of N: field `f` (in 4-byte words) of the record.
/// Embree's `RTCRayN_*`/`RTCHitN_*` accessors are FORCEINLINE; this is their layout.
struct Packet {
    base: *mut u32,
    n: usize,
}

impl Packet {
    /// # Safety
    /// `base` must point at an SoA record of `n` lanes holding field `f`, lane `i < n`.
    unsafe fn f32(&self, f: usize, i: usize) -> f32 {
        // SAFETY: guaranteed by the caller.
        unsafe { f32::from_bits(*self.base.add(f * self.n + i)) }
    }

    /// # Safety
    /// As for `f32`, and the record must be writable.
    unsafe fn set_f32(&self, f: usize, i: usize, v: f32) {
        // SAFETY: guaranteed by the caller.
        unsafe { *self.base.add(f * self.n + i) = v.to_bits() }
    }

    /// # Safety
    /// As for `set_f32`.
    unsafe fn set_u32(&self, f: usize, i: usize, v: u32) {
        // SAFETY: guaranteed by the caller.
        unsafe { *self.base.add(f * self.n + i) = v }
    }

    /// # Safety
    /// As for `f32`.
    unsafe fn ray(&self, i: usize) -> Ray {
        // SAFETY: fields 0..9 of an RTCRayN: org xyz, tnear, dir xyz, time, tfar.
        unsafe {
            Ray {
                origin: Vec3::new(self.f32(0, i), self.f32(1, i), self.f32(2, i)),
                dir: Vec3::new(self.f32(4, i), self.f32(5, i), self.f32(6, i)),
                tnear: self.f32(3, i),
                tfar: self.f32(8, i),
            }
        }
    }
}

/// Word offsets in RTCRayN and, after the 12 ray words, in RTCHitN.
const TFAR: usize = 8;
const RAY_WORDS: usize = 12;
const NG_X: usize = 0;
const U: usize = 3;
const V: usize = 4;
const PRIM_ID: usize = 5;
const GEOM_ID: usize = 6;
const INST_ID: usize = 7;
const LEVELS: usize = sys::RTC_MAX_INSTANCE_LEVEL_COUNT as usize;

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
    let bounds = match data.panics.guard(None, || prim.map(T::bounds)) {
        Some(b) if !b.is_empty() && b.min.is_finite() && b.max.is_finite() => b,
        _ => Bounds {
            min: Vec3::ZERO,
            max: Vec3::ZERO,
        },
    };
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
    let rays = Packet {
        base: args.rayhit as *mut u32,
        n,
    };
    let hits = Packet {
        // SAFETY: the hit part of an RTCRayHitN starts after the 12 ray words of N lanes.
        base: unsafe { (args.rayhit as *mut u32).add(RAY_WORDS * n) },
        n,
    };
    for i in 0..n {
        // SAFETY: `valid` has N entries.
        let valid = unsafe { &mut *args.valid.add(i) };
        if *valid != -1 {
            continue;
        }
        // SAFETY: lane i < N of a live RTCRayHitN.
        let ray = unsafe { rays.ray(i) };
        let found = data
            .panics
            .guard(None, || prim.and_then(|p| p.intersect(&ray)));
        let hit = found.filter(|h| h.t >= ray.tnear && h.t < ray.tfar && h.t.is_finite());
        let Some(hit) = hit else {
            // Embree 4 asks for 0 on a miss; Embree 3 wants the lane left alone.
            #[cfg(embree4)]
            {
                *valid = 0;
            }
            continue;
        };
        // SAFETY: lane i < N of a live, writable RTCRayHitN; the context is valid for the call.
        unsafe {
            rays.set_f32(TFAR, i, hit.t);
            hits.set_f32(NG_X, i, hit.ng.x);
            hits.set_f32(NG_X + 1, i, hit.ng.y);
            hits.set_f32(NG_X + 2, i, hit.ng.z);
            hits.set_f32(U, i, hit.u);
            hits.set_f32(V, i, hit.v);
            hits.set_u32(PRIM_ID, i, args.primID);
            hits.set_u32(GEOM_ID, i, args.geomID);
            let context = &*args.context;
            for level in 0..LEVELS {
                hits.set_u32(INST_ID + level, i, context.instID[level]);
                #[cfg(embree_inst_prim_id)]
                hits.set_u32(INST_ID + LEVELS + level, i, context.instPrimID[level]);
            }
        }
        // Embree 4: the callback reports the accepted hit.
        #[cfg(embree4)]
        {
            *valid = -1;
        }
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
    let rays = Packet {
        base: args.ray as *mut u32,
        n,
    };
    for i in 0..n {
        // SAFETY: `valid` has N entries.
        let valid = unsafe { &mut *args.valid.add(i) };
        if *valid != -1 {
            continue;
        }
        // SAFETY: lane i < N of a live RTCRayN.
        let ray = unsafe { rays.ray(i) };
        let blocked = data
            .panics
            .guard(false, || prim.is_some_and(|p| p.occluded(&ray)));
        if blocked {
            // SAFETY: lane i < N of a live, writable RTCRayN.
            unsafe { rays.set_f32(TFAR, i, f32::NEG_INFINITY) };
        }
        #[cfg(embree4)]
        {
            *valid = if blocked { -1 } else { 0 };
        }
    }
}
