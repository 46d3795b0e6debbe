//! Lights and the radiance they send to a point.
//!
//! Point, spot and directional lights are given in the scene file. Area lights are
//! the scene's emissive geometry: every emissive triangle and every emissive
//! sphere becomes one (see `scene::emitters`), so a light is always visible,
//! casts shadows and is found by bounces as well as by light sampling. The
//! environment light (`environment`) is the radiance of rays that leave the
//! scene, sampled by the path tracer beside the area lights.

mod pick;

pub use pick::{LightPick, LightPicker, LightRef};

mod beam;
mod emission_map;
mod emit;
mod environment;
mod fade;

pub use beam::{Beam, PovBeam};
pub use emission_map::EmissionMap;
pub use emit::Emission;
pub use environment::{Environment, EnvironmentSource};
pub use fade::Fade;

use crate::math::Vec3;
use crate::sampling::warp;

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub enum Light {
    /// Radiant intensity I (W/sr per channel): irradiance I·cosθ / d² at distance d.
    Point { position: Vec3, intensity: Vec3 },
    /// POV-Ray's point `light_source`: the same irradiance at every
    /// distance (its `fade_power 0`) unless it fades as POV-Ray's lights
    /// do; not a physical light, for scenes read from POV-Ray's language.
    /// Hashed under its earlier name, so that scenes keep their hashes.
    #[serde(rename = "Unfading")]
    PovPoint {
        position: Vec3,
        irradiance: Vec3,
        #[serde(skip_serializing_if = "Option::is_none")]
        fade: Option<Fade>,
        #[serde(skip_serializing_if = "Shadowing::is_plain")]
        shadowing: Shadowing,
    },
    /// POV-Ray's `spotlight`, `cylinder` or `parallel` light: a `PovPoint`
    /// times the share of its beam (see `beam`).
    PovBeam(PovBeam),
    /// Irradiance E on a surface facing the light; `direction` is where light travels.
    Directional { direction: Vec3, irradiance: Vec3 },
    /// A point light shining into a cone about the unit `direction` (pbrt-v4's
    /// spot light): intensity I inside `cos_start`, none outside `cos_end`,
    /// and a smoothstep in cos θ between them.
    Spot {
        position: Vec3,
        direction: Vec3,
        intensity: Vec3,
        cos_end: f32,
        cos_start: f32,
    },
    /// An emissive sphere of uniform radiance L, emitting outwards.
    Sphere {
        center: Vec3,
        radius: f32,
        radiance: Vec3,
    },
    /// An emissive triangle p0, p0 + edge1, p0 + edge2 of radiance
    /// `radiance` (times its emission map's colour, where it has one),
    /// emitting on the side edge1 × edge2 points to: the side a hit calls its
    /// front (the counter-clockwise side), as pbrt and Mitsuba area lights do.
    Triangle {
        p0: Vec3,
        edge1: Vec3,
        edge2: Vec3,
        radiance: Vec3,
        #[serde(skip_serializing_if = "Option::is_none")]
        map: Option<Box<EmissionMap>>,
    },
}

/// What POV-Ray's lights do with what lies between them and a shading
/// point (their `light_source` keywords): a `shadowless` light casts no
/// shadows, and a `media_attenuation` one (with `media_interaction`, on by
/// default) is dimmed by the fogs on its way through the air, as a ray that
/// comes back to the camera is. Every other light casts shadows and is not
/// dimmed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct Shadowing {
    pub shadowless: bool,
    pub fogged: bool,
}

impl Shadowing {
    /// Whether this is every other light's: hashed only otherwise, so that
    /// scenes written before it keep their hashes.
    pub fn is_plain(&self) -> bool {
        *self == Shadowing::default()
    }
}

/// What a light sends towards a shading point: the unit direction to the light,
/// the distance to it (inf for directional lights) and the irradiance it gives a
/// surface facing it — for area lights an unbiased one-sample estimate, L / pdf
/// of the sampled direction.
pub struct Incident {
    pub wi: Vec3,
    pub distance: f32,
    pub irradiance: Vec3,
    /// The solid-angle density with which `wi` was sampled (for multiple
    /// importance sampling); 0 for point and directional lights, which no
    /// bounce can reach.
    pub pdf: f32,
}

