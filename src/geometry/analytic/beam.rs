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

use glam::{DAffine3, DVec3};

use super::csg::{Csg, Part};
use super::{Shape, Surface};
use crate::math::Bounds;
use crate::poly::trivariate::Trivariate;
use discriminant::Discriminant;

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

/// A bound on the rounding of the proof's own steps (the expansion, the
/// shifts, the conversion, the halvings: some 150 roundings at most), as a
/// fraction of the magnitude of G's terms: 2^-40, some 50 times above it.
const ROUNDING: f64 = 1.0 / (1u64 << 40) as f64;

/// How much nearer the light each stretch before a shadow ray's start
/// reaches than the one after it (`ShapeBeams::lights`): each is proven
/// over the window widened for its nearest depth.
const BACK: f64 = 8.0;

/// Halvings of a stretch of s tried before a rectangle is given up.
const SPLITS: u32 = 6;

/// Halvings of a stretch of s over which a tree is proven outside a piece
/// at a time (`outside_by_pieces`).
const TREE_SPLITS: u32 = 2;

/// Halvings tried for a monotone stretch: it is thin (the depths of a
/// tile's points), and on POV-Ray's quartic samples more halvings proved
/// no more tiles.
const MONOTONE_SPLITS: u32 = 2;

/// How far, as a fraction of its length, a shadow ray's f32 direction
/// may point beside the light: far above the few roundings of f32's
/// normalised difference (each about 6e-8).
const SHADOW_DIRECTION: f64 = 1e-6;

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
    /// The rays from a point light at `eye` towards `target`: D(u, v) =
    /// forward + u·right + v·down, with the three axes orthonormal and
    /// forward towards the target, so a point p in front of the light is
    /// eye + s·D(u, v) at s = (p − eye)·forward (`coords`). None where the
    /// target is the light's own position, or not finite.
    pub fn toward(eye: DVec3, target: DVec3) -> Option<Pinhole> {
        let forward = (target - eye).try_normalize()?;
        let right = forward.any_orthonormal_vector();
        Some(Pinhole {
            eye,
            top_left: forward,
            right,
            down: forward.cross(right),
        })
    }

    /// (u, v, s) with p = eye + s·D(u, v), for a pinhole made by `toward`;
    /// None for a point not in front of the eye.
    pub fn coords(&self, p: DVec3) -> Option<(f64, f64, f64)> {
        let q = p - self.eye;
        let s = q.dot(self.top_left);
        (s > 0.0 && s.is_finite()).then(|| (q.dot(self.right) / s, q.dot(self.down) / s, s))
    }

    fn dir(&self, x: f64, y: f64) -> DVec3 {
        self.top_left + x * self.right + y * self.down
    }

    /// The rectangle [x0, x1] × [y0, y1] of pixel coordinates outside
    /// which no ray eye + s·D(x, y), s > 0, meets the box [lo, hi]: the
    /// bounds of its corners' images, grown by a margin far above their
    /// rounding. None where some corner is not in front of the eye (or
    /// not finite), as for a box around the eye.
    pub fn screen(&self, lo: DVec3, hi: DVec3) -> Option<[f64; 4]> {
        // p − eye = s·(top_left + x·right + y·down): s from the normal of
        // the image plane, then x and y from the dual basis of (right,
        // down), which need not be orthogonal (POV-Ray's `right`, `up`).
        let normal = self.right.cross(self.down);
        let depth = self.top_left.dot(normal);
        let (across, along) = (self.down.cross(normal), normal.cross(self.right));
        let (across, along) = (
            across / self.right.dot(across),
            along / self.down.dot(along),
        );
        let mut rect = [
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for corner in 0..8 {
            let pick = |bit: usize, l: f64, h: f64| if corner & bit == 0 { l } else { h };
            let p = DVec3::new(
                pick(1, lo.x, hi.x),
                pick(2, lo.y, hi.y),
                pick(4, lo.z, hi.z),
            );
            let q = p - self.eye;
            let s = q.dot(normal) / depth;
            if !(s > 0.0 && s.is_finite()) {
                return None;
            }
            let w = q / s - self.top_left;
            let (x, y) = (w.dot(across), w.dot(along));
            rect = [
                rect[0].min(x),
                rect[1].max(x),
                rect[2].min(y),
                rect[3].max(y),
            ];
        }
        // A few roundings of each coordinate above, and of a ray's
        // direction: 2^-20 of a pixel and of the coordinates' size.
        let margin = SCREEN_MARGIN * (1.0 + rect.iter().fold(0.0_f64, |m, c| m.max(c.abs())));
        let grown = [
            rect[0] - margin,
            rect[1] + margin,
            rect[2] - margin,
            rect[3] + margin,
        ];
        grown.iter().all(|c| c.is_finite()).then_some(grown)
    }
}

