//! Colour patterns a material's albedo can follow across a surface: POV-Ray's
//! `checker`, so a `.pov` checkered floor keeps its squares.

use glam::{DAffine3, DVec3};

use crate::math::Vec3;

/// POV-Ray 3.7's nudge (`EPSILON` in its `CheckerPattern`): each coordinate
/// is moved up by it before the floor, so a point exactly on a cube face
/// takes the cube above the face. (POV-Ray 3.6 and older nudged by 10^-3,
/// which moves a checker scaled by 32,000 by 32 units.)
const NUDGE: f64 = 1e-10;

/// POV-Ray's `checker`: unit cubes of two colours alternating in the pattern's space.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Checker {
    pub colours: [Vec3; 2],
    /// World space to the pattern's space (the inverse of the object's and the pigment's transforms).
    pub to_pattern: DAffine3,
}

impl Checker {
    /// The colour at world point `p`, within `error` (per axis) of the
    /// exact point: `colours[0]` where the cube's integer coordinates sum to
    /// an even number, `colours[1]` where odd. A coordinate within the
    /// error's image of a face is taken to be on it: a floor at y = −1,
    /// hit a rounding below, is in the cubes above the face wholly, as the
    /// exact point is, instead of flickering between both.
    pub fn colour_at(&self, p: Vec3, error: Vec3) -> Vec3 {
        // f64, because f32's step far from the origin is larger than the
        // nudge.
        let q = self.to_pattern.transform_point3(p.as_dvec3());
        // p's error, at least its own rounding, through the linear map.
        let e = error.max(p.abs() * f32::EPSILON).as_dvec3();
        let m = self.to_pattern.matrix3.transpose();
        let slack = DVec3::new(
            m.x_axis.abs().dot(e),
            m.y_axis.abs().dot(e),
            m.z_axis.abs().dot(e),
        );
        let cube = |c: f64, slack: f64| {
            let face = c.round();
            let c = if (c - face).abs() <= slack { face } else { c };
            (c + NUDGE).floor()
        };
        let sum = cube(q.x, slack.x) + cube(q.y, slack.y) + cube(q.z, slack.z);
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
        assert_eq!(c.colour_at(Vec3::new(0.5, 0.5, 0.5), Vec3::ZERO), A);
        // Across each face of it: one coordinate changes by one, so the parity flips.
        assert_eq!(c.colour_at(Vec3::new(1.5, 0.5, 0.5), Vec3::ZERO), B);
        assert_eq!(c.colour_at(Vec3::new(0.5, 1.5, 0.5), Vec3::ZERO), B);
        assert_eq!(c.colour_at(Vec3::new(0.5, 0.5, 1.5), Vec3::ZERO), B);
        // Either side of the face x = 1, close to it but beyond the tolerance.
        assert_eq!(c.colour_at(Vec3::new(0.99, 0.5, 0.5), Vec3::ZERO), A);
        assert_eq!(c.colour_at(Vec3::new(1.01, 0.5, 0.5), Vec3::ZERO), B);
        // Two steps: even again.
        assert_eq!(c.colour_at(Vec3::new(1.5, 1.5, 0.5), Vec3::ZERO), A);
    }

    #[test]
    fn negative_coordinates_floor_downwards() {
        let c = unit();
        // ⌊−0.5⌋ = −1: the cube (−1, 0, 0) is odd; truncation would make it 0, even.
        assert_eq!(c.colour_at(Vec3::new(-0.5, 0.5, 0.5), Vec3::ZERO), B);
        // (−1, −1, 0): even.
        assert_eq!(c.colour_at(Vec3::new(-0.5, -0.5, 0.5), Vec3::ZERO), A);
        // (−1, −1, −1): odd.
        assert_eq!(c.colour_at(Vec3::new(-0.5, -0.5, -0.5), Vec3::ZERO), B);
    }

