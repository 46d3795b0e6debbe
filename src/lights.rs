//! Lights and the radiance they send to a point.

use crate::math::Vec3;

#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// Radiant intensity I (W/sr per channel): irradiance I·cosθ / d² at distance d.
    Point { position: Vec3, intensity: Vec3 },
    /// Irradiance E on a surface facing the light; `direction` is where light travels.
    Directional { direction: Vec3, irradiance: Vec3 },
}

/// What a light sends towards a shading point: the unit direction to the light,
/// the distance to it (inf for directional lights) and the irradiance on a
/// surface facing it.
pub struct Incident {
    pub wi: Vec3,
    pub distance: f32,
    pub irradiance: Vec3,
}

impl Light {
    pub fn incident(&self, p: Vec3) -> Incident {
        match self {
            Light::Point {
                position,
                intensity,
            } => {
                let to = *position - p;
                let d2 = to.length_squared();
                let distance = d2.sqrt();
                Incident {
                    wi: to / distance,
                    distance,
                    irradiance: *intensity / d2,
                }
            }
            Light::Directional {
                direction,
                irradiance,
            } => Incident {
                wi: -direction.normalize(),
                distance: f32::INFINITY,
                irradiance: *irradiance,
            },
        }
    }
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
        let inc = light.incident(Vec3::ZERO);
        assert_eq!(inc.wi, Vec3::Y);
        assert_eq!(inc.distance, 2.0);
        assert_eq!(inc.irradiance, Vec3::splat(2.0));
    }

    #[test]
    fn directional_light_points_back_along_its_direction() {
        let light = Light::Directional {
            direction: Vec3::new(0.0, -2.0, 0.0),
            irradiance: Vec3::ONE,
        };
        let inc = light.incident(Vec3::new(5.0, 1.0, 3.0));
        assert_eq!(inc.wi, Vec3::Y);
        assert!(inc.distance.is_infinite());
    }
}
