//! Real roots of a polynomial in an interval, for ray intersection: Sturm
//! counts isolate each distinct root in its own interval, then bisection,
//! safeguarded Newton or Illinois regula falsi refines it.
//!
//! Tolerance: refinement stops once the bracket known to hold the root is
//! no wider than `tolerance * max(1, |t|)`, with |t| the smaller magnitude of
//! the bracket's ends (so the bound holds for the root itself): relative for
//! large roots, absolute near zero, where relative accuracy would cost
//! without end for a root at t = 0. A reported simple root is within that
//! width of a true root of the (f64) polynomial. A multiple root is refined
//! on the square-free part p / gcd(p, p'), whose coefficients carry the
//! chain's round-off: exact for exactly representable cases such as
//! (t - 1)^3, typically 1e-10 off otherwise (the exact rational path is the
//! reference for those). Roots of a cluster narrower than the tolerance
//! cannot be told apart and are reported once.
//!
//! Nothing on the rays' paths (`nearest`, `nearest_from`, `any`) allocates:
//! Sturm chains and interval stacks are fixed arrays sized by
//! [`MAX_DEGREE`], since every call runs per ray. `roots` and
//! `certified_roots`, for the `roots` tool, return the f64 answer only when
//! the exact isolation ([`Isolation::certifies`]) proves it, and otherwise
//! the exact path's, which does allocate.
//!
//! This file holds the queries; `method` the settings ([`Method`],
//! [`Solver`]), `condition` the search interval and trimming, `isolate` the
//! Sturm isolation and refinement, `direct` the closed forms and Yuksel's
//! method, `bernstein` and `monotone` the first passes.

mod bernstein;
mod condition;
mod direct;
mod isolate;
mod method;
mod monotone;

pub use method::{Method, Solver};

use crate::math::larger;
use crate::poly::MAX_DEGREE;
use crate::poly::exact::{Certificate, Isolation, MAX_EXACT_DEGREE, Relative};
use crate::poly::univariate::{Poly, PolyN, QUARTIC_SLOTS, SMALL_SLOTS, normalize_pow2};

use bernstein::{Question, Screen};
use condition::{
    Search, clip_to_root_bound, is_interval, negligible_above, opposite, strictly_inside,
};
use direct::DirectRoots;

use std::cell::Cell;

/// Which path found a certified answer's values (both are proven the same
/// way, by [`Certificate`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// The solver's f64 method, its answer certified.
    F64,
    /// The exact path, after the f64 answer failed (or above [`MAX_DEGREE`]).
    Exact,
}

thread_local! {
    /// See [`unseparated_count`].
    static UNSEPARATED: Cell<u64> = const { Cell::new(0) };
}

/// How many queries on this thread so far could not trust the f64 Sturm
/// chain to separate their roots: either the chain was degenerate at degree
/// 17 to 35 (a remainder f64 could not carry, so its counts are a best
/// guess and can skip roots, as on Wilkinson-like polynomials), or
/// isolation ended on a bracket no wider than the tolerance in which the
/// chain still counted two or more distinct roots (reported as one root at
/// the bracket's midpoint). A query counts once however many such brackets
/// it met; `any` never refines and never counts, nor does an accepted
/// warm start. The count
/// only grows: a caller reads it before and after its own work (the render
/// does per tile) and takes the difference, which depends on that work
/// alone, so the totals are the same for any thread count.
pub fn unseparated_count() -> u64 {
    UNSEPARATED.with(Cell::get)
}

/// Records one query that could not separate its roots.
fn note_unseparated() {
    UNSEPARATED.with(|c| c.set(c.get() + 1));
}

/// Runs `$call` with `$q` bound to the query's polynomial in the smallest
/// instantiation its degree fits ([`QUARTIC_SLOTS`], then [`SMALL_SLOTS`]),
/// else to the input itself: a query sets up a Sturm chain whose size is
/// quadratic in the slot count, and most rays meet degree 4 or less.
macro_rules! by_degree {
    ($p:expr, |$q:ident| $call:expr) => {
        if let Some(quartic) = $p.resized::<QUARTIC_SLOTS>() {
            let $q = &quartic;
            $call
        } else if let Some(small) = $p.resized::<SMALL_SLOTS>() {
            let $q = &small;
            $call
        } else {
            let $q = $p;
            $call
        }
    };
}

