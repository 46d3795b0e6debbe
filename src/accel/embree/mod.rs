//! The safe wrapper around Embree: ALL of the crate's unsafe code lives here.
//!
//! Bindings come from the installed header at build time (`sys`). Handles are
//! `NonNull` newtypes released on drop; a scene is built by a `SceneBuilder`
//! and queried only once committed; Embree errors reach Rust through the device
//! error callback and are drained after builds, commits and batches.

mod device;
mod fpu;
mod query;
mod scene;
mod sys;
mod user;

pub use device::{Device, HEADER_VERSION, Version};
pub use fpu::enable_flush_to_zero;
pub use scene::{BuildQuality, CommittedScene, SceneBuilder, SceneOptions};
pub use user::{UserHit, UserPrimitive};

#[cfg(test)]
mod tests;
