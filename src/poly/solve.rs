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

use std::fmt;
use std::str::FromStr;

use crate::poly::MAX_DEGREE;
use crate::poly::closed;
use crate::poly::exact::{Isolation, Relative};
use crate::poly::sturm::SturmSequence;
use crate::poly::univariate::{Poly, normalize_pow2};

/// How an isolated root is refined. Names are stable: the CLI, `accuracy`
/// and `bench` use them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Method {
    /// Interval halving: one bit per step, never fails.
    SturmBisect,
    /// Newton's method kept inside the bracket, halving when a step leaves
    /// it or does not shrink fast enough.
    SturmNewton,
    /// Regula falsi with the Illinois modification (halve the stale end's
    /// value), so both ends of the bracket move.
    SturmIllinois,
    /// The closed forms of [`crate::poly::closed`] for degree <= 4 (a
    /// comparison method: they decide double roots by a discriminant's sign);
    /// sturm-newton above degree 4.
    Closed,
    /// Yuksel's derivative intervals ("High-Performance Polynomial Root
    /// Finding for Graphics", HPG 2022), no Sturm chain: the roots of p'
    /// cut the interval into pieces where p is monotonic, so each holds at
    /// most one root, refined by bracketed Newton where p changes sign; the
    /// roots of p' come the same way from p'', down to a quadratic solved
    /// in closed form. A root of even multiplicity (no sign change, as at a
    /// tangent) is found only where p evaluates to exactly 0.
    Yuksel,
}

impl Method {
    pub const ALL: &'static [Method] = &[
        Method::SturmBisect,
        Method::SturmNewton,
        Method::SturmIllinois,
        Method::Closed,
        Method::Yuksel,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Method::SturmBisect => "sturm-bisect",
            Method::SturmNewton => "sturm-newton",
            Method::SturmIllinois => "sturm-illinois",
            Method::Closed => "closed",
            Method::Yuksel => "yuksel",
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Method {
    type Err = String;

    fn from_str(s: &str) -> Result<Method, String> {
        Method::ALL
            .iter()
            .copied()
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
                format!(
                    "unknown root-finding method {s:?}: expected one of {}",
                    names.join(", ")
                )
            })
    }
}

/// A root finder: the refinement method, the tolerance (see the module
/// docs) and a cap on refinement steps per root, which bounds the time per
/// ray whatever the input.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Solver {
    pub method: Method,
    pub tolerance: f64,
    pub max_iterations: u32,
}

impl Default for Solver {
    /// Sturm + Newton at 1e-12; 100 steps is more than bisection needs to
    /// shrink any bracket within the root bound to 1e-12 relative.
    fn default() -> Self {
        Solver {
            method: Method::SturmNewton,
            tolerance: 1e-12,
            max_iterations: 100,
        }
    }
}

/// An interval (lo, hi] with the chain's sign variations at its ends.
#[derive(Clone, Copy, Debug)]
struct Bracket {
    lo: f64,
    hi: f64,
    vlo: usize,
    vhi: usize,
}

impl Bracket {
    fn new(seq: &SturmSequence, lo: f64, hi: f64) -> Bracket {
        Bracket {
            lo,
            hi,
            vlo: seq.sign_variations(lo),
            vhi: seq.sign_variations(hi),
        }
    }

    fn count(&self) -> usize {
        self.vlo.saturating_sub(self.vhi)
    }
}

