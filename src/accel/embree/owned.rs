//! Data handed to Embree as a callback's user pointer, owned by Rust.
//!
//! A `Box` asserts unique access each time it is moved or used, so a raw
//! pointer taken from `&*boxed` stops being valid for Embree's later calls
//! once the box moves into a `Vec` or an `Arc` (Stacked Borrows). Instead the
//! allocation is turned into a raw pointer once, with `Box::leak` (that is
//! `Box::into_raw`, as a reference, so no null check is needed), and every
//! access, Embree's and ours, derives from that one pointer; the box is rebuilt
//! only to free it (rusqlite hands its callbacks' state to SQLite the same way).

use std::ffi::c_void;
use std::ptr::NonNull;

/// An owned `T` behind a stable pointer that Embree may hold. The owner must
/// release the Embree object that holds the pointer before dropping this:
/// the owners declare it after that object's handle, so fields drop in order.
pub(super) struct UserPtr<T: ?Sized>(NonNull<T>);

impl<T: ?Sized> UserPtr<T> {
    pub(super) fn new(value: Box<T>) -> UserPtr<T> {
        UserPtr(NonNull::from(Box::leak(value)))
    }

    /// The pointer to register with Embree: callbacks form only shared
    /// references from it.
    pub(super) fn as_c_void(&self) -> *mut c_void {
        self.0.as_ptr().cast()
    }

    pub(super) fn get(&self) -> &T {
        // SAFETY: the pointer came from a live Box (`new`) and is freed only in `Drop`;
        // everyone, Embree's callbacks included, forms only shared references from it.
        unsafe { self.0.as_ref() }
    }
}

impl<T: ?Sized> Drop for UserPtr<T> {
    fn drop(&mut self) {
        // SAFETY: the pointer came from `Box::leak` in `new` and is rebuilt once, here;
        // the owner has already released the Embree object that used it (field order).
        drop(unsafe { Box::from_raw(self.0.as_ptr()) });
    }
}
