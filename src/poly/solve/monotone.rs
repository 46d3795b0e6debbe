//! The first pass for quartics (issue 17's degree-4 ray path), before the
//! Bernstein pass: no transcendental call but one square root, and every
//! decision a proven sign. The roots of q'' (a quadratic, in closed form)
//! cut (lo, hi) into at most three pieces on each of which q is convex or
//! concave. On such a piece, ends of opposite signs hold exactly one root
//! (the set where q has the sign of its convex side is an interval), and
//! ends of the same sign hold none when the curvature turns q away from
//! zero (a concave q above zero stays above the smaller end). Otherwise
//! (a convex q above zero, say) the extremum decides: Newton on q' steps
//! towards it until a point where q has the other sign proves a root
//! (exactly one between the piece's start and that point), or the tangent
//! there, which a convex q never goes below, proves q away from zero on
//! the whole piece.
//!
//! A sign counts only where the value exceeds a running bound on its
//! rounding error (Horner's, on the absolute values). What this cannot
//! prove is left to the Bernstein pass and the Sturm chain: a value within
//! its rounding of zero (a ray starting on the surface, a root at the
//! interval's end, a double root at a tangent, a graze that the tangent
//! bound cannot separate from one), or q'' with nearly a double root.

use std::cmp::Ordering;

use super::bernstein::Screen;
use super::condition::{midpoint, opposite};
use crate::math::{larger, smaller};

/// Newton steps towards one extremum before the pass gives up on it: a
/// graze whose extremum is not proven by then goes to the Sturm chain.
const MAX_STEPS: u32 = 16;

/// q'' with a discriminant this small against its terms has nearly a
/// double root, and its computed roots (the pieces' ends) are not trusted.
const FLAT: f64 = 64.0 * f64::EPSILON;

/// A polynomial with its coefficients' absolute values, evaluated with a
/// bound on the rounding.
struct Bounded<const N: usize> {
    c: [f64; N],
    abs: [f64; N],
}

impl<const N: usize> Bounded<N> {
    fn new(c: [f64; N]) -> Self {
        Bounded {
            c,
            abs: c.map(f64::abs),
        }
    }

    /// The value at x by Horner's rule and a bound on its error. Horner at
    /// degree n is within γ_2n Σ |c_i| |x|^i, γ_2n < 1.01 n ε here; the
    /// bound takes 2 (n + 1) ε, which also covers one rounding in each
    /// coefficient (q' has 3 c_3) and the pieces' inexact ends (module
    /// comment of [`screen`]).
    fn eval(&self, x: f64) -> (f64, f64) {
        let ax = x.abs();
        let (mut v, mut m) = (self.c[N - 1], self.abs[N - 1]);
        for i in (0..N - 1).rev() {
            v = v * x + self.c[i];
            m = m * ax + self.abs[i];
        }
        (v, 2.0 * N as f64 * f64::EPSILON * m)
    }
}

/// Whether a value's sign is proven: it exceeds its rounding bound (false
/// for NaN).
fn proven(value: f64, bound: f64) -> bool {
    // `>` is false where either is NaN, as `partial_cmp` is not Greater.
    value.abs() > bound
}

/// What Newton towards a piece's extremum proved.
enum Extremum {
    /// q keeps its sign on the whole piece.
    Clear,
    /// q has the other sign at this point, with this value.
    Crosses(f64, f64),
    Unsure,
}