/// Newton steps the warm start may take before it gives up on the guess.
const WARM_ITERATIONS: u32 = 20;

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
    /// coefficients, increasing, with the proof the `roots` tool promises:
    /// the list is as long as the exact count, and each value is within the
    /// tolerance *relative to its magnitude* of its own exact root
    /// ([`Relative::Magnitude`]: a root of 1e-14 is not answered with
    /// 1.4e-14, as the renderer's absolute tolerance below 1 would allow).
    /// The f64 answer of this solver's method (on the coefficients scaled by
    /// a power of two, which keeps the roots and spares f64 needless
    /// overflow and underflow) is kept when [`Isolation::certifies`] it;
    /// otherwise the exact path answers, one value per root, never merged
    /// (roots closer than f64 resolution come out as one value repeated, and
    /// a root f64 cannot hold to the tolerance, such as a subnormal one, as
    /// its correctly rounded value). None if a coefficient or the tolerance
    /// is not finite, or an end is NaN.
    pub fn certified_roots(&self, coeffs: &[f64], a: f64, b: f64) -> Option<Vec<f64>> {
        if coeffs.len() > MAX_DEGREE + 1 || !self.tolerance.is_finite() {
            return None;
        }
        let isolation = Isolation::new(coeffs, a, b)?;
        let mut scaled = [0.0; MAX_DEGREE + 1];
        scaled[..coeffs.len()].copy_from_slice(coeffs);
        normalize_pow2(&mut scaled);
        let p = Poly::new(&scaled[..coeffs.len()]);
        let mut out = [0.0; MAX_DEGREE];
        let n = self.unproven_roots(&p, a, b, &mut out);
        if isolation.certifies(&out[..n], self.tolerance, Relative::Magnitude) {
            return Some(out[..n].to_vec());
        }
        isolation.roots(self.tolerance, Relative::Magnitude)
    }

    /// The f64 roots in (a, b], unproven: from the closed forms or
    /// Yuksel's method where they apply, else from the Sturm chain.
    fn unproven_roots(&self, p: &Poly, a: f64, b: f64, out: &mut [f64; MAX_DEGREE]) -> usize {
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
    pub fn nearest(&self, p: &Poly, a: f64, b: f64) -> Option<f64> {
        if !is_interval(a, b) {
            return None;
        }
        if let Some(found) = self.direct_roots(p, a, b, a) {
            return found.iter().copied().find(|&t| t > a && t < b);
        }
        let mut search = Search::EMPTY;
        if !search.prepare(p, a, b) {
            return None;
        }
        self.nearest_in(&search, a, b)
    }

    /// Whether any root lies in (a, b): for shadow rays. Counts only, never
    /// refines; a sign change between the ends answers before the chain is
    /// even built. `Closed` answers from the closed-form roots instead.
    pub fn any(&self, p: &Poly, a: f64, b: f64) -> bool {
        if !is_interval(a, b) {
            return false;
        }
        if let Some(found) = self.direct_roots(p, a, b, a) {
            return found.iter().any(|&t| t > a && t < b);
        }
        if a.is_finite() && b.is_finite() && opposite(p.eval(a), p.eval(b)) {
            return true;
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
        if !is_interval(a, b) {
            return None;
        }
        if matches!(self.method, Method::Closed | Method::Yuksel) && self.direct(p) {
            return self.nearest(p, a, b);
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

    /// Whether this method solves `p` without a Sturm chain: `Closed` up to
    /// degree 4, `Yuksel` always.
    fn direct(&self, p: &Poly) -> bool {
        match self.method {
            Method::Closed => p.degree() <= 4,
            Method::Yuksel => true,
            _ => false,
        }
    }

    /// The roots (increasing) from the closed forms or Yuksel's derivative
    /// intervals when the method and degree call for them; `None` sends the
    /// caller down the Sturm path. Terms below one rounding on the interval
    /// are dropped first, as on the Sturm path: a formula divides by the
    /// leading coefficient. Yuksel's method stops after the first root above
    /// `after` (the closed forms find all at once).
    fn direct_roots(&self, p: &Poly, a: f64, b: f64, after: f64) -> Option<DirectRoots> {
        if !self.direct(p) {
            return None;
        }
        let mut found = DirectRoots::default();
        let Some((lo, hi)) = clip_to_root_bound(p, a, b) else {
            return Some(found);
        };
        let degree = negligible_above(p, lo.abs().max(hi.abs()), f64::EPSILON);
        let p = Poly::new(&p.coeffs()[..=degree]);
        if self.method == Method::Yuksel {
            self.derivative_intervals(&p, lo, hi, after, &mut found);
            return Some(found);
        }
        let mut c = [0.0; 5];
        c[..=p.degree()].copy_from_slice(p.coeffs());
        let mut roots = [0.0; 4];
        let n = match p.degree() {
            0 => 0,
            1 | 2 => closed::quadratic(c[0], c[1], c[2], &mut roots),
            3 => closed::cubic([c[0], c[1], c[2], c[3]], &mut roots),
            _ => closed::quartic(c, &mut roots),
        };
        roots[..n].iter().for_each(|&t| found.push(t));
        Some(found)
    }

    /// Yuksel's method on [lo, hi]: the roots of p there, increasing,
    /// stopping after the first above `after`. The derivatives p^(k) are
    /// formed down to degree 2, whose roots the quadratic formula gives;
    /// then each level's roots are the sign changes of p^(k) between the
    /// roots of p^(k+1), where it is monotonic.
    fn derivative_intervals(&self, p: &Poly, lo: f64, hi: f64, after: f64, out: &mut DirectRoots) {
        let deepest = p.degree().saturating_sub(2);
        let mut chain = [Poly::ZERO; MAX_DEGREE + 1];
        chain[0] = *p;
        for k in 1..=deepest {
            chain[k] = chain[k - 1].derivative();
        }
        let mut roots = [0.0; 4];
        let c = |k: usize| chain[deepest].coeffs().get(k).copied().unwrap_or(0.0);
        let n = closed::quadratic(c(0), c(1), c(2), &mut roots);
        let mut critical = DirectRoots::default();
        for &t in roots[..n].iter().filter(|&&t| t >= lo && t <= hi) {
            critical.push(t);
        }
        for k in (0..deepest).rev() {
            let mut next = DirectRoots::default();
            let stop = if k == 0 { after } else { f64::INFINITY };
            self.monotonic_pieces(&chain[k], lo, hi, &critical, stop, &mut next);
            critical = next;
        }
        *out = critical;
    }

    /// The roots of f in [lo, hi], where f is monotonic between consecutive
    /// `critical` points: one per piece whose ends have opposite signs, or
    /// an end where f is exactly 0. Stops after the first root above `after`.
    fn monotonic_pieces(
        &self,
        f: &Poly,
        lo: f64,
        hi: f64,
        critical: &DirectRoots,
        after: f64,
        out: &mut DirectRoots,
    ) {
        let (mut x0, mut f0) = (lo, f.eval(lo));
        for &x1 in critical.iter().chain(std::iter::once(&hi)) {
            if x1 <= x0 {
                continue;
            }
            let f1 = f.eval(x1);
            if f0 == 0.0 {
                out.push(x0);
            } else if opposite(f0, f1) {
                out.push(self.newton(f, x0, x1, f0, f1));
            }
            if out.last().is_some_and(|t| t > after) {
                return;
            }
            (x0, f0) = (x1, f1);
        }
        if f0 == 0.0 {
            out.push(x0);
        }
    }

    /// Roots found without the f64 Sturm chain that lie in (a, b], those
    /// closer than the tolerance to the previous one merged into it, as the
    /// Sturm path would report them.
    fn roots_in(&self, found: &DirectRoots, a: f64, b: f64, out: &mut [f64; MAX_DEGREE]) -> usize {
        let mut n = 0;
        for &t in found.iter() {
            if t > a && t <= b && (n == 0 || t - out[n - 1] > self.width_tol(out[n - 1], t)) {
                out[n] = t;
                n += 1;
            }
        }
        n
    }

    /// Depth-first bisection on counts, left half first so roots come out
    /// increasing. Every pending interval holds at least one root, so the
    /// stack never holds more than MAX_DEGREE of them.
    fn isolate_all(&self, search: &Search, out: &mut [f64; MAX_DEGREE]) -> usize {
        let seq = &search.seq;
        let whole = search.whole();
        let mut stack = [whole; MAX_DEGREE + 1];
        let mut top = usize::from(whole.count() > 0);
        let mut n = 0;
        while top > 0 && n < MAX_DEGREE {
            top -= 1;
            let br = stack[top];
            let t = if br.count() == 1 {
                self.refine(search, br)
            } else if self.narrow(br.lo, br.hi) || top + 2 > stack.len() {
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
        n
    }

    /// The nearest root in (a, b).
    fn nearest_in(&self, search: &Search, a: f64, b: f64) -> Option<f64> {
        let seq = &search.seq;
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
    fn refine(&self, search: &Search, mut br: Bracket) -> f64 {
        let (seq, f) = (&search.seq, search.refine());
        for _ in 0..=self.max_iterations {
            if self.narrow(br.lo, br.hi) {
                break;
            }
            if let Some(input) = search.untrimmed() {
                let (ilo, ihi) = (input.eval(br.lo), input.eval(br.hi));
                if opposite(ilo, ihi) {
                    return self.refine_bracket(input, br.lo, br.hi, ilo, ihi);
                }
            }
            let (flo, fhi) = (f.eval(br.lo), f.eval(br.hi));
            if fhi == 0.0 {
                return br.hi;
            }
            if opposite(flo, fhi) {
                return self.refine_bracket(f, br.lo, br.hi, flo, fhi);
            }
            let (left, right) = split(seq, br, self.halve(br.lo, br.hi));
            br = if left.count() > 0 { left } else { right };
        }
        midpoint(br.lo, br.hi)
    }

    /// Refines a simple root of `f` in [lo, hi], where f(lo) and f(hi) have
    /// opposite signs.
    fn refine_bracket(&self, f: &Poly, lo: f64, hi: f64, flo: f64, fhi: f64) -> f64 {
        match self.method {
            Method::SturmBisect => self.bisect(f, lo, hi, flo),
            // Yuksel never reaches the Sturm path; its pieces refine by Newton too.
            Method::SturmNewton | Method::Closed | Method::Yuksel => {
                self.newton(f, lo, hi, flo, fhi)
            }
            Method::SturmIllinois => self.illinois(f, lo, hi, flo, fhi),
        }
    }

    fn bisect(&self, f: &Poly, mut lo: f64, mut hi: f64, flo: f64) -> f64 {
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

    /// Newton inside the bracket (Numerical Recipes' rtsafe, with the
    /// bracket test from the tolerance): a step that leaves the bracket or
    /// is not at most half the previous one becomes a halving. Once a step
    /// is below half the tolerance the iterate is pushed half a tolerance
    /// past the root, so the next evaluation lands on the other side and
    /// the bracket, not just the step, proves the accuracy.
    fn newton(&self, f: &Poly, mut lo: f64, mut hi: f64, mut flo: f64, mut fhi: f64) -> f64 {
        let lo_negative = flo < 0.0;
        let mut x = self.halve(lo, hi);
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
    fn illinois(&self, f: &Poly, mut lo: f64, mut hi: f64, mut flo: f64, mut fhi: f64) -> f64 {
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
    fn warm_newton(&self, f: &Poly, a: f64, b: f64, guess: f64) -> Option<f64> {
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
    fn proves_nearest(&self, search: &Search, a: f64, b: f64, t: f64) -> bool {
        let seq = &search.seq;
        let delta = self.width_tol(t, t);
        let lo = (t - delta).max(a);
        let hi = (t + delta).min(b);
        let near = Bracket::new(seq, lo, hi);
        let none_before = lo <= a || seq.sign_variations(a) == near.vlo;
        let excluded = hi == b && search.refine().eval(b) == 0.0;
        none_before && near.count() > usize::from(excluded)
    }

    /// The largest bracket width accepted around a root in [lo, hi].
    /// Where to halve [lo, hi]: the midpoint, unless the bracket is too wide
    /// for halvings to reach the tolerance within the step limit (a search
    /// of (0, inf) clipped to a root bound of 1e100, say). Then the
    /// midpoint of the ends' bit patterns, which halves the number of f64
    /// values between them, so that some 64 halvings reach any root.
    fn halve(&self, lo: f64, hi: f64) -> f64 {
        if hi - lo <= WIDE_BRACKET * self.width_tol(lo, hi) {
            midpoint(lo, hi)
        } else {
            bit_midpoint(lo, hi)
        }
    }

    fn width_tol(&self, lo: f64, hi: f64) -> f64 {
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

/// Roots found without the f64 Sturm chain (closed forms, derivative
/// intervals, the exact path), increasing; one of equal neighbours kept.
#[derive(Clone, Copy, Debug, Default)]
struct DirectRoots {
    roots: [f64; MAX_DEGREE],
    len: usize,
}

impl DirectRoots {
    fn iter(&self) -> impl Iterator<Item = &f64> {
        self.roots[..self.len].iter()
    }

    fn last(&self) -> Option<f64> {
        self.len.checked_sub(1).map(|i| self.roots[i])
    }

    /// Appends t if it is above the last root (a polynomial of degree n has
    /// at most n, so storage cannot run out for degree <= MAX_DEGREE).
    fn push(&mut self, t: f64) {
        if self.last().is_none_or(|last| t > last) && self.len < MAX_DEGREE {
            self.roots[self.len] = t;
            self.len += 1;
        }
    }
}

/// What a query searches: the chain that counts, the polynomial that
/// refines, and the part of (a, b] that can hold roots.
struct Search {
    seq: SturmSequence,
    /// The input's square-free part (the input, normalised, unless its own
    /// chain found a common factor), kept when the chain counts a trimmed
    /// version of the input (`trimmed`).
    input: Poly,
    trimmed: bool,
    lo: f64,
    hi: f64,
}

/// Terms this small relative to others on the interval (see
/// [`without_negligible_terms`]) are dropped before counting, but only when
/// the full chain degenerated. A tiny
/// leading coefficient (a ray close to an asymptotic direction of the
/// surface) leaves the chain's last remainders at the size of that
/// coefficient, below their round-off from about 1e-12 relative on; a tiny
/// coefficient inside (one that is zero in exact arithmetic, say, but not
/// after rounding) gives some remainder such a leading coefficient: the
/// chain of -144.2 + 735.2t^2 - 5t^3 - 5.3e-10t^4 - 606.9t^6 counts no root
/// in (-2.5, -0.5] for the one at -0.9948. The count then comes from the
/// trimmed polynomial, whose roots in the interval are the input's moved by
/// at most this fraction of its scale, and refinement runs on the input
/// wherever the input changes sign.
const DEGENERATE_TRIM: f64 = 1e-8;

impl Search {
    /// Storage for [`Search::prepare`]: a chain is some 5 KB, so queries
    /// build it in place on their own stack instead of returning it.
    const EMPTY: Search = Search {
        seq: SturmSequence::EMPTY,
        input: Poly::ZERO,
        trimmed: false,
        lo: 0.0,
        hi: 0.0,
    };

    /// Sets up the search of (a, b] for roots of `p`; false if no root can
    /// lie there (or `p` is constant).
    fn prepare(&mut self, p: &Poly, a: f64, b: f64) -> bool {
        let Some((lo, hi)) = clip_to_root_bound(p, a, b) else {
            return false;
        };
        (self.lo, self.hi) = (lo, hi);
        let t_max = lo.abs().max(hi.abs());
        // Terms below one rounding of the largest are noise whatever happens.
        let degree = negligible_above(p, t_max, f64::EPSILON);
        self.seq.rebuild(p, degree);
        self.trimmed = false;
        if self.seq.is_degenerate() {
            let trimmed = without_negligible_terms(p, t_max, DEGENERATE_TRIM);
            if trimmed != Poly::new(&p.coeffs()[..=degree]) {
                self.input = *self.seq.squarefree();
                self.seq.rebuild(&trimmed, trimmed.degree());
                self.trimmed = true;
            }
        }
        true
    }

    /// The polynomial whose sign changes refine roots: the input's
    /// square-free part if the chain counts a trimmed input without finding
    /// multiple roots, the chain's own square-free part otherwise.
    fn refine(&self) -> &Poly {
        if self.trimmed && self.seq.gcd().degree() == 0 {
            &self.input
        } else {
            self.seq.squarefree()
        }
    }

    /// The input's square-free part, where [`Search::refine`] is the
    /// trimmed one's: the better polynomial wherever it changes sign.
    fn untrimmed(&self) -> Option<&Poly> {
        (self.trimmed && self.seq.gcd().degree() > 0).then_some(&self.input)
    }

    fn whole(&self) -> Bracket {
        Bracket::new(&self.seq, self.lo, self.hi)
    }

    /// Whether the search ends at the caller's `b` and `b` is an exact
    /// root, which the open queries exclude.
    fn root_at_end(&self, b: f64) -> bool {
        self.hi == b && self.refine().eval(b) == 0.0
    }
}

/// Splits at `mid`, with one more chain evaluation.
fn split(seq: &SturmSequence, br: Bracket, mid: f64) -> (Bracket, Bracket) {
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

/// (a, b) narrowed to Cauchy's bound, |t| < 1 + max |c_i / c_n| for every
/// root, so bisection starts from finite ends; `None` if nothing is left or
/// the polynomial is constant (no isolated roots).
fn clip_to_root_bound(p: &Poly, a: f64, b: f64) -> Option<(f64, f64)> {
    let (lead, rest) = p.coeffs().split_last()?;
    if rest.is_empty() {
        return None;
    }
    let max_rest = rest.iter().fold(0.0, |m: f64, c| m.max(c.abs()));
    let bound = (2.0 + max_rest / lead.abs() * (1.0 + 1e-9)).min(f64::MAX);
    let (lo, hi) = (a.max(-bound), b.min(bound));
    (lo < hi).then_some((lo, hi))
}

/// The degree of `p` without the leading terms that stay below `rel` times
/// its largest term everywhere in |t| <= `t_max`. Such a term moves roots
/// inside the interval by no more than its size, and its own roots lie far
/// outside. Unlike [`Poly::trimmed`] this judges terms where they are
/// evaluated, so it never drops a small leading coefficient that matters on
/// a wide interval.
fn negligible_above(p: &Poly, t_max: f64, rel: f64) -> usize {
    let mut terms = [0.0; MAX_DEGREE + 1];
    let mut power = 1.0;
    for (term, ci) in terms.iter_mut().zip(p.coeffs()) {
        *term = ci.abs() * power;
        power *= t_max;
    }
    // Against the lower terms only: a term that overflows to infinity at
    // t_max must not make every other term look negligible.
    let mut degree = p.degree();
    while degree > 0 {
        let rest = terms[..degree].iter().fold(0.0, |m: f64, x| m.max(*x));
        if terms[degree] > rel * rest {
            break;
        }
        degree -= 1;
    }
    degree
}

/// `p` without the terms that stay below `rel` times some other term
/// everywhere in 0 < |t| <= `t_max`: leading terms as in
/// [`negligible_above`], and a term c_i t^i inside when a lower term c_j t^j
/// and a higher one c_k t^k keep it that small between them (the smaller
/// of the two ratios peaks where the two terms are equal, or at `t_max`).
/// A term small only against the largest term at `t_max` is kept: near
/// t = 0 it may decide where the roots are.
fn without_negligible_terms(p: &Poly, t_max: f64, rel: f64) -> Poly {
    let degree = negligible_above(p, t_max, rel);
    let c = p.coeffs();
    let mut out = [0.0; MAX_DEGREE + 1];
    out[..=degree].copy_from_slice(&c[..=degree]);
    // In logarithms: the sizes may span hundreds of orders of magnitude,
    // and a power that underflowed to 0 would make any term look dominated.
    let log_size = |i: usize| c[i].abs().ln();
    let (log_t_max, log_rel) = (t_max.ln(), rel.ln());
    for (i, slot) in out.iter_mut().enumerate().take(degree).skip(1) {
        let dominated = (0..i).any(|j| {
            (i + 1..=degree).any(|k| {
                if c[j] == 0.0 || c[k] == 0.0 {
                    return false;
                }
                let log_cross = ((log_size(j) - log_size(k)) / (k - j) as f64).min(log_t_max);
                log_size(i) + (i - j) as f64 * log_cross <= log_rel + log_size(j)
            })
        });
        if dominated {
            *slot = 0.0;
        }
    }
    Poly::from_array(out, degree)
}

/// Whether (a, b) is a non-empty interval; false for NaN ends.
fn is_interval(a: f64, b: f64) -> bool {
    a < b
}

fn opposite(x: f64, y: f64) -> bool {
    (x < 0.0 && y > 0.0) || (x > 0.0 && y < 0.0)
}

fn midpoint(lo: f64, hi: f64) -> f64 {
    0.5 * lo + 0.5 * hi
}

/// Brackets wider than this many tolerances are halved by [`bit_midpoint`]:
/// 2^60 takes 60 halvings, well within the default 100 steps.
const WIDE_BRACKET: f64 = (1u64 << 60) as f64;

/// The f64 halfway between lo < hi in the order of f64 values: 0 when the
/// bracket holds it, else the mean of the magnitudes' bit patterns (which
/// grow with the magnitude for non-negative floats).
fn bit_midpoint(lo: f64, hi: f64) -> f64 {
    if lo < 0.0 && hi > 0.0 {
        0.0
    } else if hi <= 0.0 {
        -bit_midpoint(-hi, -lo)
    } else {
        f64::from_bits((lo.abs().to_bits() + hi.to_bits()) / 2)
    }
}

/// The end of the final bracket where |f| is smaller: the last iterate of a
/// converging method, and within the bracket's width of the root either way.
fn closer_to_zero(lo: f64, flo: f64, hi: f64, fhi: f64) -> f64 {
    if flo.abs() <= fhi.abs() { lo } else { hi }
}

/// `t` moved, if needed, to the nearest f64 strictly inside (a, b): a root
/// within tolerance of an end may be refined onto it, and callers compare
/// hits against the open interval.
fn strictly_inside(t: f64, a: f64, b: f64) -> f64 {
    if t <= a {
        above(a).min(midpoint(a, b))
    } else if t >= b {
        below(b).max(midpoint(a, b))
    } else {
        t
    }
}

/// The next f64 above `x`, skipping subnormals: a thread with DAZ set reads
/// them as zero, so "just above 0" must be the smallest normal. Only
/// comparisons with normal numbers decide, so both modes agree.
fn above(x: f64) -> f64 {
    let near_zero = (-f64::MIN_POSITIVE..f64::MIN_POSITIVE).contains(&x);
    if !near_zero {
        x.next_up()
    } else if x < 0.0 {
        0.0
    } else {
        f64::MIN_POSITIVE
    }
}

fn below(x: f64) -> f64 {
    -above(-x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::poly::exact::{exact_count, exact_roots};
    use crate::poly::univariate::from_roots;
    use proptest::prelude::*;

    const STURM: [Method; 3] = [
        Method::SturmBisect,
        Method::SturmNewton,
        Method::SturmIllinois,
    ];

    fn solver(method: Method) -> Solver {
        Solver {
            method,
            ..Solver::default()
        }
    }

    fn roots_of(s: &Solver, p: &Poly, a: f64, b: f64) -> Vec<f64> {
        let mut out = [0.0; MAX_DEGREE];
        let n = s.roots(p, a, b, &mut out);
        out[..n].to_vec()
    }

    /// Asserts `got` matches the constructed roots `want` one for one, each
    /// within `tol * max(1, |root|)`.
    #[track_caller]
    fn assert_near(got: &[f64], want: &[f64], tol: f64) {
        assert_eq!(got.len(), want.len(), "got {got:?}, want {want:?}");
        for (g, w) in got.iter().zip(want) {
            assert!(
                (g - w).abs() <= tol * w.abs().max(1.0),
                "got {got:?}, want {want:?}"
            );
        }
    }

    #[test]
    fn worked_examples_roots() {
        for m in Method::ALL {
            let s = solver(*m);
            assert_near(
                &roots_of(&s, &Poly::new(&[-1.0, 0.0, 1.0]), -2.0, 2.0),
                &[-1.0, 1.0],
                1e-12,
            );
            assert_near(
                &roots_of(&s, &Poly::new(&[0.0, -1.0, 0.0, 1.0]), -2.0, 2.0),
                &[-1.0, 0.0, 1.0],
                1e-12,
            );
        }
        for m in STURM {
            let t4_t2 = Poly::new(&[0.0, 0.0, -1.0, 0.0, 1.0]);
            assert_near(
                &roots_of(&solver(m), &t4_t2, -2.0, 2.0),
                &[-1.0, 0.0, 1.0],
                1e-12,
            );
        }
    }

    #[test]
    fn repeated_roots_are_found_once_to_tolerance() {
        let cases: [(&[f64], &[f64]); 6] = [
            (&[1.0, 1.0], &[1.0]),
            (&[1.0, 1.0, 1.0], &[1.0]),
            (&[1.0, 1.0, 2.0], &[1.0, 2.0]),
            (&[-1.0, 0.0, 0.0, 1.0], &[-1.0, 0.0, 1.0]),
            (&[0.5, 0.5, 0.5, 0.5, -1.25], &[-1.25, 0.5]),
            (&[3.0, 3.0, -0.75, -0.75, -0.75], &[-0.75, 3.0]),
        ];
        for m in STURM {
            for (built, distinct) in cases {
                let p = from_roots(1.0, built);
                let got = roots_of(&solver(m), &p, -2.0, 4.0);
                assert_near(&got, distinct, 1e-12);
                let seq = SturmSequence::new(&p);
                assert_eq!(seq.count(-2.0, 4.0), distinct.len(), "{built:?}");
            }
        }
    }

    #[test]
    fn repeated_roots_with_rounded_coefficients() {
        // Not exactly representable: the f64 polynomial's own roots moved by
        // up to eps^(1/k) for multiplicity k, a double root split into two
        // simple ones or none. The f64 chain cannot tell, so `roots` reports
        // the exact path's answer for the f64 polynomial.
        let cases: [(&[f64], &[f64]); 3] = [
            (&[0.1, 0.1, 0.3], &[0.1, 0.3]),
            (&[0.7, 0.7, 0.7], &[0.7]),
            (&[-1.3, -1.3, 0.2, 2.9, 2.9], &[-1.3, 0.2, 2.9]),
        ];
        for m in STURM {
            for (built, distinct) in cases {
                let p = from_roots(1.0, built);
                let got = roots_of(&solver(m), &p, -2.0, 4.0);
                let exact = exact_roots(p.coeffs(), -2.0, 4.0, 0.0).unwrap();
                assert_near(&got, &exact, 1e-12);
                for g in got {
                    assert!(distinct.iter().any(|d| (g - d).abs() < 1e-5), "{g}");
                }
            }
        }
    }

    #[test]
    fn nearest_and_any_see_double_roots() {
        // A tangent ray: (t - 2)^2, no sign change anywhere.
        let p = from_roots(3.0, &[2.0, 2.0]);
        for m in STURM {
            let s = solver(m);
            let near = s.nearest(&p, 0.0, 5.0).unwrap();
            assert!((near - 2.0).abs() <= 2e-12, "{m}: {near}");
            assert!(s.any(&p, 0.0, 5.0));
            assert!(!s.any(&p, 0.0, 2.0));
            assert_eq!(s.nearest(&p, 2.0, 5.0), None);
        }
    }

    #[test]
    fn clustered_roots() {
        let ten: Vec<f64> = (1..=10).map(f64::from).collect();
        let p = from_roots(1.0, &ten);
        let pair = from_roots(1.0, &[1.0 - 1e-6, 1.0 + 1e-6]);
        let triple = from_roots(-2.0, &[1.0 - 1e-6, 1.0 + 1e-6, 3.0]);
        for m in STURM {
            let s = solver(m);
            assert_near(&roots_of(&s, &p, 0.0, 11.0), &ten, 1e-8);
            assert_near(
                &roots_of(&s, &pair, 0.0, 2.0),
                &[1.0 - 1e-6, 1.0 + 1e-6],
                1e-9,
            );
            assert_near(
                &roots_of(&s, &triple, 0.0, 4.0),
                &[1.0 - 1e-6, 1.0 + 1e-6, 3.0],
                1e-9,
            );
            let near = s.nearest(&pair, 0.0, 2.0).unwrap();
            assert!((near - (1.0 - 1e-6)).abs() < 1e-9, "{m}: {near}");
            let near = s.nearest(&p, 4.5, 20.0).unwrap();
            assert!((near - 5.0).abs() < 1e-8, "{m}: {near}");
        }
    }

    #[test]
    fn root_at_an_interval_end() {
        let p = from_roots(1.0, &[1.0, 2.0]);
        for m in Method::ALL {
            let s = solver(*m);
            assert_eq!(
                roots_of(&s, &p, 1.0, 2.0),
                vec![2.0],
                "{m}: (a, b] holds b, not a"
            );
            assert_eq!(roots_of(&s, &p, 0.0, 1.0), vec![1.0], "{m}");
            assert_eq!(
                s.nearest(&p, 1.0, 2.0),
                None,
                "{m}: (a, b) holds neither end"
            );
            assert_eq!(s.nearest(&p, 1.0, 3.0), Some(2.0), "{m}");
            assert_eq!(s.nearest(&p, 0.0, 2.0), Some(1.0), "{m}");
            assert!(!s.any(&p, 1.0, 2.0), "{m}");
            assert!(!s.any(&p, 0.0, 1.0), "{m}");
            assert!(s.any(&p, 0.0, 1.5), "{m}");
            assert!(s.any(&p, 1.0, 2.5), "{m}");
        }
    }

    #[test]
    fn ray_starting_on_the_surface_skips_its_own_root() {
        // Roots 0 (the ray's origin) and 3: t^2 - 3t.
        let p = Poly::new(&[0.0, -3.0, 1.0]);
        for m in Method::ALL {
            let s = solver(*m);
            let near = s.nearest(&p, 0.0, 10.0).unwrap();
            assert!((near - 3.0).abs() < 1e-12, "{m}: {near}");
            assert!(!s.any(&p, 0.0, 2.0), "{m}");
            let near = s.nearest_from(&p, 0.0, 10.0, 1e-3).unwrap();
            assert!((near - 3.0).abs() < 1e-12, "{m}: {near}");
        }
    }

    #[test]
    fn no_roots_in_the_interval() {
        let none = [
            (Poly::new(&[1.0, 0.0, 1.0]), -10.0, 10.0),
            (from_roots(1.0, &[5.0, 6.0]), 0.0, 4.0),
            (from_roots(1.0, &[-1.0, 1.0, 2.0, 3.0]), 1.1, 1.9),
            (Poly::new(&[4.0]), -1.0, 1.0),
            (Poly::ZERO, -1.0, 1.0),
        ];
        for m in Method::ALL {
            let s = solver(*m);
            for (p, a, b) in &none {
                assert!(roots_of(&s, p, *a, *b).is_empty(), "{m}: {p:?}");
                assert_eq!(s.nearest(p, *a, *b), None, "{m}: {p:?}");
                assert_eq!(s.nearest_from(p, *a, *b, 0.5 * (a + b)), None, "{m}: {p:?}");
                assert!(!s.any(p, *a, *b), "{m}: {p:?}");
            }
            let p = from_roots(1.0, &[1.0]);
            assert!(roots_of(&s, &p, 2.0, 1.0).is_empty(), "{m}: empty interval");
            assert!(roots_of(&s, &p, f64::NAN, 3.0).is_empty(), "{m}: NaN end");
        }
    }

    #[test]
    fn roots_answer_the_exact_count_where_the_chain_miscounts() {
        // Found by `make fuzz`: the f64 chain counts no root in (-0.5, 1.5],
        // and p > 0 at both ends, so parity cannot tell either.
        let c = [
            -1.0,
            -674.7134819353886,
            0.0,
            0.0,
            0.0,
            0.0,
            0.0,
            0.0,
            649.9810629293474,
            -8.985278822260234e-10,
            0.0,
            1.0,
        ];
        let (a, b) = (-0.5, 1.5);
        let p = Poly::new(&c);
        assert_eq!(exact_count(&c, a, b), Some(2));
        assert_ne!(
            SturmSequence::new(&p).count(a, b),
            2,
            "the f64 chain counts this one right now: pick a harder case"
        );
        for m in STURM {
            let s = solver(m);
            let want = exact_roots(&c, a, b, s.tolerance).unwrap();
            assert_near(&roots_of(&s, &p, a, b), &want, 1e-12);
        }
    }

    #[test]
    fn roots_of_a_trimmed_chain_are_refined_on_the_input() {
        // t^3 (588.3 + 3t^2 - 3t^3 - 2.7e-10 t^4): the tiny leading term
        // degenerates the chain, which then counts the trimmed polynomial
        // (with the triple root at 0); its root near 6.163 is 1.3e-9 from
        // the input's.
        let c = [
            0.0,
            0.0,
            0.0,
            588.3205658607934,
            0.0,
            3.0,
            -3.0,
            -2.6695779584047033e-10,
        ];
        let p = Poly::new(&c);
        let want = exact_roots(&c, 3.5, 6.5, 0.0).unwrap();
        assert_eq!(want.len(), 1);
        for m in STURM {
            let s = solver(m);
            let near = s.nearest(&p, 3.5, 6.5).unwrap();
            assert!(
                (near - want[0]).abs() < 1e-11,
                "{m}: {near} for {}",
                want[0]
            );
            assert_near(&roots_of(&s, &p, 3.5, 6.5), &want, 1e-11);
        }
    }

    #[test]
    fn a_tiny_coefficient_inside_does_not_hide_a_root() {
        // The 5.3e-10 t^4 term leaves a remainder with a leading coefficient
        // of 7e-13 relative, and the chain counted no root in (-2.5, -0.5]
        // for the one at -0.9948. Found by a sweep of random polynomials
        // against the exact count.
        let c = [
            -144.20804782892182,
            0.0,
            735.1777929034166,
            -5.0,
            -5.318248212515959e-10,
            0.0,
            -606.9473473192332,
        ];
        let p = Poly::new(&c);
        let want = exact_roots(&c, -2.5, -0.5, 0.0).unwrap();
        assert_eq!(want.len(), 1);
        for m in STURM {
            let near = solver(m).nearest(&p, -2.5, -0.5).unwrap();
            assert!(
                (near - want[0]).abs() < 1e-12,
                "{m}: {near} for {}",
                want[0]
            );
            assert!(solver(m).any(&p, -2.5, -0.5), "{m}");
        }
    }

    #[test]
    fn a_term_that_overflows_at_the_bound_does_not_hide_the_others() {
        // 1e-20 t^16 overflows to infinity at t = 1e21; compared with it,
        // every lower term looked negligible and the chain became a
        // constant (found in review).
        let cases: [(&[f64], f64, f64); 2] = [
            (&[-0.5, 1.0, 0.0, 0.0, 1e-100], 0.0, f64::INFINITY),
            (
                &[
                    -0.5, 1.0, 0., 0., 0., 0., 0., 0., 0., 0., 0., 0., 0., 0., 0., 0., 1e-20,
                ],
                -1e21,
                1e21,
            ),
        ];
        for (c, a, b) in cases {
            let p = Poly::new(c);
            let want = exact_roots(c, a, b, 0.0).unwrap();
            for m in STURM {
                let near = solver(m).nearest(&p, a, b).unwrap();
                assert!((near - want[0]).abs() < 1e-9, "{m}: {near} for {want:?}");
                assert!(solver(m).any(&p, a, b), "{m}");
            }
        }
    }

    #[test]
    fn inner_terms_are_judged_without_underflow() {
        // The t term of 1e-200 + t + 1e200 t^3 dominates near t = 1e-100,
        // where the other two are equal; (1e-200 / 1e200)^(1/3) underflowed
        // to 0 and the term was dropped (found in review).
        let p = Poly::new(&[1e-200, 1.0, 0.0, 1e200]);
        assert_eq!(without_negligible_terms(&p, 1.0, DEGENERATE_TRIM), p);
        // A term that is dominated everywhere still goes: 1e-12 t against
        // 1 + t^2, which are at least 2|t| on any interval.
        let q = Poly::new(&[1.0, 1e-12, 1.0]);
        let dropped = without_negligible_terms(&q, 10.0, DEGENERATE_TRIM);
        assert_eq!(dropped, Poly::new(&[1.0, 0.0, 1.0]));
    }

    #[test]
    fn leading_coefficient_near_zero() {
        // 1e-20 t^2 + t - 0.5: the quadratic term is noise; one root at
        // 0.5 (to 1e-20), the other near -1e20, out of the interval.
        let p = Poly::new(&[-0.5, 1.0, 1e-20]);
        // A cylinder seen along its axis: round-off of either sign on top.
        let q = from_roots(1.0, &[0.25, 1.75]);
        let mut qc = q.coeffs().to_vec();
        qc.push(-3e-17);
        let q_noisy = Poly::new(&qc);
        for m in Method::ALL {
            let s = solver(*m);
            let cases: [(Poly, &[f64]); 3] = [
                (p, &[0.5]),
                (p.trimmed(1e-14, 1.0), &[0.5]),
                (q_noisy.trimmed(1e-14, 1.0), &[0.25, 1.75]),
            ];
            for (poly, want) in cases {
                assert_near(&roots_of(&s, &poly, -2.0, 2.0), want, 1e-12);
                let near = s.nearest(&poly, 0.0, 10.0).unwrap();
                assert!((near - want[0]).abs() < 1e-12, "{m}");
            }
        }
    }

    #[test]
    fn small_leading_coefficients_without_trimming() {
        // eps t^(n+1) + Q(t): a ray close to an asymptotic direction. The
        // extra root sits near -1/eps, outside; the others move by about
        // eps r^(n+1) / Q'(r). The Sturm path needs no trimming by the
        // caller for any eps (the closed forms do: they divide by eps).
        let bases: [&[f64]; 3] = [&[0.25, 1.75], &[-0.5, 0.25, 1.75], &[-0.7, 0.3, 0.9, 1.2]];
        for base in bases {
            let q = from_roots(1.0, base);
            for k in 6..=20 {
                for eps in [10f64.powi(-k), -(10f64.powi(-k))] {
                    let mut c = q.coeffs().to_vec();
                    c.push(eps);
                    let p = Poly::new(&c);
                    for t_max in [2.0, 10.0, 1e3] {
                        for m in STURM {
                            let got = roots_of(&solver(m), &p, -1.0, t_max);
                            let ctx = format!("{m} {base:?} eps {eps:e} t_max {t_max}: {got:?}");
                            assert_eq!(got.len(), base.len(), "{ctx}");
                            for (g, r) in got.iter().zip(base) {
                                let slope = q.derivative().eval(*r).abs();
                                let moved = eps.abs() * r.abs().powi(c.len() as i32 - 1) / slope;
                                assert!((g - r).abs() <= 2.0 * moved + 1e-10, "{ctx}");
                            }
                            let near = solver(m).nearest(&p, -1.0, t_max).unwrap();
                            assert!((near - got[0]).abs() <= 1e-10, "{ctx}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn coefficient_scale_does_not_matter() {
        let want = [-1.25, 0.5, 0.75, 3.0];
        let p = from_roots(1.0, &want);
        for m in Method::ALL {
            let s = solver(*m);
            for scale in [1e-100, 1e-30, -1.0, 1e30, -1e100, 1e300, 1e-300] {
                let scaled = p.scaled(scale);
                assert_near(&roots_of(&s, &scaled, -2.0, 4.0), &want, 1e-12);
                assert!(
                    !s.any(&scaled, 0.6, 0.7) && s.any(&scaled, 0.6, 0.8),
                    "{m} {scale}"
                );
                let near = s.nearest(&scaled, 0.6, 10.0).unwrap();
                assert!((near - 0.75).abs() < 1e-12, "{m} {scale}");
            }
        }
    }

    #[test]
    fn infinite_intervals_use_the_root_bound() {
        let want = [-300.0, -0.5, 2.0, 1e4];
        let p = from_roots(0.5, &want);
        for m in Method::ALL {
            let s = solver(*m);
            assert_near(
                &roots_of(&s, &p, f64::NEG_INFINITY, f64::INFINITY),
                &want,
                1e-12,
            );
            let near = s.nearest(&p, 0.0, f64::INFINITY).unwrap();
            assert!((near - 2.0).abs() < 1e-12, "{m}");
            assert!(s.any(&p, 3.0, f64::INFINITY), "{m}");
            assert!(!s.any(&p, 1e4, f64::INFINITY), "{m}");
        }
    }

    #[test]
    fn nearest_never_skips_a_nearer_root() {
        // A ray through both tubes of a torus: two close pairs.
        let want = [1.0, 1.001, 3.0, 3.001];
        let p = from_roots(1.0, &want);
        for m in Method::ALL {
            let s = solver(*m);
            // The f64 polynomial's own roots are within ~1e-11 of these.
            for (a, nearest) in [
                (0.0, 1.0),
                (0.9999, 1.0),
                (1.0005, 1.001),
                (1.002, 3.0),
                (2.0, 3.0),
            ] {
                let got = s.nearest(&p, a, 10.0).unwrap();
                assert!((got - nearest).abs() < 1e-10, "{m}: from {a} got {got}");
            }
            assert_eq!(s.nearest(&p, 3.002, 10.0), None);
        }
    }

    #[test]
    fn nearest_from_validates_the_warm_start() {
        let p = from_roots(1.0, &[1.0, 1.001, 3.0, 3.001]);
        for m in Method::ALL {
            let s = solver(*m);
            // A guess beside the far pair converges there; the count check
            // must reject it.
            for guess in [0.9, 1.0004, 2.9, 3.0004, 9.0, -5.0, f64::NAN] {
                let got = s.nearest_from(&p, 0.0, 10.0, guess).unwrap();
                assert!((got - 1.0).abs() < 1e-10, "{m}: guess {guess} gave {got}");
            }
            let got = s.nearest_from(&p, 2.0, 10.0, 3.0004).unwrap();
            assert!((got - 3.0).abs() < 1e-10, "{m}: {got}");
            assert_eq!(s.nearest_from(&p, 2.0, 3.0, 2.99), None, "{m}");
        }
        // A double root, where Newton on p itself would crawl.
        let q = from_roots(1.0, &[0.5, 0.5, 2.0]);
        let got = Solver::default().nearest_from(&q, 0.0, 3.0, 0.6).unwrap();
        assert!((got - 0.5).abs() < 1e-12, "{got}");
    }

    #[test]
    fn tolerance_is_a_bracket_width() {
        let p = Poly::new(&[-2.0, 0.0, 1.0]);
        for m in STURM {
            for tol in [1e-2, 1e-6, 1e-10, 1e-14] {
                let s = Solver {
                    method: m,
                    tolerance: tol,
                    max_iterations: 200,
                };
                let got = s.nearest(&p, 0.0, 10.0).unwrap();
                assert!(
                    (got - std::f64::consts::SQRT_2).abs() <= tol * 1.5,
                    "{m} {tol}: {got}"
                );
            }
        }
        // Relative for large roots.
        let big = from_roots(1.0, &[1e6, 3e6]);
        for m in STURM {
            let got = solver(m).nearest(&big, 0.0, 1e7).unwrap();
            assert!((got - 1e6).abs() <= 1e-12 * 1e6, "{m}: {got}");
        }
        // Tolerances below f64 resolution stop at adjacent floats.
        let s = Solver {
            tolerance: 0.0,
            ..Solver::default()
        };
        let got = s.nearest(&p, 0.0, 10.0).unwrap();
        assert!(
            (got - std::f64::consts::SQRT_2).abs() <= 2.0 * f64::EPSILON,
            "{got}"
        );
    }

    #[test]
    fn closed_method_matches_and_falls_back() {
        let s = solver(Method::Closed);
        let quartic = from_roots(2.0, &[-3.0, -1.0, 0.5, 2.5]);
        assert_near(
            &roots_of(&s, &quartic, -5.0, 5.0),
            &[-3.0, -1.0, 0.5, 2.5],
            1e-13,
        );
        assert_eq!(
            s.nearest(&quartic, -1.0, 5.0)
                .map(|t| (t - 0.5).abs() < 1e-13),
            Some(true)
        );
        let cubic = from_roots(1.0, &[-2.0, 0.0, 3.0]);
        assert_near(&roots_of(&s, &cubic, -5.0, 5.0), &[-2.0, 0.0, 3.0], 1e-13);
        let linear = Poly::new(&[1.0, 4.0]);
        assert_near(&roots_of(&s, &linear, -5.0, 5.0), &[-0.25], 0.0);
        // Degree 6: sturm-newton.
        let sextic = from_roots(1.0, &[-2.0, -1.0, 0.0, 1.0, 2.0, 3.0]);
        assert_near(
            &roots_of(&s, &sextic, -5.0, 5.0),
            &[-2.0, -1.0, 0.0, 1.0, 2.0, 3.0],
            1e-12,
        );
    }

    #[test]
    fn yuksel_finds_every_root_of_high_degree_polynomials() {
        let s = solver(Method::Yuksel);
        // Roots 1..10, and ten roots of a Chebyshev-like spread in (-1, 1).
        let integers: Vec<f64> = (1..=10).map(f64::from).collect();
        let cheb: Vec<f64> = (0..10)
            .map(|k| (std::f64::consts::PI * (f64::from(k) + 0.5) / 10.0).cos())
            .rev()
            .collect();
        for want in [integers, cheb] {
            let p = from_roots(1.0, &want);
            let got = roots_of(&s, &p, -2.0, 11.0);
            assert_near(&got, &want, 1e-9);
            let near = s.nearest(&p, want[3], 11.0).unwrap();
            assert!((near - want[4]).abs() < 1e-9, "{near}");
            assert!(s.any(&p, want[3] + 1e-3, want[4] + 1e-3));
            assert!(!s.any(&p, want[3] + 1e-3, want[4] - 1e-3));
        }
    }

    #[test]
    fn yuksel_tolerance_and_odd_multiplicity() {
        let p = Poly::new(&[-2.0, 0.0, 1.0]);
        for tol in [1e-2, 1e-6, 1e-10, 1e-14] {
            let s = Solver {
                method: Method::Yuksel,
                tolerance: tol,
                max_iterations: 200,
            };
            let got = s.nearest(&p, 0.0, 10.0).unwrap();
            assert!(
                (got - std::f64::consts::SQRT_2).abs() <= tol * 1.5,
                "{tol}: {got}"
            );
        }
        // A triple root changes sign: found, to the cube root of rounding.
        let triple = from_roots(1.0, &[0.3, 0.3, 0.3, 2.0]);
        let got = solver(Method::Yuksel).nearest(&triple, 0.0, 3.0).unwrap();
        assert!((got - 0.3).abs() < 1e-4, "{got}");
        // A tangent with no crossing: (t - 1)^2 + 1e-12 has no real root.
        let touch = Poly::new(&[1.0 + 1e-12, -2.0, 1.0]);
        assert_eq!(solver(Method::Yuksel).nearest(&touch, 0.0, 3.0), None);
    }

    #[test]
    fn every_root_is_a_crossing_or_comes_from_the_exact_path() {
        // Found by tests/fuzz_poly.rs: roots on the open end a reported,
        // a multiple root on b lost or reported twice, a quadruple root
        // reported twice (the chain took noise for a remainder and counted
        // two roots near it), a phantom root from a chain that divided by
        // noise, and a root near -3.85e-5 reported as 0 (a remainder
        // 60 times its error estimate taken for a gcd).
        let cases: [(&[f64], f64, f64, &[f64]); 8] = [
            // t^2 (t + 3)^2 (t - 3)
            (&[0.0, 0.0, -27.0, -9.0, 3.0, 1.0], -3.0, -2.5, &[]),
            // (t - 2)^3 (t - 2.5)^2
            (&[-50.0, 115.0, -105.5, 48.25, -11.0, 1.0], 2.0, 2.5, &[2.5]),
            (
                &[-1728.0, -432.0, 396.0, 71.0, -33.0, -3.0, 1.0],
                -5.0,
                4.0,
                &[-3.0, 4.0],
            ),
            // (t + 2.5)^2 (t - 0.5)^2
            (&[1.5625, -5.0, 1.5, 4.0, 1.0], -5.0, -2.5, &[-2.5]),
            (
                &[576.0, -384.0, -1256.0, -580.0, 6.25, 60.25, 14.0, 1.0],
                -4.5,
                -4.0,
                &[-4.0],
            ),
            // Roots 2 and 3.5 (of multiplicity 4) in the interval.
            (
                &[
                    -750.3125, 182.21875, 629.34375, -367.9375, -3.25, 48.0, -12.5, 1.0,
                ],
                0.0,
                9.517386142912624,
                &[2.0, 3.5],
            ),
            (
                &[
                    -1.0,
                    0.0,
                    8.663053858603911e-11,
                    0.0,
                    -114.78162187541942,
                    152.92263966434385,
                ],
                0.0,
                1.0,
                &[0.7692601072953948],
            ),
            (
                &[
                    1.4842386762401313e-12,
                    -1.3329307065093328e-10,
                    0.0,
                    25.94724897905935,
                ],
                -0.5,
                0.0,
                &[-0.000038574896734644426],
            ),
        ];
        for m in STURM {
            for (c, a, b, want) in cases {
                let got = roots_of(&solver(m), &Poly::new(c), a, b);
                assert_near(&got, want, 1e-12);
            }
        }
    }

    #[test]
    fn a_root_the_chain_lost_between_ends_of_opposite_signs() {
        // Found by tests/fuzz_poly.rs: the tiny t^4 coefficient left the
        // chain counting 0 roots in (-1, 0].
        let p = Poly::new(&[
            74.0708084071424,
            3.0,
            0.0,
            907.9238821826626,
            6.027905747477918e-10,
            0.0,
            -170.1871154478272,
        ]);
        for m in STURM {
            let got = roots_of(&solver(m), &p, -1.0, 0.0);
            assert_near(&got, &[-0.4290752462521165], 1e-12);
        }
    }

    #[test]
    fn simple_root_beside_a_double_root_on_the_open_end() {
        // t^2 (-1 + 834.7t + t^4 + 2t^6) on (0, 0.5]: found by
        // tests/fuzz_poly.rs with no root at all for 0.0011980.
        let p = Poly::new(&[0.0, 0.0, -1.0, 834.699808367765, 0.0, 0.0, 1.0, 0.0, 2.0]);
        for m in STURM {
            let got = roots_of(&solver(m), &p, 0.0, 0.5);
            assert_near(&got, &[0.0011980354970546614], 1e-12);
        }
    }

    #[test]
    fn illinois_falls_back_to_bisection_when_its_steps_run_out() {
        // Found by tests/fuzz_poly.rs: Illinois returned -2.7199 for the
        // root -2.7329 on the root bound's wide bracket after 100 steps.
        let p = Poly::new(&[
            -2.0, -3.0, 5.0, 0.0, 2.0, 1.0, -7.0, 302.2, 0.0, 0.0, 4.0, -4.0,
        ]);
        let want = [-2.732864725128479, 0.49532316282557076, 3.2290574698979526];
        let got = roots_of(
            &solver(Method::SturmIllinois),
            &p,
            f64::NEG_INFINITY,
            f64::INFINITY,
        );
        assert_near(&got, &want, 1e-11);
    }

    #[test]
    fn nudges_inside_skip_subnormals() {
        assert_eq!(above(0.0), f64::MIN_POSITIVE);
        assert_eq!(above(-f64::MIN_POSITIVE), 0.0);
        assert_eq!(above(1.0), 1.0 + f64::EPSILON);
        assert_eq!(below(0.0), -f64::MIN_POSITIVE);
        assert_eq!(strictly_inside(0.0, 0.0, 1.0), f64::MIN_POSITIVE);
        assert_eq!(strictly_inside(1.0, 0.0, 1.0), 1.0 - f64::EPSILON / 2.0);
        assert_eq!(strictly_inside(0.5, 0.0, 1.0), 0.5);
    }

    #[test]
    fn method_names_round_trip() {
        for m in Method::ALL {
            assert_eq!(m.name().parse::<Method>(), Ok(*m));
            assert_eq!(m.to_string(), m.name());
        }
        let err = "newton".parse::<Method>().unwrap_err();
        for m in Method::ALL {
            assert!(err.contains(m.name()), "{err}");
        }
        assert_eq!(Solver::default().method, Method::SturmNewton);
        assert_eq!(Solver::default().tolerance, 1e-12);
    }

    /// Sorted roots in [-4, 4], pairwise more than 0.1 apart.
    fn separated_roots() -> impl Strategy<Value = Vec<f64>> {
        prop::collection::vec(-4.0f64..4.0, 1..=7).prop_filter_map("roots too close", |mut r| {
            r.sort_by(f64::total_cmp);
            r.windows(2).all(|w| w[1] - w[0] > 0.1).then_some(r)
        })
    }

    fn leading() -> impl Strategy<Value = f64> {
        (-3i32..=3, any::<bool>())
            .prop_map(|(e, neg)| if neg { -(10f64.powi(e)) } else { 10f64.powi(e) })
    }

    /// Distinct quarter-integer roots in [-3, 3] with multiplicities 1 to
    /// 3, at most degree 8: with a power-of-two leading coefficient the
    /// expanded coefficients need under 40 bits, so the f64 polynomial has
    /// exactly these multiple roots.
    fn exact_multiple_roots() -> impl Strategy<Value = (Vec<f64>, Vec<f64>)> {
        prop::collection::btree_map(-12i32..=12, 1usize..=3, 1..=4).prop_filter_map(
            "degree above 8",
            |m| {
                let distinct: Vec<f64> = m.keys().map(|&k| f64::from(k) / 4.0).collect();
                let all: Vec<f64> = m
                    .iter()
                    .flat_map(|(&k, &n)| std::iter::repeat_n(f64::from(k) / 4.0, n))
                    .collect();
                (all.len() <= 8).then_some((all, distinct))
            },
        )
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]

        #[test]
        fn roots_finds_constructed_roots(
            roots in separated_roots(), lead in leading(), m in 0usize..Method::ALL.len(),
        ) {
            let p = from_roots(lead, &roots);
            let s = solver(Method::ALL[m]);
            let got = roots_of(&s, &p, -5.0, 5.0);
            prop_assert_eq!(got.len(), SturmSequence::new(&p).count(-5.0, 5.0));
            prop_assert_eq!(got.len(), roots.len());
            for (g, w) in got.iter().zip(&roots) {
                prop_assert!(
                    (g - w).abs() <= 1e-7 * w.abs().max(1.0), "got {:?}, want {:?}", got, roots
                );
            }
        }

        #[test]
        fn multiple_roots_are_found_once(
            (all, distinct) in exact_multiple_roots(), e in -40i32..40, m in 0usize..3,
        ) {
            let p = from_roots(2f64.powi(e), &all);
            let s = solver(STURM[m]);
            let got = roots_of(&s, &p, -4.0, 4.0);
            prop_assert_eq!(SturmSequence::new(&p).count(-4.0, 4.0), distinct.len());
            prop_assert_eq!(got.len(), distinct.len(), "got {:?}, want {:?}", got, distinct);
            // Not to 1e-12: the roots are those of the square-free part,
            // whose coefficients carry the round-off of the chain that found
            // gcd(p, p') (the exact path is the reference for these).
            for (g, w) in got.iter().zip(&distinct) {
                prop_assert!((g - w).abs() <= 1e-7 * w.abs().max(1.0), "got {:?}", got);
            }
            // The ray path (`nearest`) does not reduce p to its square-free
            // part, so a root of multiplicity m is known only to within its
            // f64 conditioning, (noise / |a_m|)^(1/m) with a_m = p^(m)(r)/m!
            // (a triple root 0.25 from another triple root: 1.2e-7 off).
            let near = s.nearest(&p, -4.0, 4.0);
            let r = distinct[0];
            let m = all.iter().filter(|&&x| x == r).count();
            let others = all.iter().filter(|&&x| x != r);
            let a_m = 2f64.powi(e) * others.map(|&x| r - x).product::<f64>();
            let noise = f64::EPSILON
                * p.coeffs().iter().rev().fold(0.0, |acc, c| acc * r.abs() + c.abs());
            let within = (noise / a_m.abs()).powf(1.0 / m as f64).max(1e-7);
            prop_assert!(
                near.is_some_and(|t| (t - r).abs() <= within),
                "nearest {:?}, want {} within {}", near, r, within
            );
            prop_assert!(s.any(&p, -4.0, 4.0));
        }

        #[test]
        fn nearest_and_any_agree_with_the_construction(
            roots in separated_roots(),
            lead in leading(),
            m in 0usize..Method::ALL.len(),
            a in -4.5f64..4.5,
            len in 0.01f64..9.0,
        ) {
            let b = a + len;
            prop_assume!(roots.iter().all(|r| (r - a).abs() > 1e-6 && (r - b).abs() > 1e-6));
            let p = from_roots(lead, &roots);
            let s = solver(Method::ALL[m]);
            let want = roots.iter().copied().find(|&r| r > a && r < b);
            let got = s.nearest(&p, a, b);
            prop_assert_eq!(got.is_some(), want.is_some(), "got {:?}, want {:?}", got, want);
            if let (Some(g), Some(w)) = (got, want) {
                prop_assert!((g - w).abs() <= 1e-7 * w.abs().max(1.0), "got {}, want {}", g, w);
            }
            prop_assert_eq!(s.any(&p, a, b), want.is_some());
            let warm = s.nearest_from(&p, a, b, roots[roots.len() - 1] + 0.01);
            prop_assert_eq!(warm.is_some(), want.is_some());
            if let (Some(g), Some(w)) = (warm, want) {
                prop_assert!(
                    (g - w).abs() <= 1e-7 * w.abs().max(1.0), "warm got {}, want {}", g, w
                );
            }
        }
    }
}
