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

use super::{Box3, RayPoly, Shape, Surface};
use crate::poly::MAX_DEGREE;
use crate::poly::closed::quadratic;

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
    /// The roots of the surface alone, before the box's faces are known
    /// (t, width, entering): scratch space of `Shape::crossings`, kept here
    /// to be reused with it.
    roots: [(f64, f64, bool); CAPACITY],
    /// Whether the walk stopped where the caller asked it to (see
    /// `Shape::crossings`): crossings further on were not looked for.
    stopped: bool,
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
            roots: [(0.0, 0.0, false); CAPACITY],
            stopped: false,
        }
    }
}

impl Crossings {
    pub fn as_slice(&self) -> &[Crossing] {
        &self.items[..self.len]
    }

    /// Whether the walk that gave these stopped early, at the caller's
    /// `stop` (see `Shape::crossings`): the last of them may not be the
    /// line's last.
    pub fn stopped(&self) -> bool {
        self.stopped
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

/// Where a line enters and leaves a shape's box: the t, and whether the
/// box, not the ray's own interval, ends it there (so a face is crossed).
struct Ends {
    entry: (f64, bool),
    exit: (f64, bool),
}

impl Crossings {
    /// The crossings from the surface's first `n` roots (in `roots`) and,
    /// for a `solid` that is `inside` where the line's interval starts, the
    /// box's faces where F < 0 on them (`faces`: which the line enters and
    /// leaves by, asked only for a face crossed); returns whether the line
    /// is inside at its start (where tmin, not the box, starts the interval).
    fn assemble(
        &mut self,
        n: usize,
        solid: bool,
        mut inside: bool,
        ends: &Ends,
        faces: impl Fn() -> (u8, u8),
    ) -> bool {
        // At the box's ends the face is crossed, with the face's normal:
        // where the surface meets the face too, the point is on an edge of
        // the solid, where either normal is right and the gradient may
        // vanish (a cone's apex).
        let face = |t: f64, face: u8, entering| Crossing {
            t,
            width: face_width(t),
            entering,
            face: Some(face),
        };
        let mut starts_inside = false;
        // Where tmin, not the box, starts the interval, the line is already there.
        if inside && ends.entry.1 {
            self.push(face(ends.entry.0, faces().0, true));
        } else {
            starts_inside = inside;
        }
        for i in 0..n {
            let (t, width, entering) = self.roots[i];
            // A solid's crossings alternate: one that repeats the state is the
            // root the box's end already accounted for.
            if solid && entering == inside {
                continue;
            }
            inside = entering;
            self.push(Crossing {
                t,
                width,
                entering,
                face: None,
            });
        }
        // Not where the walk stopped early: the line may cross again first.
        // A sheet has no inside, so no face: where its line leaves the box
        // after crossing inwards, the surface is open.
        if solid && inside && ends.exit.1 && !self.stopped {
            self.push(face(ends.exit.0, faces().1, false));
        }
        starts_inside
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
        self.crossings_until(o, d, tmin, tmax, solid, out, |_| false)
    }

    /// `crossings`, stopping after the first root of the surface at whose
    /// t `stop` answers true (`out.stopped()`): a caller that needs only
    /// the first crossing of some kind saves finding and refining the rest.
    #[allow(clippy::too_many_arguments)]
    pub fn crossings_until(
        &self,
        o: DVec3,
        d: DVec3,
        tmin: f64,
        tmax: f64,
        solid: bool,
        out: &mut Crossings,
        mut stop: impl FnMut(f64) -> bool,
    ) -> bool {
        out.len = 0;
        out.stopped = false;
        if let Some(starts) = self.closed_crossings(o, d, tmin, tmax, solid, out, &mut stop) {
            return starts;
        }
        out.len = 0;
        out.stopped = false;
        in_storage!(self, S => self.crossings_in::<S>(o, d, tmin, tmax, solid, out, stop))
    }

    /// `crossings_until` for a sphere or a quadric in closed form, in the
    /// ray's own t: the roots of Q(t) = c0 + c1 t + c2 t² by the stable
    /// formula, each kept only where it is certified to lie within a
    /// quarter of its refinement width of the true root (the rounding of
    /// Q's terms there over |Q'|, plus the formula's own few roundings),
    /// and the roots apart by more than their widths. Then the root is a
    /// simple crossing, entering where Q' < 0, as the general walk's
    /// polish would find it, to its width. None where that fails (a graze,
    /// a far or tiny shape, a state at the start within the noise), and
    /// for other surfaces: the general walk answers. A clipping sphere's
    /// crossings took some 1,900 instructions a line that way, forming Q
    /// in the unit frame and polishing each root (`valgrind
    /// --tool=callgrind`, POV-Ray's tcubic.pov).
    #[allow(clippy::too_many_arguments)]
    fn closed_crossings(
        &self,
        o: DVec3,
        d: DVec3,
        tmin: f64,
        tmax: f64,
        solid: bool,
        out: &mut Crossings,
        stop: &mut impl FnMut(f64) -> bool,
    ) -> Option<bool> {
        if !self.quadratic() {
            return None;
        }
        let (o, d, length) = self.object_line(o, d)?;
        let Some((t0, t1)) = self.object_box.clip_ray(o, d, tmin, tmax) else {
            return Some(false);
        };
        if !(t0.is_finite() && t1.is_finite()) {
            return None;
        }
        let ends = Ends {
            entry: (t0, t0 > tmin),
            exit: (t1, t1 < tmax),
        };
        let faces = || self.object_box.faces(o, d);
        // Q in u = t − t0, from where the line enters the box: its terms,
        // and so their rounding, are the box's size, not the way from a
        // far origin (as the general walk forms Q at its frame's start).
        let start = o + t0 * d;
        // A box (F = c ≠ 0 within its box): Q is that c along the whole
        // line, with no root, and c's sign is the side, which is what the
        // steps below find for it (at a finite start, where each of Q's
        // terms is c or a zero). Those steps were a third of the box's
        // crossings, the clip objects of POV-Ray's monkey, trough and
        // quarpara samples (`valgrind --tool=callgrind`).
        if let Surface::Quadric(quadric) = &self.surface
            && let Some(c) = quadric.constant()
            && start.is_finite()
        {
            return Some(out.assemble(0, solid, solid && c < 0.0, &ends, faces));
        }
        let [c0, c1, c2] = self.surface.along_line(start, d)?;
        let q = |u: f64| c0 + u * (c1 + u * c2);
        // The rounding of Q's terms at u: F's terms made positive there.
        let noise =
            |u: f64| 16.0 * f64::EPSILON * self.surface.magnitude(start.abs() + u.abs() * d.abs());
        let width = |u: f64| self.refine_width(u * length) / length;
        let hi = t1 - t0;
        let mut closed = [0.0; 4];
        let found = quadratic(c0, c1, c2, &mut closed);
        let (from, to) = (
            closed[..found].partition_point(|&u| u <= 0.0),
            closed[..found].partition_point(|&u| u < hi),
        );
        // A line that touches the box at one point (hi = 0) and the
        // surface there has a root at 0 = hi: none lies strictly between.
        let roots = &closed[from..to.max(from)];
        for (k, &u) in roots.iter().enumerate() {
            // The root's error, and t0 + u's rounding.
            let error = noise(u) / (2.0 * c2 * u + c1).abs() + 4.0 * f64::EPSILON * (t0 + u).abs();
            let apart = roots
                .get(k + 1)
                .is_none_or(|&next| next - u > 4.0 * width(next));
            if !(error <= 0.25 * width(u) && apart) {
                return None;
            }
        }
        let first = roots.first().copied().unwrap_or(hi);
        let side = |u: f64| {
            let value = q(u);
            (value.abs() > noise(u)).then_some(value < 0.0)
        };
        let inside = match solid {
            true => side(0.0).or_else(|| side(0.5 * first))?,
            false => false,
        };
        let mut n = 0;
        for &u in roots {
            out.roots[n] = (t0 + u, width(u), 2.0 * c2 * u + c1 < 0.0);
            n += 1;
            out.stopped = stop(t0 + u);
            if out.stopped {
                break;
            }
        }
        Some(out.assemble(n, solid, inside, &ends, faces))
    }

    /// `crossings` with the ray's Q in `S` slots (see `ray_polynomial_in`).
    #[allow(clippy::too_many_arguments)]
    fn crossings_in<const S: usize>(
        &self,
        o: DVec3,
        d: DVec3,
        tmin: f64,
        tmax: f64,
        solid: bool,
        out: &mut Crossings,
        mut stop: impl FnMut(f64) -> bool,
    ) -> bool {
        let Some(ray) = self.ray_polynomial_in::<S>(o, d, tmin, tmax) else {
            return false;
        };
        let to_t = |s: f64| (ray.t0 + s) / ray.length;
        let mut n = 0;
        let mut first = ray.hi;
        self.each_crossing(&ray, |s, entering, _| {
            if n == 0 {
                first = s;
            }
            out.roots[n] = (to_t(s), self.refine_width(s) / ray.length, entering);
            n += 1;
            out.stopped = stop(to_t(s));
            n < CAPACITY - 2 && !out.stopped
        });
        // Where F is 0 at the face (a cylinder's side meeting its box, a
        // cone's apex on its cap), its sign before the first crossing says
        // the state: F keeps one sign between crossings.
        let inside = solid
            && self
                .side_of_start(&ray)
                .unwrap_or_else(|| self.side(ray.start + 0.5 * first * ray.d, ray.d) == Some(true));
        let ends = Ends {
            entry: (to_t(0.0), ray.enters_after(tmin)),
            exit: (to_t(ray.hi), ray.leaves_before(tmax)),
        };
        out.assemble(n, solid, inside, &ends, || {
            self.object_box.faces(ray.start - ray.t0 * ray.d, ray.d)
        })
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

#[cfg(test)]
mod tests {
    use glam::{DAffine3, DMat3, DQuat, DVec3};

    use super::super::{Box3, Quadric, Shape, Surface};
    use super::Crossings;
    use crate::poly::solve::Solver;

    /// A line that touches a capped cylinder's box only at a point of its
    /// rim, where the cylinder's surface meets the box's edge, is answered
    /// with finite crossings, whichever way it goes and from either side
    /// (the closed form panicked on it, a root at the box's one point: POV-Ray's
    /// qtvrpanorama.pov with its box of cylinders unturned).
    #[test]
    fn a_line_touching_the_rim_at_one_point_is_answered() {
        let cylinder = Shape::new(
            Surface::Quadric(Quadric {
                a: DMat3::from_diagonal(DVec3::new(1.0, 1.0, 0.0)),
                b: DVec3::ZERO,
                c: -1.0,
            }),
            DAffine3::IDENTITY,
            Some(Box3::cube(1.0)),
            0,
            Solver::default(),
        )
        .unwrap();
        let rim = DVec3::new(1.0, 0.0, 1.0);
        for d in [DVec3::new(1.0, 0.0, -1.0), DVec3::new(-1.0, 0.0, 1.0)] {
            for (o, tmin) in [(rim, 0.0), (rim - 2.0 * d, 0.0), (rim - 2.0 * d, 1.0)] {
                for solid in [true, false] {
                    let mut out = Crossings::default();
                    cylinder.crossings(o, d, tmin, f64::INFINITY, solid, &mut out);
                    assert!(
                        out.as_slice().iter().all(|c| c.t.is_finite()),
                        "{o} {d} {tmin}: {:?}",
                        out.as_slice()
                    );
                }
            }
        }
    }

    /// Shapes a CSG tree clips with: a ball, an ellipsoid (a scaled ball),
    /// a capped cylinder (cut by its box), a hyperboloid of one sheet and
    /// a cone's double nappe, each turned and moved off the origin.
    fn shapes() -> Vec<Shape> {
        let place = |scale: DVec3| {
            DAffine3::from_scale_rotation_translation(
                scale,
                DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -0.7, 1.1),
                DVec3::new(0.4, -0.2, 0.3),
            )
        };
        let quadric = |diagonal: DVec3, c: f64| {
            Surface::Quadric(Quadric {
                a: DMat3::from_diagonal(diagonal),
                b: DVec3::ZERO,
                c,
            })
        };
        let boxed = |half: f64| Some(Box3::cube(half));
        let shape = |surface, scale, clip| {
            Shape::new(surface, place(scale), clip, 0, Solver::default()).unwrap()
        };
        vec![
            shape(Surface::Sphere { radius: 1.0 }, DVec3::ONE, None),
            shape(
                Surface::Sphere { radius: 1.0 },
                DVec3::new(1.5, 0.5, 1.0),
                None,
            ),
            shape(
                quadric(DVec3::new(1.0, 1.0, 0.0), -0.64),
                DVec3::ONE,
                boxed(1.0),
            ),
            shape(
                quadric(DVec3::new(1.0, 1.0, -1.0), -0.25),
                DVec3::ONE,
                boxed(1.2),
            ),
            shape(
                quadric(DVec3::new(1.0, 1.0, -1.0), 0.0),
                DVec3::ONE,
                boxed(1.0),
            ),
        ]
    }

    /// Where the closed form answers, it gives the general walk's
    /// crossings: as many, with the same directions and faces, each within
    /// the two walks' widths of the other's; and it answers at least 99% of
    /// the lines (99.7-100% per shape when this was written).
    /// Lines from far and near, many through the shapes' edges and grazing
    /// them, solid and sheet, with and without a ray interval. (Where tmax
    /// ended a line inside the box, the general walk once put the box's
    /// face a rounding short of tmax, a crossing that is not there: found
    /// by this test.)
    #[test]
    fn closed_form_crossings_are_the_general_walks() {
        for (k, shape) in shapes().iter().enumerate() {
            let (mut closed, mut lines) = (0, 0);
            for i in 0..4000 {
                let x = f64::from(i);
                let aim = DVec3::new((x * 0.37).sin(), (x * 0.61).cos(), (x * 0.83).sin());
                let from = DVec3::new((x * 0.11).cos(), (x * 0.29).sin(), (x * 0.47).cos())
                    * (0.2 + 6.0 * (0.5 + 0.5 * (x * 0.93).sin()));
                let d = (aim * 1.1 + DVec3::new(0.4, -0.2, 0.3) - from)
                    * (0.5 + (x * 0.17).cos().abs());
                let (tmin, tmax) = match i % 3 {
                    0 => (f64::NEG_INFINITY, f64::INFINITY),
                    1 => (0.0, f64::INFINITY),
                    _ => (0.1, 0.9),
                };
                for solid in [true, false] {
                    lines += 1;
                    let mut short = Crossings::default();
                    let Some(starts) =
                        shape.closed_crossings(from, d, tmin, tmax, solid, &mut short, &mut |_| {
                            false
                        })
                    else {
                        continue;
                    };
                    closed += 1;
                    let mut whole = Crossings::default();
                    let whole_starts = in_storage!(shape, S => {
                        shape.crossings_in::<S>(from, d, tmin, tmax, solid, &mut whole, |_| false)
                    });
                    let (a, b) = (short.as_slice(), whole.as_slice());
                    let same = starts == whole_starts
                        && a.len() == b.len()
                        && a.iter().zip(b).all(|(a, b)| {
                            a.entering == b.entering
                                && a.face == b.face
                                && (a.t - b.t).abs() <= a.width + b.width
                        });
                    assert!(
                        same,
                        "shape {k}, line {i} from {from} along {d}, ({tmin}, {tmax}), solid {solid}: {a:?} ({starts}) against {b:?} ({whole_starts})"
                    );
                }
            }
            assert!(
                closed * 100 >= lines * 99,
                "shape {k}: the closed form answered {closed} of {lines} lines"
            );
        }
    }
}