/// The first pass over (lo, hi) (finite, clipped to the root bound) for
/// the quartic with coefficients `p` (lowest first, p[4] != 0), or the
/// cubic with p[4] = 0 and p[3] != 0: `Nearest`
/// with a bracket of the nearest root and of no other, `Empty`, or
/// `Unsure`. With `WALK` (for `nearest` by sturm-newton) a piece that may
/// hold the nearest root is first walked by [`Quartic::march`], whose
/// bracket is about as narrow as the tolerance. (A constant, so the pass
/// without it compiles as lean as before: `any` never walks.)
///
/// The pieces' ends are the computed roots of q'', off the true ones by a
/// few roundings (their discriminant is kept away from zero by [`FLAT`]).
/// Between a computed end and the true root, |q''| is at most that offset
/// times |q'''|, so q departs from the curvature assumed there by less than
/// the square of that offset times q''''s size: far below the rounding
/// bound that every proven value of q must clear.
///
/// A cubic's q'' is linear: its one root is the stable formula's c/q, and
/// the other, s / 0, is infinite and so outside (lo, hi). Its padded zero
/// adds nothing to Horner's values and only widens their bounds.
pub(super) fn screen<const WALK: bool>(p: [f64; 5], lo: f64, hi: f64, tolerance: f64) -> Screen {
    let [c0, c1, c2, c3, c4] = p;
    let quartic = Quartic {
        q: Bounded::new([c0, c1, c2, c3, c4]),
        g: Bounded::new([c1, 2.0 * c2, 3.0 * c3, 4.0 * c4]),
        h: [2.0 * c2, 6.0 * c3, 12.0 * c4],
        degree: if c4 == 0.0 { 3.0 } else { 4.0 },
    };
    let h = quartic.h;
    let disc = h[1] * h[1] - 4.0 * h[2] * h[0];
    if disc
        .abs()
        .partial_cmp(&(FLAT * (h[1] * h[1] + (4.0 * h[2] * h[0]).abs())))
        != Some(Ordering::Greater)
    {
        return Screen::Unsure;
    }
    // The pieces' ends after lo, increasing: the roots of q'' inside, then hi.
    let mut ends = [hi; 3];
    let mut n = 0;
    if disc > 0.0 {
        // The stable quadratic formula; s != 0 since disc > 0.
        let s = -0.5 * (h[1] + disc.sqrt().copysign(h[1]));
        let (r1, r2) = (s / h[2], h[0] / s);
        for r in [r1.min(r2), r1.max(r2)] {
            if r > lo && r < hi {
                ends[n] = r;
                n += 1;
            }
        }
    }
    let (mut x0, (mut q0, mut e0)) = (lo, quartic.q.eval(lo));
    if !proven(q0, e0) {
        return Screen::Unsure;
    }
    for &x1 in &ends[..=n] {
        let (q1, e1) = quartic.q.eval(x1);
        if !proven(q1, e1) {
            return Screen::Unsure;
        }
        let curvature = quartic.curvature(midpoint(x0, x1));
        // Whether q's sign at an end and the piece's curvature agree: from
        // there Newton-like steps approach a root from the side they cannot
        // overshoot.
        let convex_at = |qx: f64| opposite(curvature, -qx);
        if opposite(q0, q1) {
            // Exactly one root: walked to from the end where q turns
            // towards zero, else refined from the bracket's middle.
            if !WALK {
                return nearest((x0, q0), (x1, q1), None);
            }
            let (from, to) = if convex_at(q0) { (x0, x1) } else { (x1, x0) };
            return match quartic.march(from, to, tolerance) {
                Ok(found) => found,
                Err(Stop {
                    proven: (x, qx, _), ..
                }) if from == x0 => nearest((x, qx), (x1, q1), None),
                Err(Stop {
                    proven: (x, qx, _), ..
                }) => nearest((x0, q0), (x, qx), None),
            };
        }
        if convex_at(q0) {
            // q turns towards zero: the walk, then the extremum decide,
            // between where the walk stopped and where it found q rising.
            let (mut start, mut end) = ((x0, q0, e0), (x1, q1, e1));
            if WALK {
                match quartic.march(x0, x1, tolerance) {
                    Ok(found) => return found,
                    Err(stop) => (start, end) = (stop.proven, stop.past.unwrap_or(end)),
                }
            }
            let (y0, r0, f0) = start;
            match extremum(&quartic, (y0, end.0), (r0, f0), (end.1, end.2)) {
                Extremum::Clear => {}
                Extremum::Crosses(x, qx) => return nearest((y0, r0), (x, qx), None),
                Extremum::Unsure => return Screen::Unsure,
            }
        }
        (x0, q0, e0) = (x1, q1, e1);
    }
    Screen::Empty
}