/// How far `Pinhole::screen` grows a box's image, in pixels per pixel of
/// its coordinates' size.
const SCREEN_MARGIN: f64 = 1.0 / (1 << 20) as f64;

/// Coefficients of a polynomial in (s, x, y), indexed by the powers [s][x][y].
type Tensor = [[[f64; N]; N]; N];

/// One shape's F along a pinhole's rays, and where those rays can hit it.
#[derive(Clone, Debug)]
pub struct ShapeBeams<'a> {
    form: Form<'a>,
    pinhole: Pinhole,
    /// Where along the rays G is expanded about: its σ is s − depth.
    depth: f64,
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
    /// A sphere or a quadric, missed where no line through the rectangle
    /// meets it.
    Quadratic(Box<Discriminant>),
    /// A tree, missed where the solid leaves that F > 0 leaves outside
    /// leave the whole tree outside (`Csg::outside`): each leaf's G, for
    /// algebraic leaves (a sphere's or a box's crossings cost a ray less
    /// than a proof costs a rectangle); and each sphere's or quadric's
    /// discriminant, which shows it outside along the whole of every ray
    /// in a few dozen operations (as tcubic.pov's clipping ball, beside
    /// which a rectangle's Bernstein proofs had cost the render loop some
    /// 13% of its instructions).
    Tree(&'a Csg, Vec<Option<Expanded>>, Vec<Option<Discriminant>>),
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
    /// The most halvings of a stretch its proofs take (`Window::sign`).
    splits: u32,
}

impl Shape {
    /// The shape's F along `pinhole`'s rays, hit only inside `bounds`
    /// (world), expanded about `depth` along them (see `Expanded::of`):
    /// for an algebraic surface of degree 4 or less, and for a tree with
    /// such solid leaves; for a sphere or a quadric other than a plane,
    /// its discriminant (`Discriminant`: camera rays only). None for
    /// others, and for a box that is not finite.
    pub fn beams(&self, pinhole: &Pinhole, depth: f64, bounds: &Bounds) -> Option<ShapeBeams<'_>> {
        let finite = |b: &Bounds| {
            let (min, max) = (b.min.as_dvec3(), b.max.as_dvec3());
            (min.is_finite() && max.is_finite() && min.cmple(max).all()).then_some((min, max))
        };
        let hits = finite(bounds)?;
        let form = match &self.surface {
            Surface::Csg(tree) => {
                let leaves: Vec<_> = (tree.leaves().iter())
                    .map(|leaf| match &leaf.part {
                        _ if leaf.inverse => None,
                        Part::Solid(shape) => Expanded::of_leaf(shape, pinhole, depth),
                        // A half-space n·p < offset, in world space.
                        &Part::Plane { normal, offset } => {
                            let [a, b, c] = normal.to_array();
                            let f = Trivariate::from_terms([
                                ([1, 0, 0], a),
                                ([0, 1, 0], b),
                                ([0, 0, 1], c),
                                ([0, 0, 0], -offset),
                            ]);
                            Expanded::of_polynomial(&DAffine3::IDENTITY, &f, pinhole, depth, 1)
                        }
                        _ => None,
                    })
                    .collect();
                // A tree of spheres and quadrics alone is not worth a proof:
                // their crossings cost a ray less than a proof a rectangle.
                let algebraic = (tree.leaves().iter().zip(&leaves)).any(|(leaf, e)| {
                    e.is_some()
                        && matches!(&leaf.part, Part::Solid(s) if matches!(s.surface, Surface::Algebraic(_)))
                });
                // Camera rays only (`misses`), as for a plain quadric.
                let quadratics = (tree.leaves().iter())
                    .map(|leaf| match &leaf.part {
                        Part::Solid(shape) if !leaf.inverse => Discriminant::of(shape, pinhole),
                        _ => None,
                    })
                    .collect();
                algebraic.then_some(Form::Tree(tree, leaves, quadratics))?
            }
            Surface::Sphere { .. } | Surface::Quadric(_) => {
                Form::Quadratic(Box::new(Discriminant::of(self, pinhole)?))
            }
            _ => Form::Plain(Box::new(Expanded::of(self, pinhole, depth)?)),
        };
        Some(ShapeBeams {
            form,
            pinhole: *pinhole,
            depth,
            hits,
            gate: self.gate.as_ref().and_then(|gate| finite(&gate.bounds())),
        })
    }
}

