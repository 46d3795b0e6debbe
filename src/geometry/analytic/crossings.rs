//! Every crossing of one shape along a line, with its direction: what CSG
//! combines. Inside is where F < 0 (see `surface`) and, for a solid, within
//! the shape's box, so a clip box closes a surface it cuts (a cylinder cut
//! by its box is a capped solid): where the line enters or leaves the box
//! while F < 0 there, the box's face is a crossing too.
//!
//! Only crossings count, as for the nearest hit: a tangent touch, or a
//! double root touching from outside, changes no inside state and is no
//! crossing. No allocation: a line crosses a surface of degree n at most n
//! times, plus the two faces of the box.

use glam::DVec3;

use super::{Box3, RayPoly, Shape};
use crate::poly::MAX_DEGREE;

/// One crossing of a line o + t·d, in the line's own parameter t.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    pub t: f64,
    /// How far apart, in t, two crossings may be found and still be one
    /// point (the root's refinement width): CSG takes crossings of two
    /// children this close as simultaneous.
    pub width: f64,
    /// From outside (F > 0) to inside (F < 0).
    pub entering: bool,
    /// The face of the shape's box crossed (axis · 2, plus 1 for the max
    /// side), or None for the surface itself.
    pub face: Option<u8>,
}

/// At most degree + 2 crossings, increasing in t.
const CAPACITY: usize = MAX_DEGREE + 2;

/// The crossings of one shape along one line, in a fixed-capacity array.
/// Reuse one for many lines: making one zeroes 1.5 KB, which per leaf and
/// ray was 3% of the instructions of POV-Ray's helix.pov
/// (`valgrind --tool=callgrind`).
#[derive(Clone, Copy, Debug)]
pub struct Crossings {
    items: [Crossing; CAPACITY],
    len: usize,
    /// The roots of the surface alone, before the box's faces are known:
    /// scratch space of `Shape::crossings`, kept here to be reused with it.
    roots: [(f64, bool); CAPACITY],
}

impl Default for Crossings {
    fn default() -> Crossings {
        let none = Crossing {
            t: 0.0,
            width: 0.0,
            entering: false,
            face: None,
        };
        Crossings {
            items: [none; CAPACITY],
            len: 0,
            roots: [(0.0, false); CAPACITY],
        }
    }
}

impl Crossings {
    pub fn as_slice(&self) -> &[Crossing] {
        &self.items[..self.len]
    }

    fn push(&mut self, c: Crossing) -> bool {
        if self.len == CAPACITY {
            return false;
        }
        self.items[self.len] = c;
        self.len += 1;
        true
    }
}

impl Box3 {
    /// The faces (axis · 2 + side) where the line o + s·d enters and leaves
    /// the box's slabs last and first: the faces of `clip_ray`'s interval.
    fn faces(&self, o: DVec3, d: DVec3) -> (u8, u8) {
        let (mut entry, mut exit) = ((f64::NEG_INFINITY, 0), (f64::INFINITY, 0));
        for axis in 0..3 {
            if d[axis] == 0.0 {
                continue;
            }
            let (near, far) = if d[axis] > 0.0 {
                (self.min[axis], self.max[axis])
            } else {
                (self.max[axis], self.min[axis])
            };
            let side = |bound: f64| axis as u8 * 2 + u8::from(bound == self.max[axis]);
            let (tn, tf) = ((near - o[axis]) / d[axis], (far - o[axis]) / d[axis]);
            if tn > entry.0 {
                entry = (tn, side(near));
            }
            if tf < exit.0 {
                exit = (tf, side(far));
            }
        }
        (entry.1, exit.1)
    }
}

impl Shape {
    /// Every crossing of the world line o + t·d with t in (tmin, tmax),
    /// increasing, into `out`. With `solid`, the faces of the shape's box
    /// where F < 0 count too (see the module's doc); pass tmin = −∞ to have
    /// every crossing from where the line enters the box, where it is outside.
    /// Returns whether a solid's line is inside at tmin (when tmin, not the
    /// box, starts the interval; F's sign there, see `side`).
    pub fn crossings(
        &self,
        o: DVec3,
        d: DVec3,
        tmin: f64,
        tmax: f64,
        solid: bool,
        out: &mut Crossings,
    ) -> bool {
        out.len = 0;
        in_storage!(self, S => self.crossings_in::<S>(o, d, tmin, tmax, solid, out))
    }

