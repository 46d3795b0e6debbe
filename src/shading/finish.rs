//! POV-Ray's `finish` and `interior` as one set of numbers: the parameters of
//! the classic material, and the parts of the model both integrators share
//! (the reflected fraction at an angle, the highlight colour, the local
//! shading POV-Ray does per light).

use std::f32::consts::PI;

use crate::math::Vec3;
use crate::shading::{COS_EPS, fresnel};

/// The finish of a classic material, with POV-Ray's names and defaults except
/// `ambient` (see its field). Every fraction lies in [0, 1]; `roughness` and
/// `phong_size` are > 0 (the scene loader checks both).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Finish {
    /// The lit fraction of the pigment (POV-Ray's 0.6).
    pub diffuse: f32,
    /// Light the surface gives off without any light source, times the
    /// pigment. 0, not POV-Ray's 0.1: sturmray's lights are physical, and a
    /// constant glow would be light from nowhere that the path tracer could
    /// not account for; a POV-Ray scene states it where it wants it.
    pub ambient: f32,
    /// The Blinn highlight's strength and width: (n·h)^(1/roughness).
    pub specular: f32,
    pub roughness: f32,
    /// The Phong highlight's strength and exponent: (r·l)^phong_size.
    pub phong: f32,
    pub phong_size: f32,
    /// The mirrored fraction head-on, and at grazing (`reflection { min max }`).
    pub reflection: f32,
    pub reflection_max: f32,
    /// Between the two by the dielectric Fresnel term of the material's ior
    /// (`fresnel on`), instead of POV-Ray's default linear falloff in 1 − cos.
    pub fresnel: bool,
    /// How much highlights and reflections take the pigment's colour
    /// (0 white, 1 the pigment).
    pub metallic: f32,
    /// The fraction refracted through the surface (a pigment's `transmit`);
    /// the diffuse and ambient parts keep 1 − transmit of their light.
    pub transmit: f32,
    /// The part of `transmit` the pigment's colour tints (POV-Ray's
    /// `filter`; the rest is its untinted `transmit`); left out of the scene
    /// hash when 0, so the hashes of materials without one stay as they were.
    #[serde(skip_serializing_if = "is_zero")]
    pub filter: f32,
    /// The diffuse part's power of the cosine at the light (POV-Ray's
    /// `brilliance`): cos^brilliance, flatter below 1, more like a highlight
    /// above. Left out of the scene hash when 1, so the hashes of materials
    /// without one stay as they were.
    #[serde(skip_serializing_if = "is_one")]
    pub brilliance: f32,
    /// How light fades inside (POV-Ray's interior `fade_distance`,
    /// `fade_power` and `fade_color`); none when left out of the hash.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fade: Option<InteriorFade>,
}

/// POV-Ray's fade of the light that crosses an interior: after a distance
/// d inside, colour + (1 − colour) / (1 + (d / distance)^power), or for a
/// power of 1000 or more exp(−(1 − colour) d / distance), per channel
/// (POV-Ray 3.7's `ComputeLightedTexture`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct InteriorFade {
    pub distance: f32,
    pub power: f32,
    pub colour: Vec3,
}

impl InteriorFade {
    /// The fade of an interior, or None where POV-Ray draws none: a
    /// distance of 0 (its test against 1e-10). A negative distance counts
    /// by its size.
    pub fn new(distance: f64, power: f64, colour: Vec3) -> Option<InteriorFade> {
        (distance.abs() > 1e-10).then(|| InteriorFade {
            distance: distance.abs() as f32,
            power: power as f32,
            colour,
        })
    }

    /// What is left of the light after `d` inside.
    pub fn share(&self, d: f32) -> Vec3 {
        let r = d / self.distance;
        if self.power >= 1000.0 {
            ((self.colour - Vec3::ONE) * r).exp()
        } else {
            self.colour + (Vec3::ONE - self.colour) / (1.0 + r.powf(self.power))
        }
    }

    /// `share` for a shadow ray: POV-Ray's shadows fade only with a power
    /// above 0 (its `ComputeShadowTexture`), where seen light fades by half
    /// with a power of 0.
    pub fn shadow_share(&self, d: f32) -> Vec3 {
        if self.power > 0.0 {
            self.share(d)
        } else {
            Vec3::ONE
        }
    }
}

impl Default for Finish {
    fn default() -> Finish {
        Finish {
            diffuse: 0.6,
            ambient: 0.0,
            specular: 0.0,
            roughness: 0.05,
            phong: 0.0,
            phong_size: 40.0,
            reflection: 0.0,
            reflection_max: 0.0,
            fresnel: false,
            metallic: 0.0,
            transmit: 0.0,
            filter: 0.0,
            brilliance: 1.0,
            fade: None,
        }
    }
}

fn is_zero(v: &f32) -> bool {
    *v == 0.0
}

