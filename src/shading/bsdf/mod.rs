//! Scattering functions (BSDFs): the `Bsdf` enum, which dispatches eval, pdf
//! and sampling to one type per lobe (one submodule each, with the GGX
//! microfacet distribution the rough ones share), and what every lobe shares.
//!
//! # Conventions
//!
//! - **Normal.** The caller builds the [`Frame`] from the surface's *outward*
//!   normal (out of the material, e.g. a sphere's gradient), **not** a normal
//!   flipped toward the viewer. A dielectric needs it to tell entering from
//!   leaving: `wo` on the normal's side means the path is outside. Opaque
//!   reflection lobes (Lambert, plastic, mirror, metal) are two-sided: seen
//!   from the back they reflect into the back hemisphere, so meshes with
//!   either winding shade alike.
//! - **Directions** are unit world vectors pointing *away* from the surface:
//!   `wo` toward the viewer (the previous path vertex), `wi` toward the light
//!   or the next vertex. Internally everything works in the local frame where
//!   the normal is +z, so cosθ = `w.z`. The lobe types work in that frame;
//!   the opaque ones see both directions moved to the upper hemisphere, and
//!   `Bsdf` converts and moves them back.
//! - **ior** is the material's index relative to the outside medium
//!   (η = n_inside / n_outside), as in [`super::fresnel`].
//! - **Values.** [`Bsdf::eval`] returns f (no cosine); the rendering equation
//!   term is `f·|cos θi|`. A [`BsdfSample`] carries f and pdf with the
//!   convention throughput ×= f·|cos θi| / pdf for every lobe, delta ones
//!   included (pbrt's convention: a delta lobe's pdf is the discrete
//!   probability of picking it and f holds the value divided by |cos θi|),
//!   and carries that product ready-made as `weight`, computed without the
//!   cancelling divisions.
//! - **Numerics.** f32 throughout; no allocation; no NaN. Directions within
//!   [`COS_EPS`] of the tangent plane scatter nothing: f ∝ 1/cos there and the
//!   set has measure zero, so dropping it costs no energy worth measuring.

mod classic;
mod dielectric;
mod ggx;
mod lambert;
mod metal;
mod mirror;
mod plastic;
#[cfg(test)]
mod tests;

pub use classic::Classic;
pub use dielectric::Dielectric;
pub use ggx::{MIN_ALPHA, shininess_to_alpha};
pub use lambert::Lambert;
pub use metal::Metal;
pub use mirror::Mirror;
pub use plastic::Plastic;

use crate::math::{Frame, Vec3};
use crate::shading::{Material, MaterialKind, Surface};

/// The normal-incidence reflectance of a dielectric of index 1.5,
/// ((1.5 − 1)/(1.5 + 1))²: what glTF and Blender's Principled BSDF give a
/// surface that is not metal.
pub const DIELECTRIC_F0: f32 = 0.04;

/// Cosines smaller than this count as grazing: such directions get f = 0,
/// pdf = 0 and no sample, which keeps every 1/cos finite.
pub const COS_EPS: f32 = 1e-6;

/// Which kind of scattering a sample took: the ray kind for statistics and
/// for path-space decisions (photons are stored at diffuse vertices only).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Lobe {
    DiffuseReflection,
    GlossyReflection,
    SpecularReflection,
    SpecularTransmission,
}

impl Lobe {
    pub fn is_reflection(self) -> bool {
        !self.is_transmission()
    }

    pub fn is_transmission(self) -> bool {
        self == Lobe::SpecularTransmission
    }

    pub fn is_diffuse(self) -> bool {
        self == Lobe::DiffuseReflection
    }

    pub fn is_glossy(self) -> bool {
        self == Lobe::GlossyReflection
    }

    /// A delta lobe: one outgoing direction per incoming one.
    pub fn is_specular(self) -> bool {
        matches!(self, Lobe::SpecularReflection | Lobe::SpecularTransmission)
    }
}

/// What a path carries, which decides the refraction scaling (Veach 1997,
/// §5.2). Radiance crossing into a denser medium grows by (n_t/n_i)²: the
/// same flux squeezes into a narrower cone. A camera path, sampled backwards
/// from `wo`, therefore weights a refraction by 1/η² with η = n_t/n_i seen
/// from `wo`'s side (1/ior² looking into glass, ior² looking out), and a
/// round trip through glass cancels. Flux carried by photons from the lights
/// is not rescaled. Only smooth refraction is affected.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Transport {
    #[default]
    Radiance,
    Importance,
}

