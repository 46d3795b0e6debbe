//! Shapes: triangle meshes (and, with the analytic-surface work, spheres,
//! quadrics, tori and algebraic surfaces).

mod mesh;

pub use mesh::Mesh;