/// Coefficients (lowest first) of a cubic or quartic as [`screen`] takes
/// them: five, a cubic's with a zero quartic term.
pub(super) fn padded(c: &[f64]) -> [f64; 5] {
    std::array::from_fn(|i| c.get(i).copied().unwrap_or(0.0))
}

/// The bracket between two points (x, q(x)) of opposite signs, in either
/// order.
fn nearest(a: (f64, f64), b: (f64, f64), start: Option<f64>) -> Screen {
    let ((lo, flo), (hi, fhi)) = if a.0 < b.0 { (a, b) } else { (b, a) };
    Screen::Nearest {
        lo,
        hi,
        flo,
        fhi,
        start,
    }
}

/// A quartic or cubic q with q' and q'' for the pass, and its degree
/// (for Laguerre's step).
struct Quartic {
    q: Bounded<5>,
    g: Bounded<4>,
    h: [f64; 3],
    degree: f64,
}

/// q, q' and q'' at x, with the rounding bounds of q and q'.
#[derive(Clone, Copy)]
struct Probe {
    x: f64,
    q: f64,
    eq: f64,
    g: f64,
    eg: f64,
    h: f64,
}

impl Quartic {
    fn curvature(&self, x: f64) -> f64 {
        (self.h[2] * x + self.h[1]) * x + self.h[0]
    }

    fn probe(&self, x: f64) -> Probe {
        let (q, eq) = self.q.eval(x);
        let (g, eg) = self.g.eval(x);
        Probe {
            x,
            q,
            eq,
            g,
            eg,
            h: self.curvature(x),
        }
    }

    /// Walks from `from` (q's sign s there proven, and s q convex from
    /// there to `to`) towards the first root, by Laguerre steps: exact for
    /// (x - r)^4, they cross the far field of four close roots in a step or
    /// two where Newton gains a quarter of the distance per step. A step is
    /// kept only if it proves itself: at the new point s q is still proven
    /// positive and proven decreasing along the way, so by convexity s q
    /// decreases all the way from `from` and no root lies behind. The walk
    /// ends with the nearest root bracketed (`Ok`): by a point where s q is
    /// proven negative (between them lies the one root a convex piece has
    /// before its extremum), or by a point before the extremum within
    /// rounding of zero, bracketed with one Newton step pushed half the
    /// tolerance past it, by the plain signs refinement trusts. Otherwise
    /// (a step backwards or past `to`, past the extremum, where two roots
    /// may lie behind it, or not proven) it gives up ([`Stop`]).
    fn march(&self, from: f64, to: f64, tolerance: f64) -> Result<Screen, Stop> {
        let mut a = self.probe(from);
        let s = a.q.signum();
        let d = (to - from).signum();
        let descending = |p: &Probe| d * s * p.g < -p.eg;
        let inside = |y: f64, after: f64| d * (y - after) > 0.0 && d * (to - y) > 0.0;
        let mut past = None;
        if descending(&a) {
            for _ in 0..MAX_STEPS {
                let y = a.x - laguerre(&a, self.degree);
                if !inside(y, a.x) {
                    break;
                }
                let b = self.probe(y);
                if s * b.q > b.eq {
                    if descending(&b) {
                        a = b;
                        continue;
                    }
                    if d * s * b.g > b.eg {
                        past = Some((b.x, b.q, b.eq));
                    }
                    break;
                }
                if !(-s * b.q > b.eq || descending(&b)) {
                    break;
                }
                let newton = y - b.q / b.g;
                if opposite(b.q, s) {
                    return Ok(nearest((a.x, a.q), (y, b.q), Some(newton)));
                }
                let z = newton + d * 0.5 * tolerance * y.abs().max(1.0);
                let qz = self.q.eval(z).0;
                if inside(z, y) && opposite(qz, s) {
                    // q(y) = 0 exactly brackets nothing: the bracket then
                    // starts behind, and refinement begins at y itself.
                    let behind = if b.q == 0.0 { (a.x, a.q) } else { (y, b.q) };
                    return Ok(nearest(behind, (z, qz), Some(newton)));
                }
                break;
            }
        }
        Err(Stop {
            proven: (a.x, a.q, a.eq),
            past,
        })
    }
}