    /// `crossings` with the ray's Q in `S` slots (see `ray_polynomial_in`).
    fn crossings_in<const S: usize>(
        &self,
        o: DVec3,
        d: DVec3,
        tmin: f64,
        tmax: f64,
        solid: bool,
        out: &mut Crossings,
    ) -> bool {
        let Some(ray) = self.ray_polynomial_in::<S>(o, d, tmin, tmax) else {
            return false;
        };
        let to_t = |s: f64| (ray.t0 + s) / ray.length;
        let (entry, exit) = self.object_box.faces(ray.start - ray.t0 * ray.d, ray.d);
        // At the box's ends the face is crossed, with the face's normal: where
        // the surface meets the face too, the point is on an edge of the solid,
        // where either normal is right and the gradient may vanish (a cone's apex).
        let end = |s: f64, face: u8, entering: bool| Crossing {
            t: to_t(s),
            width: face_width(to_t(s)),
            entering,
            face: Some(face),
        };
        let mut n = 0;
        self.each_crossing(&ray, |s, entering, _| {
            out.roots[n] = (s, entering);
            n += 1;
            n < CAPACITY - 2
        });
        let mut inside = false;
        let mut starts_inside = false;
        if solid {
            // Where F is 0 at the face (a cylinder's side meeting its box, a
            // cone's apex on its cap), its sign before the first crossing says
            // the state: F keeps one sign between crossings.
            let first = out.roots[..n].first().map_or(ray.hi, |r| r.0);
            inside = self
                .side_of_start(&ray)
                .unwrap_or_else(|| self.side(ray.start + 0.5 * first * ray.d, ray.d) == Some(true));
            // Where tmin, not the box, starts the interval, the line is already there.
            if inside && ray.enters_after(tmin) {
                out.push(end(0.0, entry, true));
            } else {
                starts_inside = inside;
            }
        }
        for i in 0..n {
            let (s, entering) = out.roots[i];
            // A solid's crossings alternate: one that repeats the state is the
            // root the box's end already accounted for.
            if solid && entering == inside {
                continue;
            }
            inside = entering;
            out.push(Crossing {
                t: to_t(s),
                width: self.refine_width(s) / ray.length,
                entering,
                face: None,
            });
        }
        if inside && ray.leaves_before(tmax) {
            out.push(end(ray.hi, exit, false));
        }
        starts_inside
    }

    /// Whether the world ray o + t·d certainly crosses neither the surface
    /// nor, as a `solid`, its box's faces for t in (tmin, tmax), found
    /// without refining a root: Q has no root there (the solver's certified
    /// `any`), so F keeps one sign, and a face is crossed only where the box,
    /// not the interval, ends and F < 0 there. A ray that may cross answers
    /// false.
    pub(super) fn crosses_nothing(
        &self,
        o: DVec3,
        d: DVec3,
        tmin: f64,
        tmax: f64,
        solid: bool,
    ) -> bool {
        in_storage!(self, S => self.crosses_nothing_in::<S>(o, d, tmin, tmax, solid))
    }

    /// `crosses_nothing` with the ray's Q in `S` slots.
    fn crosses_nothing_in<const S: usize>(
        &self,
        o: DVec3,
        d: DVec3,
        tmin: f64,
        tmax: f64,
        solid: bool,
    ) -> bool {
        let Some(ray) = self.ray_polynomial_in::<S>(o, d, tmin, tmax) else {
            return true;
        };
        if self.solver.any(&ray.q, 0.0, ray.hi) {
            return false;
        }
        let faces = ray.enters_after(tmin) || ray.leaves_before(tmax);
        !solid || !faces || self.side_of_start(&ray) == Some(false)
    }

    /// Whether the object-space point p is inside (F < 0) or outside, or
    /// None where F is within its rounding noise of 0.
    pub(super) fn side(&self, p: DVec3, d: DVec3) -> Option<bool> {
        in_storage!(self, S => self.side_in::<S>(p, d))
    }

    fn side_in<const S: usize>(&self, p: DVec3, d: DVec3) -> Option<bool> {
        let q = self.surface.along_in::<S>(p, d);
        self.side_from(p, q.coeffs().len(), q.eval(0.0))
    }

    /// `side` at the ray's start, from the ray's own Q: its value at 0 is
    /// F(start), the same bits a second substitution gave (trimming drops
    /// leading terms only), which cost 7% of the instructions of POV-Ray's
    /// tcubic.pov (`valgrind --tool=callgrind`).
    fn side_of_start<const S: usize>(&self, ray: &RayPoly<S>) -> Option<bool> {
        self.side_from(ray.start, ray.formed, ray.q.eval(0.0))
    }

    /// The side for F's value `f` at p, from a Q of `len` coefficients.
    fn side_from(&self, p: DVec3, len: usize, f: f64) -> Option<bool> {
        let noise = f64::EPSILON * (4 * len) as f64 * self.surface.magnitude(p);
        (f.abs() > noise).then_some(f < 0.0)
    }

    /// The world normal (unnormalised) of the hit `c` of the world line o + t·d.
    pub fn crossing_normal(&self, o: DVec3, d: DVec3, c: &Crossing) -> DVec3 {
        match c.face {
            Some(face) => {
                let mut n = DVec3::ZERO;
                n[usize::from(face / 2)] = if face % 2 == 1 { 1.0 } else { -1.0 };
                self.normal_to_world * n
            }
            None => self.normal_at(
                self.to_object.transform_point3(o) + c.t * self.to_object.transform_vector3(d),
            ),
        }
    }
}

/// How far apart two crossings computed in closed form (a box face, a
/// plane) may be and still be one point: a few roundings of t.
pub fn face_width(t: f64) -> f64 {
    8.0 * f64::EPSILON * t.abs().max(1.0)
}