impl Expanded {
    /// `shape`'s F along `pinhole`'s rays eye + (depth + σ)·(T + x·R + y·D),
    /// as a polynomial G(σ, x, y), for an algebraic surface of degree 4 or
    /// less: F(c + σ·T + a·R + b·D) in its object space, c = eye +
    /// depth·T, a = (depth + σ)·x and b = (depth + σ)·y. About a depth
    /// near the shape, G's terms are of the size of F's values there: a
    /// far light's own position would give terms that cancel by many
    /// orders, and a rounding bound as large.
    fn of(shape: &Shape, pinhole: &Pinhole, depth: f64) -> Option<Expanded> {
        match &shape.surface {
            Surface::Algebraic(f) => {
                Expanded::of_polynomial(&shape.to_object, f, pinhole, depth, SPLITS)
            }
            _ => None,
        }
    }

    /// `of` for a tree's leaf, where a sphere's or a quadric's sign may
    /// show the line outside where the others' cannot (`outside_by_pieces`).
    /// Their sign over a stretch is plain or it crosses: halving it seldom
    /// proves more, and a tree asks it for every rectangle, so once.
    fn of_leaf(shape: &Shape, pinhole: &Pinhole, depth: f64) -> Option<Expanded> {
        let to_object = &shape.to_object;
        match &shape.surface {
            Surface::Algebraic(f) => Expanded::of_polynomial(to_object, f, pinhole, depth, SPLITS),
            surface => {
                Expanded::of_polynomial(to_object, &quadratic_of(surface)?, pinhole, depth, 1)
            }
        }
    }

    /// `of`, for an F given as `f` in the space `to_object` maps the world
    /// to, whose proofs halve a stretch up to `splits` times.
    fn of_polynomial(
        to_object: &DAffine3,
        f: &Trivariate,
        pinhole: &Pinhole,
        depth: f64,
        splits: u32,
    ) -> Option<Expanded> {
        if f.degree() > MOST_DEGREE {
            return None;
        }
        let o = (to_object.transform_point3(pinhole.eye + depth * pinhole.top_left)).to_array();
        let axes = [pinhole.top_left, pinhole.right, pinhole.down]
            .map(|v| to_object.transform_vector3(v).to_array());
        let m: [[f64; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|k| axes[k][i]));
        let positive = Trivariate::from_terms(f.terms().iter().map(|&(e, c)| (e, c.abs())));
        let g = tensor(&f.compose_affine(m, o), depth);
        let magnitude = tensor(
            &positive.compose_affine(m.map(|r| r.map(f64::abs)), o.map(f64::abs)),
            depth.abs(),
        );
        let all_finite = |t: &Tensor| flat(t).iter().all(|c| c.is_finite());
        (all_finite(&g) && all_finite(&magnitude)).then_some(Expanded {
            g,
            magnitude,
            degree: f.degree(),
            splits,
        })
    }