/// Where [`Quartic::march`] stopped: q has no root between its start and
/// `proven`, and s q rises from `past` on (so has no root there either),
/// when it stepped past the extremum with s q still proven positive.
struct Stop {
    proven: (f64, f64, f64),
    past: Option<(f64, f64, f64)>,
}

/// The Laguerre step at a point of a polynomial of degree n (the root
/// estimate is x less this): G = q'/q, H = G^2 - q''/q, step
/// n / (G ± sqrt((n - 1) (nH - G^2))), the square root's sign that of G.
/// A negative radicand (complex roots nearby) gives twice Newton's step
/// instead: Newton's alone crawls where four roots lie ahead, and the radicand taken as zero (four times
/// Newton's) mostly lands past the extremum, where the walk must stop.
/// On the bench's torus rays (`cargo bench --bench poly`), per `nearest`
/// call: 1,514 instructions with twice, 1,630 with once, 1,527 with four
/// times Newton's step.
fn laguerre(p: &Probe, n: f64) -> f64 {
    let inv = 1.0 / p.q;
    let big_g = p.g * inv;
    let big_h = big_g * big_g - p.h * inv;
    let radicand = (n - 1.0) * (n * big_h - big_g * big_g);
    if radicand >= 0.0 {
        n / (big_g + radicand.sqrt().copysign(big_g))
    } else {
        2.0 * p.q / p.g
    }
}

/// On a piece [x0, x1] where q(x0) = q0 and q(x1) = q1 (with their
/// rounding bounds) have the same sign and the curvature turns q towards
/// zero (s q convex, s the sign of q0): the tangents at the ends, then
/// safeguarded Newton on q' towards the extremum, until q's sign is proven
/// there or a tangent proves the piece clear.
// Inlined as it was before the walk: `any` queries spend most of their
// pass here, and the call costs them some 5% of their instructions.
#[inline(always)]
fn extremum(
    quartic: &Quartic,
    (x0, x1): (f64, f64),
    (q0, e0): (f64, f64),
    (q1, e1): (f64, f64),
) -> Extremum {
    let (q, g, h) = (&quartic.q, &quartic.g, quartic.h);
    let s = q0.signum();
    let curvature = |x: f64| (h[2] * x + h[1]) * x + h[0];
    // s q lies above its tangent at x on the whole piece: the least of the
    // tangent there, less the roundings of q(x) and of q'(x) over the reach.
    let clear = |x: f64, qx: f64, eq: f64, gx: f64, eg: f64| {
        let slope = s * gx;
        // x0, x1 and x are finite, so only an infinite or NaN slope (an
        // overflowed q') gives a NaN candidate; `smaller` then leaves no
        // side clear, where `f64::min` could take the other, infinite one.
        let low = smaller(slope * (x0 - x), slope * (x1 - x));
        s * qx - eq - eg * larger(x - x0, x1 - x) + low > 0.0
    };
    let (g0, eg0) = g.eval(x0);
    let (g1, eg1) = g.eval(x1);
    if clear(x0, q0, e0, g0, eg0) || clear(x1, q1, e1, g1, eg1) {
        return Extremum::Clear;
    }
    // Newton from the end with the shorter step: the other may be a root
    // of q'' (a step that goes nowhere useful) or the far end of a search
    // clipped only by Cauchy's bound, from which Newton on the cubic q'
    // gains a third of the distance per step.
    let (step0, step1) = (g0 / curvature(x0), g1 / curvature(x1));
    let next = if step0.abs() <= step1.abs() {
        x0 - step0
    } else {
        x1 - step1
    };
    let (mut u, mut v) = (x0, x1);
    let mut x = if next > u && next < v {
        next
    } else {
        midpoint(u, v)
    };
    for _ in 0..MAX_STEPS {
        let (qx, eq) = q.eval(x);
        if -s * qx > eq {
            return Extremum::Crosses(x, qx);
        }
        let (gx, eg) = g.eval(x);
        if clear(x, qx, eq, gx, eg) {
            return Extremum::Clear;
        }
        // s q' increases: the extremum is past x where s q' < 0.
        if s * gx < 0.0 {
            u = x;
        } else {
            v = x;
        }
        let next = x - gx / curvature(x);
        x = if next > u && next < v {
            next
        } else {
            midpoint(u, v)
        };
        if !(x > u && x < v) {
            break;
        }
    }
    Extremum::Unsure
}

