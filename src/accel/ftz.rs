//! Flush-to-zero and denormals-are-zero for the calling thread, set on every
//! thread that traces or solves, whichever backend: denormal arithmetic takes a
//! slow path on x86, Embree asks for both modes, and the pure-Rust backends and
//! the root finders run under the same modes so every backend rounds alike.
//!
//! Writing MXCSR takes inline assembly (`ldmxcsr`; std's `_mm_setcsr` is
//! deprecated, and there is no checked intrinsic), which the crate allows
//! only in `accel/embree/`. So the instruction stays there, in
//! `embree/fpu.rs`, and this module is the backend-neutral name the rest of
//! the crate imports, which does not tie render or report to Embree.

pub use super::embree::fpu::enable_flush_to_zero;