    /// G over the rays through [x0, x1] × [y0, y1], x = x0 + (x1 − x0) u
    /// and y likewise, in Bernstein's form in (u, v) on [0, 1]²: the part
    /// of a proof every stretch of σ over the rectangle shares.
    fn window(&self, (x0, x1): (f64, f64), (y0, y1): (f64, f64)) -> Window {
        let mut rect = Bounded {
            g: self.g,
            magnitude: self.magnitude,
        };
        rect.along::<1>(|c, positive| shift(c, if positive { x0.abs() } else { x0 }, x1 - x0));
        rect.along::<2>(|c, positive| shift(c, if positive { y0.abs() } else { y0 }, y1 - y0));
        rect.along::<1>(|c, _| to_bernstein(c));
        rect.along::<2>(|c, _| to_bernstein(c));
        Window {
            rect,
            degree: self.degree,
            splits: self.splits,
        }
    }
}

/// G over a rectangle of rays (`Expanded::window`).
struct Window {
    rect: Bounded,
    degree: usize,
    splits: u32,
}

impl Window {
    /// The sign (true: positive) G keeps, clear of zero, over σ in (σ0, σ1)
    /// (halved up to `splits` times, and no more than its surface's own
    /// limit), and with `far` beyond σ1 too; None where that is not
    /// proven. An empty stretch (σ0 = σ1) asks only about what lies beyond.
    fn sign(&self, (s0, s1): (f64, f64), far: bool, splits: u32) -> Option<bool> {
        let sign = if s0 < s1 {
            Some(self.rect.over(s0, s1).sign(splits.min(self.splits))?)
        } else {
            None
        };
        if !far {
            return sign;
        }
        // σ = σ1 / w, w in (0, 1]: G's sign is w^n G(σ1 / w)'s, a
        // polynomial in w (the coefficients reversed and scaled), whose
        // value at w = 0 is G's leading part, its sign far along the rays.
        let n = self.degree;
        let mut beyond = self.rect;
        beyond.along::<0>(|c, _| {
            let mut reversed = [0.0; N];
            let mut power = 1.0;
            for m in 0..=n {
                reversed[n - m] = c[m] * power;
                power *= s1;
            }
            *c = reversed;
            to_bernstein(c);
        });
        let beyond = beyond.sign(SPLITS)?;
        sign.is_none_or(|sign| sign == beyond).then_some(beyond)
    }

    /// Whether G is monotone, with its rate of change clear of zero, along
    /// every ray over σ in [σ0, σ1].
    fn monotone(&self, (s0, s1): (f64, f64)) -> bool {
        self.rect.over(s0, s1).monotone(MONOTONE_SPLITS).is_some()
    }
}

/// A sphere's or a quadric's F as a polynomial in its object space (None
/// for other surfaces, and for a box's constant quadric, whose inside is
/// its box).
fn quadratic_of(surface: &Surface) -> Option<Trivariate> {
    match surface {
        Surface::Sphere { radius } => Some(Trivariate::from_terms([
            ([2, 0, 0], 1.0),
            ([0, 2, 0], 1.0),
            ([0, 0, 2], 1.0),
            ([0, 0, 0], -radius * radius),
        ])),
        Surface::Quadric(q) if q.constant().is_none() => {
            let unit = |i: usize| {
                let mut e = [0u8; 3];
                e[i] += 1;
                e
            };
            let pair = |i: usize, j: usize| {
                let mut e = unit(i);
                e[j] += 1;
                e
            };
            let a = |i: usize, j: usize| q.a.col(j)[i];
            let mut terms = vec![([0, 0, 0], q.c)];
            for i in 0..3 {
                terms.push((unit(i), q.b[i]));
                terms.push((pair(i, i), a(i, i)));
                for j in i + 1..3 {
                    terms.push((pair(i, j), a(i, j) + a(j, i)));
                }
            }
            Some(Trivariate::from_terms(terms))
        }
        _ => None,
    }
}

