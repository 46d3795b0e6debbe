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

use super::csg::{Csg, Part};
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

/// One shape's F along a pinhole's rays, and where those rays can hit it.
#[derive(Clone, Debug)]
pub struct ShapeBeams<'a> {
    form: Form<'a>,
    pinhole: Pinhole,
    /// The world box that holds every hit on the shape.
    hits: (DVec3, DVec3),
    /// The world box of the shape's gate (`bounded_by`), if it has one:
    /// where the surface's own stretch ends, an unbounded surface's box
    /// reaching far beyond it. The rays beyond it are proven as one
    /// stretch out to infinity (see `Expanded::sign`).
    gate: Option<(DVec3, DVec3)>,
}

#[derive(Clone, Debug)]
enum Form<'a> {
    /// A surface, missed where F keeps either sign.
    Plain(Box<Expanded>),
    /// A tree, missed where the solid leaves that F > 0 leaves outside
    /// leave the whole tree outside (`Csg::outside`): each leaf's G, for
    /// algebraic leaves (a sphere's or a box's crossings cost a ray less
    /// than a proof costs a rectangle).
    Tree(&'a Csg, Vec<Option<Expanded>>),
}

/// G(s, x, y) of one surface, in its own object space.
#[derive(Clone, Debug)]
struct Expanded {
    g: Tensor,
    /// G with F's coefficients and the map's entries made positive: the
    /// magnitude of G's terms, which bounds the rounding of every step.
    magnitude: Tensor,
    /// G's degree in s.
    degree: usize,
}

impl Shape {
    /// The shape's F along `pinhole`'s rays, hit only inside `bounds`
    /// (world): for an algebraic surface of degree 4 or less, and for a
    /// tree with such solid leaves (None for others, and for a box that
    /// is not finite).
    pub fn beams(&self, pinhole: &Pinhole, bounds: &Bounds) -> Option<ShapeBeams<'_>> {
        let finite = |b: &Bounds| {
            let (min, max) = (b.min.as_dvec3(), b.max.as_dvec3());
            (min.is_finite() && max.is_finite() && min.cmple(max).all()).then_some((min, max))
        };
        let hits = finite(bounds)?;
        let form = match &self.surface {
            Surface::Csg(tree) => {
                let leaves: Vec<_> = (tree.leaves().iter())
                    .map(|leaf| match &leaf.part {
                        Part::Solid(shape) if !leaf.inverse => Expanded::of(shape, pinhole),
                        _ => None,
                    })
                    .collect();
                leaves
                    .iter()
                    .any(Option::is_some)
                    .then_some(Form::Tree(tree, leaves))?
            }
            _ => Form::Plain(Box::new(Expanded::of(self, pinhole)?)),
        };
        Some(ShapeBeams {
            form,
            pinhole: *pinhole,
            hits,
            gate: self.gate.as_ref().and_then(|gate| finite(&gate.bounds())),
        })
    }
}

impl Expanded {
    /// `shape`'s F along `pinhole`'s rays, for an algebraic surface of
    /// degree 4 or less: F(o + s·T + σ·R + ρ·D) in its object space,
    /// σ = s·x and ρ = s·y.
    fn of(shape: &Shape, pinhole: &Pinhole) -> Option<Expanded> {
        let Surface::Algebraic(f) = &shape.surface else {
            return None;
        };
        if f.degree() > MOST_DEGREE {
            return None;
        }
        let o = shape.to_object.transform_point3(pinhole.eye).to_array();
        let axes = [pinhole.top_left, pinhole.right, pinhole.down]
            .map(|v| shape.to_object.transform_vector3(v).to_array());
        let m: [[f64; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|k| axes[k][i]));
        let positive = Trivariate::from_terms(f.terms().iter().map(|&(e, c)| (e, c.abs())));
        let g = tensor(&f.compose_affine(m, o));
        let magnitude =
            tensor(&positive.compose_affine(m.map(|r| r.map(f64::abs)), o.map(f64::abs)));
        let all_finite = |t: &Tensor| flat(t).iter().all(|c| c.is_finite());
        (all_finite(&g) && all_finite(&magnitude)).then_some(Expanded {
            g,
            magnitude,
            degree: f.degree(),
        })
    }

    /// The sign (true: positive) F keeps, clear of zero, on the rays
    /// through [x0, x1] × [y0, y1] over s in (s0, s1), and with `far`
    /// beyond s1 too; None where that is not proven.
    fn sign(
        &self,
        (x0, x1): (f64, f64),
        (y0, y1): (f64, f64),
        (s0, s1): (f64, f64),
        far: bool,
    ) -> Option<bool> {
        // x = x0 + (x1 − x0) u, y likewise, u and v in [0, 1].
        let mut rect = Bounded {
            g: self.g,
            magnitude: self.magnitude,
        };
        rect.along::<1>(|c, positive| shift(c, if positive { x0.abs() } else { x0 }, x1 - x0));
        rect.along::<2>(|c, positive| shift(c, if positive { y0.abs() } else { y0 }, y1 - y0));
        let bernstein = |mut b: Bounded| {
            b.along::<0>(|c, _| to_bernstein(c));
            b.along::<1>(|c, _| to_bernstein(c));
            b.along::<2>(|c, _| to_bernstein(c));
            b.sign(SPLITS)
        };
        // s = s0 + (s1 − s0) τ, τ in [0, 1].
        let mut near = rect;
        near.along::<0>(|c, _| shift(c, s0, s1 - s0));
        let sign = bernstein(near)?;
        if !far {
            return Some(sign);
        }
        // s = s1 / w, w in (0, 1]: G's sign is w^n G(s1 / w)'s, a
        // polynomial in w (the coefficients reversed and scaled), whose
        // value at w = 0 is G's leading part, its sign far along the rays.
        let n = self.degree;
        let mut beyond = rect;
        beyond.along::<0>(|c, _| {
            let mut reversed = [0.0; N];
            let mut power = 1.0;
            for m in 0..=n {
                reversed[n - m] = c[m] * power;
                power *= s1;
            }
            *c = reversed;
        });
        (bernstein(beyond)? == sign).then_some(sign)
    }
}