impl Light {
    /// What the light does with what lies on its way (see [`Shadowing`]).
    pub fn shadowing(&self) -> Shadowing {
        match self {
            Light::PovPoint { shadowing, .. } => *shadowing,
            Light::PovBeam(light) => light.shadowing,
            _ => Shadowing::default(),
        }
    }

    /// Where every ray of the light leaves from, for a light that has one
    /// point (point and spot lights): its shadow rays all end there.
    pub fn point(&self) -> Option<Vec3> {
        match self {
            Light::Point { position, .. }
            | Light::Spot { position, .. }
            | Light::PovPoint { position, .. } => Some(*position),
            _ => None,
        }
    }

    /// The light as seen from p; area lights pick a point with `u`. None when
    /// the light sends nothing to p (p inside a sphere light, behind a quad).
    pub fn incident(&self, p: Vec3, u: [f32; 2]) -> Option<Incident> {
        match self {
            // A point light is a spot whose scale is 1 everywhere.
            Light::Point {
                position,
                intensity,
            }
            | Light::Spot {
                position,
                intensity,
                ..
            } => {
                let to = *position - p;
                let d2 = to.length_squared();
                let distance = d2.sqrt();
                let wi = to / distance;
                let scale = self.spot_scale(-wi);
                (scale > 0.0).then(|| Incident {
                    wi,
                    distance,
                    irradiance: *intensity * scale / d2,
                    pdf: 0.0,
                })
            }
            Light::PovPoint {
                position,
                irradiance,
                fade,
                ..
            } => {
                let to = *position - p;
                let distance = to.length();
                Some(Incident {
                    wi: to / distance,
                    distance,
                    irradiance: *irradiance * fade::share(fade.as_ref(), p, None),
                    pdf: 0.0,
                })
            }
            Light::PovBeam(light) => light.incident(p),
            Light::Directional {
                direction,
                irradiance,
            } => Some(Incident {
                wi: -direction.normalize(),
                distance: f32::INFINITY,
                irradiance: *irradiance,
                pdf: 0.0,
            }),
            Light::Sphere {
                center,
                radius,
                radiance,
            } => {
                // The cone the sphere fills, sampled uniformly: pdf = 1 / solid angle.
                let to = *center - p;
                let d2 = to.length_squared();
                let sin2_max = radius * radius / d2;
                if sin2_max >= 1.0 {
                    return None;
                }
                let axis = to / d2.sqrt();
                let local = warp::uniform_cone_sin2(u, sin2_max);
                let (s, t) = basis(axis);
                let wi = (local.x * s + local.y * t + local.z * axis).normalize();
                // Distance to the near side of the sphere along wi.
                let b = to.dot(wi);
                let distance = b - (b * b - d2 + radius * radius).max(0.0).sqrt();
                let pdf = warp::uniform_cone_sin2_pdf(sin2_max);
                Some(Incident {
                    wi,
                    distance,
                    irradiance: *radiance / pdf,
                    pdf,
                })
            }
            Light::Triangle {
                p0,
                edge1,
                edge2,
                radiance,
                map,
            } => {
                let (b1, b2) = warp::uniform_triangle(u);
                let radiance = *radiance * emission_map::factor(map.as_deref(), b1, b2);
                let point = *p0 + b1 * *edge1 + b2 * *edge2;
                let to = point - p;
                let d2 = to.length_squared();
                // `to.length()`, as `pdf` finds it too: computed once.
                let distance = d2.sqrt();
                let wi = to / distance;
                let pdf = triangle_pdf(*edge1, *edge2, to, d2, distance);
                (pdf > 0.0).then(|| Incident {
                    wi,
                    distance,
                    irradiance: radiance / pdf,
                    pdf,
                })
            }
        }
    }

    /// The solid-angle density with which [`Light::incident`] from `p` picks
    /// the direction towards `point`, a point on the light (where a bounce
    /// from p found it). Zero for point and directional lights, and for the
    /// back of a triangle.
    pub fn pdf(&self, p: Vec3, point: Vec3) -> f32 {
        match self {
            Light::Point { .. }
            | Light::Spot { .. }
            | Light::PovPoint { .. }
            | Light::PovBeam(_)
            | Light::Directional { .. } => 0.0,
            Light::Sphere { center, radius, .. } => {
                let sin2_max = radius * radius / (*center - p).length_squared();
                if sin2_max >= 1.0 {
                    0.0
                } else {
                    warp::uniform_cone_sin2_pdf(sin2_max)
                }
            }
            Light::Triangle { edge1, edge2, .. } => {
                let to = point - p;
                let d2 = to.length_squared();
                triangle_pdf(*edge1, *edge2, to, d2, d2.sqrt())
            }
        }
    }

