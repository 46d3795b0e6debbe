//! Raw bindings to the installed Embree: bindgen's output for its header,
//! made at build time (see README.md). No safe API here: sturmray's
//! `accel::embree` wraps these, and is the only code that calls them.
#![allow(
    non_upper_case_globals,
    non_camel_case_types,
    non_snake_case,
    dead_code,
    unsafe_op_in_unsafe_fn,
    clippy::all,
    clippy::undocumented_unsafe_blocks,
    clippy::multiple_unsafe_ops_per_block
)]

include!(concat!(env!("OUT_DIR"), "/embree_sys.rs"));

/// `RTC_INVALID_GEOMETRY_ID` is the cast macro `((unsigned int)-1)`, which bindgen drops.
pub const RTC_INVALID_GEOMETRY_ID: u32 = u32::MAX;
