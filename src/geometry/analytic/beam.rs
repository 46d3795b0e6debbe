//! Camera rays a rectangle of pixels at a time. A pinhole camera's ray
//! through pixel coordinates (x, y) is eye + s·D(x, y), with D affine in
//! (x, y), so along all of them a surface's F(eye + s·D) is one polynomial
//! G(s, x, y), formed once a render. Over a rectangle of pixels, and the
//! stretch of s where those rays can be in the shape's box, G's Bernstein
//! coefficients bound it (each value is an average of them). Where they
//! all have one sign, clear of zero by far more than any rounding, no ray
//! through the rectangle meets the surface, and the render skips the
//! shape for those rays: the same image, since the search those rays
//! would have made finds no root (its Q is as clear of zero as G is).
//!
//! Most of the camera rays of POV-Ray's quartic samples that pass a
//! shape's `bounded_by` sphere miss the surface, each after a search that
//! proves it (some 2,000 instructions a ray on quarcyl.pov, `valgrind
//! --tool=callgrind`); one proof answers for a tile's 256 rays.

use glam::DVec3;

use super::{Shape, Surface};
use crate::math::Bounds;
use crate::poly::trivariate::Trivariate;

/// The highest degree proven: the cubics and quartics of POV-Ray's
/// samples. The tensor of coefficients has (degree + 1)³ entries.
const MOST_DEGREE: usize = 4;
const N: usize = MOST_DEGREE + 1;

/// How far clear of zero every Bernstein coefficient must lie, as a
/// fraction of the magnitude of G's terms over the rectangle (G with every
/// coefficient and coordinate made positive). The proof's own roundings
/// (the expansion, the shifts, the conversion: a few hundred ε of that
/// magnitude at most) and a ray's search (whose F has the same terms, at
/// points off these by a few roundings) are far below it.
const CLEAR: f64 = 1.0 / (1u64 << 20) as f64;

/// Halvings of a stretch of s tried before a rectangle is given up.
const SPLITS: u32 = 6;

/// How much the stretch of s is widened each way, relative: the rays a
/// search follows are these rounded, their boxes' ends a few roundings off.
const SLACK: f64 = 1e-9;

/// The rays eye + s·(top_left + x·right + y·down) of a pinhole camera,
/// for pixel coordinates (x, y) (see `CameraFrame::ray64`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pinhole {
    pub eye: DVec3,
    pub top_left: DVec3,
    pub right: DVec3,
    pub down: DVec3,
}

impl Pinhole {
    fn dir(&self, x: f64, y: f64) -> DVec3 {
        self.top_left + x * self.right + y * self.down
    }
}

/// Coefficients of a polynomial in (s, x, y), indexed by the powers [s][x][y].
type Tensor = [[[f64; N]; N]; N];

/// One shape's G along a pinhole's rays, and where those rays can hit it.
#[derive(Clone, Debug)]
pub struct ShapeBeams {
    g: Tensor,
    /// G with F's coefficients and the map's entries made positive: the
    /// magnitude of G's terms, which bounds the rounding of every step.
    magnitude: Tensor,
    /// G's degree in s.
    degree: usize,
    pinhole: Pinhole,
    /// The world box that holds every hit on the shape.
    hits: (DVec3, DVec3),
    /// The world box of the shape's gate (`bounded_by`), if it has one:
    /// where the surface's own stretch ends, an unbounded surface's box
    /// reaching far beyond it. The rays beyond it are proven as one
    /// stretch out to infinity (see `ShapeBeams::misses`).
    gate: Option<(DVec3, DVec3)>,
}

