//! A quadric missed by a rectangle of rays from one point, by its
//! discriminant. Along the line e + s·D (object space) a quadric F(p) =
//! pᵀAp + b·p + c is Q(s) = (DᵀAD)·s² + 2(D·g)·s + F(e), g = Ae + b/2, with
//! a quarter discriminant (D·g)² − (DᵀAD)·F(e). For a pinhole's rays D is
//! affine in the pixel coordinates (x, y), so the discriminant is a
//! quadratic form in (1, x, y), whose largest value over a rectangle is at
//! a corner, on an edge or at its one stationary point: found exactly, in
//! a few dozen operations. Where it is below zero by far more than any
//! rounding, no line through the rectangle meets the surface at all.
//!
//! The Bernstein proofs of `Expanded` cost more for a quadric than its
//! rays' searches save (steiner.pov +9.5% instructions), but POV-Ray's
//! `Axes` (three unbounded thin cylinders in steiner.pov and grafbic.pov)
//! were tried by every camera ray: 150M of steiner.pov's 700M
//! instructions of rendering at 400×300 (`valgrind --tool=callgrind`).

use glam::{DMat3, DVec3};

use super::{CLEAR, Pinhole};
use crate::geometry::analytic::{Shape, Surface};

/// The discriminant of a sphere's or a quadric's Q along a pinhole's
/// rays, with what bounds the rounding of a ray's search for their roots.
#[derive(Clone, Debug)]
pub(super) struct Discriminant {
    /// The quarter discriminant's form zᵀNz, z = (1, x, y): [N₀₀, N₀₁,
    /// N₀₂, N₁₁, N₁₂, N₂₂].
    n: [f64; 6],
    /// D(x, y) = u₀ + x·u₁ + y·u₂ in object space.
    u: [DVec3; 3],
    /// A and b with every entry made positive.
    abs_a: DMat3,
    abs_b: DVec3,
    /// A bound on each coordinate's size of where a ray's search forms
    /// its Q: the eye, or where the ray enters the shape's box.
    at: DVec3,
    /// F's terms made positive at `at`.
    m0: f64,
    /// Whether F > 0 at the eye: where no line through a rectangle meets
    /// the surface, F keeps that sign along every one of them, since
    /// (DᵀAD)·F(e) then exceeds (D·g)² ≥ 0.
    outside: bool,
}

impl Discriminant {
    /// For a sphere or a quadric whose rays leave `pinhole`'s eye at
    /// t = 0 (camera rays); None for other surfaces, and for a plane (A =
    /// 0), which every line but its parallels meets.
    pub(super) fn of(shape: &Shape, pinhole: &Pinhole) -> Option<Discriminant> {
        let (a, b, c) = match &shape.surface {
            Surface::Sphere { radius } => (DMat3::IDENTITY, DVec3::ZERO, -radius * radius),
            Surface::Quadric(q) if q.a != DMat3::ZERO => (q.a, q.b, q.c),
            _ => return None,
        };
        let to_object = &shape.to_object;
        let eye = to_object.transform_point3(pinhole.eye);
        let u =
            [pinhole.top_left, pinhole.right, pinhole.down].map(|v| to_object.transform_vector3(v));
        let g = a * eye + 0.5 * b;
        let f = eye.dot(a * eye) + b.dot(eye) + c;
        let w = u.map(|v| v.dot(g));
        let entry = |i: usize, j: usize| w[i] * w[j] - f * u[i].dot(a * u[j]);
        let n = [
            entry(0, 0),
            entry(0, 1),
            entry(0, 2),
            entry(1, 1),
            entry(1, 2),
            entry(2, 2),
        ];
        // A ray from inside the box (where the search looks for roots)
        // forms Q at the eye, its t starting at 0; one from outside, where
        // it enters the box.
        let (min, max) = (shape.object_box.min, shape.object_box.max);
        let inside = eye.cmpgt(min).all() && eye.cmplt(max).all();
        let at = if inside {
            eye.abs()
        } else {
            eye.abs().max(min.abs()).max(max.abs())
        };
        let (abs_a, abs_b) = (
            DMat3::from_cols(a.x_axis.abs(), a.y_axis.abs(), a.z_axis.abs()),
            b.abs(),
        );
        let m0 = at.dot(abs_a * at) + abs_b.dot(at) + c.abs();
        let finite = n.iter().all(|v| v.is_finite()) && m0.is_finite();
        finite.then_some(Discriminant {
            n,
            u,
            abs_a,
            abs_b,
            at,
            m0,
            outside: f > 0.0,
        })
    }

