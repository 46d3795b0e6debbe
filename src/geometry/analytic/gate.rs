//! POV-Ray's `bounded_by` as a gate on a shape: rays that neither start
//! inside it nor cross its surface beyond their start never reach the
//! shape. Checked first in `Shape::intersect` and `Shape::occluded`; a shape
//! without a gate pays one branch for it.

use glam::DVec3;

use super::{Shape, Surface};

impl Shape {
    /// Gives the shape POV-Ray's `bounded_by` object: a ray is tested
    /// against the shape only if it starts inside the gate or crosses the
    /// gate's surface somewhere beyond its tmin, however far (past its tmax
    /// too); then every hit of the shape counts, inside the gate or not. For
    /// a gate that holds the shape this only saves time; for an unbounded
    /// surface it decides what is seen. The shape's box stays its own: the
    /// gate cuts rays, not space. Inside is the gate's own (F < 0 within its
    /// box, or a tree's state); a sheet has none and gates by crossings only.
    /// A tree is gated as a whole: the gate of a shape used as a tree's leaf
    /// is not consulted (a leaf gives its crossings along the whole line).
    pub fn set_gate(&mut self, gate: Shape) {
        self.gate = Some(Box::new(gate));
    }

    /// Whether this shape, as another's gate, lets the ray from o + tmin·d on
    /// through (see `set_gate`).
    pub(super) fn lets_through(&self, o: DVec3, d: DVec3, tmin: f64) -> bool {
        if let Surface::Csg(tree) = &self.surface {
            return tree.inside_or_crossed(o, d, tmin);
        }
        if self.quadratic() {
            return self.comes_near(o, d, tmin);
        }
        let p = self.to_object.transform_point3(o + tmin * d);
        let in_box = p.cmpge(self.object_box.min).all() && p.cmple(self.object_box.max).all();
        // On the surface (F within its noise) counts as inside: a gate that
        // opens once too often costs time, never a hit.
        (in_box && self.side(p, DVec3::X) != Some(false))
            || self.search(o, d, tmin, f64::INFINITY, true).is_some()
    }

    /// `lets_through` for a sphere or quadric gate, without refining a root:
    /// whether Q(s) = c0 + c1 s + c2 s² comes within its rounding noise of
    /// zero, or below it, anywhere on the ray inside the gate's box beyond
    /// tmin. That holds whenever the ray starts inside or crosses the
    /// surface, and also for the few rays that enter the inside through a
    /// face of the box or pass within rounding of a tangent, for which the
    /// gate only opens needlessly. The full test's polish was most of the
    /// gate's cost: a fifth of the instructions of POV-Ray's torus.pov,
    /// whose quartic has a bounding sphere (`valgrind --tool=callgrind`).
    fn comes_near(&self, o: DVec3, d: DVec3, tmin: f64) -> bool {
        // In the quartic storage: a gate needs no solver's Q.
        let Some(ray) = self.ray_frame(o, d, tmin, f64::INFINITY) else {
            return false;
        };
        let c = self.small_polynomial(&ray).0;
        let c = c.coeffs();
        let coeff = |k: usize| c.get(k).copied().unwrap_or(0.0);
        let (c0, c1, c2) = (coeff(0), coeff(1), coeff(2));
        let q = |s: f64| c0 + s * (c1 + s * c2);
        let hi = ray.hi;
        let noise = 16.0 * f64::EPSILON * (c0.abs() + hi * (c1.abs() + hi * c2.abs()));
        let mut least = q(0.0).min(q(hi));
        if c2 > 0.0 {
            let vertex = -c1 / (2.0 * c2);
            if vertex > 0.0 && vertex < hi {
                least = least.min(q(vertex));
            }
        }
        // A NaN (a ray at infinity) opens the gate: the shape decides.
        least.is_nan() || least <= noise
    }
}
