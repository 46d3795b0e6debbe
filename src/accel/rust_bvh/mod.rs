//! The pure-Rust backends: the same scenes and the same answers as Embree,
//! through BVHs from crates.io. Both index one shared primitive list
//! (`primitives`): mesh triangles, tested as Embree's robust mode tests them
//! (`triangle`), and analytic shapes, tested by the same f64 intersectors
//! Embree calls back into.

mod cwbvh;
mod list;
mod primitives;
mod sah;
mod triangle;

pub use cwbvh::CwbvhScene;
pub use list::{LightBeams, ListBeams, ListScene, ShapeSet};
pub use sah::SahScene;

#[cfg(test)]
mod tests;
