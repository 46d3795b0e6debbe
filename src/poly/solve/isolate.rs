//! Sturm isolation and refinement: brackets split by the f64 chain's counts
//! until each holds one distinct root, then refined by bisection,
//! safeguarded Newton or Illinois regula falsi; the warm start and its
//! proof; the tolerance tests every method stops on.

use crate::poly::MAX_DEGREE;
use crate::poly::sturm::SturmSequence;
use crate::poly::univariate::{PolyN, SMALL_SLOTS};

use super::condition::{Search, WIDE_BRACKET, bit_midpoint, midpoint, opposite, strictly_inside};
use super::{Method, Solver, note_unseparated};

/// Whether a chain's counts are too weak a proof to go unreported: it is
/// degenerate (a remainder f64 could not carry; see
/// [`SturmSequence::is_degenerate`]) at degree 17 to 35. Below that,
/// degenerate chains are common and harmless after trimming (770 queries in
/// the algebraic gallery at 2 spp; the accuracy study finds no wrong hit on
/// any scene); above it they skipped nearer roots in 5 of 50 Wilkinson-like
/// polynomials of the study's high-degree set.
fn unreliable<const S: usize>(seq: &SturmSequence<S>) -> bool {
    S > SMALL_SLOTS && seq.is_degenerate()
}

/// An interval (lo, hi] with the chain's sign variations at its ends.
#[derive(Clone, Copy, Debug)]
pub(super) struct Bracket {
    lo: f64,
    hi: f64,
    vlo: usize,
    vhi: usize,
}

impl Bracket {
    pub(super) fn new<const S: usize>(seq: &SturmSequence<S>, lo: f64, hi: f64) -> Bracket {
        Bracket {
            lo,
            hi,
            vlo: seq.sign_variations(lo),
            vhi: seq.sign_variations(hi),
        }
    }

    pub(super) fn count(&self) -> usize {
        self.vlo.saturating_sub(self.vhi)
    }
}

/// Newton steps the warm start may take before it gives up on the guess.
const WARM_ITERATIONS: u32 = 20;

impl Solver {
    /// Depth-first bisection on counts, left half first so roots come out
    /// increasing. Every pending interval holds at least one root, so the
    /// stack never holds more than MAX_DEGREE of them.
    pub(super) fn isolate_all<const S: usize>(
        &self,
        search: &Search<S>,
        out: &mut [f64; MAX_DEGREE],
    ) -> usize {
        let seq = &search.seq;
        let whole = search.whole();
        let mut stack = [whole; S];
        let mut top = usize::from(whole.count() > 0);
        let mut n = 0;
        let mut unseparated = unreliable(seq);
        while top > 0 && n < S - 1 {
            top -= 1;
            let br = stack[top];
            let t = if br.count() == 1 {
                self.refine(search, br)
            } else if self.narrow(br.lo, br.hi) || top + 2 > stack.len() {
                unseparated = true;
                midpoint(br.lo, br.hi)
            } else {
                let (left, right) = split(seq, br, self.halve(br.lo, br.hi));
                for half in [right, left] {
                    if half.count() > 0 {
                        stack[top] = half;
                        top += 1;
                    }
                }
                continue;
            };
            if n == 0 || t > out[n - 1] {
                out[n] = t;
                n += 1;
            }
        }
        if unseparated {
            note_unseparated();
        }
        n
    }

    /// The nearest root in (a, b).
    pub(super) fn nearest_in<const S: usize>(
        &self,
        search: &Search<S>,
        a: f64,
        b: f64,
    ) -> Option<f64> {
        let seq = &search.seq;
        if unreliable(seq) {
            note_unseparated();
        }
        let mut br = search.whole();
        // A root exactly at b is counted in (lo, b] but is not in (a, b).
        let mut excluded = usize::from(search.root_at_end(b));
        loop {
            if br.count() <= excluded {
                return None;
            }
            if br.count() == 1 {
                return Some(strictly_inside(self.refine(search, br), a, b));
            }
            if self.narrow(br.lo, br.hi) {
                if !unreliable(seq) {
                    note_unseparated();
                }
                return Some(strictly_inside(midpoint(br.lo, br.hi), a, b));
            }
            let (left, right) = split(seq, br, self.halve(br.lo, br.hi));
            if left.count() > 0 {
                br = left;
                excluded = 0;
            } else {
                br = right;
            }
        }
    }