impl Solver {
    /// All distinct real roots in (a, b], increasing, written to `out`;
    /// returns how many. Isolation by bisection on Sturm counts, then
    /// refinement by the method. `Closed` uses the closed forms for degree
    /// <= 4 and falls back to sturm-newton above. Infinite ends are allowed:
    /// the search is clipped to Cauchy's bound on the roots. The zero
    /// polynomial has no isolated roots and reports none.
    ///
    /// On the Sturm path the answer must prove itself: the exact isolation
    /// of p's rational coefficients ([`Isolation::certifies`]) must show as
    /// many roots as were found, each alone within the tolerance of one
    /// found. The f64 chain alone cannot be trusted for that: a root of even
    /// multiplicity has no sign change, and a remainder of pure round-off
    /// that passes for a true one (or the reverse) loses or invents roots
    /// with nothing in f64 to show it (the double root 3.5 of a sextic, two
    /// simple roots of a degree-11 chain with a 9e-10 coefficient).
    /// Otherwise the answer comes from the exact rational path, merged to
    /// the tolerance as the Sturm path would report it.
    /// The exact chain costs about 0.19 ms at degree 8 and 1.25 ms at 16
    /// (`cargo bench --bench poly -- exact_count`), which the `roots` tool
    /// can afford and a ray cannot.
    pub fn roots(&self, p: &Poly, a: f64, b: f64, out: &mut [f64; MAX_DEGREE]) -> usize {
        let n = self.unproven_roots(p, a, b, out);
        if self.direct(p) || !is_interval(a, b) {
            return n; // the comparison methods answer as they are
        }
        let Some(isolation) = Isolation::new(p.coeffs(), a, b) else {
            return n; // a coefficient is not finite: no exact polynomial
        };
        if isolation.certifies(&out[..n], self.tolerance, Relative::MagnitudeOrOne) {
            return n;
        }
        let mut found = DirectRoots::default();
        let exact = isolation
            .roots(self.tolerance, Relative::MagnitudeOrOne)
            .unwrap_or_default();
        exact.iter().for_each(|&t| found.push(t));
        self.roots_in(&found, a, b, out)
    }

    /// Every distinct real root in (a, b] of the polynomial with these
    /// coefficients, increasing, with the proof the `roots` tool promises
    /// ([`Certificate`]): the list is as long as the exact count, and each
    /// value lies in an interval with exact ends that holds exactly its own
    /// root, no farther from the value than the tolerance *relative to its
    /// magnitude* ([`Relative::Magnitude`]: a root of 1e-14 is not answered
    /// with 1.4e-14, as the renderer's absolute tolerance below 1 would
    /// allow). The f64 answer of this solver's method (on the coefficients
    /// scaled by a power of two, which keeps the roots and spares f64
    /// needless overflow and underflow) is kept when [`Isolation::certify`]
    /// proves it; otherwise, and always above degree [`MAX_DEGREE`] (the f64
    /// path's fixed storage), the exact path answers, one value per root,
    /// never merged (roots closer than f64 resolution come out as one value
    /// repeated, and a root f64 cannot hold to the tolerance, such as a
    /// subnormal one, as its correctly rounded value). None if a coefficient
    /// or the tolerance is not finite, an end is NaN, or the degree is above
    /// [`MAX_EXACT_DEGREE`].
    pub fn certified(&self, coeffs: &[f64], a: f64, b: f64) -> Option<(Certificate, Source)> {
        if coeffs.len() > MAX_EXACT_DEGREE + 1 || !self.tolerance.is_finite() {
            return None;
        }
        let isolation = Isolation::new(coeffs, a, b)?;
        if coeffs.len() <= MAX_DEGREE + 1 {
            let mut scaled = [0.0; MAX_DEGREE + 1];
            scaled[..coeffs.len()].copy_from_slice(coeffs);
            normalize_pow2(&mut scaled);
            let p = Poly::new(&scaled[..coeffs.len()]);
            let mut out = [0.0; MAX_DEGREE];
            let n = self.unproven_roots(&p, a, b, &mut out);
            if let Some(c) = isolation.certify(&out[..n], self.tolerance, Relative::Magnitude) {
                return Some((c, Source::F64));
            }
        }
        let c = isolation.solve(self.tolerance, Relative::Magnitude)?;
        Some((c, Source::Exact))
    }

    /// The values of [`Solver::certified`].
    pub fn certified_roots(&self, coeffs: &[f64], a: f64, b: f64) -> Option<Vec<f64>> {
        Some(self.certified(coeffs, a, b)?.0.values())
    }

