//! A material's values at one shading point, its maps looked up once.

use crate::math::{Vec2, Vec3};
use crate::shading::{Material, MaterialKind};

/// What a material is at one hit: its constants, times its maps' values
/// where it has maps and the surface has texture coordinates. Built once
/// per hit ([`Material::surface_at`]) and handed to the BSDF, the local
/// model and the emission, so every integrator (Whitted, path, photon
/// pass) sees the same textured values; without maps it is a copy of the
/// constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    /// Diffuse reflectance: the albedo map's, the checker's, a vertex
    /// colour or Kd.
    pub albedo: Vec3,
    /// Specular colour: Ks × `map_Ks`.
    pub specular: Vec3,
    /// A metal's perceptual roughness: Pr × `map_Pr`.
    pub roughness: f32,
    /// A metal's metalness: Pm × `map_Pm`, 1 without the map; where it is
    /// below 0.5 the metal is its dielectric counterpart there.
    pub metallic: f32,
    /// Emitted radiance: Ke × `map_Ke`.
    pub emission: Vec3,
}

impl Material {
    /// The material's values at world point `p` (within `error` per axis of
    /// the exact point) with texture coordinates `uv` (see [`Surface`]), its albedo `colour` where the mesh has vertex
    /// colours (as meshlab and trimesh show a coloured PLY; the material
    /// keeps its kind). Without maps beyond the albedo's this is the albedo
    /// lookup and four copies.
    pub fn surface_at(
        &self,
        p: Vec3,
        error: Vec3,
        uv: Option<Vec2>,
        colour: Option<Vec3>,
    ) -> Surface {
        let mut surface = Surface {
            albedo: colour.unwrap_or_else(|| self.albedo_at(p, error, uv)),
            ..self.constant_surface()
        };
        let Some(uv) = uv.filter(|_| self.maps.scales()) else {
            return surface;
        };
        let maps = &self.maps;
        if let Some(map) = &maps.specular {
            surface.specular *= map.rgb(uv);
        }
        if let Some(map) = &maps.roughness {
            surface.roughness *= map.scalar(uv);
        }
        if let Some(metallic) = &maps.metallic {
            surface.metallic = metallic.scale * metallic.map.scalar(uv);
        }
        if let Some(map) = &maps.emission {
            surface.emission *= map.rgb(uv);
        }
        surface
    }

    /// The material's constants, away from any map or pattern: for the
    /// plan's questions about its lobes, which no map changes.
    pub fn constant_surface(&self) -> Surface {
        Surface {
            albedo: self.albedo,
            specular: self.specular,
            roughness: self.roughness,
            metallic: if self.kind == MaterialKind::Metal {
                1.0
            } else {
                0.0
            },
            emission: self.emission,
        }
    }
}