/// Whether a tree is proven outside over σ in (σ0, σ1) (`outside`, given
/// a stretch, whether beyond it too, and the halvings each leaf's proof
/// may take) a piece at a time: a line can leave one leaf's solid before
/// it enters another's, so that no single leaf keeps it outside
/// throughout. Up to `splits` halvings, each piece's leaves with one more
/// halving of their own.
fn outside_by_pieces(
    outside: &impl Fn((f64, f64), bool, u32) -> bool,
    (s0, s1): (f64, f64),
    splits: u32,
) -> bool {
    if splits == 0 {
        return false;
    }
    let middle = 0.5 * (s0 + s1);
    let half = |piece| outside(piece, false, 1) || outside_by_pieces(outside, piece, splits - 1);
    half((s0, middle)) && half((middle, s1))
}

/// A tensor's coefficients in one slice.
fn flat(t: &Tensor) -> &[f64] {
    t.as_flattened().as_flattened()
}

/// A polynomial in (σ, a, b) with a = (depth + σ)·x, b = (depth + σ)·y,
/// as one in (σ, x, y): a^j b^k = x^j y^k Σ_m C(j + k, m) depth^(j+k−m) σ^m.
/// With depth ≥ 0 every weight is positive, so the magnitude's terms map
/// to a magnitude of the result's.
fn tensor(p: &Trivariate, depth: f64) -> Tensor {
    let mut t = [[[0.0; N]; N]; N];
    for &([i, j, k], c) in p.terms() {
        let [i, j, k] = [i, j, k].map(usize::from);
        for m in 0..=j + k {
            let weight = binomial(j + k, m) * depth.powi((j + k - m) as i32);
            t[i + m][j][k] += c * weight;
        }
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
    /// With σ = s0 + (s1 − s0) τ, τ in [0, 1], in Bernstein's form in τ.
    fn over(mut self, s0: f64, s1: f64) -> Bounded {
        self.along::<0>(|c, positive| {
            shift(c, if positive { s0.abs() } else { s0 }, s1 - s0);
            to_bernstein(c);
        });
        self
    }

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

    /// The sign (true: rising) of every difference of neighbouring
    /// coefficients in s (Bernstein's, on [0, 1]³), each clear of zero by
    /// `ROUNDING` of the two magnitudes, or, `splits` more times, of each
    /// half in s; None where they differ. The differences are, up to a
    /// positive factor, the Bernstein coefficients of ∂G/∂s.
    fn monotone(&self, splits: u32) -> Option<bool> {
        let (mut rising, mut falling, mut finite) = (true, true, true);
        for s in 0..N - 1 {
            for x in 0..N {
                for y in 0..N {
                    let d = self.g[s + 1][x][y] - self.g[s][x][y];
                    let m = self.magnitude[s + 1][x][y] + self.magnitude[s][x][y];
                    rising &= d > ROUNDING * m;
                    falling &= d < -ROUNDING * m;
                    finite &= d.is_finite() && m.is_finite();
                }
            }
        }
        if rising || falling {
            return Some(rising);
        }
        // The differences at the corners are ∂G/∂s there, up to a
        // positive factor: two of opposite signs, and no halving helps.
        let last = N - 1;
        let corners = [(0, 1), (last - 1, last)]
            .map(|(a, b)| [0, last].map(|x| [0, last].map(|y| self.g[b][x][y] - self.g[a][x][y])));
        let corners = corners.as_flattened().as_flattened();
        let crossed = corners.iter().any(|&c| c > 0.0) && corners.iter().any(|&c| c < 0.0);
        if splits == 0 || crossed || !finite {
            return None;
        }
        let [low, high] = self.halves();
        let rate = low.monotone(splits - 1)?;
        (high.monotone(splits - 1)? == rate).then_some(rate)
    }
}

impl ShapeBeams<'_> {
    /// Whether no ray through pixel coordinates (x, y) in [x0, x1] × [y0, y1]
    /// meets the shape's surface inside its box: false where that is not
    /// proven.
    pub fn misses(&self, xs: (f64, f64), ys: (f64, f64)) -> bool {
        if let Form::Quadratic(q) = &self.form {
            return q.misses(xs, ys);
        }
        // A tree whose sphere or quadric leaves, missed by every line,
        // leave it outside, whatever the stretch.
        let quadratics_outside = match &self.form {
            Form::Tree(_, _, quadratics) => (quadratics.iter().enumerate())
                .filter(|(_, q)| q.as_ref().is_some_and(|q| q.outside(xs, ys)))
                .fold(0u64, |set, (i, _)| {
                    set | 1u64.checked_shl(i as u32).unwrap_or(0)
                }),
            _ => 0,
        };
        let quadratic_outside = |i: usize| {
            1u64.checked_shl(i as u32)
                .is_some_and(|b| quadratics_outside & b != 0)
        };
        if let Form::Tree(tree, ..) = &self.form
            && quadratics_outside != 0
            && tree.outside(&mut |i| quadratic_outside(i))
        {
            return true;
        }
        let Some(reach) = self.reach(xs, ys) else {
            return false;
        };
        let (s0, s1) = reach.stretch(self.hits);
        // Beyond the gate's box, to infinity, as one stretch.
        let (s1, far) = match self.gate {
            Some(gate) => (s1.min(reach.stretch(gate).1), true),
            None => (s1, false),
        };
        // In σ = s − depth, which the stretch beyond the gate needs
        // positive at its start.
        let (s0, s1) = (s0 - self.depth, s1 - self.depth);
        if !(s0 + self.depth >= 0.0 && s1 > s0 && s1.is_finite() && (!far || s1 > 0.0)) {
            return false;
        }
        match &self.form {
            Form::Plain(e) => e.window(xs, ys).sign((s0, s1), far, SPLITS).is_some(),
            Form::Quadratic(_) => false,
            Form::Tree(tree, leaves, _) => {
                let windows: Vec<_> = (leaves.iter())
                    .map(|e| e.as_ref().map(|e| e.window(xs, ys)))
                    .collect();
                let outside = |piece: (f64, f64), far: bool, splits: u32| {
                    tree.outside(&mut |i| {
                        quadratic_outside(i)
                            || (windows[i].as_ref()).and_then(|w| w.sign(piece, far, splits))
                                == Some(true)
                    })
                };
                // Pieces help only where two leaves can each be outside
                // on some of them.
                let pieces = windows.iter().flatten().count() > 1;
                outside((s0, s1), far, SPLITS)
                    || pieces
                        && (!far || outside((s1, s1), true, 0))
                        && outside_by_pieces(&outside, (s0, s1), TREE_SPLITS)
            }
        }
    }

    /// Whether `lights` can prove anything: a quadric's rays are proven
    /// only as a camera's (`misses`).
    pub fn proves_lights(&self) -> bool {
        !matches!(self.form, Form::Quadratic(_))
    }

    /// Whether no shadow ray towards the pinhole, a point light's
    /// (`Pinhole::toward`), meets the shape, from any of `points`: each
    /// a point of the surface (of the tree's leaf `leaf`; a plain
    /// surface's is 0), with a bound on how far from it (world) its
    /// shadow ray starts, just off the surface on the light's side. The
    /// rays stop short of the light by `short` of their length. False
    /// where that is not proven.
    ///
    /// Over the window of (u, v) and the stretch [s0, s1] of depths that
    /// hold the points, F must be monotone along every ray of the window,
    /// and clear of zero, by more than a ray's search could round, before
    /// s0 (as far back as the rays run in the shape's box). Along each
    /// ray the surface is then met at most once up to s1, where the point
    /// is; the start of its shadow ray, between the point and the light on
    /// the same side of the surface as the light, is reached by no
    /// crossing.
    ///
    /// A tree's leaf (one whose box's faces never show, so that every hit
    /// on it is on its surface: `Csg::faces_hidden`) then keeps, along
    /// every such shadow ray in the tree's box, the sign it was proven to
    /// have before s0: where that leaves none of the tree's surfaces to
    /// meet (`Csg::unseen`), the shadow rays cross none. So the first
    /// stretch before s0 is proven for a tree even where the box starts
    /// past s0.
    pub fn lights(&self, leaf: usize, points: &[(DVec3, f64)], short: f64) -> bool {
        let e = match &self.form {
            Form::Plain(e) if leaf == 0 => e,
            // The points must lie on the leaf's surface, not on the faces
            // that close its solid.
            Form::Tree(tree, leaves, _) if tree.faces_hidden(leaf) => match leaves.get(leaf) {
                Some(Some(e)) => e,
                _ => return false,
            },
            _ => return false,
        };
        let p = &self.pinhole;
        let (mut us, mut vs) = ((f64::MAX, f64::MIN), (f64::MAX, f64::MIN));
        let mut ss = (f64::MAX, 0.0_f64);
        for &(q, pad) in points {
            let Some((u, v, s)) = p.coords(q) else {
                return false;
            };
            // A move of pad in the world moves (u, v) by at most this
            // much, seen from at least s − pad away.
            let near = s - pad;
            let w = pad * (1.0 + u.abs() + v.abs()) / near;
            if !(near > 0.0 && w.is_finite()) {
                return false;
            }
            us = (us.0.min(u - w), us.1.max(u + w));
            vs = (vs.0.min(v - w), vs.1.max(v + w));
            ss = (ss.0.min(near), ss.1.max(s + pad));
        }
        if points.is_empty() {
            return false;
        }
        // The points sample the surface at pixels; between them, towards
        // the window's corners, the light's rays meet it nearer or
        // farther by about as much as the points' depths differ. The
        // stretch proven monotone takes that in on either side.
        let spread = ss.1 - ss.0;
        let (s0, s1) = (ss.0 - spread, ss.1 + spread);
        // A shadow ray is an f32 ray: its direction is the way to the
        // light to a few roundings, so at depth s its line passes beside
        // the light's ray by up to SHADOW_DIRECTION of its length, at
        // most s1: in (u, v), by `w(s)`. Nearer the light the window
        // widens, a stretch at a time.
        let most = 1.0 + us.0.abs().max(us.1.abs()) + vs.0.abs().max(vs.1.abs());
        let w = |s: f64| SHADOW_DIRECTION * s1 * most * most / s;
        let widened = |w: f64| ((us.0 - w, us.1 + w), (vs.0 - w, vs.1 + w));
        // One window, widened for the stretches that reach no nearer the
        // light than s0 / BACK, serves the slab and those stretches.
        let d = self.depth;
        let mut widest = w(s0 / BACK);
        let window_of = |w: f64| {
            let (xs, ys) = widened(w);
            e.window(xs, ys)
        };
        let mut window = window_of(widest);
        if !(s0 > 0.0 && s1.is_finite() && window.monotone((s0 - d, s1 - d))) {
            return false;
        }
        // The rays end `short` of their length from the light, and no
        // point is nearer it than s0. Back from s0, stretches each BACK
        // times longer than the one after it (F grows away from the
        // surface, and a stretch's Bernstein bounds are as fine as its
        // length is to the distance from the surface), and reaching no
        // nearer the light than 1 / BACK of their far end (the window,
        // widened for the near end, holds the rays to the far end).
        let end = 0.5 * short * s0;
        let (mut to, mut step) = (s0, 4.0 * (s1 - s0));
        // The sign of the stretches proven (all one: F is clear of zero
        // where they meet).
        let mut sign = None;
        loop {
            // Where the rays enter the box, found for the window widened
            // for the stretch's farthest reach back (a wider window's
            // rays enter no later).
            let back = (to - step).max(to / BACK).max(end);
            let (xs, ys) = widened(w(back));
            let Some(reach) = self.reach(xs, ys) else {
                return false;
            };
            let entry = reach.stretch(self.hits).0;
            let from = match (&self.form, sign) {
                (Form::Tree(..), None) => back,
                _ => back.max(entry),
            };
            if w(from) > widest {
                widest = w(from);
                window = window_of(widest);
            }
            if from < to {
                match window.sign((from - d, to - d), false, SPLITS) {
                    Some(s) if sign.is_none_or(|t| t == s) => sign = Some(s),
                    _ => return false,
                }
            }
            if from <= end.max(entry) || from >= to {
                break;
            }
            (to, step) = (from, step * BACK);
        }
        match &self.form {
            Form::Plain(_) => true,
            Form::Tree(tree, ..) => sign.is_some_and(|positive| tree.unseen(leaf, !positive)),
            // Not proven along a light's rays (see `e` above).
            Form::Quadratic(_) => false,
        }
    }

    /// The least and greatest |D| over the rectangle, None where a ray
    /// through it is not well defined.
    fn reach(&self, (x0, x1): (f64, f64), (y0, y1): (f64, f64)) -> Option<Reach> {
        let p = &self.pinhole;
        let corners = [(x0, y0), (x1, y0), (x0, y1), (x1, y1)].map(|(x, y)| p.dir(x, y).length());
        let longest = corners.into_iter().fold(0.0, f64::max);
        // |D| is convex: at least its value at the centre less the most
        // it can change from there.
        let shortest = p.dir(0.5 * (x0 + x1), 0.5 * (y0 + y1)).length()
            - 0.5 * ((x1 - x0) * p.right.length() + (y1 - y0) * p.down.length());
        (shortest > 0.0 && longest.is_finite()).then_some(Reach {
            eye: p.eye,
            shortest,
            longest,
        })
    }
}