    /// A point, spot or directional light: one direction reaches it, no
    /// bounce can.
    pub fn is_delta(&self) -> bool {
        matches!(
            self,
            Light::Point { .. }
                | Light::Spot { .. }
                | Light::PovPoint { .. }
                | Light::PovBeam(_)
                | Light::Directional { .. }
        )
    }

    /// A spot light's share of its intensity along the unit direction `w`
    /// (leaving the light): 1 inside the inner cone, 0 outside the outer,
    /// pbrt-v4's smoothstep between; 1 for any other light.
    pub fn spot_scale(&self, w: Vec3) -> f32 {
        let Light::Spot {
            direction,
            cos_end,
            cos_start,
            ..
        } = self
        else {
            return 1.0;
        };
        let cos = w.dot(*direction);
        if cos_start <= cos_end {
            return if cos < *cos_end { 0.0 } else { 1.0 };
        }
        let t = ((cos - cos_end) / (cos_start - cos_end)).clamp(0.0, 1.0);
        t * t * (3.0 - 2.0 * t)
    }
}

/// The solid-angle density of a point picked uniformly on the triangle of
/// edges `edge1`, `edge2`, seen along `to` (from the shading point to the
/// point; `d2` its squared length, `distance` its length): d² / (A cos θ),
/// zero from behind.
fn triangle_pdf(edge1: Vec3, edge2: Vec3, to: Vec3, d2: f32, distance: f32) -> f32 {
    let normal = edge1.cross(edge2);
    let double_area = normal.length();
    let cos_light = -to.dot(normal) / (distance * double_area);
    if cos_light > 0.0 && double_area > 0.0 {
        d2 / (0.5 * double_area * cos_light)
    } else {
        0.0
    }
}

