//! Materials, and how OBJ/MTL parameters map onto them.

use std::f32::consts::PI;

use crate::math::{Vec2, Vec3};
use crate::shading::{Checker, Finish, Mapped, Surface, Texture};

/// What a surface does with light. The local shading of the foundation
/// renderer uses albedo, specular and emission; the specular kinds gain their
/// ray-tree behaviour with the shading layer. Read from a scene file's `type = "diffuse"` (lowercase there only: the
/// scene hash serialises the names as written here).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all(deserialize = "lowercase"))]
pub enum MaterialKind {
    Diffuse,
    /// Diffuse plus a Blinn-Phong highlight.
    Plastic,
    Mirror,
    /// A rough conductor: a GGX microfacet lobe whose F0 is the albedo.
    Metal,
    Dielectric,
    Emissive,
    /// POV-Ray's finish and interior: diffuse, Blinn and Phong highlights,
    /// and fractions of mirror reflection and refraction (see [`Finish`]).
    Classic,
}

impl MaterialKind {
    /// Every kind, for messages that list those a key suits.
    pub const ALL: [MaterialKind; 7] = [
        MaterialKind::Diffuse,
        MaterialKind::Plastic,
        MaterialKind::Mirror,
        MaterialKind::Metal,
        MaterialKind::Dielectric,
        MaterialKind::Emissive,
        MaterialKind::Classic,
    ];

    /// The kind as a scene file spells it.
    pub fn name(self) -> String {
        format!("{self:?}").to_lowercase()
    }
}

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Material {
    pub name: String,
    pub kind: MaterialKind,
    /// Diffuse reflectance (Kd).
    pub albedo: Vec3,
    /// Specular reflectance (Ks).
    pub specular: Vec3,
    /// Blinn-Phong exponent (Ns).
    pub shininess: f32,
    /// A metal's perceptual roughness in [0, 1] (MTL's Pr); GGX α is its square.
    pub roughness: f32,
    /// Index of refraction (Ni).
    pub ior: f32,
    /// Emitted radiance (Ke).
    pub emission: Vec3,
    /// A classic material's finish; other kinds carry the default unused,
    /// which the scene hash skips so their hashes are unchanged.
    #[serde(skip_serializing_if = "Finish::is_default")]
    pub finish: Finish,
    /// A checker the albedo follows instead of `albedo` (POV-Ray's `pigment
    /// { checker … }`); left out of the scene hash when absent, so scenes
    /// without one hash as before.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub checker: Option<Checker>,
    /// A colour-mapped pattern the albedo follows instead of `albedo`
    /// (POV-Ray's `pigment { gradient y color_map { … } }`); left out of
    /// the scene hash when absent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mapped: Option<Mapped>,
    /// An image the albedo follows where the surface has texture
    /// coordinates (MTL's `map_Kd`, a scene file's `albedo = { texture }`),
    /// instead of `albedo`; left out of the scene hash when absent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub albedo_map: Option<Texture>,
    /// The MTL maps beyond `map_Kd`, each used where the surface has
    /// texture coordinates; left out of the scene hash when there are none.
    #[serde(skip_serializing_if = "Maps::is_empty")]
    pub maps: Maps,
}

/// A material's image maps other than the albedo's: MTL's `map_d`, `bump`,
/// `norm`, and the maps that scale a constant at each hit ([`Surface`]):
/// `map_Ks`, `map_Pr`, `map_Pm`, `map_Ke`.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Maps {
    /// A cut-out mask (`map_d`): where its opacity ([`Texture::opacity`])
    /// is below [`Material::CUTOFF`], rays pass through as if nothing were
    /// there, in every backend and for every kind of ray.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub alpha: Option<Texture>,
    /// A height map (`bump`, `map_Bump`) that tilts the shading normal.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bump: Option<Bump>,
    /// A tangent-space normal map (`norm`): RGB in [0, 1] is the normal's
    /// components in [−1, 1] along the tangent (dp/du), the bitangent and
    /// the normal.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub normal: Option<Texture>,
    /// The specular colour's factor (`map_Ks`, an sRGB colour map).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub specular: Option<Texture>,
    /// A metal's roughness factor (`map_Pr`, a linear scalar map).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub roughness: Option<Texture>,
    /// A metal's metalness (`map_Pm`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub metallic: Option<Metallic>,
    /// The emission's factor (`map_Ke`, an sRGB colour map).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub emission: Option<Texture>,
}

