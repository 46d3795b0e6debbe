//! POV-Ray's `fog`: what the air between a ray's start and its end does to
//! the light that comes back along it, for scenes read from POV-Ray's
//! language (POV-Ray 3.7's `ComputeFog`, `ComputeConstantFogColour` and
//! `ComputeGroundFogColour`, read for the formulas).

use glam::DVec3;

use crate::math::{Ray, Vec3};

/// Where a ray that meets nothing ends, for the fog: POV-Ray's depth of a
/// miss, far enough that a constant fog lets nothing through.
const MISS_DEPTH: f64 = 1e10;

/// One fog. The light L at the end of a way of length w becomes
/// (1 − a)·colour + a·((1 − filter) + filter·colour)·L, a = exp(−w/distance)
/// (at least the colour's transmit), the fogs one after the other.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Fog {
    pub distance: f64,
    /// The fog's colour and its filter and transmit.
    pub colour: Vec3,
    pub filter: f32,
    pub transmit: f32,
    /// `fog_type 2`: denser towards the ground.
    pub ground: Option<GroundFog>,
}

/// A ground fog's density: 1 below `offset` along `up`, 1 / (1 + h²) at
/// h = (height − offset) / `alt` above it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct GroundFog {
    pub offset: f64,
    pub alt: f64,
    /// A unit vector.
    pub up: DVec3,
}

impl Fog {
    /// What of the light at the end of the way from `origin` along the unit
    /// `dir`, `length` long, is let through: a in the formula above.
    fn attenuation(&self, origin: DVec3, dir: DVec3, length: f64) -> f64 {
        let density = self
            .ground
            .map_or(1.0, |g| g.mean_density(origin, dir, length));
        (-length * density / self.distance).exp()
    }
}

impl GroundFog {
    /// The density's mean along the way: its integral over the height, atan,
    /// over the height crossed.
    fn mean_density(&self, origin: DVec3, dir: DVec3, length: f64) -> f64 {
        let height = |p: DVec3| (p.dot(self.up) - self.offset) / self.alt;
        let start = height(origin);
        let end = height(origin + dir * length);
        match (start <= 0.0, end <= 0.0) {
            (true, true) => 1.0,
            (true, false) => (end.atan() - start) / (end - start),
            (false, true) => (start.atan() - end) / (start - end),
            (false, false) => {
                let delta = start - end;
                if delta.abs() > 1e-10 {
                    (start.atan() - end.atan()) / delta
                } else {
                    1.0 / (start * start + 1.0)
                }
            }
        }
    }
}

/// The share of light the fogs let through along `ray`, from its origin to
/// its end (all of the way, for a ray with no end): what dims a POV-Ray
/// light with `media_attenuation` on a shadow ray, which adds none of the
/// fogs' own colour.
pub fn through(fogs: &[Fog], ray: &Ray) -> Vec3 {
    let length = ray.tfar.is_finite().then(|| ray.tfar * ray.dir.length());
    along(fogs, ray.origin, ray.dir, length).1
}

/// The fogs on a ray's way from `origin` along `dir` to a hit `length` off
/// (None: it meets nothing): the light they add and the share of the light
/// from the end they let through. The light that comes back is
/// `added + through × L`.
pub fn along(fogs: &[Fog], origin: Vec3, dir: Vec3, length: Option<f32>) -> (Vec3, Vec3) {
    let (origin, dir) = (origin.as_dvec3(), dir.as_dvec3().normalize());
    let length = length.map_or(MISS_DEPTH, f64::from);
    let mut added = Vec3::ZERO;
    let mut through = Vec3::ONE;
    for fog in fogs {
        let a = fog
            .attenuation(origin, dir, length)
            .max(f64::from(fog.transmit)) as f32;
        let filtered = Vec3::splat(1.0 - fog.filter) + fog.colour * fog.filter;
        through *= a * filtered;
        added += (1.0 - a) * fog.colour;
    }
    (added, through)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn constant(distance: f64, colour: Vec3) -> Fog {
        Fog {
            distance,
            colour,
            filter: 0.0,
            transmit: 0.0,
            ground: None,
        }
    }

    #[test]
    fn a_constant_fog_lets_through_exp_of_the_way_over_its_distance() {
        let fog = [constant(2.0, Vec3::new(0.5, 0.6, 0.7))];
        let (added, through) = along(&fog, Vec3::ZERO, Vec3::new(0.0, 0.0, 3.0), Some(4.0));
        let a = (-2.0f32).exp();
        assert!((through - Vec3::splat(a)).abs().max_element() < 1e-6);
        assert!(
            (added - (1.0 - a) * Vec3::new(0.5, 0.6, 0.7))
                .abs()
                .max_element()
                < 1e-6
        );
        // A miss sees the fog's colour alone.
        let (added, through) = along(&fog, Vec3::ZERO, Vec3::Z, None);
        assert_eq!((added, through), (Vec3::new(0.5, 0.6, 0.7), Vec3::ZERO));
    }

    #[test]
    fn transmit_keeps_a_floor_and_filter_tints_what_comes_through() {
        let fog = [Fog {
            filter: 0.5,
            transmit: 0.25,
            ..constant(1.0, Vec3::new(1.0, 0.5, 0.0))
        }];
        let (_, through) = along(&fog, Vec3::ZERO, Vec3::Z, None);
        assert_eq!(through, 0.25 * Vec3::new(1.0, 0.75, 0.5));
    }

    #[test]
    fn a_ground_fog_is_whole_below_its_offset_and_thins_above() {
        let ground = GroundFog {
            offset: 1.0,
            alt: 2.0,
            up: DVec3::Y,
        };
        let fog = Fog {
            ground: Some(ground),
            ..constant(5.0, Vec3::ONE)
        };
        // Level at y = 0, under the offset: the constant fog.
        let low = fog.attenuation(DVec3::ZERO, DVec3::X, 5.0);
        assert!((low - (-1.0f64).exp()).abs() < 1e-12);
        // Level at y = 5 (h = 2): density 1/5.
        let high = fog.attenuation(DVec3::new(0.0, 5.0, 0.0), DVec3::X, 5.0);
        assert!((high - (-0.2f64).exp()).abs() < 1e-12);
        // Up from h = 0 to h = 1 (y 1 to 3): the mean of 1/(1+h²), atan 1.
        let rising = ground.mean_density(DVec3::new(0.0, 1.0, 0.0), DVec3::Y, 2.0);
        assert!((rising - std::f64::consts::FRAC_PI_4).abs() < 1e-12);
        // A ray that rises out of it forever meets a finite amount of fog.
        let up = fog.attenuation(DVec3::new(0.0, 1.0, 0.0), DVec3::Y, MISS_DEPTH);
        assert!((up - (-2.0 * std::f64::consts::FRAC_PI_2 / 5.0).exp()).abs() < 1e-6);
    }
}
