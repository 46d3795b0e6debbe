//! sturmray: a ray tracer for triangle meshes mixed with exact analytic
//! surfaces, on Intel Embree. See DESIGN.md in the shared folder for the map.

pub mod accel;
pub mod error;
pub mod math;