    /// Refines the one distinct root in (lo, hi]. Works on the square-free
    /// part, where every root is simple and changes sign; when the ends do
    /// not bracket a sign change (the root sits within round-off of an end,
    /// or an end is itself an excluded root) it halves by counts, which
    /// works for any multiplicity, until they do.
    ///
    /// When the chain counts a trimmed polynomial whose square-free part
    /// refines, that part's roots are the input's moved by up to the
    /// trimmed terms' size (9e-10 relative for t^3 (588.3 + 3t^2 - 3t^3 -
    /// 2.7e-10t^4) on (3.5, 6.5]), so a bracket across which the input
    /// itself changes sign is refined on the input instead.
    fn refine<const S: usize>(&self, search: &Search<S>, mut br: Bracket) -> f64 {
        let (seq, f) = (&search.seq, search.refine());
        for _ in 0..=self.max_iterations {
            if self.narrow(br.lo, br.hi) {
                break;
            }
            if let Some(input) = search.untrimmed() {
                let (ilo, ihi) = (input.eval(br.lo), input.eval(br.hi));
                if opposite(ilo, ihi) {
                    return self.refine_bracket(input, br.lo, br.hi, ilo, ihi, None);
                }
            }
            let (flo, fhi) = (f.eval(br.lo), f.eval(br.hi));
            if fhi == 0.0 {
                return br.hi;
            }
            if opposite(flo, fhi) {
                return self.refine_bracket(f, br.lo, br.hi, flo, fhi, None);
            }
            let (left, right) = split(seq, br, self.halve(br.lo, br.hi));
            br = if left.count() > 0 { left } else { right };
        }
        midpoint(br.lo, br.hi)
    }

    /// Refines a simple root of `f` in [lo, hi], where f(lo) and f(hi) have
    /// opposite signs; Newton begins at `start` when it lies in the bracket
    /// (a point a first pass found near the root), else in the middle.
    pub(super) fn refine_bracket<const S: usize>(
        &self,
        f: &PolyN<S>,
        lo: f64,
        hi: f64,
        flo: f64,
        fhi: f64,
        start: Option<f64>,
    ) -> f64 {
        match self.method {
            Method::SturmBisect => self.bisect(f, lo, hi, flo),
            // Yuksel never reaches the Sturm path; its pieces refine by Newton too.
            Method::SturmNewton | Method::Closed | Method::Yuksel => {
                let x = start
                    .filter(|&x| x > lo && x < hi)
                    .unwrap_or_else(|| self.halve(lo, hi));
                self.newton(f, lo, hi, flo, fhi, x)
            }
            Method::SturmIllinois => self.illinois(f, lo, hi, flo, fhi),
        }
    }

