//! Univariate polynomials in f64 with fixed storage, so that the per-ray
//! root finders never allocate.

use crate::math::larger;
use crate::poly::MAX_DEGREE;

/// Number of coefficient slots of [`Poly`]: a polynomial of degree
/// `MAX_DEGREE` has one more coefficient than its degree.
pub const SLOTS: usize = MAX_DEGREE + 1;

/// Slots of the small instantiation, [`SmallPoly`]: degree <= 16, the limit
/// before degree 35 was allowed. Every query of the solver on such a
/// polynomial runs on chains of this size, so spheres, quadrics, tori and
/// most algebraic surfaces pay nothing for the higher limit (a chain is
/// quadratic in the slot count: 5 KB at 17 slots, 21 KB at 36, and a ray
/// sets one up per query).
pub const SMALL_SLOTS: usize = 17;

/// Slots of the quartic instantiation: degree <= 4, what spheres, quadrics,
/// tori and POV-Ray's quartics give. At 17 slots a degree-4 query spent
/// more on zeroing and copying its 5 KB chain than on the arithmetic (23%
/// of the instructions of POV-Ray's torus.pov, `valgrind --tool=callgrind`);
/// at 5 slots the chain is 0.4 KB. The arithmetic is the same, so the
/// roots are the same bits.
pub const QUARTIC_SLOTS: usize = 5;

/// A polynomial of degree at most [`MAX_DEGREE`]: what callers build.
pub type Poly = PolyN<SLOTS>;

/// A polynomial of degree at most `SMALL_SLOTS - 1`, for the solver's
/// low-degree instantiation.
pub type SmallPoly = PolyN<SMALL_SLOTS>;

/// A polynomial of degree at most `S - 1`, coefficients lowest degree
/// first, in `S` fixed slots.
///
/// Invariant: the leading coefficient is nonzero unless the polynomial is a
/// constant, and every slot above the degree holds `0.0`, so that the derived
/// `PartialEq` compares polynomials, not leftovers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolyN<const S: usize> {
    coeffs: [f64; S],
    degree: usize,
}

impl<const S: usize> Default for PolyN<S> {
    fn default() -> Self {
        Self::ZERO
    }
}

impl<const S: usize> PolyN<S> {
    pub const ZERO: Self = Self {
        coeffs: [0.0; S],
        degree: 0,
    };

    /// Builds a polynomial from coefficients, lowest degree first; exact zero
    /// leading coefficients are dropped (use [`Poly::trimmed`] for
    /// round-off-sized ones).
    ///
    /// # Panics
    /// If `coeffs.len() > MAX_DEGREE + 1`: callers validate degrees at the
    /// input boundary (the parser, the `roots` tool).
    pub fn new(coeffs: &[f64]) -> Self {
        assert!(
            coeffs.len() <= S,
            "polynomial of degree {} exceeds MAX_DEGREE = {}",
            coeffs.len().saturating_sub(1),
            S - 1
        );
        let mut array = [0.0; S];
        array[..coeffs.len()].copy_from_slice(coeffs);
        Self::from_array(array, coeffs.len().saturating_sub(1))
    }

    /// Builds from a full coefficient array whose slots above `degree` are
    /// ignored; trims exact zero leading coefficients. For the arithmetic of
    /// this module and the Sturm chain, which work on arrays in place.
    pub(crate) fn from_array(mut coeffs: [f64; S], degree: usize) -> Self {
        let degree = degree.min(S - 1);
        coeffs[degree + 1..].fill(0.0);
        let mut p = Self { coeffs, degree };
        p.trim_zeros();
        p
    }

    /// The same polynomial in `T` slots, if its degree fits: the solver
    /// moves low-degree input into its small instantiation this way.
    pub fn resized<const T: usize>(&self) -> Option<PolyN<T>> {
        (self.degree < T).then(|| {
            // Slots above the degree hold zeros, so a copy of fixed length
            // (no call to memcpy, as a copy of `degree + 1` makes) will do.
            let n = S.min(T);
            let mut coeffs = [0.0; T];
            coeffs[..n].copy_from_slice(&self.coeffs[..n]);
            PolyN {
                coeffs,
                degree: self.degree,
            }
        })
    }

    /// The polynomial without its terms above `degree` (itself if there
    /// are none).
    pub fn truncated(&self, degree: usize) -> Self {
        if degree >= self.degree {
            *self
        } else {
            Self::from_array(self.coeffs, degree)
        }
    }