/// A metalness map (`map_Pm`, a linear scalar map) and the constant Pm it
/// scales: where their product is below 0.5 a metal is its dielectric
/// counterpart (the same threshold that makes an MTL material a metal).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Metallic {
    pub map: Texture,
    pub scale: f32,
}

/// A bump map: heights (the luminance of a linear image) times `scale`
/// (MTL's `-bm`), in the scene's units, along the normal.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Bump {
    pub heights: Texture,
    pub scale: f32,
}

/// The uv step of a bump map's finite differences, pbrt-v4's where a ray
/// has no differentials.
const BUMP_DU: f32 = 0.0005;

impl Maps {
    pub fn is_empty(&self) -> bool {
        *self == Maps::default()
    }

    /// Whether any map scales one of the constants of [`Surface`].
    pub fn scales(&self) -> bool {
        self.specular.is_some()
            || self.roughness.is_some()
            || self.metallic.is_some()
            || self.emission.is_some()
    }

    /// Whether the maps change the shading normal.
    pub fn bends(&self) -> bool {
        self.bump.is_some() || self.normal.is_some()
    }

    /// The shading normal at `uv` with the normal or bump map applied, as
    /// pbrt-v4's `NormalMap` and `BumpMap` do (without the dn/du terms): `ns`
    /// is the unmapped unit normal, `dpdu` and `dpdv` the surface's
    /// derivatives in uv. The geometric normal is not changed; the caller
    /// turns the result to its side. A normal map wins over a bump map.
    pub fn shading_normal(&self, ns: Vec3, dpdu: Vec3, dpdv: Vec3, uv: Vec2) -> Vec3 {
        if let Some(map) = &self.normal {
            let local = (2.0 * map.rgb(uv) - Vec3::ONE).normalize_or(Vec3::Z);
            let t = (dpdu - ns * ns.dot(dpdu)).normalize_or_zero();
            if t == Vec3::ZERO {
                return ns;
            }
            let b = ns.cross(t);
            return (local.x * t + local.y * b + local.z * ns).normalize_or(ns);
        }
        let Some(bump) = &self.bump else {
            return ns;
        };
        let height = |uv: Vec2| bump.scale * bump.heights.scalar(uv);
        let here = height(uv);
        let du = (height(uv + Vec2::new(BUMP_DU, 0.0)) - here) / BUMP_DU;
        let dv = (height(uv + Vec2::new(0.0, BUMP_DU)) - here) / BUMP_DU;
        let bumped = (dpdu + du * ns).cross(dpdv + dv * ns).normalize_or(ns);
        if bumped.dot(ns) < 0.0 {
            -bumped
        } else {
            bumped
        }
    }
}

impl Material {
    /// The grey diffuse material faces without one get.
    pub fn default_grey() -> Material {
        Material::diffuse("default", Vec3::splat(0.7))
    }

    pub fn diffuse(name: &str, albedo: Vec3) -> Material {
        Material {
            name: name.to_owned(),
            kind: MaterialKind::Diffuse,
            albedo,
            specular: Vec3::ZERO,
            shininess: 0.0,
            roughness: 0.3,
            ior: 1.5,
            emission: Vec3::ZERO,
            finish: Finish::default(),
            checker: None,
            mapped: None,
            albedo_map: None,
            maps: Maps::default(),
        }
    }

    /// The opacity below which a cut-out mask lets rays through, as
    /// Blender's alpha clip and pbrt-v4's alpha test (which skips a hit whose
    /// alpha is 0 and, between 0 and 1, stochastically; a fixed threshold
    /// keeps every backend's answers and renders deterministic).
    pub const CUTOFF: f32 = 0.5;

