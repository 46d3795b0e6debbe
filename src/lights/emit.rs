//! Lights as photon sources: the total flux each emits and one sampled ray of
//! it, for the photon pass. Each light is sampled in proportion to its own
//! emission, so every emitted photon of a light carries that light's whole
//! power (the photon pass divides by the photon count).

use std::f32::consts::{PI, TAU};

use super::{Beam, Light, PovBeam, basis};
use crate::math::{Bounds, Vec3, gamma};
use crate::sampling::warp;

/// One photon leaving a light: where, which way, and the flux it carries when
/// it alone stands for the light (the light's power, by sampling in proportion
/// to emission).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Emission {
    pub origin: Vec3,
    /// The unit normal of the emitting surface at `origin`; zero for point and
    /// directional lights, which are not geometry.
    pub normal: Vec3,
    /// A bound on the error of `origin` per axis, so the photon's ray leaves
    /// the light's own geometry by `math::offset` as every spawned ray does.
    pub error: Vec3,
    pub dir: Vec3,
    pub flux: Vec3,
}

/// A point on an area light, drawn uniformly by area.
struct SurfacePoint {
    p: Vec3,
    /// Unit normal of the emitting side.
    n: Vec3,
    error: Vec3,
    /// The radiance's factor there: an emission map's colour, else 1.
    factor: Vec3,
}

/// The disk through the scene's centre, perpendicular to the light, that a
/// directional light's photons start from: it covers the scene's bounding
/// sphere. Its radius is 0 for an empty scene.
pub(super) fn bounding_disk(bounds: Bounds) -> (Vec3, f32) {
    if bounds.is_empty() {
        return (Vec3::ZERO, 0.0);
    }
    (bounds.center(), 0.5 * bounds.diagonal().length())
}

impl Light {
    /// The total flux the light emits (W per channel). A directional light
    /// counts what crosses the scene's bounding disk: irradiance × its area.
    pub fn power(&self, bounds: Bounds) -> Vec3 {
        match self {
            Light::Point { intensity, .. } => 4.0 * PI * *intensity,
            // ∫ smoothstep over the cone: the inner cap whole, the falloff
            // ring at half (pbrt-v4's SpotLight::Phi).
            Light::Spot {
                intensity,
                cos_end,
                cos_start,
                ..
            } => *intensity * (2.0 * PI * ((1.0 - cos_start) + 0.5 * (cos_start - cos_end))),
            // What crosses the scene's bounding disk, as for a directional
            // light: an unfading light has no finite total.
            Light::Directional { irradiance, .. } | Light::PovPoint { irradiance, .. } => {
                let (_, radius) = bounding_disk(bounds);
                *irradiance * (PI * radius * radius)
            }
            Light::PovBeam(light) => light.irradiance * beam_power(light, bounding_disk(bounds).1),
            // A Lambertian emitter of radiance L sends π L per unit area;
            // with an emission map, the image's mean stands for the
            // footprint's (see `EmissionMap`).
            Light::Sphere { radiance, .. } => PI * self.area() * *radiance,
            Light::Triangle { radiance, map, .. } => {
                PI * self.area() * *radiance * map.as_ref().map_or(Vec3::ONE, |m| m.mean)
            }
        }
    }

