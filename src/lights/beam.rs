//! POV-Ray's `spotlight`, `cylinder` and `parallel` lights: its point
//! light (`Light::PovPoint`) times POV-Ray 3.7's attenuation of its beam,
//! with the same formulas, defaults and quirks (see docs/povray.md).

use super::fade::{self, Fade};
use super::{Incident, Shadowing};
use crate::math::Vec3;

/// The shape of a POV-Ray light's beam.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub enum Beam {
    /// No cone: a `parallel` point light.
    Round,
    /// `spotlight`: the cosines of `radius` (full light inside) and
    /// `falloff` (none outside), and `tightness`, the power of cos θ.
    Spot {
        cos_radius: f32,
        cos_falloff: f32,
        tightness: f32,
    },
    /// `cylinder`: `radius` and `falloff` as distances from the axis.
    Cylinder {
        radius: f32,
        falloff: f32,
        tightness: f32,
    },
}

/// POV-Ray's `cubic_spline`: 0 below `low`, 1 from `high`, and the
/// smoothstep 3t² − 2t³ between.
fn cubic_spline(low: f32, high: f32, pos: f32) -> f32 {
    if pos < low {
        return 0.0;
    }
    if pos >= high {
        return 1.0;
    }
    let t = (pos - low) / (high - low);
    (3.0 - 2.0 * t) * t * t
}

impl Beam {
    /// A spotlight's share of the light along a direction whose cosine with
    /// the axis is `cos`: POV-Ray's `Attenuate_Light` for `SPOT_SOURCE`.
    pub fn spot(cos: f32, cos_radius: f32, cos_falloff: f32, tightness: f32) -> f32 {
        if cos <= 0.0 {
            return 0.0;
        }
        let mut share = cos.powf(tightness);
        if cos_radius > 0.0 && cos < cos_radius {
            share *= cubic_spline(cos_falloff, cos_radius, cos);
        }
        share
    }

    /// A cylinder light's share at distance `r` from its axis, in front of
    /// its plane: POV-Ray's `Attenuate_Light` for `CYLINDER_SOURCE`.
    pub fn cylinder(r: f32, radius: f32, falloff: f32, tightness: f32) -> f32 {
        if r >= falloff {
            return 0.0;
        }
        let dist = 1.0 - r / falloff;
        let mut share = dist.powf(tightness);
        if radius > 0.0 && r > radius {
            share *= cubic_spline(0.0, 1.0 - radius / falloff, dist);
        }
        share
    }

    /// The cosine below which a spotlight sends nothing (at least 0: no
    /// light goes backwards).
    pub fn spot_edge(cos_radius: f32, cos_falloff: f32) -> f32 {
        // With falloff inside radius, the spline cuts at radius.
        let edge = if cos_radius > 0.0 {
            cos_falloff.min(cos_radius)
        } else {
            0.0
        };
        edge.max(0.0)
    }
}

/// POV-Ray's beam light (see [`super::Light::PovBeam`]).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PovBeam {
    pub position: Vec3,
    /// The unit vector from the light to its `point_at`.
    pub direction: Vec3,
    pub irradiance: Vec3,
    pub beam: Beam,
    /// Rays all along `direction`, from the plane through `position`.
    pub parallel: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fade: Option<Fade>,
    #[serde(skip_serializing_if = "Shadowing::is_plain")]
    pub shadowing: Shadowing,
}