    /// Whether F > 0 (outside) all along every ray through the rectangle:
    /// `misses` it, from an eye outside.
    pub(super) fn outside(&self, xs: (f64, f64), ys: (f64, f64)) -> bool {
        self.outside && self.misses(xs, ys)
    }

    /// Whether no ray through pixel coordinates (x, y) in [x0, x1] ×
    /// [y0, y1] meets the surface anywhere along its line. Each of their
    /// Q's discriminants must be below zero by `CLEAR` of the size of its
    /// terms (those of DᵀAD, 2D·g and F at `at`, D as large on each axis
    /// as at the rectangle's largest corner, since |D| is affine on each
    /// axis): far beyond the few roundings that a ray's search makes in
    /// forming its Q, and those made here.
    pub(super) fn misses(&self, (x0, x1): (f64, f64), (y0, y1): (f64, f64)) -> bool {
        let [u0, u1, u2] = self.u;
        let d = [(x0, y0), (x1, y0), (x0, y1), (x1, y1)]
            .map(|(x, y)| (u0 + x * u1 + y * u2).abs())
            .into_iter()
            .fold(DVec3::ZERO, DVec3::max);
        let ad = self.abs_a * d;
        let (m2, m1) = (d.dot(ad), 2.0 * self.at.dot(ad) + self.abs_b.dot(d));
        let noise = CLEAR * (m1 * m1 + 4.0 * m2 * self.m0);
        // A NaN (from a NaN rectangle) proves nothing.
        4.0 * self.greatest((x0, x1), (y0, y1)) < -noise
    }

    /// The quarter discriminant's greatest value over the rectangle; NaN
    /// if any value it weighed is.
    fn greatest(&self, (x0, x1): (f64, f64), (y0, y1): (f64, f64)) -> f64 {
        let [n00, n01, n02, n11, n12, n22] = self.n;
        let q = |x: f64, y: f64| {
            n00 + 2.0 * (n01 * x + n02 * y + n12 * x * y) + n11 * x * x + n22 * y * y
        };
        let mut best = f64::NEG_INFINITY;
        let mut weigh = |x: f64, y: f64| {
            let v = q(x, y);
            // NaN stays once it is in.
            if v > best || v.is_nan() && !best.is_nan() {
                best = v;
            }
        };
        for (x, y) in [(x0, y0), (x1, y0), (x0, y1), (x1, y1)] {
            weigh(x, y);
        }
        // Along each edge, a maximum between its ends where the form
        // curves down that way.
        let between = |v: f64, (lo, hi): (f64, f64)| lo < v && v < hi;
        if n11 < 0.0 {
            for y in [y0, y1] {
                let x = -(n01 + n12 * y) / n11;
                if between(x, (x0, x1)) {
                    weigh(x, y);
                }
            }
        }
        if n22 < 0.0 {
            for x in [x0, x1] {
                let y = -(n02 + n12 * x) / n22;
                if between(y, (y0, y1)) {
                    weigh(x, y);
                }
            }
        }
        // Inside, a maximum only where the form curves down every way.
        let det = n11 * n22 - n12 * n12;
        if n11 < 0.0 && det > 0.0 {
            let (x, y) = ((n12 * n02 - n22 * n01) / det, (n12 * n01 - n11 * n02) / det);
            if between(x, (x0, x1)) && between(y, (y0, y1)) {
                weigh(x, y);
            }
        }
        best
    }
}