    #[test]
    fn a_plane_on_a_cube_face_takes_the_cubes_above_it() {
        let c = unit();
        // The plane y = −1, hit a rounding below or above the face: both
        // are in cube y = −1 (the one above the face), so the colour is that
        // of x + z − 1; along the floor only x and z change it.
        let ulp = f32::EPSILON; // the f32 step just above 1
        for (y, error) in [
            (-1.0f32, 0.0),
            (-1.0 - ulp, 0.0),
            (-1.0 + ulp / 2.0, 0.0),
            // Further off, within the hit's own error bound.
            (-1.0 - 5e-4, 1e-3),
        ] {
            let error = Vec3::splat(error);
            assert_eq!(c.colour_at(Vec3::new(0.5, y, 0.5), error), B, "y = {y}");
            assert_eq!(c.colour_at(Vec3::new(1.5, y, 0.5), error), A, "y = {y}");
        }
        // Beyond its error a point is where it is, as in POV-Ray 3.7 (whose
        // nudge is 1e-10): y = −1.0005 is in cube −2.
        assert_eq!(c.colour_at(Vec3::new(0.5, -1.0005, 0.5), Vec3::ZERO), A);
    }

    #[test]
    fn a_long_cube_changes_at_zero() {
        // POV-Ray's iortest.pov floor: `checker … scale <32000, 1, 2>`. Its
        // cubes meet at x = 0, where the colours swap (3.6's nudge of 1e-3
        // in pattern space moved the swap to x = −32).
        let long = Checker {
            to_pattern: DAffine3::from_scale(DVec3::new(32000.0, 1.0, 2.0)).inverse(),
            ..unit()
        };
        let error = Vec3::splat(1e-5);
        for z in [0.5, 2.5, -1.5] {
            let left = long.colour_at(Vec3::new(-0.01, -1.0, z), error);
            let right = long.colour_at(Vec3::new(0.01, -1.0, z), error);
            assert_ne!(left, right, "z = {z}");
            assert_eq!(left, long.colour_at(Vec3::new(-31.0, -1.0, z), error));
        }
    }

    #[test]
    fn the_transform_moves_and_sizes_the_cubes() {
        // Cubes of side 2: the world point (1.5, 0.5, 0.5) is pattern (0.75, 0.25, 0.25), cube 0.
        let scaled = Checker {
            to_pattern: DAffine3::from_scale(DVec3::splat(0.5)),
            ..unit()
        };
        assert_eq!(scaled.colour_at(Vec3::new(1.5, 0.5, 0.5), Vec3::ZERO), A);
        assert_eq!(scaled.colour_at(Vec3::new(2.5, 0.5, 0.5), Vec3::ZERO), B);
        // Rotated by 90° about z (the pigment's), inverted for world → pattern:
        // the world point (0.5, 1.5, 0.5) is pattern (1.5, −0.5, 0.5), cube
        // (1, −1, 0), even; unrotated it is cube (0, 1, 0), odd.
        let rotate = DAffine3::from_quat(DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2));
        let rotated = Checker {
            to_pattern: rotate.inverse(),
            ..unit()
        };
        let p = Vec3::new(0.5, 1.5, 0.5);
        assert_eq!(unit().colour_at(p, Vec3::ZERO), B);
        assert_eq!(rotated.colour_at(p, Vec3::ZERO), A);
        // Translated by half a cube along x: (0.7, 0.5, 0.5) is pattern 0.2, cube 0;
        // (0.3, …) is pattern −0.2, cube −1.
        let moved = Checker {
            to_pattern: DAffine3::from_translation(DVec3::new(-0.5, 0.0, 0.0)),
            ..unit()
        };
        assert_eq!(moved.colour_at(Vec3::new(0.7, 0.5, 0.5), Vec3::ZERO), A);
        assert_eq!(moved.colour_at(Vec3::new(0.3, 0.5, 0.5), Vec3::ZERO), B);
    }

    #[test]
    fn far_points_still_give_one_of_the_colours() {
        let c = Checker {
            to_pattern: DAffine3::from_scale(DVec3::splat(1e30)),
            ..unit()
        };
        for p in [Vec3::splat(1.8e18), Vec3::splat(-1.8e18), Vec3::ZERO] {
            let colour = c.colour_at(p, Vec3::ZERO);
            assert!(colour == A || colour == B, "{colour}");
        }
    }
}