impl Shape {
    /// The shape's G along `pinhole`'s rays, hit only inside `bounds`
    /// (world): for an algebraic surface of degree 4 or less and no CSG
    /// (None for others, and for a box that is not finite).
    pub fn beams(&self, pinhole: &Pinhole, bounds: &Bounds) -> Option<ShapeBeams> {
        let Surface::Algebraic(f) = &self.surface else {
            return None;
        };
        let finite = |b: &Bounds| {
            let (min, max) = (b.min.as_dvec3(), b.max.as_dvec3());
            (min.is_finite() && max.is_finite() && min.cmple(max).all()).then_some((min, max))
        };
        let hits = finite(bounds)?;
        if f.degree() > MOST_DEGREE {
            return None;
        }
        // F(o + s·T + σ·R + ρ·D) in object space, σ = s·x and ρ = s·y.
        let o = self.to_object.transform_point3(pinhole.eye).to_array();
        let axes = [pinhole.top_left, pinhole.right, pinhole.down]
            .map(|v| self.to_object.transform_vector3(v).to_array());
        let m: [[f64; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|k| axes[k][i]));
        let positive = Trivariate::from_terms(f.terms().iter().map(|&(e, c)| (e, c.abs())));
        let g = tensor(&f.compose_affine(m, o));
        let magnitude =
            tensor(&positive.compose_affine(m.map(|r| r.map(f64::abs)), o.map(f64::abs)));
        let all_finite = |t: &Tensor| t.iter().flatten().flatten().all(|c| c.is_finite());
        (all_finite(&g) && all_finite(&magnitude)).then_some(ShapeBeams {
            g,
            magnitude,
            degree: f.degree(),
            pinhole: *pinhole,
            hits,
            gate: self.gate.as_ref().and_then(|gate| finite(&gate.bounds())),
        })
    }
}

/// A polynomial in (s, σ, ρ) with σ = s·x, ρ = s·y, as one in (s, x, y).
fn tensor(p: &Trivariate) -> Tensor {
    let mut t = [[[0.0; N]; N]; N];
    for &([i, j, k], c) in p.terms() {
        let [i, j, k] = [i, j, k].map(usize::from);
        t[i + j + k][j][k] += c;
    }
    t
}

/// A polynomial in (s, x, y) with the magnitude of its terms.
#[derive(Clone, Copy)]
struct Bounded {
    g: Tensor,
    magnitude: Tensor,
}

impl Bounded {
    /// `f` on every line along `axis` of both: `f` must take a polynomial
    /// with positive coefficients to one with positive coefficients,
    /// through sums of products of positive factors, and the magnitude
    /// then bounds each coefficient's rounding (as Horner's bound does).
    fn along(&mut self, axis: usize, f: impl Fn(&mut [f64; N], bool)) {
        along(&mut self.g, axis, |c| f(c, false));
        along(&mut self.magnitude, axis, |c| f(c, true));
    }

    /// Whether every coefficient (Bernstein's, on [0, 1]³) is clear of
    /// zero by `CLEAR` of its magnitude, on one side, or, `splits` more
    /// times, the coefficients of each half in s are.
    fn one_sign(&self, splits: u32) -> bool {
        let pairs =
            || (self.g.iter().flatten().flatten()).zip(self.magnitude.iter().flatten().flatten());
        if pairs().all(|(&b, &m)| b > CLEAR * m) || pairs().all(|(&b, &m)| b < -CLEAR * m) {
            return true;
        }
        if splits == 0 || !pairs().all(|(b, m)| b.is_finite() && m.is_finite()) {
            return false;
        }
        let (mut low, mut high) = (*self, *self);
        for (half, of) in [(&mut low, 0), (&mut high, 1)] {
            half.along(0, |c, _| *c = halves(*c)[of]);
        }
        low.one_sign(splits - 1) && high.one_sign(splits - 1)
    }
}