    /// The coefficients, lowest degree first; `degree() + 1` of them.
    pub fn coeffs(&self) -> &[f64] {
        &self.coeffs[..=self.degree]
    }

    pub fn degree(&self) -> usize {
        self.degree
    }

    pub fn is_zero(&self) -> bool {
        self.degree == 0 && self.coeffs[0] == 0.0
    }

    /// The leading coefficient (the constant term for a constant).
    pub fn leading(&self) -> f64 {
        self.coeffs[self.degree]
    }

    pub fn eval(&self, t: f64) -> f64 {
        let c = self.coeffs();
        let mut value = c[self.degree];
        for &ci in c[..self.degree].iter().rev() {
            value = value * t + ci;
        }
        value
    }

    /// Value and first derivative by one Horner pass: Newton needs both at
    /// every step, and one pass halves the work.
    pub fn eval_with_derivative(&self, t: f64) -> (f64, f64) {
        let c = self.coeffs();
        let mut value = c[self.degree];
        let mut slope = 0.0;
        for &ci in c[..self.degree].iter().rev() {
            slope = slope * t + value;
            value = value * t + ci;
        }
        (value, slope)
    }

    /// The sign of p(x) as -1, 0 or 1, 0 unless the value computed by
    /// Horner's rule exceeds its rounding error bound, 2n eps times the sum
    /// of |c_i x^i| (Higham's bound is half that; the margin covers the
    /// bound's own rounding).
    pub(crate) fn sure_sign(&self, x: f64) -> f64 {
        let (mut value, mut size) = (0.0, 0.0);
        for &c in self.coeffs().iter().rev() {
            value = value * x + c;
            size = size * x.abs() + c.abs();
        }
        let bound = 2.0 * self.degree as f64 * f64::EPSILON * size;
        if value.abs() > bound {
            value.signum()
        } else {
            0.0
        }
    }

    pub fn derivative(&self) -> Self {
        if self.degree == 0 {
            return Self::ZERO;
        }
        let mut out = [0.0; S];
        for (i, slot) in out[..self.degree].iter_mut().enumerate() {
            *slot = (i + 1) as f64 * self.coeffs[i + 1];
        }
        Self::from_array(out, self.degree - 1)
    }

    /// Quotient and remainder of long division; the remainder's degree is
    /// below the divisor's (its top slots are set to zero exactly rather than
    /// left as round-off, since they cancel by construction).
    ///
    /// # Panics
    /// If `divisor` is the zero polynomial, like integer division by zero.
    pub fn div_rem(&self, divisor: &Self) -> (Self, Self) {
        assert!(!divisor.is_zero(), "polynomial division by zero");
        let m = divisor.degree;
        if self.degree < m {
            return (Self::ZERO, *self);
        }
        let mut rem = self.coeffs;
        let mut quot = [0.0; S];
        let lead = divisor.leading();
        for k in (0..=self.degree - m).rev() {
            let q = rem[k + m] / lead;
            quot[k] = q;
            rem[k + m] = 0.0;
            for j in 0..m {
                rem[k + j] -= q * divisor.coeffs[j];
            }
        }
        let rem_degree = m.saturating_sub(1);
        (
            Self::from_array(quot, self.degree - m),
            Self::from_array(rem, rem_degree),
        )
    }

    /// Drops leading terms that are negligible on [0, len]: c_n with
    /// |c_n| len^n <= rel * max |c_k| len^k over the lower terms. A ray nearly
    /// parallel to a cylinder's axis makes the t^2 coefficient round-off
    /// noise, and keeping it would put a spurious root near infinity and make
    /// every division by the polynomial ill-conditioned. The terms are
    /// compared by what they contribute over the interval, not coefficient by
    /// coefficient: along a sphere of radius 1e8 the t^2 coefficient is 1 and
    /// the constant 1e16, yet both matter equally. Lengths below 1 count as 1
    /// (then the comparison is the plain coefficients', which keeps more).
    /// Takes `self` by value and trims it in place: a ray's Q goes straight
    /// from `Surface::along` through here, and a copy of the full-size
    /// storage per call showed as memmove in the profile.
    pub fn trimmed(mut self, rel: f64, len: f64) -> Self {
        // 1/len^j, computed by repeated multiplication: at most 1, so it
        // underflows harmlessly instead of overflowing at high degree.
        let shrink = 1.0 / len.max(1.0);
        let mut degree = self.degree;
        while degree > 0 {
            let mut weight = 1.0;
            let mut largest = 0.0f64;
            for c in self.coeffs[..degree].iter().rev() {
                weight *= shrink;
                largest = larger(largest, c.abs() * weight);
            }
            if self.coeffs[degree].abs() > rel * largest {
                break;
            }
            degree -= 1;
        }
        self.coeffs[degree + 1..].fill(0.0);
        self.degree = degree;
        self.trim_zeros();
        self
    }

