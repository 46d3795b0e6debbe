//! Materials and the local shading model.

mod bsdf;
mod finish;
pub mod fresnel;
mod mapped;
mod material;
mod pattern;
mod surface;
mod texture;

pub use bsdf::{
    Bsdf, BsdfSample, COS_EPS, Classic, DIELECTRIC_F0, Dielectric, Lambert, Lobe, MIN_ALPHA, Metal,
    Mirror, Plastic, Transport, shininess_to_alpha,
};
pub use finish::{Finish, InteriorFade};
pub use mapped::{Mapped, PatternKind, Wave};
pub(crate) use material::metalness;
pub use material::{Bump, Maps, Material, MaterialKind, Metallic};
pub use pattern::Checker;
pub use surface::Surface;
pub use texture::{Image, Texture, TextureSource, srgb_to_linear};