/// Two unit vectors completing an orthonormal basis with unit `n`.
fn basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_light_falls_off_with_inverse_square() {
        let light = Light::Point {
            position: Vec3::new(0.0, 2.0, 0.0),
            intensity: Vec3::splat(8.0),
        };
        let inc = light.incident(Vec3::ZERO, [0.5; 2]).unwrap();
        assert_eq!(inc.wi, Vec3::Y);
        assert_eq!(inc.distance, 2.0);
        assert_eq!(inc.irradiance, Vec3::splat(2.0));
    }

    #[test]
    fn unfading_light_gives_the_same_irradiance_at_every_distance() {
        let light = Light::PovPoint {
            position: Vec3::new(0.0, 2.0, 0.0),
            irradiance: Vec3::splat(3.0),
            fade: None,
            shadowing: Shadowing::default(),
        };
        for p in [Vec3::ZERO, Vec3::new(0.0, -98.0, 0.0)] {
            let inc = light.incident(p, [0.5; 2]).unwrap();
            assert_eq!(inc.wi, Vec3::Y);
            assert_eq!(inc.distance, 2.0 - p.y);
            assert_eq!(inc.irradiance, Vec3::splat(3.0));
        }
    }

    #[test]
    fn directional_light_points_back_along_its_direction() {
        let light = Light::Directional {
            direction: Vec3::new(0.0, -2.0, 0.0),
            irradiance: Vec3::ONE,
        };
        let inc = light.incident(Vec3::new(5.0, 1.0, 3.0), [0.5; 2]).unwrap();
        assert_eq!(inc.wi, Vec3::Y);
        assert!(inc.distance.is_infinite());
    }

    /// Mean of the one-sample estimates over many u: the exact irradiance.
    fn mean_irradiance(light: &Light, p: Vec3, n: Vec3) -> f32 {
        let mut rng = crate::sampling::Rng::for_sample(3, 0, 0);
        let count = 200_000;
        let mut sum = 0.0f64;
        for _ in 0..count {
            if let Some(inc) = light.incident(p, rng.next_2d()) {
                sum += f64::from(inc.irradiance.x * inc.wi.dot(n).max(0.0));
            }
        }
        (sum / f64::from(count)) as f32
    }

    #[test]
    fn sphere_light_irradiance_is_pi_l_sin2() {
        // A sphere light straight above a surface gives E = π L (r/d)² exactly.
        let light = Light::Sphere {
            center: Vec3::new(0.0, 0.0, 4.0),
            radius: 1.0,
            radiance: Vec3::splat(3.0),
        };
        let e = mean_irradiance(&light, Vec3::ZERO, Vec3::Z);
        let exact = std::f32::consts::PI * 3.0 / 16.0;
        assert!((e - exact).abs() < 2e-3 * exact, "{e} vs {exact}");
        assert!(
            light.incident(Vec3::new(0.0, 0.0, 4.5), [0.5; 2]).is_none(),
            "inside"
        );
        // The sampled point lies on the sphere's near side.
        for u in [[0.5, 0.5], [0.0, 0.0], [0.99, 0.3]] {
            let inc = light.incident(Vec3::ZERO, u).unwrap();
            let on = inc.wi * inc.distance - Vec3::new(0.0, 0.0, 4.0);
            assert!(
                (on.length() - 1.0).abs() < 1e-4 && on.z < 0.0,
                "{u:?}: {on}"
            );
        }
    }

    #[test]
    fn two_triangle_lights_give_the_form_factor_of_their_square() {
        // A unit square at height 1, centred on the point's normal, facing down. By
        // the classic closed form, a rectangle a × b whose corner is at height h right
        // above the point gives E = L/2 [a'/√(1+a'²) atan(b'/√(1+a'²)) + b'/√(1+b'²)
        // atan(a'/√(1+b'²))] with a' = a/h, b' = b/h; the square is four such quarters.
        let corner = Vec3::new(-0.5, -0.5, 1.0);
        let (x_edge, y_edge) = (Vec3::X, Vec3::Y);
        let radiance = Vec3::splat(2.0);
        let halves = [
            Light::Triangle {
                p0: corner,
                edge1: y_edge,
                edge2: x_edge + y_edge,
                radiance,
                map: None,
            },
            Light::Triangle {
                p0: corner,
                edge1: x_edge + y_edge,
                edge2: x_edge,
                radiance,
                map: None,
            },
        ];
        let (x, y) = (0.5f32, 0.5f32);
        let quarter = 0.5
            * (x / (1.0 + x * x).sqrt() * (y / (1.0 + x * x).sqrt()).atan()
                + y / (1.0 + y * y).sqrt() * (x / (1.0 + y * y).sqrt()).atan());
        let exact = 2.0 * 4.0 * quarter;
        let e: f32 = halves
            .iter()
            .map(|t| mean_irradiance(t, Vec3::ZERO, Vec3::Z))
            .sum();
        assert!((e - exact).abs() < 5e-3 * exact, "{e} vs {exact}");
        // From above, they show their backs: nothing.
        for t in &halves {
            assert!(t.incident(Vec3::new(0.0, 0.0, 2.0), [0.5; 2]).is_none());
        }
    }

    #[test]
    fn pdf_agrees_with_the_sampled_density() {
        let lights = [
            Light::Sphere {
                center: Vec3::new(0.3, -0.2, 3.0),
                radius: 0.7,
                radiance: Vec3::ONE,
            },
            Light::Triangle {
                // edge1 × edge2 points down, towards p.
                p0: Vec3::new(-1.0, 0.0, 2.0),
                edge1: Vec3::new(0.0, 1.5, -0.5),
                edge2: Vec3::new(2.0, 0.5, 0.0),
                radiance: Vec3::ONE,
                map: None,
            },
        ];
        let p = Vec3::new(0.1, 0.2, -0.3);
        for light in &lights {
            for u in [[0.1, 0.9], [0.5, 0.5], [0.8, 0.2]] {
                let inc = light.incident(p, u).unwrap();
                let pdf = light.pdf(p, p + inc.distance * inc.wi);
                assert!((pdf - inc.pdf).abs() < 1e-4 * pdf, "{pdf} vs {}", inc.pdf);
            }
        }
    }
}