    /// The f64 roots in (a, b], unproven: from the closed forms or
    /// Yuksel's method where they apply, else from the Sturm chain. What
    /// [`Solver::roots`] and [`Solver::certified`] check; public for the
    /// accuracy study, which counts how often the check fails.
    pub fn unproven_roots(&self, p: &Poly, a: f64, b: f64, out: &mut [f64; MAX_DEGREE]) -> usize {
        by_degree!(p, |q| self.unproven_roots_in(q, a, b, out))
    }

    fn unproven_roots_in<const S: usize>(
        &self,
        p: &PolyN<S>,
        a: f64,
        b: f64,
        out: &mut [f64; MAX_DEGREE],
    ) -> usize {
        if !is_interval(a, b) {
            return 0;
        }
        if let Some(found) = self.direct_roots(p, a, b, f64::INFINITY) {
            return self.roots_in(&found, a, b, out);
        }
        let mut search = Search::EMPTY;
        if !search.prepare(p, a, b) {
            return 0;
        }
        self.isolate_all(&search, out)
    }

    /// The nearest root in (a, b): for camera and secondary rays. The
    /// leftmost root interval is isolated first, by Sturm counts on halves,
    /// so a farther root is never returned while a nearer one exists. A root
    /// exactly at b is not reported.
    pub fn nearest<const S: usize>(&self, p: &PolyN<S>, a: f64, b: f64) -> Option<f64> {
        by_degree!(p, |q| self.nearest_of(q, a, b))
    }

    fn nearest_of<const S: usize>(&self, p: &PolyN<S>, a: f64, b: f64) -> Option<f64> {
        if !is_interval(a, b) {
            return None;
        }
        if let Some(found) = self.direct_roots(p, a, b, a) {
            return found.iter().copied().find(|&t| t > a && t < b);
        }
        match self.screen(p, a, b, Question::Nearest) {
            (Screen::Empty, _) => return None,
            (
                Screen::Nearest {
                    lo,
                    hi,
                    flo,
                    fhi,
                    start,
                },
                counted,
            ) => {
                let t = self.refine_bracket(&counted, lo, hi, flo, fhi, start);
                return Some(strictly_inside(t, a, b));
            }
            _ => {}
        }
        let mut search = Search::EMPTY;
        if !search.prepare(p, a, b) {
            return None;
        }
        self.nearest_in(&search, a, b)
    }

    /// The first pass (at degree 4 [`monotone`], then [`bernstein`]) at
    /// degree 16 or less, on p
    /// as the Sturm chain counts it: within the root bound, without the
    /// leading terms below one rounding on the interval. Returns that
    /// polynomial too, which refines the root.
    fn screen<const S: usize>(
        &self,
        p: &PolyN<S>,
        a: f64,
        b: f64,
        question: Question,
    ) -> (Screen, PolyN<S>) {
        if p.degree() >= SMALL_SLOTS {
            return (Screen::Unsure, *p);
        }
        let Some((lo, hi)) = clip_to_root_bound(p, a, b) else {
            return (Screen::Unsure, *p);
        };
        let degree = negligible_above(p, larger(lo.abs(), hi.abs()), f64::EPSILON);
        let counted = p.truncated(degree);
        // Quartics (tori) and cubics first by their curvature pieces, which
        // prove queries in fewer instructions than the Bernstein pass
        // (issue 17 in docs/accuracy.md); the Bernstein pass takes what
        // they leave. A cubic is padded with a zero quartic term.
        if degree == 3 || degree == 4 {
            // sturm-newton's nearest walks to the root (Quartic::march);
            // the other methods refine the bracket by their own steps.
            let c = monotone::padded(counted.coeffs());
            let proven = if question == Question::Nearest && self.method == Method::SturmNewton {
                monotone::screen::<true>(c, lo, hi, self.tolerance)
            } else {
                monotone::screen::<false>(c, lo, hi, self.tolerance)
            };
            match proven {
                Screen::Unsure => {}
                Screen::Nearest { .. } if question == Question::Any => {
                    return (Screen::Some, counted);
                }
                proven => return (proven, counted),
            }
        }
        (restarted(&counted, lo, hi, question, RESTARTS), counted)
    }

    /// Whether any root lies in (a, b): for shadow rays. Counts only, never
    /// refines; a sign change between the ends answers before the chain is
    /// even built. `Closed` answers from the closed-form roots instead.
    pub fn any<const S: usize>(&self, p: &PolyN<S>, a: f64, b: f64) -> bool {
        by_degree!(p, |q| self.any_of(q, a, b))
    }

