//! Shapes: triangle meshes (and, with the analytic-surface work, spheres,
//! quadrics, tori and algebraic surfaces).

mod analytic;
mod mesh;

pub use analytic::csg::{Csg, CsgError, Leaf, Node, Op, Part};
pub use analytic::{
    Box3, Crossing, Crossings, Pinhole, Quadric, RayPoly, Shape, ShapeBeams, ShapeHit, Surface,
    shadow_start_bound,
};
pub use mesh::Mesh;
