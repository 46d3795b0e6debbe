//! A cheap first pass for the Sturm methods: Descartes' rule of signs on
//! the Bernstein coefficients of p over halves of the interval. Over
//! [t0, t1], p = Σ b_i B_i,n with the Bernstein basis B_i,n ≥ 0, so the
//! number of roots in (t0, t1), counted with multiplicity, is at most the
//! number of sign changes of b_0 … b_n, and of the same parity. No change
//! proves the piece empty, one change proves exactly one simple root with
//! p(t0) = b_0 and p(t1) = b_n of opposite signs. Most rays are settled
//! that way after a few halvings, at a fraction of the cost of building a
//! Sturm chain: a ray that misses, or one whose nearest root is apart from
//! the others.
//!
//! Every sign is a proof or it is not used: a coefficient counts only if it
//! is larger than a bound on its rounding error, computed alongside it from
//! the absolute values. Whatever the pass cannot prove (a double root at a
//! tangent, a root at the interval's start, roots too close to separate
//! within [`MAX_DEPTH`] halvings) it leaves to the Sturm chain, which then
//! answers the whole query as before.

use crate::poly::univariate::{PolyN, QUARTIC_SLOTS};

use super::condition::{midpoint, opposite};

/// Halvings before the Sturm chain takes over: 2^-12 of the searched
/// interval separates the roots of the rays that are not near-tangent; the
/// rest cost the chain as before, plus at most 2 · 12 conversions.
const MAX_DEPTH: u32 = 12;

/// What the first pass proved about the roots of p in (a, b).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Screen {
    /// No root.
    Empty,
    /// The nearest root is the only one in [lo, hi], a simple root, with
    /// p(lo) = flo and p(hi) = fhi of opposite signs, as evaluated; `start`
    /// is where refinement should begin if the pass knows a point near the
    /// root (else the bracket's middle).
    Nearest {
        lo: f64,
        hi: f64,
        flo: f64,
        fhi: f64,
        start: Option<f64>,
    },
    /// Some root (for `any`: an odd number of sign changes proves one).
    Some,
    /// Not proven either way: ask the Sturm chain.
    Unsure,
}

/// Which question the pass answers.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Question {
    /// The nearest root, isolated.
    Nearest,
    /// Whether there is any root.
    Any,
}

/// The first pass over (a, b) for a polynomial of degree 1 or more.
pub(super) fn screen<const S: usize>(p: &PolyN<S>, a: f64, b: f64, question: Question) -> Screen {
    if p.degree() == 0 {
        return Screen::Unsure;
    }
    // Every polynomial of degree 4 or less is taken as a quartic (the
    // Bernstein basis of a higher degree than p's is as good a proof): in
    // 5 slots the loops then have a fixed length, which the compiler
    // unrolls (a third of the cost of a variable degree), and the 17-slot
    // instantiation does the same operations, so both answer the same bits.
    let n = if S == QUARTIC_SLOTS {
        S - 1
    } else {
        p.degree().max(QUARTIC_SLOTS - 1)
    };
    let mut piece = match Piece::start(p, n, a, b) {
        Start::Empty => return Screen::Empty,
        Start::Unsure => return Screen::Unsure,
        Start::Piece(piece) => piece,
    };
    // The left half keeps b_0 = p(lo) exactly: if its sign is noise (a ray
    // that starts on the surface), no halving proves anything at the start.
    if !piece.proven(0) {
        return Screen::Unsure;
    }
    // Until the first halving there is nothing to come back to, and most
    // queries end before one: the stack of pending halves, zeroed on
    // every call, was 2% of the instructions of POV-Ray's tcubic.pov
    // (`valgrind --tool=callgrind`).
    loop {
        match piece.step(p, n, question) {
            Step::Done(screen) => return screen,
            Step::Empty => return Screen::Empty,
            Step::Cut(next) => piece = next,
            Step::Halves(left, right) => return halves_first(p, n, question, left, right),
        }
    }
}