    /// One photon of the light from four uniform numbers: u[0..2] place it,
    /// u[2..4] aim it. None when the light emits nothing (a directional light
    /// over an empty scene).
    pub fn emit(&self, u: [f32; 4], bounds: Bounds) -> Option<Emission> {
        // The power of most lights is every photon's flux; a beam's is an
        // integral, its photons' flux is not.
        let flux = || self.power(bounds);
        match self {
            Light::Point { position, .. } | Light::PovPoint { position, .. } => Some(Emission {
                origin: *position,
                normal: Vec3::ZERO,
                error: Vec3::ZERO,
                dir: warp::uniform_sphere([u[0], u[1]]),
                flux: flux(),
            }),
            Light::Spot {
                position,
                direction,
                intensity,
                cos_end,
                ..
            } => {
                // Uniform in the outer cone, each photon weighted by the
                // falloff over the cone's density: unbiased for the power.
                let local = warp::uniform_cone([u[0], u[1]], *cos_end);
                let (s, t) = basis(*direction);
                let dir = (local.x * s + local.y * t + local.z * *direction).normalize();
                Some(Emission {
                    origin: *position,
                    normal: Vec3::ZERO,
                    error: Vec3::ZERO,
                    dir,
                    flux: *intensity * self.spot_scale(dir) / warp::uniform_cone_pdf(*cos_end),
                })
            }
            Light::PovBeam(light) => beam_emit(light, u, bounds),
            Light::Directional { direction, .. } => {
                let (center, radius) = bounding_disk(bounds);
                if radius <= 0.0 {
                    return None;
                }
                // A uniform point of the disk, moved back out of the scene so the
                // photon crosses all of it.
                let dir = direction.normalize();
                let (s, t) = basis(dir);
                let [x, y] = warp::concentric_disk([u[0], u[1]]);
                Some(Emission {
                    origin: center + radius * (x * s + y * t - dir),
                    normal: Vec3::ZERO,
                    error: Vec3::ZERO,
                    dir,
                    flux: flux(),
                })
            }
            Light::Sphere { radiance, .. } | Light::Triangle { radiance, .. } => {
                let point = self.surface_point([u[0], u[1]])?;
                // Cosine-weighted about the normal: the Lambertian emitter's own
                // distribution, so every photon carries the same flux.
                let local = warp::cosine_hemisphere([u[2], u[3]]);
                let (s, t) = basis(point.n);
                Some(Emission {
                    origin: point.p,
                    normal: point.n,
                    error: point.error,
                    dir: (local.x * s + local.y * t + local.z * point.n).normalize(),
                    // π L(p) A: its mean over uniform points is the power.
                    flux: PI * self.area() * *radiance * point.factor,
                })
            }
        }
    }

    /// The emitting area of an area light (0 for point and directional lights).
    pub(super) fn area(&self) -> f32 {
        match self {
            Light::Point { .. }
            | Light::Spot { .. }
            | Light::PovPoint { .. }
            | Light::PovBeam(_)
            | Light::Directional { .. } => 0.0,
            Light::Sphere { radius, .. } => 4.0 * PI * radius * radius,
            Light::Triangle { edge1, edge2, .. } => 0.5 * edge1.cross(*edge2).length(),
        }
    }

    /// A point uniform in area on an area light, with the normal of its
    /// emitting side; None for point and directional lights.
    fn surface_point(&self, u: [f32; 2]) -> Option<SurfacePoint> {
        Some(match self {
            Light::Sphere { center, radius, .. } => {
                let n = warp::uniform_sphere(u);
                // c + r·n: a few roundings of terms as large as |c| + r.
                let error = gamma(5) * (center.abs() + Vec3::splat(*radius));
                SurfacePoint {
                    p: *center + *radius * n,
                    n,
                    error,
                    factor: Vec3::ONE,
                }
            }
            Light::Triangle {
                p0,
                edge1,
                edge2,
                map,
                ..
            } => {
                let (b1, b2) = warp::uniform_triangle(u);
                let error = gamma(6) * (p0.abs() + edge1.abs() + edge2.abs());
                SurfacePoint {
                    p: *p0 + b1 * *edge1 + b2 * *edge2,
                    n: edge1.cross(*edge2).normalize(),
                    error,
                    factor: super::emission_map::factor(map.as_deref(), b1, b2),
                }
            }
            Light::Point { .. }
            | Light::Spot { .. }
            | Light::PovPoint { .. }
            | Light::PovBeam(_)
            | Light::Directional { .. } => {
                return None;
            }
        })
    }
}

/// The steps of the midpoint rule [`beam_power`] integrates a beam's share
/// with: the power only weighs the lights against each other when photons
/// pick one, and each photon's own flux is exact.
const POWER_STEPS: u32 = 64;

/// The midpoint rule's sum of `f` over [a, b].
fn integral(a: f32, b: f32, f: impl Fn(f32) -> f32) -> f32 {
    let h = (b - a) / POWER_STEPS as f32;
    (0..POWER_STEPS)
        .map(|i| f(a + (i as f32 + 0.5) * h))
        .sum::<f32>()
        * h
}