    /// Maps an MTL material: Ke > 0 → emissive; the PBR extension's metallic
    /// Pm ≥ 0.5 → metal (F0 = Kd, roughness Pr, else from Ns); illum 3 → mirror
    /// (Ks its reflectance); illum 4, 6, 7, 9 with Ni > 1, or d < 1 → dielectric
    /// with Ni (Maya writes `illum 4` with `Ni 1.00` and `d` 1 for every
    /// opaque lambert: glass that bends nothing and lets all through is no
    /// glass, and Blender's importer keeps such a material opaque); a
    /// nonzero Ks → plastic with Ns; otherwise diffuse. Kd defaults to 0.7 grey.
    /// A map given without its constant (`map_Ks` without Ks, `map_Ke`
    /// without Ke, `map_Pr` without Pr, `map_Pm` without Pm) takes the
    /// constant 1: the map alone sets the value, as in Blender's importer.
    pub fn from_mtl(m: &tobj::Material) -> Material {
        let mapped = |key: &str| m.unknown_param.contains_key(key);
        let albedo = m.diffuse.map_or(Vec3::splat(0.7), Vec3::from);
        let unset = |map: bool| if map { Vec3::ONE } else { Vec3::ZERO };
        let specular = m
            .specular
            .map_or(unset(m.specular_texture.is_some()), Vec3::from);
        let emission = m.emissive.map_or(unset(mapped("map_Ke")), Vec3::from);
        let illum = m
            .illumination_model
            .unwrap_or(if specular == Vec3::ZERO { 1 } else { 2 });
        let transparent = m.dissolve.is_some_and(|d| d < 1.0);
        let refracts = m.optical_density.is_some_and(|n| n > 1.0);
        let kind = if emission.max_element() > 0.0 {
            MaterialKind::Emissive
        } else if metalness(m) >= 0.5 {
            MaterialKind::Metal
        } else if illum == 3 {
            MaterialKind::Mirror
        } else if (matches!(illum, 4 | 6 | 7 | 9) && refracts) || transparent {
            MaterialKind::Dielectric
        } else if specular.max_element() > 0.0 && illum >= 2 {
            MaterialKind::Plastic
        } else {
            MaterialKind::Diffuse
        };
        Material {
            name: m.name.clone(),
            kind,
            albedo,
            specular,
            shininess: m.shininess.unwrap_or(0.0),
            // Without Pr, the GGX width that matches the Phong exponent (α = roughness²).
            roughness: match pbr(m, "Pr") {
                Some(r) => r.clamp(0.0, 1.0),
                None if mapped("map_Pr") => 1.0,
                None => crate::shading::shininess_to_alpha(m.shininess.unwrap_or(0.0)).sqrt(),
            },
            // Ni = 1 (or missing) in a glass material means "not set": use glass's 1.5.
            ior: m.optical_density.filter(|&n| n > 1.0).unwrap_or(1.5),
            emission,
            finish: Finish::default(),
            checker: None,
            mapped: None,
            albedo_map: None,
            maps: Maps::default(),
        }
    }

    /// Whether the surface is a light: emissive with some radiance (at some
    /// point: an emission map may be dark in places).
    pub fn emits(&self) -> bool {
        self.kind == MaterialKind::Emissive && self.emission.max_element() > 0.0
    }

    /// The albedo at world point `p` (within `error` per axis of the exact
    /// point) with texture coordinates `uv` (a mesh's that has them): the image's colour at `uv` if the material has one
    /// and the surface has uv, else the checker's or the mapped pattern's
    /// colour, in uv where there is uv and at `p` in space elsewhere, else
    /// `albedo`. Every use of the
    /// albedo at a hit goes through here; without a pattern it costs two
    /// branches.
    pub fn albedo_at(&self, p: Vec3, error: Vec3, uv: Option<Vec2>) -> Vec3 {
        if let (Some(map), Some(uv)) = (&self.albedo_map, uv) {
            return map.rgb(uv);
        }
        let at = || uv.map_or(p, |uv| uv.extend(0.0));
        match (&self.checker, &self.mapped) {
            (None, None) => self.albedo,
            (Some(checker), _) => match uv {
                Some(_) => checker.colour_at(at(), Vec3::ZERO),
                None => checker.colour_at(p, error),
            },
            (None, Some(mapped)) => mapped.colour_at(at()),
        }
    }

    /// What a mirror reflects at a hit whose values are `s`: its specular
    /// colour (MTL's Ks, times `map_Ks`) if the material has one, else its
    /// albedo there.
    pub fn reflectance(&self, s: &Surface) -> Vec3 {
        if self.specular.max_element() > 0.0 {
            s.specular
        } else {
            s.albedo
        }
    }

