//! File formats: EXR images, PNG previews, .npy rays and hits, film states,
//! texture images in.
//!
//! Each writer produces the same bytes for the same data (no timestamps, no
//! hash-map order), so equal renders give equal files and tests can compare
//! them byte for byte. Readers reject malformed files with [`Error::Input`]
//! naming the path and what was expected; failures of the file system
//! itself are [`Error::Io`]. Inputs are opened with [`input::open_regular`]
//! and checked against their size before anything is allocated; outputs are
//! written with [`output::write_atomic`], so none is ever left half written.
//!
//! [`Error::Input`]: crate::error::Error::Input
//! [`Error::Io`]: crate::error::Error::Io

pub mod console;
pub mod exr;
pub mod input;
pub mod npy;
pub mod output;
pub mod png;
pub mod state;
pub mod texture;