fn is_one(v: &f32) -> bool {
    *v == 1.0
}

impl Finish {
    /// Whether this is the default finish, which other material kinds carry
    /// unused and the scene hash leaves out (so their hashes stay as they were).
    pub fn is_default(&self) -> bool {
        *self == Finish::default()
    }

    /// The colour of highlights and reflections over a pigment `albedo`.
    pub fn tint(&self, albedo: Vec3) -> Vec3 {
        Vec3::ONE + (albedo - Vec3::ONE) * self.metallic
    }

    /// The part of the pigment that diffuse and ambient light see.
    pub fn diffuse_colour(&self, albedo: Vec3) -> Vec3 {
        albedo * (self.diffuse * (1.0 - self.transmit))
    }

    /// The radiance ambient light gives: POV-Ray's ambient × pigment, for the
    /// part that does not transmit.
    pub fn ambient_colour(&self, albedo: Vec3) -> Vec3 {
        albedo * (self.ambient * (1.0 - self.transmit))
    }

    /// Whether the surface shades from lights: a diffuse part or a highlight.
    pub fn shades_locally(&self) -> bool {
        self.diffuse * (1.0 - self.transmit) > 0.0 || self.specular > 0.0 || self.phong > 0.0
    }

    /// Whether the surface spawns reflected rays: a reflection, or a
    /// refraction that total internal reflection can turn back (ior ≠ 1).
    pub fn reflects(&self, ior: f32) -> bool {
        self.reflection.max(self.reflection_max) > 0.0 || (self.transmits() && ior != 1.0)
    }

    pub fn transmits(&self) -> bool {
        self.transmit > 0.0
    }

    /// What of the light through the surface comes out, over a pigment
    /// `albedo`: POV-Ray's colour × filter + transmit.
    pub fn transmitted(&self, albedo: Vec3) -> Vec3 {
        albedo * self.filter + Vec3::splat(self.transmit - self.filter)
    }

    /// The mirrored fraction for a viewer at cosine `cos_o` to the outward
    /// normal (negative inside): `reflection` head-on, `reflection_max` at
    /// grazing, by Fresnel or linearly in 1 − |cos|.
    pub fn reflectance(&self, cos_o: f32, ior: f32) -> f32 {
        let (min, max) = (self.reflection, self.reflection_max);
        if min == max {
            return min;
        }
        let t = if self.fresnel {
            fresnel::dielectric(cos_o, ior)
        } else {
            1.0 - cos_o.abs().min(1.0)
        };
        min + (max - min) * t
    }

    /// POV-Ray's per-light shading as a BRDF for the Whitted integrator, for
    /// unit n, wo (to the viewer) and wi (to the light) on one side: the
    /// diffuse part over π, as a Lambertian's (times cos^(brilliance − 1),
    /// since POV-Ray's diffuse is cos^brilliance), plus the Blinn and Phong
    /// highlights. POV-Ray does not weight those by the cosine at the light,
    /// so they are divided by it here (the caller multiplies by it); over π as
    /// well, so that a light giving irradiance π is one of POV-Ray's unit lights.
    pub fn local_brdf(&self, albedo: Vec3, n: Vec3, wo: Vec3, wi: Vec3) -> Vec3 {
        let cos_i = n.dot(wi);
        let diffuse = self.diffuse_colour(albedo) / PI;
        let diffuse = if self.brilliance != 1.0 && cos_i > 0.0 {
            diffuse * cos_i.powf(self.brilliance - 1.0)
        } else {
            diffuse
        };
        if cos_i < COS_EPS {
            return diffuse;
        }
        let blinn = if self.specular > 0.0 {
            let h = (wo + wi).normalize_or_zero();
            self.specular * n.dot(h).max(0.0).powf(1.0 / self.roughness)
        } else {
            0.0
        };
        let phong = if self.phong > 0.0 {
            let r = 2.0 * n.dot(wo) * n - wo;
            self.phong * r.dot(wi).max(0.0).powf(self.phong_size)
        } else {
            0.0
        };
        diffuse + self.tint(albedo) * ((blinn + phong) / (PI * cos_i))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brilliance_raises_the_diffuse_cosine_to_its_power() {
        let n = Vec3::Z;
        let wi = Vec3::new(0.6, 0.0, 0.8);
        for brilliance in [0.4f32, 1.0, 4.0] {
            let f = Finish {
                diffuse: 1.0,
                brilliance,
                ..Finish::default()
            };
            // What the integrator takes: the BRDF times the cosine, times π
            // for POV-Ray's unit light.
            let shaded = f.local_brdf(Vec3::ONE, n, n, wi).x * 0.8 * PI;
            assert!(
                (shaded - 0.8f32.powf(brilliance)).abs() < 1e-6,
                "{brilliance}: {shaded}"
            );
        }
    }
}
