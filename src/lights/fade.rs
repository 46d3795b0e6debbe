//! POV-Ray's `fade_distance` and `fade_power`: how its lights, which
//! otherwise give the same light at every distance, fade with it.

use crate::math::Vec3;

/// A light's colour times 2 / (1 + (d / distance)^power) at distance d,
/// POV-Ray 3.7's `Attenuate_Light`: the light's own colour at
/// `fade_distance`, twice that at the light, and falling as d^−power far off.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Fade {
    pub distance: f32,
    pub power: f32,
    /// Where d is measured from: the light, or an area light's centre
    /// (POV-Ray attenuates an area light once, along the ray to its centre).
    pub from: Vec3,
}

impl Fade {
    /// The fade POV-Ray applies for `fade_distance` and `fade_power`: none
    /// unless the power is above 0 and the distance is not 0 (its own
    /// test, against its 1e-10). A negative distance, which POV-Ray would
    /// raise to the power as it is, counts by its size.
    pub fn new(distance: f64, power: f64, from: Vec3) -> Option<Fade> {
        (power > 0.0 && distance.abs() > 1e-10).then(|| Fade {
            distance: distance.abs() as f32,
            power: power as f32,
            from,
        })
    }

    /// The share of the light that reaches distance d.
    pub fn share(&self, d: f32) -> f32 {
        2.0 / (1.0 + (d / self.distance).powf(self.power))
    }

    /// The share at p, d measured straight from the light, or for a
    /// parallel light along its unit `direction` from its plane (POV-Ray's
    /// depth of the shadow ray; behind the plane, where POV-Ray raises a
    /// negative depth to the power, by its size).
    pub fn share_at(&self, p: Vec3, parallel: Option<Vec3>) -> f32 {
        let d = match parallel {
            Some(direction) => (p - self.from).dot(direction).abs(),
            None => (self.from - p).length(),
        };
        self.share(d)
    }
}

/// The share of `fade`, or all where there is none.
pub fn share(fade: Option<&Fade>, p: Vec3, parallel: Option<Vec3>) -> f32 {
    fade.map_or(1.0, |f| f.share_at(p, parallel))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_light_is_its_colour_at_the_fade_distance_and_twice_at_the_light() {
        let fade = Fade::new(4.0, 2.0, Vec3::ZERO).unwrap();
        assert_eq!(fade.share(0.0), 2.0);
        assert_eq!(fade.share(4.0), 1.0);
        // Far off it falls as (distance / d)^power, times 2.
        let far = fade.share(400.0);
        assert!((far / (2.0 * 1e-4) - 1.0).abs() < 1e-3, "{far}");
        let p = Vec3::new(0.0, 3.0, 4.0);
        assert_eq!(fade.share_at(p, None), 2.0 / (1.0 + 1.5625));
        // Parallel: the depth along the direction from the light's plane.
        assert_eq!(fade.share_at(p, Some(Vec3::Z)), 1.0);
        assert_eq!(
            fade.share_at(p - Vec3::Z, Some(Vec3::Z)),
            2.0 / (1.0 + 0.5625)
        );
        assert_eq!(fade.share_at(-p, Some(Vec3::Z)), 1.0);
    }

    #[test]
    fn no_fade_without_a_power_or_a_distance() {
        assert_eq!(Fade::new(4.0, 0.0, Vec3::ZERO), None);
        assert_eq!(Fade::new(0.0, 2.0, Vec3::ZERO), None);
        assert_eq!(share(None, Vec3::ONE, None), 1.0);
        let negative = Fade::new(-4.0, 1.0, Vec3::ZERO).unwrap();
        assert_eq!(negative.share(4.0), 1.0);
    }
}