/// One sampled scattering direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// The sampled direction in world space, pointing away from the surface.
    pub wi: Vec3,
    /// The BSDF value (no cosine). For a delta lobe the value divided by
    /// |cos θi|, so that `f·|cos θi|/pdf` is the weight for every lobe.
    pub f: Vec3,
    /// Solid-angle density of `wi`; for a delta lobe the discrete probability
    /// of choosing it (1 for a mirror, F or 1 − F for glass). Always > 0.
    pub pdf: f32,
    /// `f·|cos θi|/pdf`, the factor the path throughput is multiplied by.
    pub weight: Vec3,
    /// A delta lobe: `wi` is the only direction, so light sampling and MIS
    /// cannot reach it and `eval`/`pdf` report 0 for it.
    pub delta: bool,
    pub kind: Lobe,
}
impl BsdfSample {
    /// A sample as a lobe makes it, `wi` in the local frame; `delta` follows
    /// from the kind.
    fn new(wi: Vec3, f: Vec3, pdf: f32, weight: Vec3, kind: Lobe) -> BsdfSample {
        BsdfSample {
            wi,
            f,
            pdf,
            weight,
            delta: kind.is_specular(),
            kind,
        }
    }
}

/// A surface's scattering function: one variant per lobe type, each of which
/// documents its model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bsdf {
    Lambert(Lambert),
    Plastic(Plastic),
    Mirror(Mirror),
    Metal(Metal),
    Dielectric(Dielectric),
    Classic(Classic),
}

impl Bsdf {
    /// The scattering function of a material away from any pattern or map:
    /// for the plan's questions about its lobes, which they do not change.
    pub fn from_material(m: &Material) -> Bsdf {
        Bsdf::at(m, &m.constant_surface())
    }

    /// The scattering function of a material whose values at the hit are
    /// `s` ([`Material::surface_at`]). Emissive surfaces reflect as
    /// Lambert with their albedo; their emission belongs to the lights. A
    /// mirror reflects its specular colour (MTL Ks) if it has one, else its
    /// albedo. A metal where its metalness is below 0.5 (`map_Pm`) is its
    /// dielectric counterpart, glTF's and Blender's: plastic with the
    /// albedo as base, F0 = [`DIELECTRIC_F0`] and the metal's roughness.
    /// Glass is untinted; an ior that is not a positive finite number
    /// becomes 1.5 so a bad value cannot produce NaN.
    pub fn at(m: &Material, s: &Surface) -> Bsdf {
        let albedo = s.albedo;
        match m.kind {
            MaterialKind::Diffuse | MaterialKind::Emissive => Bsdf::Lambert(Lambert { albedo }),
            MaterialKind::Plastic => Bsdf::Plastic(Plastic {
                albedo,
                specular: s.specular,
                roughness: shininess_to_alpha(m.shininess),
            }),
            MaterialKind::Mirror => Bsdf::Mirror(Mirror {
                reflectance: m.reflectance(s),
            }),
            MaterialKind::Metal if s.metallic < 0.5 => Bsdf::Plastic(Plastic {
                albedo,
                specular: Vec3::splat(DIELECTRIC_F0),
                roughness: (s.roughness * s.roughness).clamp(MIN_ALPHA, 1.0),
            }),
            MaterialKind::Metal => Bsdf::Metal(Metal {
                f0: albedo,
                roughness: (s.roughness * s.roughness).clamp(MIN_ALPHA, 1.0),
            }),
            MaterialKind::Dielectric => Bsdf::Dielectric(Dielectric {
                ior: if m.ior.is_finite() && m.ior > 0.0 {
                    m.ior
                } else {
                    1.5
                },
                tint: Vec3::ONE,
            }),
            MaterialKind::Classic => Bsdf::Classic(Classic {
                albedo,
                finish: m.finish,
                ior: m.ior,
            }),
        }
    }

    /// Only delta lobes: eval and pdf are zero everywhere, so light sampling
    /// is useless here and the integrator must follow `sample`.
    pub fn is_delta(&self) -> bool {
        match self {
            Bsdf::Mirror(_) | Bsdf::Dielectric(_) => true,
            Bsdf::Classic(c) => !c.has_local(),
            _ => false,
        }
    }

    /// Spawns refraction rays (the render plan's "refraction" kind).
    pub fn has_transmission(&self) -> bool {
        match self {
            Bsdf::Dielectric(_) => true,
            Bsdf::Classic(c) => c.finish.transmits(),
            _ => false,
        }
    }

    /// Has a delta (perfectly specular) lobe: needs recursive reflection or
    /// refraction rays in a Whitted tracer, and is the "S" of L S+ D caustic
    /// paths.
    pub fn has_specular(&self) -> bool {
        match self {
            Bsdf::Classic(c) => c.finish.reflects(c.ior) || c.finish.transmits(),
            _ => self.is_delta(),
        }
    }

    /// Has a glossy (microfacet) lobe: highlights that light sampling can
    /// reach, and reflections a path tracer samples.
    pub fn has_glossy(&self) -> bool {
        match self {
            Bsdf::Plastic(_) | Bsdf::Metal(_) => true,
            Bsdf::Classic(c) => c.has_local() && c.finish.specular + c.finish.phong > 0.0,
            _ => false,
        }
    }