/// `screen` on from its first halving: depth-first, left half first, so the
/// first piece proven to hold a root holds the nearest one, every piece left
/// of it having been proven empty.
fn halves_first<const S: usize>(
    p: &PolyN<S>,
    n: usize,
    question: Question,
    left: Piece<S>,
    right: Piece<S>,
) -> Screen {
    let mut pending = [Piece::<S>::EMPTY; MAX_DEPTH as usize];
    pending[0] = right;
    let mut stack = 1;
    let mut piece = left;
    loop {
        match piece.step(p, n, question) {
            Step::Done(screen) => return screen,
            Step::Empty => {
                if stack == 0 {
                    return Screen::Empty;
                }
                stack -= 1;
                piece = pending[stack];
            }
            Step::Cut(next) => piece = next,
            Step::Halves(left, right) => {
                pending[stack] = right;
                stack += 1;
                piece = left;
            }
        }
    }
}

/// What one piece of the pass settles.
enum Step<const S: usize> {
    /// The query's answer.
    Done(Screen),
    /// The piece holds no root: on to the next pending one.
    Empty,
    /// Its start, which holds no root, cut off: the rest to look at.
    Cut(Piece<S>),
    /// Its two halves to look at, the left first.
    Halves(Piece<S>, Piece<S>),
}

/// The least fraction of a piece a cut must remove to be taken instead of
/// a halving (Bézier clipping's usual rule of thumb).
const CLIP_GAIN: f64 = 0.2;

/// p over [t0, t1] in the Bernstein basis of its degree n, with a bound on
/// every coefficient's rounding error.
#[derive(Clone, Copy)]
struct Piece<const S: usize> {
    t0: f64,
    t1: f64,
    b: [f64; S],
    err: f64,
    /// The largest |b_i| of the first piece, which bounds every later
    /// piece's (de Casteljau's combinations are convex): each halving's
    /// rounding is taken against it, without a pass over the coefficients.
    scale: f64,
    depth: u32,
}

impl<const S: usize> Piece<S> {
    const EMPTY: Self = Self {
        t0: 0.0,
        t1: 0.0,
        b: [0.0; S],
        err: 0.0,
        scale: 0.0,
        depth: 0,
    };