impl ShapeBeams {
    /// Whether no ray through pixel coordinates (x, y) in [x0, x1] × [y0, y1]
    /// meets the surface inside the shape's box: false where that is not
    /// proven.
    pub fn misses(&self, (x0, x1): (f64, f64), (y0, y1): (f64, f64)) -> bool {
        let p = &self.pinhole;
        let corners = [(x0, y0), (x1, y0), (x0, y1), (x1, y1)].map(|(x, y)| p.dir(x, y).length());
        let longest = corners.into_iter().fold(0.0, f64::max);
        // |D| is convex: at least its value at the centre less the most
        // it can change from there.
        let shortest = p.dir(0.5 * (x0 + x1), 0.5 * (y0 + y1)).length()
            - 0.5 * ((x1 - x0) * p.right.length() + (y1 - y0) * p.down.length());
        if !(shortest > 0.0 && longest.is_finite()) {
            return false;
        }
        // The stretch of s where a ray meets a box.
        let stretch = |(min, max): (DVec3, DVec3)| {
            let (min, max) = (min - p.eye, max - p.eye);
            let nearest = DVec3::ZERO.max(min).max(-max).length();
            let farthest = min.abs().max(max.abs()).length();
            (
                nearest / longest * (1.0 - SLACK),
                farthest / shortest * (1.0 + SLACK),
            )
        };
        let (s0, s1) = stretch(self.hits);
        // Beyond the gate's box, to infinity, as one stretch.
        let s1 = self.gate.map_or(s1, |gate| s1.min(stretch(gate).1));
        if !(s0 >= 0.0 && s1 > s0 && s1.is_finite()) {
            return false;
        }
        // x = x0 + (x1 − x0) u, y likewise, u and v in [0, 1].
        let mut rect = Bounded {
            g: self.g,
            magnitude: self.magnitude,
        };
        rect.along(1, |c, positive| {
            shift(c, if positive { x0.abs() } else { x0 }, x1 - x0)
        });
        rect.along(2, |c, positive| {
            shift(c, if positive { y0.abs() } else { y0 }, y1 - y0)
        });
        let bernstein = |mut b: Bounded| {
            for axis in 0..3 {
                b.along(axis, |c, _| to_bernstein(c));
            }
            b.one_sign(SPLITS)
        };
        // s = s0 + (s1 − s0) τ, τ in [0, 1].
        let mut near = rect;
        near.along(0, |c, _| shift(c, s0, s1 - s0));
        if !bernstein(near) {
            return false;
        }
        if self.gate.is_none() {
            return true;
        }
        // s = s1 / w, w in (0, 1]: G's sign is w^n G(s1 / w)'s, a
        // polynomial in w (the coefficients reversed and scaled), whose
        // value at w = 0 is G's leading part, its sign far along the rays.
        let n = self.degree;
        let mut far = rect;
        far.along(0, |c, _| {
            let mut reversed = [0.0; N];
            let mut power = 1.0;
            for m in 0..=n {
                reversed[n - m] = c[m] * power;
                power *= s1;
            }
            *c = reversed;
        });
        bernstein(far)
    }
}

/// `f` on each line of `t` along `axis` (0: s, 1: x, 2: y).
fn along(t: &mut Tensor, axis: usize, f: impl Fn(&mut [f64; N])) {
    for a in 0..N {
        for b in 0..N {
            let at = |k: usize| match axis {
                0 => (k, a, b),
                1 => (a, k, b),
                _ => (a, b, k),
            };
            let mut line: [f64; N] = std::array::from_fn(|k| {
                let (i, j, l) = at(k);
                t[i][j][l]
            });
            f(&mut line);
            for (k, v) in line.into_iter().enumerate() {
                let (i, j, l) = at(k);
                t[i][j][l] = v;
            }
        }
    }
}

/// p(from + width·t) from p(t)'s coefficients (lowest first), in place:
/// Taylor's shift by Horner's steps, then the scaling. With `from` ≥ 0
/// and `width` > 0 every step adds products of positive factors, so the
/// same steps on the magnitude bound the rounding of these.
fn shift(c: &mut [f64; N], from: f64, width: f64) {
    for i in 0..N - 1 {
        for j in (i..N - 1).rev() {
            c[j] += from * c[j + 1];
        }
    }
    let mut power = 1.0;
    for v in c.iter_mut() {
        *v *= power;
        power *= width;
    }
}

/// The Bernstein coefficients of degree `N − 1` on [0, 1] of the
/// polynomial with coefficients `c` (lowest first), in place:
/// b_i = Σ_{j ≤ i} C(i, j) / C(n, j) a_j, every weight positive.
fn to_bernstein(c: &mut [f64; N]) {
    let n = N - 1;
    let binomial =
        |n: usize, k: usize| (0..k).fold(1.0, |b, i| b * (n - i) as f64 / (i + 1) as f64);
    let a = *c;
    for (i, b) in c.iter_mut().enumerate() {
        *b = (0..=i)
            .map(|j| binomial(i, j) / binomial(n, j) * a[j])
            .sum();
    }
}

/// The two halves (on [0, 1/2] and [1/2, 1]) of a Bernstein polynomial,
/// by de Casteljau's averages.
fn halves(b: [f64; N]) -> [[f64; N]; 2] {
    let (mut low, mut high, mut c) = ([0.0; N], [0.0; N], b);
    for r in 0..N {
        low[r] = c[0];
        high[N - 1 - r] = c[N - 1 - r];
        for i in 0..N - 1 - r {
            c[i] = 0.5 * (c[i] + c[i + 1]);
        }
    }
    [low, high]
}

#[cfg(test)]
mod tests;
