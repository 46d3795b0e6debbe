//! The safe wrapper around Embree: ALL of the crate's unsafe code lives here.
//!
//! Bindings come from the installed header at build time (`sys`, the
//! embree-sys crate in ffi/). Handles are
//! `NonNull` newtypes released on drop; a scene is built by a `SceneBuilder`
//! and queried only once committed; Embree errors reach Rust through the device
//! error callback and are drained after builds, commits and batches.

mod device;
mod exit;
mod filter;
// Crate-visible for `accel::ftz`, the neutral name of its one function.
pub(crate) mod fpu;
mod instance;
mod owned;
mod query;
mod scene;
// The raw bindings, from the workspace's embree-sys crate (ffi/).
use embree_sys as sys;
mod user;

pub use device::{Device, HEADER_VERSION, Version};
pub use exit::exit_at_once;
pub use scene::{BuildQuality, CommittedScene, STREAM, SceneBuilder, SceneOptions};

#[cfg(test)]
mod tests;