    /// The colour for the albedo AOV: the diffuse colour, a mirror's
    /// reflectance, a metal's F0, glass's tint.
    pub fn albedo(&self) -> Vec3 {
        match *self {
            Bsdf::Lambert(Lambert { albedo })
            | Bsdf::Plastic(Plastic { albedo, .. })
            | Bsdf::Classic(Classic { albedo, .. }) => albedo,
            Bsdf::Mirror(Mirror { reflectance }) => reflectance,
            Bsdf::Metal(Metal { f0, .. }) => f0,
            Bsdf::Dielectric(Dielectric { tint, .. }) => tint,
        }
    }

    /// f(wo, wi) for world directions pointing away from the surface; zero
    /// for delta lobes, for directions on opposite sides (no lobe here
    /// transmits diffusely) and for grazing directions.
    pub fn eval(&self, frame: &Frame, wo: Vec3, wi: Vec3) -> Vec3 {
        let Some((wo, wi)) = same_side(frame.to_local(wo), frame.to_local(wi)) else {
            return Vec3::ZERO;
        };
        match self {
            Bsdf::Lambert(l) => l.eval(),
            Bsdf::Plastic(p) => p.eval(wo, wi),
            Bsdf::Mirror(m) => m.eval(),
            Bsdf::Metal(m) => m.eval(wo, wi),
            Bsdf::Dielectric(d) => d.eval(),
            Bsdf::Classic(c) => c.eval(wo, wi),
        }
    }

    /// The solid-angle density with which [`Bsdf::sample`] picks `wi` given
    /// `wo` (not symmetric in its arguments); zero for delta lobes.
    pub fn pdf(&self, frame: &Frame, wo: Vec3, wi: Vec3) -> f32 {
        let Some((wo, wi)) = same_side(frame.to_local(wo), frame.to_local(wi)) else {
            return 0.0;
        };
        match self {
            Bsdf::Lambert(l) => l.pdf(wi),
            Bsdf::Plastic(p) => p.pdf(wo, wi),
            Bsdf::Mirror(m) => m.pdf(),
            Bsdf::Metal(m) => m.pdf(wo, wi),
            Bsdf::Dielectric(d) => d.pdf(),
            Bsdf::Classic(c) => c.pdf(wo, wi),
        }
    }

    /// Samples `wi` for a camera path (radiance transport). `u` holds three
    /// uniform numbers in [0, 1): u[0] picks a lobe (plastic, glass), u[1]
    /// and u[2] the direction. `None` means the path ends here: a grazing
    /// `wo`, or a microfacet sample below the horizon (which the pdf
    /// accounts for, so no bias).
    pub fn sample(&self, frame: &Frame, wo: Vec3, u: [f32; 3]) -> Option<BsdfSample> {
        self.sample_with(frame, wo, u, Transport::Radiance)
    }

    /// [`Bsdf::sample`] with an explicit transport mode: light paths (photons)
    /// pass [`Transport::Importance`] so refraction does not rescale flux.
    pub fn sample_with(
        &self,
        frame: &Frame,
        wo_world: Vec3,
        u: [f32; 3],
        mode: Transport,
    ) -> Option<BsdfSample> {
        let wo = frame.to_local(wo_world);
        if wo.z.is_nan() || wo.z.abs() < COS_EPS {
            return None;
        }
        let local = match self {
            Bsdf::Lambert(l) => two_sided(wo, |_| l.sample(u)),
            Bsdf::Plastic(p) => two_sided(wo, |up| p.sample(up, u)),
            Bsdf::Mirror(m) => Some(m.sample(wo)),
            Bsdf::Metal(m) => two_sided(wo, |up| m.sample(up, u)),
            Bsdf::Dielectric(d) => d.sample(wo, u[0], mode),
            Bsdf::Classic(c) => c.sample(wo, u, mode),
        }?;
        Some(BsdfSample {
            wi: frame.to_world(local.wi),
            ..local
        })
    }
}

/// The two local directions moved to the upper hemisphere together, or
/// `None` if they lie on opposite sides or either grazes the surface.
fn same_side(wo: Vec3, wi: Vec3) -> Option<(Vec3, Vec3)> {
    if !(wo.z.abs() >= COS_EPS && wi.z.abs() >= COS_EPS) || (wo.z > 0.0) != (wi.z > 0.0) {
        return None;
    }
    if wo.z > 0.0 {
        Some((wo, wi))
    } else {
        Some((Vec3::new(wo.x, wo.y, -wo.z), Vec3::new(wi.x, wi.y, -wi.z)))
    }
}

/// Samples an opaque reflection lobe, which works in the upper hemisphere,
/// for a local `wo` on either side: the lobe sees `wo` moved up, and its `wi`
/// goes back to wo's side (two-sided shading).
fn two_sided(wo: Vec3, sample: impl FnOnce(Vec3) -> Option<BsdfSample>) -> Option<BsdfSample> {
    let side = 1.0f32.copysign(wo.z);
    let s = sample(Vec3::new(wo.x, wo.y, wo.z.abs()))?;
    Some(BsdfSample {
        wi: Vec3::new(s.wi.x, s.wi.y, side * s.wi.z),
        ..s
    })
}