    fn bisect<const S: usize>(&self, f: &PolyN<S>, mut lo: f64, mut hi: f64, flo: f64) -> f64 {
        let lo_negative = flo < 0.0;
        for _ in 0..self.max_iterations {
            if self.narrow(lo, hi) {
                break;
            }
            let mid = self.halve(lo, hi);
            let fm = f.eval(mid);
            if fm == 0.0 {
                return mid;
            }
            if (fm < 0.0) == lo_negative {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        midpoint(lo, hi)
    }

    /// Newton from x inside the bracket (Numerical Recipes' rtsafe, with the
    /// bracket test from the tolerance): a step that leaves the bracket or
    /// is not at most half the previous one becomes a halving. Once a step
    /// is below half the tolerance the iterate is pushed half a tolerance
    /// past the root, so the next evaluation lands on the other side and
    /// the bracket, not just the step, proves the accuracy.
    pub(super) fn newton<const S: usize>(
        &self,
        f: &PolyN<S>,
        mut lo: f64,
        mut hi: f64,
        mut flo: f64,
        mut fhi: f64,
        mut x: f64,
    ) -> f64 {
        let lo_negative = flo < 0.0;
        let mut last_step = hi - lo;
        for _ in 0..self.max_iterations {
            let (fx, dfx) = f.eval_with_derivative(x);
            if fx == 0.0 {
                return x;
            }
            if (fx < 0.0) == lo_negative {
                (lo, flo) = (x, fx);
            } else {
                (hi, fhi) = (x, fx);
            }
            if self.narrow(lo, hi) {
                break;
            }
            let next = self.newton_next(x, fx / dfx, lo, hi, last_step);
            last_step = next - x;
            x = next;
        }
        closer_to_zero(lo, flo, hi, fhi)
    }

    fn newton_next(&self, x: f64, ratio: f64, lo: f64, hi: f64, last_step: f64) -> f64 {
        let next = x - ratio;
        if !(next > lo && next < hi) || 2.0 * ratio.abs() > last_step.abs() {
            return self.halve(lo, hi);
        }
        let half_tol = 0.5 * self.width_tol(lo, hi);
        if ratio.abs() >= half_tol {
            return next;
        }
        let pushed = next - half_tol.copysign(ratio);
        if pushed > lo && pushed < hi {
            pushed
        } else {
            next
        }
    }

    /// Regula falsi with the Illinois rule: when the same end survives two
    /// steps in a row its stored value is halved, which moves the next
    /// secant point past the root and restores superlinear convergence.
    /// Probes stay half a tolerance inside the bracket, so it closes from
    /// both sides.
    fn illinois<const S: usize>(
        &self,
        f: &PolyN<S>,
        mut lo: f64,
        mut hi: f64,
        mut flo: f64,
        mut fhi: f64,
    ) -> f64 {
        let lo_negative = flo < 0.0;
        let (mut wlo, mut whi) = (flo, fhi);
        let mut last_moved_lo: Option<bool> = None;
        for _ in 0..self.max_iterations {
            if self.narrow(lo, hi) {
                break;
            }
            let x = self.secant_point(lo, hi, wlo, whi);
            let fx = f.eval(x);
            if fx == 0.0 {
                return x;
            }
            let moved_lo = (fx < 0.0) == lo_negative;
            if moved_lo {
                (lo, flo, wlo) = (x, fx, fx);
            } else {
                (hi, fhi, whi) = (x, fx, fx);
            }
            match (last_moved_lo, moved_lo) {
                (Some(true), true) => whi *= 0.5,
                (Some(false), false) => wlo *= 0.5,
                _ => {}
            }
            last_moved_lo = Some(moved_lo);
        }
        // Secant steps can crawl from one end of a wide bracket (a steep
        // high-degree polynomial) and use up their steps far from the root:
        // bisection's steps always halve what is left.
        if !self.narrow(lo, hi) {
            return self.bisect(f, lo, hi, flo);
        }
        closer_to_zero(lo, flo, hi, fhi)
    }

    fn secant_point(&self, lo: f64, hi: f64, wlo: f64, whi: f64) -> f64 {
        let x = lo - wlo * ((hi - lo) / (whi - wlo));
        let x = if x > lo && x < hi {
            x
        } else {
            self.halve(lo, hi)
        };
        let half_tol = 0.5 * self.width_tol(lo, hi);
        x.max(lo + half_tol).min(hi - half_tol)
    }

    /// Plain Newton from the guess, abandoned as soon as it leaves (a, b),
    /// stalls or runs out of steps: the Sturm check afterwards decides.
    pub(super) fn warm_newton<const S: usize>(
        &self,
        f: &PolyN<S>,
        a: f64,
        b: f64,
        guess: f64,
    ) -> Option<f64> {
        if !(guess > a && guess < b) {
            return None;
        }
        let mut x = guess;
        for _ in 0..self.max_iterations.min(WARM_ITERATIONS) {
            let (fx, dfx) = f.eval_with_derivative(x);
            if fx == 0.0 {
                return Some(x);
            }
            let step = fx / dfx;
            x -= step;
            if !(x > a && x < b) {
                return None;
            }
            if step.abs() <= 0.5 * self.width_tol(x, x) {
                return Some(x);
            }
        }
        None
    }

    /// Whether Sturm counts show a root within the tolerance of `t` and
    /// none in (a, t - tolerance].
    pub(super) fn proves_nearest<const S: usize>(
        &self,
        search: &Search<S>,
        a: f64,
        b: f64,
        t: f64,
    ) -> bool {
        let seq = &search.seq;
        let delta = self.width_tol(t, t);
        let lo = (t - delta).max(a);
        let hi = (t + delta).min(b);
        let near = Bracket::new(seq, lo, hi);
        let none_before = lo <= a || seq.sign_variations(a) == near.vlo;
        let excluded = hi == b && search.refine().eval(b) == 0.0;
        none_before && near.count() > usize::from(excluded)
    }

    /// Where to halve [lo, hi]: the midpoint, unless the bracket is too wide
    /// for halvings to reach the tolerance within the step limit (a search
    /// of (0, inf) clipped to a root bound of 1e100, say). Then the
    /// midpoint of the ends' bit patterns, which halves the number of f64
    /// values between them, so that some 64 halvings reach any root.
    pub(super) fn halve(&self, lo: f64, hi: f64) -> f64 {
        if hi - lo <= WIDE_BRACKET * self.width_tol(lo, hi) {
            midpoint(lo, hi)
        } else {
            bit_midpoint(lo, hi)
        }
    }

    /// The largest bracket width accepted around a root in [lo, hi].
    pub(super) fn width_tol(&self, lo: f64, hi: f64) -> f64 {
        self.tolerance * lo.abs().min(hi.abs()).max(1.0)
    }

    /// Whether [lo, hi] is within the tolerance, or has no f64 strictly
    /// inside left to try.
    fn narrow(&self, lo: f64, hi: f64) -> bool {
        let mid = midpoint(lo, hi);
        let wide = hi - lo > self.width_tol(lo, hi);
        let room = mid > lo && mid < hi;
        !(wide && room)
    }
}

/// Splits at `mid`, with one more chain evaluation.
fn split<const S: usize>(seq: &SturmSequence<S>, br: Bracket, mid: f64) -> (Bracket, Bracket) {
    let vm = seq.sign_variations(mid);
    (
        Bracket {
            hi: mid,
            vhi: vm,
            ..br
        },
        Bracket {
            lo: mid,
            vlo: vm,
            ..br
        },
    )
}

/// The end of the final bracket where |f| is smaller: the last iterate of a
/// converging method, and within the bracket's width of the root either way.
fn closer_to_zero(lo: f64, flo: f64, hi: f64, fhi: f64) -> f64 {
    if flo.abs() <= fhi.abs() { lo } else { hi }
}