    /// The local reflection model (cosine not included): Lambert plus, for
    /// plastic, a normalised Blinn-Phong lobe, for unit vectors n, wo (towards
    /// the viewer) and wi (towards the light); a classic material's is
    /// POV-Ray's ([`Finish::local_brdf`]); a metal's is its BSDF. `s` is
    /// the material at the hit ([`Material::surface_at`]).
    pub fn local_brdf(&self, s: &Surface, n: Vec3, wo: Vec3, wi: Vec3) -> Vec3 {
        let diffuse = s.albedo / PI;
        match self.kind {
            MaterialKind::Plastic => {}
            MaterialKind::Classic => return self.finish.local_brdf(s.albedo, n, wo, wi),
            MaterialKind::Metal => {
                let frame = crate::math::Frame::from_normal(n);
                return crate::shading::Bsdf::at(self, s).eval(&frame, wo, wi);
            }
            _ => return diffuse,
        }
        let h = (wo + wi).normalize_or_zero();
        let cos_h = n.dot(h).max(0.0);
        // (s + 8) / 8π keeps the lobe's energy roughly constant as s changes.
        let lobe = (self.shininess + 8.0) / (8.0 * PI) * cos_h.powf(self.shininess);
        diffuse + s.specular * lobe
    }
}

/// A number of the MTL PBR extension (`Pr`, `Pm`), if the material has a
/// finite one.
fn pbr(m: &tobj::Material, key: &str) -> Option<f32> {
    m.unknown_param
        .get(key)
        .and_then(|v| v.trim().parse::<f32>().ok())
        .filter(|v| v.is_finite())
}

