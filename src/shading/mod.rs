//! Materials and the local shading model.

mod bsdf;
mod finish;
pub mod fresnel;
mod material;
mod pattern;
mod texture;

pub use bsdf::{
    Bsdf, BsdfSample, COS_EPS, Classic, Dielectric, Lambert, Lobe, MIN_ALPHA, Metal, Mirror,
    Plastic, Transport, shininess_to_alpha,
};
pub use finish::Finish;
pub use material::{Bump, Maps, Material, MaterialKind};
pub use pattern::Checker;
pub use texture::{Image, Texture, TextureSource, srgb_to_linear};