    /// NaN coefficients are ignored, as `f64::max` would; written as a plain
    /// comparison because `f64::max`'s NaN handling costs several
    /// instructions per coefficient, and this runs for every chain member.
    pub fn max_abs_coeff(&self) -> f64 {
        self.coeffs().iter().fold(0.0, |m, c| {
            let a = c.abs();
            if a > m { a } else { m }
        })
    }

    pub fn scaled(&self, factor: f64) -> Self {
        let mut out = self.coeffs;
        for c in &mut out[..=self.degree] {
            *c *= factor;
        }
        Self::from_array(out, self.degree)
    }

    /// Scaled by a power of two so the largest |coefficient| lands in
    /// [1, 4). A power of two is positive (signs, hence Sturm counts, are
    /// kept) and exact (no rounding is added). Coefficients left subnormal
    /// are set to zero, so results do not depend on whether the thread
    /// flushes subnormals (render threads do). Infinite or NaN coefficients
    /// are left alone: there is no meaningful scale.
    pub fn normalized(&self) -> Self {
        let mut out = *self;
        out.normalize();
        out
    }

    /// [`Poly::normalized`] in place; returns the factor applied (1 when
    /// there was no finite scale), so error estimates can follow.
    pub(crate) fn normalize(&mut self) -> f64 {
        let max = self.max_abs_coeff();
        if !max.is_finite() {
            return 1.0;
        }
        if max < f64::MIN_POSITIVE {
            *self = Self::ZERO;
            return 1.0;
        }
        let factor = pow2_reciprocal(max);
        for c in &mut self.coeffs[..=self.degree] {
            let scaled = *c * factor;
            *c = if scaled.abs() < f64::MIN_POSITIVE {
                0.0
            } else {
                scaled
            };
        }
        self.trim_zeros();
        factor
    }

    /// Drops exact zero leading coefficients (restores the invariant after
    /// arithmetic in place).
    fn trim_zeros(&mut self) {
        while self.degree > 0 && self.coeffs[self.degree] == 0.0 {
            self.coeffs[self.degree] = 0.0;
            self.degree -= 1;
        }
    }

    /// Negated in place: the Sturm chain's next member is minus a remainder.
    pub(crate) fn negate(&mut self) {
        for c in &mut self.coeffs[..=self.degree] {
            *c = -*c;
        }
    }
}

/// In-place arithmetic for the Sturm chain, which writes each member once
/// into fixed storage: returning 144-byte polynomials by value and copying
/// them into place costs more than the arithmetic at low degree. Each
/// keeps the invariant (zeros above the degree) whatever the slot held.
impl<const S: usize> PolyN<S> {
    /// Overwrites `self` with the first `degree + 1` coefficients of `p`
    /// (`p` truncated to that degree, exact zero leading ones trimmed).
    pub(crate) fn set_truncated(&mut self, p: &Self, degree: usize) {
        let degree = degree.min(p.degree);
        self.coeffs[degree + 1..=self.degree.max(degree)].fill(0.0);
        self.coeffs[..=degree].copy_from_slice(&p.coeffs[..=degree]);
        self.degree = degree;
        self.trim_zeros();
    }

    /// Overwrites `self` with p'.
    pub(crate) fn set_derivative(&mut self, p: &Self) {
        let old = self.degree;
        let degree = p.degree.saturating_sub(1);
        for i in 0..=degree {
            self.coeffs[i] = (i + 1) as f64 * p.coeffs[i + 1];
        }
        self.coeffs[degree + 1..=old.max(degree)].fill(0.0);
        self.degree = degree;
        self.trim_zeros();
    }

    /// Overwrites `self` with rem(a, d) for deg a >= deg d > 0, of degree
    /// deg d - 1 before trimming, and `quotient` with the quotient's
    /// coefficients (lowest first), from which the caller bounds the error.
    pub(crate) fn set_remainder(&mut self, a: &Self, d: &Self, quotient: &mut [f64; S]) {
        let (n, m) = (a.degree, d.degree);
        debug_assert!(n >= m && m > 0);
        let mut r = a.coeffs;
        let lead = d.leading();
        for k in (0..=n - m).rev() {
            let q = r[k + m] / lead;
            quotient[k] = q;
            for (rj, dj) in r[k..k + m].iter_mut().zip(&d.coeffs[..m]) {
                *rj -= q * dj;
            }
        }
        let old = self.degree;
        self.coeffs[..m].copy_from_slice(&r[..m]);
        self.coeffs[m..=old.max(m - 1)].fill(0.0);
        self.degree = m - 1;
        self.trim_zeros();
    }