    /// p over [a, b] ∩ [a, a + (a bound on its roots above a)] in the
    /// Bernstein basis of degree n >= p's; `Empty` if p provably has no
    /// root above a.
    fn start(p: &PolyN<S>, n: usize, a: f64, b: f64) -> Start<S> {
        if !a.is_finite() {
            return Start::Unsure;
        }
        let d = p.degree();
        let mut c = [0.0; S];
        let mut m = [0.0; S];
        c[..=d].copy_from_slice(p.coeffs());
        for (mi, ci) in m.iter_mut().zip(p.coeffs()) {
            *mi = ci.abs();
        }
        // p(a + s) in powers of s: a Taylor shift (synthetic division). `m`
        // repeats every step on absolute values, so it bounds every partial
        // result; each coefficient takes at most 2n roundings here.
        // At a = 0 (a ray's first query starts there) the shift is the
        // identity: skipped, with the same bits.
        let shift = a.abs();
        if a != 0.0 {
            for j in 0..n {
                for i in (j..n).rev() {
                    c[i] += a * c[i + 1];
                    m[i] += shift * m[i + 1];
                }
            }
        }
        // m bounds |c|, so this catches an infinite or NaN c as well.
        if !m[..=d].iter().all(|x| x.is_finite()) {
            return Start::Unsure;
        }
        // Kioustelidis' bound on the roots s > 0: 2 max_k (−c_(d−k) / c_d)^(1/k)
        // over the coefficients of the other sign than the leading one (an
        // exact copy of p's), counting every coefficient whose sign is not
        // proven as possibly of the other sign. None at all: Descartes' rule
        // in the power basis leaves no root above a.
        let lead = c[d];
        let sign = lead.signum();
        let shift_err = (2 * n + 2) as f64 * f64::EPSILON;
        // A k-th root is taken only where it can raise the maximum: a
        // quotient at most reach^k (less a margin for the power's own
        // rounding) has a root at most reach. Cube roots were a tenth of
        // the pass on torus quartics (`valgrind --tool=callgrind`). Nor is
        // any taken once a quotient above half^k (plus the same margin)
        // shows the bound past b: the interval is then (a, b] whatever the
        // rest, as the bound below would also give.
        let half = 0.5 * (b - a);
        let mut half_power = 1.0f64;
        let mut past_b = false;
        let mut reach = 0.0f64;
        let mut power = 1.0f64;
        for k in 1..=d {
            power *= reach;
            half_power *= half;
            let other = shift_err * m[d - k] - sign * c[d - k];
            let ratio = other / lead.abs();
            let margin = 4.0 * k as f64 * f64::EPSILON;
            if other > 0.0 && ratio > half_power * (1.0 + margin) {
                past_b = true;
                break;
            }
            if other > 0.0 && ratio > power * (1.0 - margin) {
                reach = reach.max(kth_root(ratio, k));
                power = reach.powi(k as i32);
            }
        }
        if !past_b && reach == 0.0 {
            return Start::Empty;
        }
        // Twice, by the bound; the k-th roots' own rounding is far below 1e-9.
        let w = if past_b {
            b - a
        } else {
            (b - a).min(2.0 * reach * (1.0 + 1e-9))
        };
        // p(a + w u) in powers of u, then in the Bernstein basis:
        // b_i = Σ_k C(i, k) / C(n, k) q_k, as q_k / C(n, k) summed by n
        // passes of Pascal's rule.
        let mut power = 1.0;
        for i in 0..=n {
            c[i] *= power;
            m[i] *= power;
            power *= w;
        }
        let mut binomial = 1.0;
        for k in 1..=n {
            binomial = binomial * (n + 1 - k) as f64 / k as f64;
            c[k] /= binomial;
            m[k] /= binomial;
        }
        for j in 0..n {
            for i in (j + 1..=n).rev() {
                c[i] += c[i - 1];
                m[i] += m[i - 1];
            }
        }
        // At most 4n + 2 roundings reach any coefficient (shift 2n, powers
        // and scaling n + 1, a division, Pascal n), each within half an ε
        // of a result that m bounds: (2n + 1) ε would do; 4 (n + 1) ε leaves
        // a factor of two for the binomials' own rounding.
        let largest = m[..=n].iter().fold(0.0, |x: f64, &y| x.max(y));
        let err = 4.0 * (n + 1) as f64 * f64::EPSILON * largest;
        if !(err.is_finite() && w.is_finite() && c[..=n].iter().all(|x| x.is_finite())) {
            return Start::Unsure;
        }
        let scale = c[..=n].iter().fold(0.0, |x: f64, &y| x.max(y.abs()));
        Start::Piece(Piece {
            t0: a,
            t1: a + w,
            b: c,
            err,
            scale,
            depth: 0,
        })
    }

    /// What this piece settles: a count of no sign changes proves it
    /// empty, one (for the nearest root) or an odd count (for any) proves a
    /// root; else its start is cut off where the control points' convex
    /// hull keeps it away from zero, while that gains much, or it is halved.
    /// Unsure once halvings run out, or where the start's sign is noise:
    /// nothing left of the piece is unproven then, so that start may be
    /// the nearest root.
    #[inline]
    fn step(&self, p: &PolyN<S>, n: usize, question: Question) -> Step<S> {
        match self.changes(n) {
            Some(0) => return Step::Empty,
            Some(1) if question == Question::Nearest => {
                let (lo, hi) = (self.t0, self.t1);
                let (flo, fhi) = (p.eval(lo), p.eval(hi));
                return Step::Done(if opposite(flo, fhi) {
                    Screen::Nearest {
                        lo,
                        hi,
                        flo,
                        fhi,
                        start: None,
                    }
                } else {
                    Screen::Unsure
                });
            }
            Some(v) if question == Question::Any && v % 2 == 1 => return Step::Done(Screen::Some),
            _ => {}
        }
        if self.depth == MAX_DEPTH || !self.proven(0) {
            return Step::Done(Screen::Unsure);
        }
        match self.first_crossing(n) {
            None => Step::Empty,
            Some(u) if u >= CLIP_GAIN => Step::Cut(self.after(n, u)),
            Some(_) => {
                let (left, right) = self.halves(n);
                Step::Halves(left, right)
            }
        }
    }