/// The power of a POV-Ray beam light per unit of its irradiance, by the convention of
/// `Light::PovPoint`: the unfading point light's πR² over the whole sphere
/// (R the scene's bounding disk), here only where the beam shines; a
/// parallel light sends πR² as a directional light does, and a cylinder
/// what crosses its disk.
fn beam_power(light: &PovBeam, radius: f32) -> f32 {
    match (light.beam, light.parallel) {
        (
            Beam::Cylinder {
                radius: inner,
                falloff,
                tightness,
            },
            _,
        ) => {
            TAU * integral(0.0, falloff, |r| {
                r * Beam::cylinder(r, inner, falloff, tightness)
            })
        }
        (
            Beam::Spot {
                cos_radius,
                cos_falloff,
                tightness,
            },
            false,
        ) => {
            // Per steradian: πR² / 4π.
            let edge = Beam::spot_edge(cos_radius, cos_falloff);
            let solid = TAU
                * integral(edge, 1.0, |c| {
                    Beam::spot(c, cos_radius, cos_falloff, tightness)
                });
            0.25 * radius * radius * solid
        }
        (Beam::Spot { .. } | Beam::Round, _) => PI * radius * radius,
    }
}

/// One photon of a POV-Ray beam light (see [`beam_power`]).
fn beam_emit(light: &PovBeam, u: [f32; 4], bounds: Bounds) -> Option<Emission> {
    let (position, direction, irradiance) = (light.position, light.direction, light.irradiance);
    let (center, radius) = bounding_disk(bounds);
    if radius <= 0.0 {
        return None;
    }
    let (s, t) = basis(direction);
    let emission = |origin, dir, flux| Emission {
        origin,
        normal: Vec3::ZERO,
        error: Vec3::ZERO,
        dir,
        flux,
    };
    if let (
        Beam::Spot {
            cos_radius,
            cos_falloff,
            tightness,
        },
        false,
    ) = (light.beam, light.parallel)
    {
        // Uniform in the lit cone, weighted by the share over the density.
        let edge = Beam::spot_edge(cos_radius, cos_falloff);
        let local = warp::uniform_cone([u[0], u[1]], edge);
        let dir = (local.x * s + local.y * t + local.z * direction).normalize();
        let share = Beam::spot(dir.dot(direction), cos_radius, cos_falloff, tightness);
        let flux = irradiance * (0.25 * radius * radius * share / warp::uniform_cone_pdf(edge));
        return Some(emission(position, dir, flux));
    }
    let [x, y] = warp::concentric_disk([u[0], u[1]]);
    let (base, disk) = match light.beam {
        // Behind its plane a parallel point light still shines: start
        // outside the scene, as a directional light's photons do.
        Beam::Round => (center - radius * direction, radius),
        // Nothing behind the plane: start on it.
        Beam::Spot { .. } => (
            center - (center - position).dot(direction) * direction,
            radius,
        ),
        Beam::Cylinder { falloff, .. } => (position, falloff),
    };
    let offset = disk * (x * s + y * t);
    let share = match light.beam {
        Beam::Cylinder {
            radius: inner,
            falloff,
            tightness,
        } => Beam::cylinder(offset.length(), inner, falloff, tightness),
        Beam::Round | Beam::Spot { .. } => 1.0,
    };
    let flux = irradiance * (PI * disk * disk * share);
    Some(emission(base + offset, direction, flux))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lights::Shadowing;
    use crate::sampling::Rng;

    fn bounds() -> Bounds {
        Bounds {
            min: Vec3::new(-1.0, -2.0, 0.0),
            max: Vec3::new(3.0, 2.0, 2.0),
        }
    }

    fn emissions(light: &Light, count: usize) -> Vec<Emission> {
        let mut rng = Rng::for_sample(5, 1, 2);
        (0..count)
            .filter_map(|_| {
                let [a, b] = rng.next_2d();
                let [c, d] = rng.next_2d();
                light.emit([a, b, c, d], bounds())
            })
            .collect()
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).abs().max_element() <= 1e-5 * b.abs().max_element()
    }

    #[test]
    fn powers_match_closed_forms() {
        let point = Light::Point {
            position: Vec3::ZERO,
            intensity: Vec3::new(1.0, 2.0, 3.0),
        };
        assert!(close(
            point.power(bounds()),
            4.0 * PI * Vec3::new(1.0, 2.0, 3.0)
        ));
        let sphere = Light::Sphere {
            center: Vec3::ONE,
            radius: 0.5,
            radiance: Vec3::splat(2.0),
        };
        // π L · 4π r².
        assert!(close(sphere.power(bounds()), Vec3::splat(PI * 2.0 * PI)));
        let triangle = Light::Triangle {
            p0: Vec3::ZERO,
            edge1: Vec3::new(2.0, 0.0, 0.0),
            edge2: Vec3::new(0.0, 3.0, 0.0),
            radiance: Vec3::splat(0.5),
            map: None,
        };
        // π L A, A = 3.
        assert!(close(triangle.power(bounds()), Vec3::splat(PI * 0.5 * 3.0)));
        let sun = Light::Directional {
            direction: Vec3::new(0.0, 0.0, -2.0),
            irradiance: Vec3::splat(4.0),
        };
        // The bounds' diagonal is 6, so the disk has radius 3.
        assert!(close(sun.power(bounds()), Vec3::splat(4.0 * PI * 9.0)));
        assert_eq!(sun.power(Bounds::EMPTY), Vec3::ZERO);
        assert!(sun.emit([0.5; 4], Bounds::EMPTY).is_none());
    }

    #[test]
    fn point_light_emits_every_way_evenly() {
        let light = Light::Point {
            position: Vec3::new(1.0, 2.0, 3.0),
            intensity: Vec3::ONE,
        };
        let all = emissions(&light, 20_000);
        let mean = all.iter().map(|e| e.dir).sum::<Vec3>() / all.len() as f32;
        // Each component of a uniform direction has variance 1/3: σ of the mean ≈ 0.004.
        assert!(mean.length() < 0.02, "{mean}");
        for e in &all {
            assert_eq!(e.origin, Vec3::new(1.0, 2.0, 3.0));
            assert!((e.dir.length() - 1.0).abs() < 1e-5);
        }
    }

    #[test]
    fn spot_photons_stay_in_the_cone_and_carry_its_power() {
        let spot = |falloff: f32| Light::Spot {
            position: Vec3::new(1.0, 2.0, 3.0),
            direction: Vec3::new(0.0, -1.0, 0.0),
            intensity: Vec3::new(1.0, 2.0, 3.0),
            cos_end: 30f32.to_radians().cos(),
            cos_start: (30.0 - falloff).to_radians().cos(),
        };
        // A hard edge: the cone's solid angle 2π (1 − cos 30°) times I.
        let hard = 2.0 * PI * (1.0 - 30f32.to_radians().cos());
        assert!(close(
            spot(0.0).power(bounds()),
            hard * Vec3::new(1.0, 2.0, 3.0)
        ));
        let light = spot(10.0);
        let power = light.power(bounds());
        assert!(power.x < hard && power.x > 0.5 * hard, "{power}");
        let all = emissions(&light, 20_000);
        for e in &all {
            assert_eq!(e.origin, Vec3::new(1.0, 2.0, 3.0));
            assert!(-e.dir.y >= 30f32.to_radians().cos() - 1e-6, "{e:?}");
        }
        // Each photon's flux is the falloff over the cone's density: their
        // mean is the power (σ of the mean ≈ 0.2% here).
        let mean = all.iter().map(|e| e.flux).sum::<Vec3>() / all.len() as f32;
        assert!(
            ((mean - power) / power).abs().max_element() < 0.01,
            "{mean} {power}"
        );
    }

    #[test]
    fn pov_beam_photons_stay_in_the_beam_and_carry_its_power() {
        let spot = Light::PovBeam(PovBeam {
            position: Vec3::new(1.0, 5.0, 1.0),
            direction: -Vec3::Y,
            irradiance: Vec3::new(1.0, 2.0, 3.0),
            beam: Beam::Spot {
                cos_radius: 20f32.to_radians().cos(),
                cos_falloff: 35f32.to_radians().cos(),
                tightness: 3.0,
            },
            parallel: false,
            fade: None,
            shadowing: Shadowing::default(),
        });
        let cylinder = Light::PovBeam(PovBeam {
            position: Vec3::new(1.0, 5.0, 1.0),
            direction: -Vec3::Y,
            irradiance: Vec3::new(1.0, 2.0, 3.0),
            beam: Beam::Cylinder {
                radius: 0.5,
                falloff: 1.5,
                tightness: 1.0,
            },
            parallel: true,
            fade: None,
            shadowing: Shadowing::default(),
        });
        for (light, is_spot) in [(&spot, true), (&cylinder, false)] {
            let power = light.power(bounds());
            let all = emissions(light, 40_000);
            for e in &all {
                if is_spot {
                    assert_eq!(e.origin, Vec3::new(1.0, 5.0, 1.0));
                    assert!(-e.dir.y >= 35f32.to_radians().cos() - 1e-6, "{e:?}");
                } else {
                    assert_eq!((e.dir, e.origin.y), (-Vec3::Y, 5.0));
                    let r = (e.origin - Vec3::new(1.0, 5.0, 1.0)).length();
                    assert!(r <= 1.5 + 1e-5, "{e:?}");
                }
            }
            // The mean flux is the power, whose integral is a midpoint
            // rule's (σ of the mean about 0.3% here).
            let mean = all.iter().map(|e| e.flux).sum::<Vec3>() / all.len() as f32;
            assert!(
                ((mean - power) / power).abs().max_element() < 0.015,
                "{mean} {power}"
            );
        }
        // The cylinder with tightness 1 and no spline would send
        // ∫ (1 − r/f) 2πr dr = π f² / 3; the spline past 0.5 takes some.
        let full = Vec3::new(1.0, 2.0, 3.0) * (PI * 1.5 * 1.5 / 3.0);
        let got = cylinder.power(bounds());
        assert!(got.x < full.x && got.x > 0.5 * full.x, "{got} {full}");
    }

    #[test]
    fn spot_falloff_is_pbrts_smoothstep() {
        let light = Light::Spot {
            position: Vec3::ZERO,
            direction: Vec3::Z,
            intensity: Vec3::ONE,
            cos_end: 0.5,
            cos_start: 0.7,
        };
        let at = |cos: f32| light.spot_scale(Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos));
        assert_eq!(at(0.49), 0.0);
        assert_eq!(at(0.71), 1.0);
        assert!((at(0.6) - 0.5).abs() < 1e-5);
        // smoothstep(0.25) = 0.25² (3 − 0.5) = 0.15625.
        assert!((at(0.55) - 0.15625).abs() < 1e-4);
        // Seen from below the cone's tip, the light sends nothing.
        assert!(
            light
                .incident(Vec3::new(0.0, 0.0, -1.0), [0.5; 2])
                .is_none()
        );
        let lit = light.incident(Vec3::new(0.0, 0.0, 2.0), [0.5; 2]).unwrap();
        assert!(close(lit.irradiance, Vec3::splat(0.25)));
    }

    #[test]
    fn sphere_light_emits_outward_from_its_surface() {
        let center = Vec3::new(0.0, 1.0, 2.0);
        let light = Light::Sphere {
            center,
            radius: 0.5,
            radiance: Vec3::ONE,
        };
        let all = emissions(&light, 5_000);
        let mut mean_cos = 0.0;
        for e in &all {
            assert!(((e.origin - center).length() - 0.5).abs() < 1e-5);
            assert!(close(e.normal, (e.origin - center) / 0.5));
            assert!(e.dir.dot(e.normal) > 0.0, "{e:?}");
            mean_cos += e.dir.dot(e.normal) / all.len() as f32;
        }
        // Cosine-weighted: E[cos θ] = 2/3.
        assert!((mean_cos - 2.0 / 3.0).abs() < 0.01, "{mean_cos}");
    }

    #[test]
    fn triangle_light_emits_on_its_front_side_only() {
        let light = Light::Triangle {
            p0: Vec3::new(-0.5, -0.5, 1.0),
            edge1: Vec3::new(0.0, 1.0, 0.0),
            edge2: Vec3::new(1.0, 0.0, 0.0),
            radiance: Vec3::ONE,
            map: None,
        };
        // edge1 × edge2 = -z: the triangle shines down.
        for e in emissions(&light, 5_000) {
            assert_eq!(e.normal, -Vec3::Z);
            assert!(e.dir.z < 0.0, "{e:?}");
            assert_eq!(e.origin.z, 1.0);
            // Inside the triangle x + y ≤ 0 (from its corner, x' + y' ≤ 1).
            let (x, y) = (e.origin.x + 0.5, e.origin.y + 0.5);
            assert!(x >= 0.0 && y >= 0.0 && x + y <= 1.0 + 1e-6, "{e:?}");
        }
    }

    #[test]
    fn directional_photons_cross_the_whole_scene_along_the_light() {
        let light = Light::Directional {
            direction: Vec3::new(1.0, 0.0, -1.0),
            irradiance: Vec3::ONE,
        };
        let dir = Vec3::new(1.0, 0.0, -1.0).normalize();
        let (center, radius) = (bounds().center(), 3.0);
        for e in emissions(&light, 2_000) {
            assert!(close(e.dir, dir));
            // Starts one radius behind the centre's plane, within the disk.
            let back = e.origin - center;
            assert!((back.dot(dir) + radius).abs() < 1e-4, "{e:?}");
            assert!((back + radius * dir).length() <= radius * (1.0 + 1e-5));
        }
    }
}