impl PovBeam {
    /// What the light sends to p.
    pub(super) fn incident(&self, p: Vec3) -> Option<Incident> {
        let (position, direction) = (self.position, self.direction);
        let (wi, distance, share) = if self.parallel {
            // Parallel rays: the shadow ray runs back to the light's plane; a
            // point behind the plane casts and receives no shadow (distance 0),
            // as POV-Ray's `ComputeOneWhiteLightRay` has it.
            let depth = (p - position).dot(direction);
            let share = match self.beam {
                Beam::Round => 1.0,
                // The cone is measured along the parallel ray itself, so it
                // is all or nothing: POV-Ray's own behaviour.
                Beam::Spot { .. } => f32::from(u8::from(depth > 0.0)),
                Beam::Cylinder {
                    radius,
                    falloff,
                    tightness,
                } => {
                    if depth <= 0.0 {
                        0.0
                    } else {
                        let r = (p - position - depth * direction).length();
                        Beam::cylinder(r, radius, falloff, tightness)
                    }
                }
            };
            (-direction, depth.max(0.0), share)
        } else {
            let to = position - p;
            let distance = to.length();
            let wi = to / distance;
            let share = match self.beam {
                Beam::Spot {
                    cos_radius,
                    cos_falloff,
                    tightness,
                } => Beam::spot(-wi.dot(direction), cos_radius, cos_falloff, tightness),
                Beam::Round | Beam::Cylinder { .. } => 1.0,
            };
            (wi, distance, share)
        };
        let share = share * fade::share(self.fade.as_ref(), p, self.parallel.then_some(direction));
        (share > 0.0).then(|| Incident {
            wi,
            distance,
            irradiance: self.irradiance * share,
            pdf: 0.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn light(position: Vec3, direction: Vec3, beam: Beam, parallel: bool) -> PovBeam {
        PovBeam {
            position,
            direction,
            irradiance: Vec3::ONE,
            beam,
            parallel,
            fade: None,
            shadowing: Shadowing::default(),
        }
    }

    fn spot_light(parallel: bool) -> PovBeam {
        let beam = Beam::Spot {
            cos_radius: 20f32.to_radians().cos(),
            cos_falloff: 40f32.to_radians().cos(),
            tightness: 2.0,
        };
        light(Vec3::new(0.0, 10.0, 0.0), -Vec3::Y, beam, parallel)
    }

    fn share(light: PovBeam, p: Vec3) -> f32 {
        light.incident(p).map_or(0.0, |i| i.irradiance.x)
    }

    #[test]
    fn a_spotlight_is_cos_to_the_tightness_inside_radius_and_dark_past_falloff() {
        let light = spot_light(false);
        // Straight below: cos 1.
        assert_eq!(share(light, Vec3::ZERO), 1.0);
        // 10° off the axis: cos² only.
        let p = Vec3::new(10.0 * 10f32.to_radians().tan(), 0.0, 0.0);
        let c = 10f32.to_radians().cos();
        assert!((share(light, p) - c * c).abs() < 1e-5);
        // 30°, halfway in cos between radius and falloff's cosines... the
        // spline at its own parameter.
        let p30 = Vec3::new(10.0 * 30f32.to_radians().tan(), 0.0, 0.0);
        let (c30, cr, cf) = (
            30f32.to_radians().cos(),
            20f32.to_radians().cos(),
            40f32.to_radians().cos(),
        );
        let t = (c30 - cf) / (cr - cf);
        let want = c30 * c30 * t * t * (3.0 - 2.0 * t);
        assert!((share(light, p30) - want).abs() < 1e-5);
        // 45°: past falloff.
        assert_eq!(share(light, Vec3::new(10.0, 0.0, 0.0)), 0.0);
        // No fade: the same share twice as far along the same ray.
        assert!((share(light, 2.0 * p - Vec3::new(0.0, 10.0, 0.0)) - c * c).abs() < 1e-5);
    }

    #[test]
    fn a_parallel_spotlight_lights_all_in_front_of_its_plane_and_nothing_behind() {
        let light = spot_light(true);
        let inc = light.incident(Vec3::new(40.0, 0.0, 3.0)).unwrap();
        assert_eq!(inc.wi, Vec3::Y);
        assert_eq!(inc.distance, 10.0);
        assert_eq!(inc.irradiance, Vec3::ONE);
        assert!(light.incident(Vec3::splat(11.0)).is_none());
    }

    #[test]
    fn a_parallel_point_light_lights_behind_its_plane_without_shadows() {
        let inc = light(Vec3::ZERO, Vec3::X, Beam::Round, true)
            .incident(-Vec3::X)
            .unwrap();
        assert_eq!((inc.wi, inc.distance), (-Vec3::X, 0.0));
        assert_eq!(inc.irradiance, Vec3::ONE);
    }

    #[test]
    fn a_cylinder_light_depends_on_the_distance_from_its_axis_only() {
        let beam = Beam::Cylinder {
            radius: 1.0,
            falloff: 2.0,
            tightness: 0.0,
        };
        let cylinder = light(Vec3::ZERO, Vec3::Z, beam, true);
        for z in [0.5, 50.0] {
            assert_eq!(share(cylinder, Vec3::new(0.9, 0.0, z)), 1.0);
            assert_eq!(share(cylinder, Vec3::new(0.0, 2.0, z)), 0.0);
            // r = 1.5: dist 0.25 on a spline over [0, 0.5]: t = 0.5.
            assert!((share(cylinder, Vec3::new(0.0, 1.5, z)) - 0.5).abs() < 1e-6);
        }
        assert_eq!(share(cylinder, Vec3::new(0.0, 0.0, -1.0)), 0.0, "behind");
        let inc = cylinder.incident(Vec3::new(0.5, 0.0, 3.0)).unwrap();
        assert_eq!((inc.wi, inc.distance), (-Vec3::Z, 3.0));
    }
}
