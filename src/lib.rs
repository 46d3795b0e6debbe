//! sturmray: a ray tracer for triangle meshes mixed with exact analytic
//! surfaces, on Intel Embree. See ARCHITECTURE.md for the map.

pub mod accel;
pub mod error;
pub mod film;
pub mod geometry;
pub mod io;
pub mod lights;
pub mod math;
pub mod poly;
pub mod render;
pub mod report;
pub mod sampling;
pub mod scene;
pub mod shading;
pub mod suggest;