/// An MTL material's metalness: Pm, else 1 where `map_Pm` alone sets it,
/// else 0.
pub(crate) fn metalness(m: &tobj::Material) -> f32 {
    pbr(m, "Pm").unwrap_or(if m.unknown_param.contains_key("map_Pm") {
        1.0
    } else {
        0.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mtl(f: impl FnOnce(&mut tobj::Material)) -> Material {
        let mut m = tobj::Material {
            name: "m".into(),
            ..Default::default()
        };
        f(&mut m);
        Material::from_mtl(&m)
    }

    #[test]
    fn mtl_parameters_choose_the_kind() {
        assert_eq!(mtl(|_| {}).kind, MaterialKind::Diffuse);
        assert_eq!(
            mtl(|m| m.specular = Some([0.04; 3])).kind,
            MaterialKind::Plastic
        );
        assert_eq!(
            mtl(|m| {
                m.specular = Some([0.04; 3]);
                m.illumination_model = Some(1);
            })
            .kind,
            MaterialKind::Diffuse
        );
        assert_eq!(
            mtl(|m| m.illumination_model = Some(3)).kind,
            MaterialKind::Mirror
        );
        let glass = mtl(|m| {
            m.illumination_model = Some(7);
            m.optical_density = Some(1.33);
        });
        assert_eq!((glass.kind, glass.ior), (MaterialKind::Dielectric, 1.33));
        assert_eq!(
            mtl(|m| m.dissolve = Some(0.5)).kind,
            MaterialKind::Dielectric
        );
        // Maya's lambert: illum 4, Ni 1, opaque. Not glass; nor without Ni.
        for ni in [Some(1.0), None] {
            let lambert = mtl(|m| {
                m.illumination_model = Some(4);
                m.optical_density = ni;
                m.diffuse = Some([0.5; 3]);
            });
            assert_eq!(lambert.kind, MaterialKind::Diffuse, "Ni {ni:?}");
        }
        let see_through = mtl(|m| {
            m.illumination_model = Some(4);
            m.optical_density = Some(1.0);
            m.dissolve = Some(0.2);
        });
        assert_eq!(see_through.kind, MaterialKind::Dielectric);
        let metal = mtl(|m| {
            m.unknown_param.insert("Pm".into(), "1".into());
            m.unknown_param.insert("Pr".into(), " 0.25".into());
        });
        assert_eq!((metal.kind, metal.roughness), (MaterialKind::Metal, 0.25));
        // Without Pr, Ns sets the width: α = √(2/(Ns+2)) = 0.1 for Ns = 198.
        let phong = mtl(|m| {
            m.unknown_param.insert("Pm".into(), "0.9".into());
            m.shininess = Some(198.0);
        });
        assert!((phong.roughness * phong.roughness - 0.1).abs() < 1e-6);
        let light = mtl(|m| m.emissive = Some([4.0, 3.0, 2.0]));
        assert_eq!(light.kind, MaterialKind::Emissive);
        assert_eq!(light.emission, Vec3::new(4.0, 3.0, 2.0));
        // A map without its constant: the constant is 1, the map alone.
        let map = |key: &str| {
            mtl(|m| {
                m.unknown_param.insert(key.into(), "x.png".into());
            })
        };
        let lit = map("map_Ke");
        assert_eq!(
            (lit.kind, lit.emission),
            (MaterialKind::Emissive, Vec3::ONE)
        );
        assert_eq!(map("map_Pm").kind, MaterialKind::Metal);
        assert_eq!(map("map_Pr").roughness, 1.0);
        let shiny = mtl(|m| m.specular_texture = Some("x.png".into()));
        assert_eq!(
            (shiny.kind, shiny.specular),
            (MaterialKind::Plastic, Vec3::ONE)
        );
        // Pm below one half stays below it whatever its map says.
        let dull = mtl(|m| {
            m.unknown_param.insert("Pm".into(), "0.3".into());
            m.unknown_param.insert("map_Pm".into(), "x.png".into());
        });
        assert_eq!(dull.kind, MaterialKind::Diffuse);
    }

    #[test]
    fn a_checker_gives_the_albedo_of_every_kind_at_the_point() {
        use crate::shading::{Bsdf, Checker, Lambert, Metal, Mirror};
        let (a, b) = (Vec3::new(0.9, 0.1, 0.1), Vec3::new(0.1, 0.1, 0.9));
        let mut m = Material::diffuse("c", Vec3::splat(0.5));
        let (even, odd) = (Vec3::splat(0.5), Vec3::new(1.5, 0.5, 0.5));
        // Without a checker, `albedo` everywhere.
        assert_eq!(
            (
                m.albedo_at(even, Vec3::ZERO, None),
                m.albedo_at(odd, Vec3::ZERO, None)
            ),
            (m.albedo, m.albedo)
        );
        m.checker = Some(Checker {
            colours: [a, b],
            to_pattern: glam::DAffine3::IDENTITY,
        });
        assert_eq!(
            (
                m.albedo_at(even, Vec3::ZERO, None),
                m.albedo_at(odd, Vec3::ZERO, None)
            ),
            (a, b)
        );
        assert_eq!(
            Bsdf::at(&m, &m.surface_at(odd, Vec3::ZERO, None, None)),
            Bsdf::Lambert(Lambert { albedo: b })
        );
        // The local model at the point: Lambert's albedo/π.
        assert_eq!(
            m.local_brdf(
                &m.surface_at(odd, Vec3::ZERO, None, None),
                Vec3::Z,
                Vec3::Z,
                Vec3::Z
            ),
            b / PI
        );
        m.kind = MaterialKind::Mirror;
        assert_eq!(
            Bsdf::at(&m, &m.surface_at(even, Vec3::ZERO, None, None)),
            Bsdf::Mirror(Mirror { reflectance: a })
        );
        m.kind = MaterialKind::Metal;
        let Bsdf::Metal(Metal { f0, .. }) =
            Bsdf::at(&m, &m.surface_at(odd, Vec3::ZERO, None, None))
        else {
            panic!("a metal's BSDF");
        };
        assert_eq!(f0, b);
    }

    #[test]
    fn lambert_integrates_to_albedo() {
        // ∫ f cosθ dω over the hemisphere = albedo for a Lambertian surface; check by
        // a midpoint rule in θ (f is constant in φ).
        let m = Material::diffuse("d", Vec3::splat(0.5));
        let n = Vec3::Z;
        let steps = 2000;
        let mut sum = 0.0;
        for i in 0..steps {
            let theta = (i as f32 + 0.5) / steps as f32 * PI / 2.0;
            let wi = Vec3::new(theta.sin(), 0.0, theta.cos());
            let f = m.local_brdf(&m.constant_surface(), n, n, wi).x;
            sum += f * theta.cos() * theta.sin() * 2.0 * PI * (PI / 2.0 / steps as f32);
        }
        assert!((sum - 0.5).abs() < 1e-3, "{sum}");
    }

    #[test]
    fn highlight_peaks_at_the_mirror_direction() {
        let mut m = Material::diffuse("p", Vec3::splat(0.5));
        m.kind = MaterialKind::Plastic;
        m.specular = Vec3::splat(0.04);
        m.shininess = 100.0;
        let n = Vec3::Z;
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let mirror = Vec3::new(-0.6, 0.0, 0.8);
        let off = Vec3::new(-0.8, 0.0, 0.6);
        assert!(
            m.local_brdf(&m.constant_surface(), n, wo, mirror).x
                > m.local_brdf(&m.constant_surface(), n, wo, off).x + 0.1
        );
        assert!(m.local_brdf(&m.constant_surface(), n, wo, off).x >= 0.5 / PI);
    }
}
