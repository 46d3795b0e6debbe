//! Input conditioning: the part of (a, b] a query searches (clipped to a
//! root bound, negligible terms trimmed where the chain degenerates), and
//! the f64 interval helpers the methods share (midpoints by value and by
//! bit pattern, nudges strictly inside an interval).

use crate::math::{larger, smaller};
use crate::poly::sturm::SturmSequence;
use crate::poly::univariate::PolyN;

use super::isolate::Bracket;

/// What a query searches: the chain that counts, the polynomial that
/// refines, and the part of (a, b] that can hold roots.
pub(super) struct Search<const S: usize> {
    pub(super) seq: SturmSequence<S>,
    /// The input's square-free part (the input, normalised, unless its own
    /// chain found a common factor), kept when the chain counts a trimmed
    /// version of the input (`trimmed`).
    input: PolyN<S>,
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
pub(super) const DEGENERATE_TRIM: f64 = 1e-8;

impl<const S: usize> Search<S> {
    /// Storage for [`Search::prepare`]: a chain is some 5 KB, so queries
    /// build it in place on their own stack instead of returning it.
    pub(super) const EMPTY: Self = Self {
        seq: SturmSequence::EMPTY,
        input: PolyN::ZERO,
        trimmed: false,
        lo: 0.0,
        hi: 0.0,
    };

    /// Sets up the search of (a, b] for roots of `p`; false if no root can
    /// lie there (or `p` is constant).
    pub(super) fn prepare(&mut self, p: &PolyN<S>, a: f64, b: f64) -> bool {
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
            if trimmed != p.truncated(degree) {
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
    pub(super) fn refine(&self) -> &PolyN<S> {
        if self.trimmed && self.seq.gcd().degree() == 0 {
            &self.input
        } else {
            self.seq.squarefree()
        }
    }

    /// The input's square-free part, where [`Search::refine`] is the
    /// trimmed one's: the better polynomial wherever it changes sign.
    pub(super) fn untrimmed(&self) -> Option<&PolyN<S>> {
        (self.trimmed && self.seq.gcd().degree() > 0).then_some(&self.input)
    }

    pub(super) fn whole(&self) -> Bracket {
        Bracket::new(&self.seq, self.lo, self.hi)
    }

    /// Whether the search ends at the caller's `b` and `b` is an exact
    /// root, which the open queries exclude.
    pub(super) fn root_at_end(&self, b: f64) -> bool {
        self.hi == b && self.refine().eval(b) == 0.0
    }
}

/// (a, b) narrowed to Cauchy's bound, |t| < 1 + max |c_i / c_n| for every
/// root, so bisection starts from finite ends; `None` if nothing is left or
/// the polynomial is constant (no isolated roots).
pub(super) fn clip_to_root_bound<const S: usize>(
    p: &PolyN<S>,
    a: f64,
    b: f64,
) -> Option<(f64, f64)> {
    let (lead, rest) = p.coeffs().split_last()?;
    if rest.is_empty() {
        return None;
    }
    let max_rest = rest.iter().fold(0.0, |m: f64, c| larger(m, c.abs()));
    let bound = (2.0 + max_rest / lead.abs() * (1.0 + 1e-9)).min(f64::MAX);
    // a and b are never NaN (callers check the interval).
    let (lo, hi) = (larger(a, -bound), smaller(b, bound));
    (lo < hi).then_some((lo, hi))
}

/// The degree of `p` without the leading terms that stay below `rel` times
/// its largest term everywhere in |t| <= `t_max`. Such a term moves roots
/// inside the interval by no more than its size, and its own roots lie far
/// outside. Unlike [`Poly::trimmed`] this judges terms where they are
/// evaluated, so it never drops a small leading coefficient that matters on
/// a wide interval.
pub(super) fn negligible_above<const S: usize>(p: &PolyN<S>, t_max: f64, rel: f64) -> usize {
    let mut terms = [0.0; S];
    let mut power = 1.0;
    for (term, ci) in terms.iter_mut().zip(p.coeffs()) {
        *term = ci.abs() * power;
        power *= t_max;
    }
    // Against the lower terms only: a term that overflows to infinity at
    // t_max must not make every other term look negligible. `below[i]` is
    // the largest of terms[..i], one pass instead of one per degree.
    let mut below = [0.0f64; S];
    for i in 1..=p.degree() {
        below[i] = larger(below[i - 1], terms[i - 1]);
    }
    let mut degree = p.degree();
    while degree > 0 {
        if terms[degree] > rel * below[degree] {
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
pub(super) fn without_negligible_terms<const S: usize>(
    p: &PolyN<S>,
    t_max: f64,
    rel: f64,
) -> PolyN<S> {
    let degree = negligible_above(p, t_max, rel);
    let c = p.coeffs();
    let mut out = [0.0; S];
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
    PolyN::<S>::from_array(out, degree)
}

/// Whether (a, b) is a non-empty interval; false for NaN ends.
pub(super) fn is_interval(a: f64, b: f64) -> bool {
    a < b
}

pub(super) fn opposite(x: f64, y: f64) -> bool {
    (x < 0.0 && y > 0.0) || (x > 0.0 && y < 0.0)
}

pub(super) fn midpoint(lo: f64, hi: f64) -> f64 {
    0.5 * lo + 0.5 * hi
}

/// Brackets wider than this many tolerances are halved by [`bit_midpoint`]:
/// 2^60 takes 60 halvings, well within the default 100 steps.
pub(super) const WIDE_BRACKET: f64 = (1u64 << 60) as f64;

/// The f64 halfway between lo < hi in the order of f64 values: 0 when the
/// bracket holds it, else the mean of the magnitudes' bit patterns (which
/// grow with the magnitude for non-negative floats).
pub(super) fn bit_midpoint(lo: f64, hi: f64) -> f64 {
    if lo < 0.0 && hi > 0.0 {
        0.0
    } else if hi <= 0.0 {
        -bit_midpoint(-hi, -lo)
    } else {
        f64::from_bits((lo.abs().to_bits() + hi.to_bits()) / 2)
    }
}

/// `t` moved, if needed, to the nearest f64 strictly inside (a, b): a root
/// within tolerance of an end may be refined onto it, and callers compare
/// hits against the open interval.
pub(super) fn strictly_inside(t: f64, a: f64, b: f64) -> f64 {
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
pub(super) fn above(x: f64) -> f64 {
    let near_zero = (-f64::MIN_POSITIVE..f64::MIN_POSITIVE).contains(&x);
    if !near_zero {
        x.next_up()
    } else if x < 0.0 {
        0.0
    } else {
        f64::MIN_POSITIVE
    }
}

pub(super) fn below(x: f64) -> f64 {
    -above(-x)
}
