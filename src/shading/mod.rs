//! Materials and the local shading model.

mod material;

pub use material::{Material, MaterialKind};