    fn any_of<const S: usize>(&self, p: &PolyN<S>, a: f64, b: f64) -> bool {
        if !is_interval(a, b) {
            return false;
        }
        if let Some(found) = self.direct_roots(p, a, b, a) {
            return found.iter().any(|&t| t > a && t < b);
        }
        if a.is_finite() && b.is_finite() && opposite(p.eval(a), p.eval(b)) {
            return true;
        }
        match self.screen(p, a, b, Question::Any).0 {
            Screen::Empty => return false,
            Screen::Some | Screen::Nearest { .. } => return true,
            Screen::Unsure => {}
        }
        let mut search = Search::EMPTY;
        if !search.prepare(p, a, b) {
            return false;
        }
        search.whole().count() > usize::from(search.root_at_end(b))
    }

    /// Newton warm start from `guess` (the last root found for the same
    /// object on the same thread). The result is accepted only if Sturm
    /// counts prove that a root lies within the tolerance of it and none
    /// lies in (a, result - tolerance], so it is never farther than the
    /// nearest root; otherwise this falls back to [`Solver::nearest`] on the
    /// same chain. `Closed` ignores the guess.
    pub fn nearest_from(&self, p: &Poly, a: f64, b: f64, guess: f64) -> Option<f64> {
        by_degree!(p, |q| self.nearest_from_of(q, a, b, guess))
    }

    fn nearest_from_of<const S: usize>(
        &self,
        p: &PolyN<S>,
        a: f64,
        b: f64,
        guess: f64,
    ) -> Option<f64> {
        if !is_interval(a, b) {
            return None;
        }
        if matches!(self.method, Method::Closed | Method::Yuksel) && self.direct(p) {
            return self.nearest_of(p, a, b);
        }
        let mut search = Search::EMPTY;
        if !search.prepare(p, a, b) {
            return None;
        }
        if let Some(t) = self.warm_newton(search.refine(), a, b, guess)
            && self.proves_nearest(&search, a, b, t)
        {
            return Some(t);
        }
        self.nearest_in(&search, a, b)
    }
}

/// How deep `restarted` splits an interval the first pass left unsure: at
/// most 2^(RESTARTS + 1) − 2 more passes, and only where the Sturm chain
/// would answer next. Three levels left a pair of roots of the test below
/// (`degree_12_roots_under_the_whole_intervals_rounding`) unfound.
const RESTARTS: u32 = 5;

/// The Bernstein first pass, and, above degree 4 where it is unsure, the
/// pass again on each part of a split from a fresh start, the nearer first.
/// A start bounds the rounding of every control point by the terms of p
/// over the whole piece (Σ|c_k| w^k), so on a long interval a cluster of
/// roots whose values sink below that bound is never proven, however far
/// the pass halves; a half starts from its own, far smaller, terms. Where
/// the pass stays unsure the f64 Sturm chain answers, and at degree 12 it
/// can degenerate and count no root at all: a poly of degree 12 (four
/// ellipsoids and a torus multiplied, less 1e-3) lost four clear roots
/// that way. Quartics keep their own passes (`monotone` first).
fn restarted<const S: usize>(
    p: &PolyN<S>,
    lo: f64,
    hi: f64,
    question: Question,
    left: u32,
) -> Screen {
    let screen = bernstein::screen(p, lo, hi, question);
    if screen != Screen::Unsure || left == 0 || p.degree() <= 4 {
        return screen;
    }
    // Not next to a root: a half whose end is one needs halvings down to
    // that distance to prove itself empty (the cluster above had a root
    // 1e-4 of the way from the middle). Of five points about the middle,
    // the one where |p| is largest.
    let split = [0.5, 0.375, 0.625, 0.4375, 0.5625]
        .map(|f| lo + f * (hi - lo))
        .into_iter()
        .filter(|&x| x > lo && x < hi)
        .max_by(|&x, &y| p.eval(x).abs().total_cmp(&p.eval(y).abs()));
    let Some(split) = split else {
        return screen;
    };
    match restarted(p, lo, split, question, left - 1) {
        // A root at the split itself leaves both halves unsure: the second
        // half's start is noise there.
        Screen::Empty => restarted(p, split, hi, question, left - 1),
        screen => screen,
    }
}

#[cfg(test)]
mod tests;
