//! Colour-mapped patterns a material's albedo can follow: POV-Ray's
//! `gradient`, `radial`, `onion`, `spherical`, `cylindrical`, `boxed`,
//! `planar`, `leopard`, and `marble` and `wood` without turbulence. A
//! pattern gives a number at each point of its space; `frequency` and
//! `phase` wrap it, its wave shapes it, and the colour map turns it into a
//! colour. The formulas are POV-Ray 3.7's (`pattern.cpp`'s patterns and
//! `Evaluate_TPat`, `Search_Blend_Map`), read for their facts and written
//! here anew; the renders are checked against POV-Ray's in the tests.

use std::f64::consts::PI;

use glam::{DAffine3, DVec3};

use crate::math::Vec3;

/// The number a pattern gives at a point of its space.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub enum PatternKind {
    /// Along a unit direction: the point's dot product with it, above 1
    /// wrapped to its fraction.
    Gradient(DVec3),
    /// Round the y axis, from 0.25 to 1.25 in a turn.
    Radial,
    /// The fraction of the distance from the origin.
    Onion,
    /// 1 at the origin down to 0 at distance 1 and beyond.
    Spherical,
    /// 1 on the y axis down to 0 at distance 1 and beyond.
    Cylindrical,
    /// 1 at the origin down to 0 on the unit cube's faces and beyond.
    Boxed,
    /// 1 in the plane y = 0 down to 0 at |y| = 1 and beyond.
    Planar,
    /// Spots on a grid: the squared mean of sin x, sin y and sin z.
    Leopard,
    /// Along x (POV-Ray's marble without turbulence).
    Marble,
    /// The distance from the z axis (POV-Ray's wood without turbulence).
    Wood,
}

/// How a pattern's number is folded into [0, 1] (POV-Ray's wave types).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub enum Wave {
    Ramp,
    Triangle,
    Sine,
    Scallop,
    Cubic,
    /// The ramp raised to a power.
    Poly(f64),
}

/// A pattern with its colour map, placed in the world.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Mapped {
    pub kind: PatternKind,
    pub wave: Wave,
    pub frequency: f64,
    pub phase: f64,
    /// The colour map's entries, by increasing value.
    pub map: Vec<(f64, Vec3)>,
    /// World space to the pattern's space.
    pub to_pattern: DAffine3,
}

impl PatternKind {
    /// The pattern's number at `p`, in its own space, before the wave.
    fn value(self, p: DVec3) -> f64 {
        let to_unit = |v: f64| v.clamp(0.0, 1.0);
        match self {
            PatternKind::Gradient(v) => {
                let value = p.dot(v);
                if value > 1.0 { value % 1.0 } else { value }
            }
            // On the axis itself, POV-Ray's value (atan2 is undefined there).
            PatternKind::Radial if p.x.abs() < 1e-3 && p.z.abs() < 1e-3 => 0.25,
            PatternKind::Radial => 0.25 + (p.x.atan2(p.z) + PI) / (2.0 * PI),
            PatternKind::Onion => p.length() % 1.0,
            PatternKind::Spherical => to_unit(1.0 - p.length()),
            PatternKind::Cylindrical => to_unit(1.0 - (p.x * p.x + p.z * p.z).sqrt()),
            PatternKind::Boxed => to_unit(1.0 - p.abs().max_element()),
            PatternKind::Planar => to_unit(1.0 - p.y.abs()),
            PatternKind::Leopard => {
                let s = (p.x.sin() + p.y.sin() + p.z.sin()) / 3.0;
                s * s
            }
            PatternKind::Marble => p.x,
            PatternKind::Wood => (p.x * p.x + p.y * p.y).sqrt(),
        }
    }
}

/// POV-Ray's modulus for `frequency` and `phase` (1.00001, not 1: its own
/// source flags the number, and a value far out drifts by it, so it is
/// kept for the same colours).
const WRAP: f64 = 1.00001;

impl Wave {
    /// The wave of `v`, already wrapped to [0, 1.00001).
    fn shape(self, v: f64) -> f64 {
        match self {
            Wave::Ramp => v,
            Wave::Triangle => {
                let f = v - v.floor();
                if f < 0.5 { 2.0 * f } else { 2.0 * (1.0 - f) }
            }
            Wave::Sine => 0.5 * (1.0 + (2.0 * PI * v).sin()),
            Wave::Scallop => (PI * v).sin().abs(),
            Wave::Cubic => v * v * (3.0 - 2.0 * v),
            Wave::Poly(e) => v.powf(e),
        }
    }
}

impl Mapped {
    /// The colour at world point `p`.
    pub fn colour_at(&self, p: Vec3) -> Vec3 {
        let q = self.to_pattern.transform_point3(p.as_dvec3());
        let mut v = self.kind.value(q);
        // A frequency of 0 leaves the value as it is, phase and all.
        if self.frequency != 0.0 {
            v = (v * self.frequency + self.phase) % WRAP;
        }
        if v < 0.0 {
            v -= v.floor();
        }
        // A value with no meaning (a pattern scaled to nothing, a frequency
        // past f64's range) takes the map's first colour, not a NaN albedo.
        let v = self.wave.shape(v);
        lookup(&self.map, if v.is_nan() { 0.0 } else { v })
    }
}

/// The colour map's colour at `v`, as POV-Ray looks it up in the entries'
/// own order: the last entry's at or above its value; else the first entry
/// at or above `v` gives its colour if `v` is its value or it is the first,
/// and otherwise the straight line from the entry before it.
fn lookup(map: &[(f64, Vec3)], v: f64) -> Vec3 {
    let Some(&(last, end)) = map.last() else {
        return Vec3::ZERO;
    };
    if v >= last {
        return end;
    }
    let i = map.iter().position(|e| e.0 >= v).unwrap_or(map.len() - 1);
    let (b, cb) = map[i];
    if i == 0 || v == b {
        return cb;
    }
    let (a, ca) = map[i - 1];
    if b == a {
        return cb;
    }
    ca + ((v - a) / (b - a)) as f32 * (cb - ca)
}