    /// Drops leading coefficients with |c| <= `noise`; the zero polynomial
    /// if every coefficient is that small.
    pub(crate) fn drop_noise(&mut self, noise: f64) {
        while self.degree > 0 && self.coeffs[self.degree].abs() <= noise {
            self.coeffs[self.degree] = 0.0;
            self.degree -= 1;
        }
        if self.degree == 0 && self.coeffs[0].abs() <= noise {
            self.coeffs[0] = 0.0;
        }
    }
}

/// 2^-e where 2^e <= x < 2^(e+1) for a positive normal `x`, with e capped at
/// 1022 so the result is never subnormal (which FTZ/DAZ would zero).
pub(crate) fn pow2_reciprocal(x: f64) -> f64 {
    let biased = ((x.to_bits() >> 52) & 0x7ff) as i64; // 1..=2046 for normals
    let e = (biased - 1023).min(1022);
    f64::from_bits(((1023 - e) as u64) << 52)
}

/// The bits of x, hidden from the optimiser: LLVM turns bit tests like
/// `bits << 1 != 0` back into float comparisons (`x != 0.0`), which a
/// thread that reads subnormals as zero (sturmray's do) answers wrongly.
fn opaque_bits(x: f64) -> u64 {
    std::hint::black_box(x.to_bits())
}

/// x ≠ 0, from the bits: true for subnormals whatever the thread's FTZ/DAZ
/// mode.
pub fn nonzero(x: f64) -> bool {
    opaque_bits(x) << 1 != 0
}

/// ⌊log2 |x|⌋ for finite nonzero x, read from the bits, so it is exact for
/// subnormals too and does not depend on the thread's FTZ/DAZ mode.
pub(crate) fn log2_floor(x: f64) -> i32 {
    let bits = opaque_bits(x) & !(1 << 63);
    let biased = (bits >> 52) as i32;
    if biased == 0 {
        // Subnormal: the value is bits · 2^-1074.
        63 - bits.leading_zeros() as i32 - 1074
    } else {
        biased - 1023
    }
}

/// 2^k for k in [-1022, 1023]: a normal number, built from its bits.
fn pow2(k: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&k));
    f64::from_bits(((1023 + k) as u64) << 52)
}

/// x · 2^n, exact unless the result overflows or falls below the normal
/// range (C's `scalbn`, after musl): the factor is applied in steps that
/// are each a normal power of two, and a result in the subnormal range is
/// rounded once, not twice. x is read from its bits as an integer times a
/// power of two, so a subnormal x is scaled exactly even on a thread that
/// reads subnormals as zero (sturmray's threads do, main included).
pub(crate) fn scale_pow2(x: f64, n: i32) -> f64 {
    let (mantissa, exponent, sign) =
        num_traits::Float::integer_decode(f64::from_bits(opaque_bits(x)));
    // mantissa < 2^53: an exact, normal f64 (or 0).
    let mut y = f64::from(sign) * mantissa as f64;
    let mut n = n.saturating_add(i32::from(exponent));
    if n > 1023 {
        y *= pow2(1023);
        n -= 1023;
        if n > 1023 {
            y *= pow2(1023);
            n = (n - 1023).min(1023);
        }
    } else if n < -1022 {
        // 2^-969 = 2^-1022 · 2^53: the last step then lands below -53.
        y *= pow2(-969);
        n += 969;
        if n < -1022 {
            y *= pow2(-969);
            n = (n + 969).max(-1022);
        }
    }
    y * pow2(n)
}

/// Scales the coefficients by the power of two that puts the largest
/// |coefficient| in [1, 2), so F and k·F (any finite k ≠ 0) become the same
/// polynomial up to the rounding of k·F itself, and nothing downstream
/// overflows or underflows for the input's scale alone. A power of two is
/// positive (signs are kept) and exact for every coefficient that stays in
/// the normal range, subnormal inputs included (they are scaled up).
/// Coefficients more than 2^1022 below the largest end up below the normal
/// range: they are set to 0, negligible beside it and read as 0 by threads
/// that flush subnormals anyway. All zeros (the exact test, `== 0.0` on
/// every coefficient) stay zeros. Returns the exponent k of the factor 2^k,
/// or None if a coefficient is not finite (then nothing is changed).
pub fn normalize_pow2(coeffs: &mut [f64]) -> Option<i32> {
    if coeffs.iter().any(|c| !c.is_finite()) {
        return None;
    }
    let Some(largest) = coeffs
        .iter()
        .filter(|&&c| nonzero(c))
        .map(|&c| log2_floor(c))
        .max()
    else {
        return Some(0);
    };
    let k = -largest;
    for c in coeffs.iter_mut() {
        *c = scale_pow2_normal(*c, k);
    }
    Some(k)
}