#[cfg(test)]
mod tests {
    use super::super::bernstein::tests::{open_count, product, root_near};
    use super::*;
    use crate::poly::exact::exact_count;
    use proptest::prelude::*;

    /// A quartic's or cubic's coefficients (lowest first) from real roots,
    /// clusters, tangent pairs and complex pairs close to the axis
    /// (grazes), with an interval (a, b).
    fn quartic_and_interval() -> impl Strategy<Value = (Vec<f64>, f64, f64)> {
        (
            3..=4usize,
            prop::collection::vec(root_near(), 4),
            prop::collection::vec(
                (
                    -2.0..40.0f64,
                    prop_oneof![1e-9..1e-3f64, 1e-3..5.0f64, 5.0..30.0f64],
                ),
                0..=2,
            ),
            prop_oneof![Just(1.0), 1e-3..1e3f64, -1e3..-1e-3f64],
            -1.0..20.0f64,
            prop_oneof![0.01..1.0f64, 1.0..100.0f64],
        )
            .prop_map(|(degree, real, pairs, lead, a, len)| {
                let pairs = &pairs[..pairs.len().min(degree / 2)];
                let c = product(lead, &real[..degree - 2 * pairs.len()], pairs);
                (c, a, a + len)
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        // Every Empty and Nearest answer is checked against the exact Sturm
        // count of the quartic or cubic whose coefficients are the f64 ones.
        #[test]
        fn what_it_proves_is_true((c, a, b) in quartic_and_interval()) {
            match screen::<false>(padded(&c), a, b, 0.0) {
                Screen::Empty => prop_assert_eq!(open_count(&c, a, b), 0, "empty, but roots"),
                Screen::Nearest { lo, hi, flo, fhi, .. } => {
                    prop_assert!(a <= lo && lo < hi && hi <= b, "[{lo}, {hi}] outside");
                    prop_assert_eq!(exact_count(&c, a, lo).unwrap(), 0, "a nearer root");
                    prop_assert_eq!(open_count(&c, lo, hi), 1, "not one root in [{}, {}]", lo, hi);
                    prop_assert!(opposite(flo, fhi));
                }
                Screen::Some => prop_assert!(false, "`Some` is the Bernstein pass's"),
                Screen::Unsure => {}
            }
        }

        // The walk (sturm-newton's `nearest`) on the same polynomials: its
        // bracket ends in plain signs, so the check allows the tolerance
        // plus what rounding allows where the walk trusted them (Horner's
        // bound over |q'|, as `agrees_with_the_chain` in the solver's
        // tests): no exact root before the bracket by more than that, and
        // one within it, widened by as much.
        #[test]
        fn what_the_walk_proves_is_true((c, a, b) in quartic_and_interval()) {
            let tolerance = 1e-12;
            match screen::<true>(padded(&c), a, b, tolerance) {
                Screen::Empty => prop_assert_eq!(open_count(&c, a, b), 0, "empty, but roots"),
                Screen::Nearest { lo, hi, flo, fhi, .. } => {
                    prop_assert!(a <= lo && lo < hi && hi <= b, "[{lo}, {hi}] outside");
                    prop_assert!(opposite(flo, fhi));
                    let [c0, c1, c2, c3, c4] = padded(&c);
                    let q = Bounded::new([c0, c1, c2, c3, c4]);
                    let g = Bounded::new([c1, 2.0 * c2, 3.0 * c3, 4.0 * c4]);
                    let slope = g.eval(lo).0.abs().min(g.eval(hi).0.abs());
                    let allowed = tolerance * lo.abs().max(1.0) + 5.0 * q.eval(lo).1 / slope;
                    let (near, far) = ((lo - allowed).max(a), (hi + allowed).min(b));
                    prop_assert_eq!(exact_count(&c, a, near).unwrap(), 0, "a nearer root");
                    prop_assert!(open_count(&c, near, far) >= 1, "no root by [{}, {}]", lo, hi);
                }
                Screen::Some => prop_assert!(false, "`Some` is the Bernstein pass's"),
                Screen::Unsure => {}
            }
        }
    }

    #[test]
    fn a_walk_onto_an_exact_zero_brackets_the_root() {
        // The walk met q = 0 exactly at a Laguerre point (found by the
        // property test): a bracket must still have ends of opposite signs.
        let c = product(
            -0.001,
            &[24.43418712374569, 27.32048149913449, 0.0, 0.0],
            &[],
        );
        let a = 4.884799338579024;
        let Screen::Nearest {
            lo, hi, flo, fhi, ..
        } = screen::<true>(padded(&c), a, a + 55.6, 1e-12)
        else {
            panic!("not bracketed");
        };
        assert!(opposite(flo, fhi), "[{lo}, {hi}]: {flo}, {fhi}");
        assert!(
            lo <= 24.43418712374569 && 24.43418712374569 <= hi,
            "[{lo}, {hi}]"
        );
    }

    #[test]
    fn what_it_cannot_prove_is_left_to_the_chain() {
        // A double root at 1 (a tangent ray).
        let c = product(1.0, &[1.0, 1.0, 3.0, 4.0], &[]);
        assert_eq!(screen::<false>(padded(&c), 0.0, 10.0, 0.0), Screen::Unsure);
        // A root at the interval's start.
        let c = product(1.0, &[0.0, 1.5, 3.0, 4.0], &[]);
        assert_eq!(screen::<false>(padded(&c), 0.0, 10.0, 0.0), Screen::Unsure);
        // A complex pair 1e-13 off the axis: no real root there, but the
        // tangent cannot tell it from a double root.
        let c = product(1.0, &[3.0, 4.0], &[(1.0, 1e-13)]);
        assert_eq!(screen::<false>(padded(&c), 0.0, 10.0, 0.0), Screen::Unsure);
        // q'' with a double root: (t - 1)^4 + t has q'' = 12 (t - 1)^2.
        assert_eq!(
            screen::<false>([2.0, -3.0, 6.0, -4.0, 1.0], -5.0, 5.0, 0.0),
            Screen::Unsure
        );
    }

    #[test]
    fn grazes_that_it_proves() {
        // A complex pair 1e-4 off the axis before two real roots: the
        // extremum is proven above zero, and the root at 3 is the nearest.
        let c = product(1.0, &[3.0, 4.0], &[(1.0, 1e-4)]);
        let Screen::Nearest { lo, hi, .. } = screen::<false>(padded(&c), 0.0, 10.0, 0.0) else {
            panic!("not proven");
        };
        assert!(lo < 3.0 && 3.0 < hi && hi < 4.0, "[{lo}, {hi}]");
        // Two real roots 1e-4 apart: a point between them is proven below
        // zero, and brackets the first.
        let c = product(1.0, &[1.0, 1.0001, 3.0, 4.0], &[]);
        let Screen::Nearest { lo, hi, .. } = screen::<false>(padded(&c), 0.0, 10.0, 0.0) else {
            panic!("not proven");
        };
        assert!(lo < 1.0 && 1.0 < hi && hi < 1.0001, "[{lo}, {hi}]");
        // No real root at all.
        let c = product(1.0, &[], &[(1.0, 1e-3), (3.0, 0.5)]);
        assert_eq!(screen::<false>(padded(&c), 0.0, 10.0, 0.0), Screen::Empty);
        // A ray at a torus 30 units away, searched up to Cauchy's bound
        // (1.8e7): Newton towards the minimum starts from the near end,
        // not the far one, and proves the first root within its steps.
        let c = [
            1574.0312499999998,
            -203.73211424953368,
            10.157571696269468,
            -0.22902205699660633,
            0.001953125000000001,
        ];
        let Screen::Nearest { lo, hi, .. } = screen::<false>(padded(&c), 0.0, 1.8e7, 0.0) else {
            panic!("not proven");
        };
        assert!(lo < 31.503 && 31.504 < hi && hi < 36.44, "[{lo}, {hi}]");
    }
}
