//! Direct methods, without a Sturm chain: the closed forms of
//! [`crate::poly::closed`] up to degree 4 and Yuksel's derivative intervals,
//! and the merging of roots found that way to the Sturm path's report.

use crate::poly::MAX_DEGREE;
use crate::poly::closed;
use crate::poly::univariate::PolyN;

use super::condition::{clip_to_root_bound, negligible_above, opposite};
use super::{Method, Solver};

impl Solver {
    /// Whether this method solves `p` without a Sturm chain: `Closed` up to
    /// degree 4, `Yuksel` always.
    pub(super) fn direct<const S: usize>(&self, p: &PolyN<S>) -> bool {
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
    pub(super) fn direct_roots<const S: usize>(
        &self,
        p: &PolyN<S>,
        a: f64,
        b: f64,
        after: f64,
    ) -> Option<DirectRoots> {
        if !self.direct(p) {
            return None;
        }
        let mut found = DirectRoots::default();
        let Some((lo, hi)) = clip_to_root_bound(p, a, b) else {
            return Some(found);
        };
        let degree = negligible_above(p, lo.abs().max(hi.abs()), f64::EPSILON);
        let p = p.truncated(degree);
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
    fn derivative_intervals<const S: usize>(
        &self,
        p: &PolyN<S>,
        lo: f64,
        hi: f64,
        after: f64,
        out: &mut DirectRoots,
    ) {
        let deepest = p.degree().saturating_sub(2);
        let mut chain = [PolyN::ZERO; S];
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
    fn monotonic_pieces<const S: usize>(
        &self,
        f: &PolyN<S>,
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
                out.push(self.newton(f, x0, x1, f0, f1, self.halve(x0, x1)));
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
    pub(super) fn roots_in(
        &self,
        found: &DirectRoots,
        a: f64,
        b: f64,
        out: &mut [f64; MAX_DEGREE],
    ) -> usize {
        let mut n = 0;
        for &t in found.iter() {
            if t > a && t <= b && (n == 0 || t - out[n - 1] > self.width_tol(out[n - 1], t)) {
                out[n] = t;
                n += 1;
            }
        }
        n
    }
}

/// Roots found without the f64 Sturm chain (closed forms, derivative
/// intervals, the exact path), increasing; one of equal neighbours kept.
#[derive(Clone, Copy, Debug)]
pub(super) struct DirectRoots {
    roots: [f64; MAX_DEGREE],
    len: usize,
}

/// Written out because std derives `Default` for arrays of at most 32.
impl Default for DirectRoots {
    fn default() -> Self {
        DirectRoots {
            roots: [0.0; MAX_DEGREE],
            len: 0,
        }
    }
}

impl DirectRoots {
    pub(super) fn iter(&self) -> impl Iterator<Item = &f64> {
        self.roots[..self.len].iter()
    }

    fn last(&self) -> Option<f64> {
        self.len.checked_sub(1).map(|i| self.roots[i])
    }

    /// Appends t if it is above the last root (a polynomial of degree n has
    /// at most n, so storage cannot run out for degree <= MAX_DEGREE).
    pub(super) fn push(&mut self, t: f64) {
        if self.last().is_none_or(|last| t > last) && self.len < MAX_DEGREE {
            self.roots[self.len] = t;
            self.len += 1;
        }
    }
}