    /// Whether b_i's sign is proven: it is larger than its rounding bound
    /// (both are finite: `start` checks).
    fn proven(&self, i: usize) -> bool {
        self.b[i].abs() > self.err
    }

    /// The sign changes of the coefficients, if every sign is proven.
    fn changes(&self, n: usize) -> Option<u32> {
        // Without early exits: at n = 4 the loop unrolls into compares and
        // adds, cheaper than the branches it would save. A change is a
        // difference of sign bits, which for proven (nonzero, finite)
        // coefficients is a difference of signs.
        let mut proven = true;
        let mut count = 0;
        for i in 0..=n {
            proven &= self.proven(i);
        }
        for i in 1..=n {
            count += ((self.b[i - 1].to_bits() ^ self.b[i].to_bits()) >> 63) as u32;
        }
        proven.then_some(count)
    }

    /// A u in [0, 1] before which p has no root on the piece, from the
    /// convex hull of the control points (i / n, b_i), which holds p's
    /// graph. With b_0 > 0, every control point lies on or above the
    /// steepest line from (0, b_0) through another one, so the hull does,
    /// and p stays positive until that line reaches zero; all lowered by
    /// the rounding bound. `None` if no control point can be at or below 0
    /// (the piece is empty). Needs b_0's sign proven.
    fn first_crossing(&self, n: usize) -> Option<f64> {
        let sign = self.b[0].signum();
        let start = sign * self.b[0] - self.err;
        let mut steepest = 0.0f64;
        let mut reaches_zero = false;
        for i in 1..=n {
            let low = sign * self.b[i] - self.err;
            reaches_zero |= low <= 0.0;
            steepest = steepest.min((low - start) * (n as f64 / i as f64));
        }
        if !reaches_zero {
            return None;
        }
        // The quotients' roundings, taken off.
        Some((start / -steepest * (1.0 - 8.0 * f64::EPSILON)).clamp(0.0, 1.0))
    }

    /// The piece from u to 1, by de Casteljau's algorithm at u. Each of its
    /// n rounds of convex combinations rounds three times (1 − u, a sum of
    /// two products), within half an ε of a value no larger than `scale`
    /// each time.
    fn after(&self, n: usize, u: f64) -> Self {
        let v = 1.0 - u;
        // The last value of each round of combinations is the next
        // coefficient of the part after u, from the far end.
        let mut right = self.b;
        let mut w = self.b;
        for r in 1..=n {
            for i in 0..=n - r {
                w[i] = v * w[i] + u * w[i + 1];
            }
            right[n - r] = w[n - r];
        }
        Piece {
            t0: self.t0 + u * (self.t1 - self.t0),
            b: right,
            err: self.err + 2.0 * n as f64 * f64::EPSILON * self.scale,
            depth: self.depth + 1,
            ..*self
        }
    }

    /// The two halves, by de Casteljau's algorithm at u = 1/2. Each of its
    /// n rounds of averages rounds once, within half an ε of a value no
    /// larger than `scale`; the halving itself is exact.
    fn halves(&self, n: usize) -> (Self, Self) {
        let err = self.err + n as f64 * f64::EPSILON * self.scale;
        let mid = midpoint(self.t0, self.t1);
        let depth = self.depth + 1;
        let mut left = Piece {
            t1: mid,
            err,
            depth,
            ..*self
        };
        let mut right = Piece {
            t0: mid,
            err,
            depth,
            ..*self
        };
        let mut w = self.b;
        for r in 1..=n {
            for i in 0..=n - r {
                w[i] = 0.5 * (w[i] + w[i + 1]);
            }
            left.b[r] = w[0];
            right.b[n - r] = w[n - r];
        }
        (left, right)
    }
}

/// How the search of a query starts.
enum Start<const S: usize> {
    Empty,
    Unsure,
    Piece(Piece<S>),
}

