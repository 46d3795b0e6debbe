//! Colour patterns a material's albedo can follow across a surface: POV-Ray's
//! `checker`, so a `.pov` checkered floor keeps its squares.

use glam::DAffine3;

use crate::math::Vec3;

/// POV-Ray's tolerance (`SMALL_TOLERANCE` in 3.7's `CheckerPattern`): each
/// coordinate is nudged up by it before the floor, so a plane lying on a
/// cube face (the classic floor at y = −1) falls wholly in the cubes above
/// the face instead of flickering between both with the hit point's rounding.
const TOLERANCE: f64 = 1e-3;

/// POV-Ray's `checker`: unit cubes of two colours alternating in the pattern's space.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Checker {
    pub colours: [Vec3; 2],
    /// World space to the pattern's space (the inverse of the object's and the pigment's transforms).
    pub to_pattern: DAffine3,
}

impl Checker {
    /// The colour at world point `p`: `colours[0]` where the cube's integer
    /// coordinates sum to an even number, `colours[1]` where odd.
    pub fn colour_at(&self, p: Vec3) -> Vec3 {
        // f64, because a floor of f32 coordinates far from the origin would
        // lose the tolerance entirely (1e-3 is below f32's step above 2^13).
        let q = self.to_pattern.transform_point3(p.as_dvec3()) + TOLERANCE;
        let sum = q.x.floor() + q.y.floor() + q.z.floor();
        // rem_euclid keeps negative cubes right (⌊−0.5⌋ = −1 is odd); beyond
        // 2^53 the parity is arbitrary but still one of the two colours.
        self.colours[usize::from(sum.rem_euclid(2.0) >= 1.0)]
    }
}

#[cfg(test)]
mod tests {
    use glam::{DQuat, DVec3};

    use super::*;

    const A: Vec3 = Vec3::new(1.0, 0.0, 0.0);
    const B: Vec3 = Vec3::new(0.0, 0.0, 1.0);

    fn unit() -> Checker {
        Checker {
            colours: [A, B],
            to_pattern: DAffine3::IDENTITY,
        }
    }

    #[test]
    fn neighbouring_cubes_alternate() {
        let c = unit();
        // Cube (0, 0, 0): sum 0, even.
        assert_eq!(c.colour_at(Vec3::new(0.5, 0.5, 0.5)), A);
        // Across each face of it: one coordinate changes by one, so the parity flips.
        assert_eq!(c.colour_at(Vec3::new(1.5, 0.5, 0.5)), B);
        assert_eq!(c.colour_at(Vec3::new(0.5, 1.5, 0.5)), B);
        assert_eq!(c.colour_at(Vec3::new(0.5, 0.5, 1.5)), B);
        // Either side of the face x = 1, close to it but beyond the tolerance.
        assert_eq!(c.colour_at(Vec3::new(0.99, 0.5, 0.5)), A);
        assert_eq!(c.colour_at(Vec3::new(1.01, 0.5, 0.5)), B);
        // Two steps: even again.
        assert_eq!(c.colour_at(Vec3::new(1.5, 1.5, 0.5)), A);
    }

    #[test]
    fn negative_coordinates_floor_downwards() {
        let c = unit();
        // ⌊−0.5⌋ = −1: the cube (−1, 0, 0) is odd; truncation would make it 0, even.
        assert_eq!(c.colour_at(Vec3::new(-0.5, 0.5, 0.5)), B);
        // (−1, −1, 0): even.
        assert_eq!(c.colour_at(Vec3::new(-0.5, -0.5, 0.5)), A);
        // (−1, −1, −1): odd.
        assert_eq!(c.colour_at(Vec3::new(-0.5, -0.5, -0.5)), B);
    }

    #[test]
    fn a_plane_on_a_cube_face_takes_the_cubes_above_it() {
        let c = unit();
        // The plane y = −1, hit a hair below or above the face by rounding: both
        // are in cube y = −1 (the one above the face), so the colour is that of
        // x + z − 1; along the floor only x and z change it.
        let ulp = f32::EPSILON; // the f32 step just above 1
        for y in [-1.0f32, -1.0 - ulp, -1.0 + ulp / 2.0, -1.0 - 5e-4] {
            assert_eq!(c.colour_at(Vec3::new(0.5, y, 0.5)), B, "y = {y}");
            assert_eq!(c.colour_at(Vec3::new(1.5, y, 0.5)), A, "y = {y}");
        }
        // Below the tolerance the face is not blurred: y = −1.002 is cube −2.
        assert_eq!(c.colour_at(Vec3::new(0.5, -1.002, 0.5)), A);
    }

    #[test]
    fn the_transform_moves_and_sizes_the_cubes() {
        // Cubes of side 2: the world point (1.5, 0.5, 0.5) is pattern (0.75, 0.25, 0.25), cube 0.
        let scaled = Checker {
            to_pattern: DAffine3::from_scale(DVec3::splat(0.5)),
            ..unit()
        };
        assert_eq!(scaled.colour_at(Vec3::new(1.5, 0.5, 0.5)), A);
        assert_eq!(scaled.colour_at(Vec3::new(2.5, 0.5, 0.5)), B);
        // Rotated by 90° about z (the pigment's), inverted for world → pattern:
        // the world point (0.5, 1.5, 0.5) is pattern (1.5, −0.5, 0.5), cube
        // (1, −1, 0), even; unrotated it is cube (0, 1, 0), odd.
        let rotate = DAffine3::from_quat(DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2));
        let rotated = Checker {
            to_pattern: rotate.inverse(),
            ..unit()
        };
        let p = Vec3::new(0.5, 1.5, 0.5);
        assert_eq!(unit().colour_at(p), B);
        assert_eq!(rotated.colour_at(p), A);
        // Translated by half a cube along x: (0.7, 0.5, 0.5) is pattern 0.2, cube 0;
        // (0.3, …) is pattern −0.2, cube −1.
        let moved = Checker {
            to_pattern: DAffine3::from_translation(DVec3::new(-0.5, 0.0, 0.0)),
            ..unit()
        };
        assert_eq!(moved.colour_at(Vec3::new(0.7, 0.5, 0.5)), A);
        assert_eq!(moved.colour_at(Vec3::new(0.3, 0.5, 0.5)), B);
    }

    #[test]
    fn far_points_still_give_one_of_the_colours() {
        let c = Checker {
            to_pattern: DAffine3::from_scale(DVec3::splat(1e30)),
            ..unit()
        };
        for p in [Vec3::splat(1.8e18), Vec3::splat(-1.8e18), Vec3::ZERO] {
            let colour = c.colour_at(p);
            assert!(colour == A || colour == B, "{colour}");
        }
    }
}