/// A tensor's coefficients in one slice.
fn flat(t: &Tensor) -> &[f64] {
    t.as_flattened().as_flattened()
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
    /// `f` on every line along `AXIS` of both: `f` must take a polynomial
    /// with positive coefficients to one with positive coefficients,
    /// through sums of products of positive factors, and the magnitude
    /// then bounds each coefficient's rounding (as Horner's bound does).
    fn along<const AXIS: usize>(&mut self, f: impl Fn(&mut [f64; N], bool)) {
        along::<AXIS>(&mut self.g, |c| f(c, false));
        along::<AXIS>(&mut self.magnitude, |c| f(c, true));
    }

    /// Both halves in s of a Bernstein form, by de Casteljau's averages.
    fn halves(&self) -> [Bounded; 2] {
        let (mut low, mut high) = (*self, *self);
        for x in 0..N {
            for y in 0..N {
                let [gl, gh] = halves(std::array::from_fn(|s| self.g[s][x][y]));
                let [ml, mh] = halves(std::array::from_fn(|s| self.magnitude[s][x][y]));
                for s in 0..N {
                    (low.g[s][x][y], high.g[s][x][y]) = (gl[s], gh[s]);
                    (low.magnitude[s][x][y], high.magnitude[s][x][y]) = (ml[s], mh[s]);
                }
            }
        }
        [low, high]
    }

    /// The sign (true: positive) of every coefficient (Bernstein's, on
    /// [0, 1]³), each clear of zero by `CLEAR` of its magnitude, or,
    /// `splits` more times, of each half in s; None where they differ.
    /// The eight corner coefficients are G's values at the box's corners:
    /// where two of them differ in sign G has a zero in the box, and no
    /// halving can prove otherwise.
    fn sign(&self, splits: u32) -> Option<bool> {
        let (g, magnitude) = (flat(&self.g), flat(&self.magnitude));
        let (mut above, mut below, mut finite) = (true, true, true);
        for (&b, &m) in g.iter().zip(magnitude) {
            above &= b > CLEAR * m;
            below &= b < -CLEAR * m;
            finite &= b.is_finite() && m.is_finite();
        }
        if above || below {
            return Some(above);
        }
        let last = N - 1;
        let corners = [0, last].map(|i| [0, last].map(|j| [0, last].map(|k| self.g[i][j][k])));
        let corners = corners.as_flattened().as_flattened();
        let crossed = corners.iter().any(|&c| c > 0.0) && corners.iter().any(|&c| c < 0.0);
        if splits == 0 || crossed || !finite {
            return None;
        }
        let [low, high] = self.halves();
        let sign = low.sign(splits - 1)?;
        (high.sign(splits - 1)? == sign).then_some(sign)
    }
}

impl ShapeBeams<'_> {
    /// Whether no ray through pixel coordinates (x, y) in [x0, x1] × [y0, y1]
    /// meets the shape's surface inside its box: false where that is not
    /// proven.
    pub fn misses(&self, xs: (f64, f64), ys: (f64, f64)) -> bool {
        let p = &self.pinhole;
        let ((x0, x1), (y0, y1)) = (xs, ys);
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
        let (s1, far) = match self.gate {
            Some(gate) => (s1.min(stretch(gate).1), true),
            None => (s1, false),
        };
        if !(s0 >= 0.0 && s1 > s0 && s1.is_finite()) {
            return false;
        }
        let sign = |e: &Expanded| e.sign(xs, ys, (s0, s1), far);
        match &self.form {
            Form::Plain(e) => sign(e).is_some(),
            Form::Tree(tree, leaves) => {
                tree.outside(&mut |i| leaves[i].as_ref().and_then(sign) == Some(true))
            }
        }
    }
}

/// `f` on each line of `t` along `AXIS` (0: s, 1: x, 2: y).
fn along<const AXIS: usize>(t: &mut Tensor, f: impl Fn(&mut [f64; N])) {
    let at = |a: usize, b: usize, k: usize| match AXIS {
        0 => (k, a, b),
        1 => (a, k, b),
        _ => (a, b, k),
    };
    for a in 0..N {
        for b in 0..N {
            let mut line: [f64; N] = std::array::from_fn(|k| {
                let (i, j, l) = at(a, b, k);
                t[i][j][l]
            });
            f(&mut line);
            for (k, v) in line.into_iter().enumerate() {
                let (i, j, l) = at(a, b, k);
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
    let a = *c;
    for (b, weights) in c.iter_mut().zip(&BERNSTEIN) {
        *b = weights.iter().zip(&a).map(|(w, a)| w * a).sum();
    }
}

/// The weights C(i, j) / C(n, j) of `to_bernstein` (0 for j > i), n = N − 1.
const BERNSTEIN: [[f64; N]; N] = {
    let mut w = [[0.0; N]; N];
    let mut i = 0;
    while i < N {
        let mut j = 0;
        while j <= i {
            w[i][j] = binomial(i, j) / binomial(N - 1, j);
            j += 1;
        }
        i += 1;
    }
    w
};

const fn binomial(n: usize, k: usize) -> f64 {
    let (mut b, mut i) = (1.0, 0);
    while i < k {
        b = b * (n - i) as f64 / (i + 1) as f64;
        i += 1;
    }
    b
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
