//! Materials and the local shading model.

mod bsdf;
pub mod fresnel;
mod material;

pub use bsdf::{
    Bsdf, BsdfSample, COS_EPS, Dielectric, Lambert, Lobe, MIN_ALPHA, Metal, Mirror, Plastic,
    Transport, shininess_to_alpha,
};
pub use material::{Material, MaterialKind};