/// x^(1/k) for x >= 0, exact operations where there are some.
fn kth_root(x: f64, k: usize) -> f64 {
    match k {
        1 => x,
        2 => x.sqrt(),
        3 => x.cbrt(),
        4 => x.sqrt().sqrt(),
        _ => x.powf(1.0 / k as f64),
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::poly::exact::{ExactPoly, exact_count};
    use num_rational::BigRational;
    use proptest::prelude::*;

    /// The product of (t − r) over `real` and (t − re)² + im² over `pairs`,
    /// times `lead`, lowest degree first.
    pub(in crate::poly::solve) fn product(
        lead: f64,
        real: &[f64],
        pairs: &[(f64, f64)],
    ) -> Vec<f64> {
        let mut c = vec![lead];
        let mut times = |factor: &[f64]| {
            let mut next = vec![0.0; c.len() + factor.len() - 1];
            for (i, ci) in c.iter().enumerate() {
                for (j, fj) in factor.iter().enumerate() {
                    next[i + j] += ci * fj;
                }
            }
            c = next;
        };
        for r in real {
            times(&[-r, 1.0]);
        }
        for (re, im) in pairs {
            times(&[re * re + im * im, -2.0 * re, 1.0]);
        }
        c
    }

    /// Distinct real roots of the exact polynomial in the open (a, b).
    pub(in crate::poly::solve) fn open_count(c: &[f64], a: f64, b: f64) -> usize {
        let at_b = ExactPoly::from_f64(c)
            .unwrap()
            .sign_at(&BigRational::from_float(b).unwrap())
            == 0;
        exact_count(c, a, b).unwrap() - usize::from(at_b)
    }

    fn check<const S: usize>(c: &[f64], a: f64, b: f64) -> Result<(), TestCaseError> {
        let p = PolyN::<S>::new(c);
        match screen(&p, a, b, Question::Nearest) {
            Screen::Empty => prop_assert_eq!(open_count(c, a, b), 0, "empty, but roots"),
            Screen::Nearest {
                lo, hi, flo, fhi, ..
            } => {
                prop_assert!(a <= lo && lo < hi && hi <= b, "[{lo}, {hi}] outside");
                prop_assert_eq!(exact_count(c, a, lo).unwrap(), 0, "a nearer root");
                prop_assert_eq!(open_count(c, lo, hi), 1, "not one root in [{}, {}]", lo, hi);
                prop_assert!(opposite(flo, fhi));
            }
            Screen::Some => prop_assert!(false, "`Some` answers `any` only"),
            Screen::Unsure => {}
        }
        match screen(&p, a, b, Question::Any) {
            Screen::Empty => prop_assert_eq!(open_count(c, a, b), 0),
            Screen::Some => prop_assert!(open_count(c, a, b) > 0),
            Screen::Nearest { .. } => prop_assert!(false, "`Nearest` answers `nearest` only"),
            Screen::Unsure => {}
        }
        Ok(())
    }

    /// Roots in clusters and tangent pairs, as rays near silhouettes give.
    pub(in crate::poly::solve) fn root_near() -> impl Strategy<Value = f64> {
        (
            -2.0..40.0f64,
            prop_oneof![Just(0.0), -1e-3..1e-3f64, -1e-7..1e-7f64],
        )
            .prop_map(|(r, jitter)| r + jitter)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        // Every Empty and Nearest answer is checked against the exact Sturm
        // count of the polynomial whose coefficients are the f64 ones.
        #[test]
        fn what_it_proves_is_true(
            real in prop::collection::vec(root_near(), 0..=4),
            pair in prop::option::of((-2.0..40.0f64, prop_oneof![1e-9..1e-3f64, 1e-3..5.0f64, 5.0..30.0f64])),
            lead in prop_oneof![Just(1.0), 1e-3..1e3f64, -1e3..-1e-3f64],
            a in -1.0..20.0f64,
            len in prop_oneof![0.01..1.0f64, 1.0..100.0f64, Just(1e7)],
        ) {
            let pairs: Vec<(f64, f64)> = pair.into_iter().collect();
            let real = &real[..real.len().min(4 - 2 * pairs.len())];
            let c = product(lead, real, &pairs);
            prop_assume!(c.len() >= 2);
            check::<5>(&c, a, a + len)?;
            check::<17>(&c, a, a + len)?;
        }

        // Degrees 5 to 16 take the general (unspecialised) loops.
        #[test]
        fn what_it_proves_is_true_at_higher_degree(
            real in prop::collection::vec(root_near(), 3..=12),
            pair in prop::option::of((-2.0..40.0f64, 1e-6..2.0f64)),
            a in -1.0..20.0f64,
            len in prop_oneof![0.1..5.0f64, 5.0..60.0f64],
        ) {
            let pairs: Vec<(f64, f64)> = pair.into_iter().collect();
            let c = product(1.0, &real, &pairs);
            prop_assume!(c.len() >= 6);
            check::<17>(&c, a, a + len)?;
        }
    }

    fn quartic(roots: [f64; 4]) -> PolyN<5> {
        PolyN::new(&product(1.0, &roots, &[]))
    }

    #[test]
    fn misses_are_proven_empty() {
        // (t² + 1)(t² + 4): no real root anywhere.
        let p = PolyN::<5>::new(&[4.0, 0.0, 5.0, 0.0, 1.0]);
        assert_eq!(screen(&p, 0.0, 10.0, Question::Nearest), Screen::Empty);
        assert_eq!(screen(&p, -10.0, 10.0, Question::Any), Screen::Empty);
    }

    #[test]
    fn the_nearest_root_is_isolated_first() {
        let p = quartic([-1.0, 2.0, 2.5, 7.0]);
        let Screen::Nearest {
            lo, hi, flo, fhi, ..
        } = screen(&p, 0.0, 10.0, Question::Nearest)
        else {
            panic!("not isolated");
        };
        assert!(lo < 2.0 && 2.0 < hi && hi <= 2.5, "[{lo}, {hi}]");
        assert!(opposite(flo, fhi));
        assert_eq!(screen(&p, 0.0, 10.0, Question::Any), Screen::Some);
        // Past all roots: empty.
        assert_eq!(screen(&p, 7.5, 1e6, Question::Nearest), Screen::Empty);
    }

    #[test]
    fn a_cut_never_passes_the_nearest_root() {
        // A ray through the top of POV-Ray's torus.pov: roots 31.503 and
        // 36.442 after a complex pair at 24.66 ± 9.70i. A cut that looked
        // only at the control points below zero skipped the first root.
        let p = PolyN::<5>::new(&[
            1574.0312499999998,
            -203.73211424953368,
            10.157571696269468,
            -0.22902205699660633,
            0.001953125000000001,
        ]);
        let Screen::Nearest { lo, hi, .. } = screen(&p, 0.0, 1.8e7, Question::Nearest) else {
            panic!("not isolated");
        };
        assert!(lo < 31.503 && 31.504 < hi && hi < 36.44, "[{lo}, {hi}]");
    }

    #[test]
    fn what_it_cannot_prove_goes_to_the_chain() {
        // A double root at 1 (a tangent ray): never two sign changes apart.
        let p = quartic([1.0, 1.0, 3.0, 4.0]);
        assert_eq!(screen(&p, 0.0, 10.0, Question::Nearest), Screen::Unsure);
        // A root at the interval's start: its sign is noise.
        let p = quartic([0.0, 1.5, 3.0, 4.0]);
        assert_eq!(screen(&p, 0.0, 10.0, Question::Nearest), Screen::Unsure);
        // Roots 1e-9 apart are not separated within the depth.
        let p = quartic([1.0, 1.0 + 1e-9, 3.0, 4.0]);
        assert_eq!(screen(&p, 0.0, 10.0, Question::Nearest), Screen::Unsure);
    }

    #[test]
    fn non_finite_input_is_left_to_the_chain() {
        let p = PolyN::<5>::new(&[f64::INFINITY, 1.0, 1.0]);
        assert_eq!(screen(&p, 0.0, 1.0, Question::Any), Screen::Unsure);
        let p = PolyN::<5>::new(&[1.0, 1.0, f64::NAN]);
        assert_eq!(screen(&p, 0.0, 1.0, Question::Nearest), Screen::Unsure);
        // Coefficients 600 orders apart, but all positive: no root above 0.
        let p = PolyN::<5>::new(&[1e300, 1e-300, 1e-300, 1e-300, 1e-300]);
        assert_eq!(screen(&p, 0.0, 1.0, Question::Any), Screen::Empty);
    }
}