/// [`scale_pow2`], with a result below the normal range set to 0 (the
/// same on threads that flush subnormals and threads that do not).
pub(crate) fn scale_pow2_normal(x: f64, n: i32) -> f64 {
    let scaled = scale_pow2(x, n);
    if scaled.abs() < f64::MIN_POSITIVE {
        0.0
    } else {
        scaled
    }
}

/// `lead` times the product of (t - r) over `roots`, expanded in f64: the
/// tests' independent reference, since the roots are known by construction,
/// and the accuracy study's synthetic cases.
pub(crate) fn from_roots(lead: f64, roots: &[f64]) -> Poly {
    let mut c = vec![lead];
    for &r in roots {
        let mut next = vec![0.0; c.len() + 1];
        for (i, &ci) in c.iter().enumerate() {
            next[i + 1] += ci;
            next[i] -= r * ci;
        }
        c = next;
    }
    Poly::new(&c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn new_trims_exact_zero_leading_coefficients() {
        let p = Poly::new(&[1.0, 2.0, 0.0, -0.0]);
        assert_eq!(p.degree(), 1);
        assert_eq!(p.coeffs(), &[1.0, 2.0]);
        assert_eq!(Poly::new(&[]), Poly::ZERO);
        assert_eq!(Poly::new(&[0.0, 0.0]), Poly::ZERO);
        assert!(Poly::ZERO.is_zero());
        assert_eq!(Poly::ZERO.coeffs(), &[0.0]);
        assert!(!Poly::new(&[3.0]).is_zero());
    }

    #[test]
    #[should_panic(expected = "exceeds MAX_DEGREE")]
    fn new_panics_above_max_degree() {
        Poly::new(&[1.0; MAX_DEGREE + 2]);
    }

    #[test]
    fn max_degree_is_accepted() {
        let p = Poly::new(&[1.0; MAX_DEGREE + 1]);
        assert_eq!(p.degree(), MAX_DEGREE);
        assert_eq!(p.eval(1.0), (MAX_DEGREE + 1) as f64);
    }

    #[test]
    fn eval_and_derivative_agree_with_hand_values() {
        // 2t^3 - 3t + 1: p(2) = 11, p'(t) = 6t^2 - 3, p'(2) = 21.
        let p = Poly::new(&[1.0, -3.0, 0.0, 2.0]);
        assert_eq!(p.eval(2.0), 11.0);
        assert_eq!(p.eval_with_derivative(2.0), (11.0, 21.0));
        assert_eq!(p.derivative(), Poly::new(&[-3.0, 0.0, 6.0]));
        assert_eq!(Poly::new(&[5.0]).derivative(), Poly::ZERO);
        assert_eq!(Poly::new(&[5.0]).eval_with_derivative(7.0), (5.0, 0.0));
    }

    #[test]
    fn div_rem_reconstructs_the_dividend() {
        // (t^3 - 2t^2 - 4) / (t - 3) = t^2 + t + 3, remainder 5.
        let p = Poly::new(&[-4.0, 0.0, -2.0, 1.0]);
        let (q, r) = p.div_rem(&Poly::new(&[-3.0, 1.0]));
        assert_eq!(q, Poly::new(&[3.0, 1.0, 1.0]));
        assert_eq!(r, Poly::new(&[5.0]));
        // Exact division leaves the zero polynomial.
        let (q, r) = Poly::new(&[-1.0, 0.0, 1.0]).div_rem(&Poly::new(&[1.0, 1.0]));
        assert_eq!(q, Poly::new(&[-1.0, 1.0]));
        assert!(r.is_zero());
        // A divisor of higher degree leaves the dividend as remainder.
        let (q, r) = Poly::new(&[1.0, 1.0]).div_rem(&p);
        assert!(q.is_zero());
        assert_eq!(r, Poly::new(&[1.0, 1.0]));
    }

    #[test]
    #[should_panic(expected = "division by zero")]
    fn div_rem_by_zero_panics() {
        Poly::new(&[1.0, 1.0]).div_rem(&Poly::ZERO);
    }

    #[test]
    fn trimmed_drops_round_off_leading_terms() {
        let p = Poly::new(&[2.0, -1.0, 1e-17, -3e-18]);
        assert_eq!(p.trimmed(1e-14, 1.0), Poly::new(&[2.0, -1.0]));
        assert_eq!(p.trimmed(0.0, 1.0), p);
        assert_eq!(Poly::new(&[1e-20, 0.0]).trimmed(1e-14, 1.0).degree(), 0);
        // Along a sphere of radius 1e8 from its bounding box: t^2 matters as
        // much as the constant over the 2e8 the ray crosses.
        let sphere = Poly::new(&[-1e16, 2e8, 1.0]);
        assert_eq!(sphere.trimmed(1e-14, 2e8), sphere);
        // Noise is still noise over a long interval.
        let noisy = Poly::new(&[-1e16, 2e8, 1e-20]);
        assert_eq!(noisy.trimmed(1e-14, 2e8).degree(), 1);
        // Over a huge interval the weights underflow, never overflow.
        let mut long = [0.0; MAX_DEGREE + 1];
        long[0] = 1.0;
        long[MAX_DEGREE] = 1.0;
        assert_eq!(Poly::new(&long).trimmed(1e-14, 1e300).degree(), MAX_DEGREE);
    }

    #[test]
    fn scaling_and_normalisation_keep_signs() {
        let p = Poly::new(&[-3.0, 0.5, 6.0]);
        assert_eq!(p.max_abs_coeff(), 6.0);
        assert_eq!(p.scaled(2.0), Poly::new(&[-6.0, 1.0, 12.0]));
        assert!(p.scaled(0.0).is_zero());
        let n = Poly::new(&[-3e-200, 1e-201, -6e-200]).normalized();
        assert!(n.max_abs_coeff() >= 1.0 && n.max_abs_coeff() < 4.0);
        assert!(n.coeffs()[0] < 0.0 && n.coeffs()[1] > 0.0 && n.coeffs()[2] < 0.0);
        assert_eq!(Poly::new(&[1e-310, 1e-320]).normalized(), Poly::ZERO);
        let big = Poly::new(&[f64::MAX, -f64::MAX]).normalized();
        assert!(big.max_abs_coeff() >= 1.0 && big.max_abs_coeff() < 4.0);
    }

    #[test]
    fn in_place_arithmetic_matches_and_clears_stale_slots() {
        let p = Poly::new(&[-4.0, 0.0, -2.0, 1.0]);
        let d = Poly::new(&[-3.0, 1.0]);
        // Slots that held a higher-degree polynomial must end up zero.
        let mut slot = Poly::new(&[9.0; MAX_DEGREE + 1]);
        let mut quotient = [0.0; SLOTS];
        slot.set_remainder(&p, &d, &mut quotient);
        let (q, r) = p.div_rem(&d);
        assert_eq!(slot, r);
        assert_eq!(&quotient[..3], q.coeffs());
        slot = Poly::new(&[9.0; MAX_DEGREE + 1]);
        slot.set_derivative(&p);
        assert_eq!(slot, p.derivative());
        slot = Poly::new(&[9.0; MAX_DEGREE + 1]);
        slot.set_truncated(&p, 2);
        assert_eq!(slot, Poly::new(&[-4.0, 0.0, -2.0]));
        slot.set_truncated(&p, 1);
        assert_eq!(slot, Poly::new(&[-4.0]), "exact zero leading terms trimmed");
        let mut noisy = Poly::new(&[1.0, 2.0, 1e-17, -1e-17]);
        noisy.drop_noise(1e-16);
        assert_eq!(noisy, Poly::new(&[1.0, 2.0]));
        noisy.drop_noise(5.0);
        assert!(noisy.is_zero());
        let mut q = Poly::new(&[1.0, -3.0]);
        q.negate();
        assert_eq!(q, Poly::new(&[-1.0, 3.0]));
    }

    #[test]
    fn pow2_reciprocal_is_exact_and_normal() {
        assert_eq!(pow2_reciprocal(1.0), 1.0);
        assert_eq!(pow2_reciprocal(3.0), 0.5);
        assert_eq!(pow2_reciprocal(0.3), 4.0);
        assert!(pow2_reciprocal(f64::MAX).is_normal());
        assert!(pow2_reciprocal(f64::MIN_POSITIVE).is_normal());
    }
}