#[cfg(test)]
mod tests {
    use super::*;

    const RED: Vec3 = Vec3::new(1.0, 0.0, 0.0);
    const GREEN: Vec3 = Vec3::new(0.0, 1.0, 0.0);
    const BLUE: Vec3 = Vec3::new(0.0, 0.0, 1.0);

    fn gradient_x(wave: Wave, frequency: f64, phase: f64, map: Vec<(f64, Vec3)>) -> Mapped {
        Mapped {
            kind: PatternKind::Gradient(DVec3::X),
            wave,
            frequency,
            phase,
            map,
            to_pattern: DAffine3::IDENTITY,
        }
    }

    fn at(m: &Mapped, x: f32) -> Vec3 {
        m.colour_at(Vec3::new(x, 0.0, 0.0))
    }

    #[test]
    fn a_map_is_looked_up_as_povray_looks_it_up() {
        // Below the first entry its colour, at or above the last the last's,
        // between two a straight line, and at a repeated value (a sharp
        // step) the first of the equal entries.
        let map = vec![(0.25, RED), (0.5, GREEN), (0.5, BLUE), (0.75, RED)];
        assert_eq!(lookup(&map, 0.1), RED);
        assert_eq!(lookup(&map, 0.9), RED);
        assert_eq!(lookup(&map, 0.75), RED);
        assert_eq!(lookup(&map, 0.375), Vec3::new(0.5, 0.5, 0.0));
        assert_eq!(lookup(&map, 0.5), GREEN);
        assert_eq!(lookup(&map, 0.625), Vec3::new(0.5, 0.0, 0.5));
        assert_eq!(lookup(&[], 0.5), Vec3::ZERO);
    }

    #[test]
    fn frequency_and_phase_wrap_and_a_negative_value_comes_round() {
        let ramp = gradient_x(
            Wave::Ramp,
            1.0,
            0.0,
            vec![(0.0, Vec3::ZERO), (1.0, Vec3::ONE)],
        );
        // A gradient above 1 wraps to its fraction, and below 0 comes round:
        // x = -0.25 is 0.75, as POV-Ray gives.
        assert!((at(&ramp, 1.25) - Vec3::splat(0.25)).length() < 1e-5);
        assert!((at(&ramp, -0.25) - Vec3::splat(0.75)).length() < 1e-5);
        // Twice the frequency and a phase of 0.1: 0.3 · 2 + 0.1 = 0.7.
        let fast = gradient_x(Wave::Ramp, 2.0, 0.1, ramp.map.clone());
        assert!((at(&fast, 0.3) - Vec3::splat(0.7)).length() < 1e-5);
        // A frequency of 0 leaves the value alone, phase and all.
        let still = gradient_x(Wave::Ramp, 0.0, 0.5, ramp.map.clone());
        assert!((at(&still, 0.3) - Vec3::splat(0.3)).length() < 1e-5);
    }

    #[test]
    fn a_value_with_no_meaning_takes_the_first_colour() {
        let map = vec![(0.0, RED), (1.0, BLUE)];
        let wild = gradient_x(Wave::Ramp, f64::INFINITY, 0.0, map.clone());
        assert_eq!(at(&wild, 0.5), RED);
        let mut flat = gradient_x(Wave::Ramp, 1.0, 0.0, map);
        flat.to_pattern = DAffine3::from_scale(DVec3::ZERO).inverse();
        assert!(at(&flat, 0.5).is_finite());
    }

    #[test]
    fn the_waves_have_povray_s_shapes() {
        let shape = |w: Wave, v: f64| w.shape(v);
        assert_eq!(shape(Wave::Triangle, 0.25), 0.5);
        assert_eq!(shape(Wave::Triangle, 0.75), 0.5);
        assert!((shape(Wave::Sine, 0.25) - 1.0).abs() < 1e-12);
        assert!((shape(Wave::Scallop, 0.5) - 1.0).abs() < 1e-12);
        assert_eq!(shape(Wave::Cubic, 0.5), 0.5);
        assert_eq!(shape(Wave::Poly(2.0), 0.5), 0.25);
    }

    #[test]
    fn the_clipped_patterns_fall_from_1_to_0_over_unit_distance() {
        let p = DVec3::new(0.3, 0.4, 0.0);
        assert!((PatternKind::Spherical.value(p) - 0.5).abs() < 1e-12);
        assert_eq!(PatternKind::Spherical.value(DVec3::new(3.0, 0.0, 0.0)), 0.0);
        assert!((PatternKind::Cylindrical.value(DVec3::new(0.6, 9.0, 0.0)) - 0.4).abs() < 1e-12);
        assert!((PatternKind::Boxed.value(DVec3::new(0.2, -0.7, 0.1)) - 0.3).abs() < 1e-12);
        assert!((PatternKind::Planar.value(DVec3::new(5.0, 0.25, 5.0)) - 0.75).abs() < 1e-12);
        assert!((PatternKind::Onion.value(DVec3::new(0.0, 1.5, 2.0)) - 0.5).abs() < 1e-12);
        // Radial on its axis is POV-Ray's 0.25; a quarter turn round adds 0.25.
        assert_eq!(PatternKind::Radial.value(DVec3::Y), 0.25);
        let (a, b) = (
            PatternKind::Radial.value(DVec3::Z),
            PatternKind::Radial.value(DVec3::X),
        );
        assert!((b - a - 0.25).abs() < 1e-12, "{a} {b}");
    }
}