/// The lengths of a rectangle's rays' D, from the pinhole's eye.
struct Reach {
    eye: DVec3,
    shortest: f64,
    longest: f64,
}

impl Reach {
    /// The stretch of s where a ray of the rectangle can meet a box.
    fn stretch(&self, (min, max): (DVec3, DVec3)) -> (f64, f64) {
        let (min, max) = (min - self.eye, max - self.eye);
        let nearest = DVec3::ZERO.max(min).max(-max).length();
        let farthest = min.abs().max(max.abs()).length();
        (
            nearest / self.longest * (1.0 - SLACK),
            farthest / self.shortest * (1.0 + SLACK),
        )
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

/// A bound on how far (world) from the exact point o + t·d the shadow rays
/// of a hit there at most start, `error` bounding the hit's t (its root's
/// error): an integrator shades the f32 point o + t·d, off by its rounding
/// and the error (`Scene::interaction`), and starts a shadow ray off the
/// surface by that error bound projected on the normal, one float further
/// (`math::offset`). Eight times those, and a millionth of the distance
/// from the origin besides: nothing rides on its being tight.
pub fn shadow_start_bound(o: DVec3, d: DVec3, t: f64, error: f64) -> f64 {
    let along = t * d;
    let epsilon = f64::from(f32::EPSILON);
    let rounding = epsilon * (o.abs() + along.abs()).element_sum();
    let off = (error + t.abs() * epsilon) * d.abs().element_sum();
    8.0 * (off + rounding) + 1e-6 * ((o + along).length() + 1.0)
}

mod discriminant;
#[cfg(test)]
mod tests;
