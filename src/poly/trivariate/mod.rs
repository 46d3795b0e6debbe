//! Trivariate polynomials F(x, y, z) in f64: the implicit form of algebraic
//! surfaces. The renderer substitutes each ray into F to get the univariate
//! Q(t) whose roots are hits, and evaluates the gradient for normals.
//!
//! Every polynomial here has total degree at most [`MAX_DEGREE`], so the
//! per-ray work can live in fixed-size stack arrays. Products while
//! expanding an expression are sparse lists of terms, merged by a stable
//! sort.

use std::fmt;

mod quartic;
mod range;
use quartic::Quartic;
#[cfg(test)]
use quartic::linear_powers;
pub use range::Dense;

use crate::poly::MAX_DEGREE;
use crate::poly::univariate::{
    QUARTIC_SLOTS, SMALL_SLOTS, nonzero, normalize_pow2, scale_pow2_normal,
};

/// Exponents per axis: 0..=MAX_DEGREE.
const SIDE: usize = MAX_DEGREE + 1;

/// A polynomial in x, y, z with f64 coefficients.
///
/// Monomials are kept sorted in descending lexicographic order of their
/// exponents (all powers of x first, highest first; within one power of x,
/// by y, then z), merged, with zero coefficients dropped. That order is the
/// nesting [`Trivariate::substitute_ray`] walks, and it makes equality of
/// polynomials plain equality of the term lists.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Trivariate {
    terms: Vec<([u8; 3], f64)>,
    degree: usize,
    /// The terms as `substitute_ray` reads them at degree 4 or less: a
    /// function of `terms`, built with them.
    #[serde(skip)]
    quartic: Option<Box<Quartic>>,
}

fn total(e: [u8; 3]) -> usize {
    usize::from(e[0]) + usize::from(e[1]) + usize::from(e[2])
}

impl Trivariate {
    /// The polynomial of `terms` (sorted, merged, no zeros) and `degree`.
    fn assemble(terms: Vec<([u8; 3], f64)>, degree: usize) -> Trivariate {
        let quartic = Quartic::of(&terms, degree);
        Trivariate {
            terms,
            degree,
            quartic,
        }
    }

    /// The zero polynomial (degree 0, no terms).
    pub fn zero() -> Trivariate {
        Trivariate::assemble(Vec::new(), 0)
    }

    /// The constant polynomial `c`.
    pub fn constant(c: f64) -> Trivariate {
        Trivariate::from_terms([([0, 0, 0], c)])
    }

    /// The variable x (`axis` 0), y (1) or z (2).
    ///
    /// # Panics
    /// If `axis` > 2.
    pub fn variable(axis: usize) -> Trivariate {
        let mut e = [0; 3];
        e[axis] = 1;
        Trivariate::from_terms([(e, 1.0)])
    }

    /// Builds a polynomial from monomials in any order; coefficients of equal
    /// exponents are summed and zero results dropped.
    ///
    /// # Panics
    /// If a monomial with a nonzero (merged) coefficient has total degree above
    /// [`MAX_DEGREE`]: the per-ray storage is sized by that limit.
    pub fn from_terms(terms: impl IntoIterator<Item = ([u8; 3], f64)>) -> Trivariate {
        let mut sorted: Vec<([u8; 3], f64)> = terms.into_iter().collect();
        sorted.sort_by_key(|&(e, _)| std::cmp::Reverse(e));
        let mut merged: Vec<([u8; 3], f64)> = Vec::with_capacity(sorted.len());
        for (e, c) in sorted {
            match merged.last_mut() {
                Some(last) if last.0 == e => last.1 += c,
                _ => merged.push((e, c)),
            }
        }
        merged.retain(|&(_, c)| nonzero(c));
        let degree = merged.iter().map(|&(e, _)| total(e)).max().unwrap_or(0);
        assert!(
            degree <= MAX_DEGREE,
            "a trivariate polynomial of degree {degree} exceeds MAX_DEGREE = {MAX_DEGREE}"
        );
        Trivariate::assemble(merged, degree)
    }

    /// The monomials: exponents of (x, y, z) and coefficient, sorted as the
    /// type's documentation describes, no zero coefficients.
    pub fn terms(&self) -> &[([u8; 3], f64)] {
        &self.terms
    }

    /// Total degree; 0 for constants and for the zero polynomial.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// True for the zero polynomial.
    pub fn is_zero(&self) -> bool {
        self.terms.is_empty()
    }

    /// The value of a polynomial that does not depend on x, y or z, else
    /// `None`.
    pub fn constant_value(&self) -> Option<f64> {
        match self.terms.as_slice() {
            [] => Some(0.0),
            [([0, 0, 0], c)] => Some(*c),
            _ => None,
        }
    }

    /// True when every coefficient is finite: expansion can overflow, and an
    /// infinite coefficient would turn every Q(t) into NaN.
    pub fn is_finite(&self) -> bool {
        self.terms.iter().all(|(_, c)| c.is_finite())
    }

    /// F(p).
    pub fn eval(&self, p: [f64; 3]) -> f64 {
        if self.degree < QUARTIC_SLOTS {
            self.eval_in::<QUARTIC_SLOTS>(p)
        } else {
            self.eval_in::<SIDE>(p)
        }
    }

    /// `eval` with power tables of `N` slots, N > degree: a quartic's
    /// tables of 36 slots were copied whole per call.
    fn eval_in<const N: usize>(&self, p: [f64; 3]) -> f64 {
        let [px, py, pz] = p.map(|v| powers::<N>(v, self.degree));
        self.terms
            .iter()
            .map(|&(e, c)| {
                c * px[usize::from(e[0])] * py[usize::from(e[1])] * pz[usize::from(e[2])]
            })
            .sum()
    }

    /// The same surface, F scaled by the power of two that puts its largest
    /// |coefficient| in [1, 2) ([`normalize_pow2`]): k·F for any finite
    /// k ≠ 0 then becomes F itself (up to the rounding of k·F's
    /// coefficients), so neither Q(t) nor the gradient overflows or
    /// underflows for the scale k alone, and a power-of-two k changes no
    /// bit of any hit. Exact for every coefficient within 2^1022 of the
    /// largest (subnormal ones included); smaller ones are dropped. Also
    /// returns the exponent s of the factor 2^s applied (0 for the zero
    /// polynomial; non-finite coefficients are left alone, s = 0).
    pub fn normalized(&self) -> (Trivariate, i32) {
        let mut coeffs: Vec<f64> = self.terms.iter().map(|&(_, c)| c).collect();
        match normalize_pow2(&mut coeffs) {
            Some(shift) => (self.with_coefficients(coeffs), shift),
            None => (self.clone(), 0),
        }
    }

    /// self · 2^k, exact for every coefficient that stays in the normal
    /// range; the others are dropped (see [`normalize_pow2`]).
    pub fn scaled_pow2(&self, k: i32) -> Trivariate {
        let coeffs = self.terms.iter().map(|&(_, c)| scale_pow2_normal(c, k));
        self.with_coefficients(coeffs.collect())
    }

    /// F(2^k p): each term c·x^i y^j z^l times 2^(k(i+j+l)), exact for every
    /// coefficient that stays in the normal range (see [`Self::scaled_pow2`]).
    pub fn at_scale_pow2(&self, k: i32) -> Trivariate {
        let coeffs = self.terms.iter().map(|&(e, c)| {
            let degree = i32::from(e[0]) + i32::from(e[1]) + i32::from(e[2]);
            scale_pow2_normal(c, k * degree)
        });
        self.with_coefficients(coeffs.collect())
    }

    /// The same monomials with new coefficients (zeros dropped).
    fn with_coefficients(&self, coeffs: Vec<f64>) -> Trivariate {
        Trivariate::from_sorted(self.terms.iter().zip(coeffs).map(|(&(e, _), c)| (e, c)))
    }

    /// The partial derivatives ∂F/∂x, ∂F/∂y, ∂F/∂z as polynomials.
    pub fn gradient(&self) -> [Trivariate; 3] {
        std::array::from_fn(|axis| {
            Trivariate::from_terms(
                self.terms
                    .iter()
                    .filter(|(e, _)| e[axis] > 0)
                    .map(|&(e, c)| {
                        let mut d = e;
                        d[axis] -= 1;
                        (d, c * f64::from(e[axis]))
                    }),
            )
        })
    }

    /// ∇F(p), straight from the terms, so a normal costs no allocation and no
    /// separate gradient polynomials need to be kept.
    pub fn eval_gradient(&self, p: [f64; 3]) -> [f64; 3] {
        if self.degree < QUARTIC_SLOTS {
            self.eval_gradient_in::<QUARTIC_SLOTS>(p)
        } else {
            self.eval_gradient_in::<SIDE>(p)
        }
    }

    /// `eval_gradient` with power tables of `N` slots (see `eval_in`).
    fn eval_gradient_in<const N: usize>(&self, p: [f64; 3]) -> [f64; 3] {
        let [px, py, pz] = p.map(|v| powers::<N>(v, self.degree));
        let mut g = [0.0; 3];
        for &(e, c) in &self.terms {
            let [a, b, k] = e.map(usize::from);
            if a > 0 {
                g[0] += c * f64::from(e[0]) * px[a - 1] * py[b] * pz[k];
            }
            if b > 0 {
                g[1] += c * f64::from(e[1]) * px[a] * py[b - 1] * pz[k];
            }
            if k > 0 {
                g[2] += c * f64::from(e[2]) * px[a] * py[b] * pz[k - 1];
            }
        }
        g
    }

    /// Q(t) = F(o + t d), lowest degree first, into `out[..=degree]`;
    /// returns degree + 1. Leading coefficients may be zero (a ray parallel
    /// to an asymptote, say); the caller trims them.
    ///
    /// The expansion is exact algebra, nested like Horner's rule over the
    /// sorted terms: F = Σ_a X^a Σ_b Y^b Σ_c f_abc Z^c with X = o_x + t d_x
    /// and so on, each inner sum built by repeated multiplication with a
    /// linear factor. That needs three accumulators of degree + 1 (rounded
    /// up to the solver's slot counts) coefficients on the stack, no power tables to fill, and work that
    /// follows the terms actually present. (Above degree 4 a variant with
    /// per-axis tables of binomial powers and convolutions measured no
    /// faster; at degree 4 and below, where every table fits five slots and
    /// the loops unroll, it is: see `quartic`.)
    ///
    /// # Panics
    /// If `out` is shorter than degree + 1.
    pub fn substitute_ray(&self, o: [f64; 3], d: [f64; 3], out: &mut [f64]) -> usize {
        if let Some(quartic) = &self.quartic {
            return quartic.substitute(o, d, out);
        }
        // Accumulators as small as the degree allows: zeroing three of
        // MAX_DEGREE + 1 slots cost a quartic more than some of its
        // arithmetic. The operations, and so the bits, are the same.
        match self.degree {
            0..SMALL_SLOTS => self.substitute_in::<SMALL_SLOTS>(o, d, out),
            _ => self.substitute_in::<SIDE>(o, d, out),
        }
    }

    fn substitute_in<const N: usize>(&self, o: [f64; 3], d: [f64; 3], out: &mut [f64]) -> usize {
        let n = self.degree + 1;
        assert!(
            out.len() >= n,
            "substitute_ray needs {n} output coefficients, got {}",
            out.len()
        );
        let terms = self.terms.as_slice();
        let (mut q, mut t, mut s) = (Acc::<N>::new(), Acc::<N>::new(), Acc::<N>::new());
        let mut i = 0;
        // Each group starts at its first exponent, so the first step
        // multiplies an empty accumulator by a zeroth power.
        let mut last_a = terms.first().map_or(0, |term| term.0[0]);
        while i < terms.len() {
            let a = terms[i].0[0];
            t.len = 0;
            let mut last_b = terms[i].0[1];
            while i < terms.len() && terms[i].0[0] == a {
                let b = terms[i].0[1];
                s.len = 0;
                let mut last_c = terms[i].0[2];
                while i < terms.len() && terms[i].0[0] == a && terms[i].0[1] == b {
                    let ([_, _, c], f) = terms[i];
                    s.mul_linear_pow(o[2], d[2], last_c - c);
                    s.add_constant(f);
                    last_c = c;
                    i += 1;
                }
                s.mul_linear_pow(o[2], d[2], last_c);
                t.mul_linear_pow(o[1], d[1], last_b - b);
                t.add(&s);
                last_b = b;
            }
            t.mul_linear_pow(o[1], d[1], last_b);
            q.mul_linear_pow(o[0], d[0], last_a - a);
            q.add(&t);
            last_a = a;
        }
        q.mul_linear_pow(o[0], d[0], last_a);
        for (k, slot) in out[..n].iter_mut().enumerate() {
            *slot = if k < q.len { q.c[k] } else { 0.0 };
        }
        n
    }

    /// The walk over the term list that `quartic` replaced, kept as the
    /// tests' reference for its bits: for degree <= 4, the powers
    /// (o_i + d_i t)^e of each axis tabled once, and each group of terms a
    /// product with a table row, over all N slots. `N` > degree, at most 5.
    #[cfg(test)]
    fn substitute_sparse<const N: usize>(
        &self,
        o: [f64; 3],
        d: [f64; 3],
        out: &mut [f64],
    ) -> usize {
        let n = self.degree + 1;
        assert!(
            out.len() >= n,
            "substitute_ray needs {n} output coefficients, got {}",
            out.len()
        );
        let [x, y, z] = std::array::from_fn(|axis| linear_powers::<N>(o[axis], d[axis]));
        let terms = self.terms.as_slice();
        let mut q = [0.0; N];
        let mut i = 0;
        while i < terms.len() {
            let a = terms[i].0[0];
            let mut t = [0.0; N];
            while i < terms.len() && terms[i].0[0] == a {
                let b = terms[i].0[1];
                let mut s = [0.0; N];
                while i < terms.len() && terms[i].0[0] == a && terms[i].0[1] == b {
                    let ([_, _, c], f) = terms[i];
                    for (sk, zk) in s.iter_mut().zip(&z[usize::from(c)]) {
                        *sk += f * zk;
                    }
                    i += 1;
                }
                add_product(&mut t, &s, &y, b);
            }
            add_product(&mut q, &t, &x, a);
        }
        out[..n].copy_from_slice(&q[..n]);
        n
    }

    /// F(M p + c) as a polynomial in p, expanded exactly: placing a surface
    /// with an affine map once, instead of transforming every ray.
    pub fn compose_affine(&self, m: [[f64; 3]; 3], c: [f64; 3]) -> Trivariate {
        let mut max_exp = [0usize; 3];
        for &(e, _) in &self.terms {
            for axis in 0..3 {
                max_exp[axis] = max_exp[axis].max(usize::from(e[axis]));
            }
        }
        // Powers of the three linear forms (M p + c)_i; every product below
        // has degree <= self.degree <= MAX_DEGREE, so the unchecked product
        // is safe.
        let powers: [Vec<Trivariate>; 3] = std::array::from_fn(|axis| {
            let row = m[axis];
            let form = Trivariate::from_terms([
                ([1, 0, 0], row[0]),
                ([0, 1, 0], row[1]),
                ([0, 0, 1], row[2]),
                ([0, 0, 0], c[axis]),
            ]);
            let mut list = vec![Trivariate::constant(1.0)];
            for k in 1..=max_exp[axis] {
                let next = list[k - 1].mul_unchecked(&form);
                list.push(next);
            }
            list
        });
        let mut result = Vec::new();
        let terms = self.terms.as_slice();
        let mut i = 0;
        while i < terms.len() {
            let a = terms[i].0[0];
            let mut t = Trivariate::zero();
            while i < terms.len() && terms[i].0[0] == a {
                let b = terms[i].0[1];
                let mut s = Vec::new();
                while i < terms.len() && terms[i].0[0] == a && terms[i].0[1] == b {
                    let ([_, _, k], f) = terms[i];
                    for &(e, g) in &powers[2][usize::from(k)].terms {
                        s.push((e, f * g));
                    }
                    i += 1;
                }
                let s = Trivariate::from_terms(s);
                t = t.add(&powers[1][usize::from(b)].mul_unchecked(&s));
            }
            powers[0][usize::from(a)].products(&t, &mut result);
        }
        Trivariate::from_terms(result)
    }

    /// self + other.
    pub fn add(&self, other: &Trivariate) -> Trivariate {
        self.merge(other, 1.0)
    }

    /// self − other.
    pub fn sub(&self, other: &Trivariate) -> Trivariate {
        self.merge(other, -1.0)
    }

    /// Merges two sorted term lists, `other` scaled by ±1 (exact).
    fn merge(&self, other: &Trivariate, sign: f64) -> Trivariate {
        let (a, b) = (&self.terms, &other.terms);
        let mut terms = Vec::with_capacity(a.len() + b.len());
        let (mut i, mut j) = (0, 0);
        while i < a.len() || j < b.len() {
            let order = match (a.get(i), b.get(j)) {
                (Some(x), Some(y)) => y.0.cmp(&x.0),
                (Some(_), None) => std::cmp::Ordering::Less,
                _ => std::cmp::Ordering::Greater,
            };
            match order {
                std::cmp::Ordering::Less => {
                    terms.push(a[i]);
                    i += 1;
                }
                std::cmp::Ordering::Greater => {
                    terms.push((b[j].0, sign * b[j].1));
                    j += 1;
                }
                std::cmp::Ordering::Equal => {
                    let c = a[i].1 + sign * b[j].1;
                    if nonzero(c) {
                        terms.push((a[i].0, c));
                    }
                    i += 1;
                    j += 1;
                }
            }
        }
        let degree = terms.iter().map(|&(e, _)| total(e)).max().unwrap_or(0);
        Trivariate::assemble(terms, degree)
    }

    /// −self.
    pub fn neg(&self) -> Trivariate {
        self.scale(-1.0)
    }

    /// s · self.
    pub fn scale(&self, s: f64) -> Trivariate {
        Trivariate::from_sorted(self.terms.iter().map(|&(e, c)| (e, c * s)))
    }

    /// self / s, dividing each coefficient (one rounding each, where
    /// multiplying by 1/s would round twice).
    pub fn div_scalar(&self, s: f64) -> Trivariate {
        Trivariate::from_sorted(self.terms.iter().map(|&(e, c)| (e, c / s)))
    }

    /// Rebuilds from terms already in order with distinct exponents, dropping
    /// coefficients that became zero (underflow, or a zero factor).
    fn from_sorted(terms: impl Iterator<Item = ([u8; 3], f64)>) -> Trivariate {
        let terms: Vec<_> = terms.filter(|&(_, c)| nonzero(c)).collect();
        let degree = terms.iter().map(|&(e, _)| total(e)).max().unwrap_or(0);
        Trivariate::assemble(terms, degree)
    }

    /// self · other, or `None` when the product's degree would exceed
    /// [`MAX_DEGREE`]; checked before any work, so runaway products fail fast.
    pub fn checked_mul(&self, other: &Trivariate) -> Option<Trivariate> {
        (self.degree + other.degree <= MAX_DEGREE).then(|| self.mul_unchecked(other))
    }

    fn mul_unchecked(&self, other: &Trivariate) -> Trivariate {
        let mut terms = Vec::with_capacity(self.terms.len() * other.terms.len());
        self.products(other, &mut terms);
        Trivariate::from_terms(terms)
    }

    /// Appends the products of self's terms with other's; degrees must sum
    /// to at most MAX_DEGREE. [`Trivariate::from_terms`] sums equal
    /// exponents in the order they were appended (its sort is stable), the
    /// order a dense accumulator adds them in, so results round the same as
    /// they did when this summed into a (MAX_DEGREE + 1)³ cube, which cost
    /// 46,656 entries per product at degree 35.
    fn products(&self, other: &Trivariate, out: &mut Vec<([u8; 3], f64)>) {
        debug_assert!(self.degree + other.degree <= MAX_DEGREE);
        for &(e, c) in &self.terms {
            for &(f, g) in &other.terms {
                out.push(([e[0] + f[0], e[1] + f[1], e[2] + f[2]], c * g));
            }
        }
    }

    /// self^n by repeated squaring, or `None` when the degree would exceed
    /// [`MAX_DEGREE`] (checked first, so `(x+y)^1000` costs nothing).
    pub fn checked_pow(&self, n: u32) -> Option<Trivariate> {
        if self.degree.checked_mul(n as usize)? > MAX_DEGREE {
            return None;
        }
        let mut result = Trivariate::constant(1.0);
        let mut base = self.clone();
        let mut n = n;
        while n > 0 {
            if n & 1 == 1 {
                result = result.mul_unchecked(&base);
            }
            n >>= 1;
            if n > 0 {
                base = base.mul_unchecked(&base);
            }
        }
        Some(result)
    }
}

/// v^0 ..= v^n in the first n + 1 entries.
fn powers<const N: usize>(v: f64, n: usize) -> [f64; N] {
    let mut p = [0.0; N];
    p[0] = 1.0;
    for k in 1..=n {
        p[k] = p[k - 1] * v;
    }
    p
}

/// acc += u·(o + d t)^e, with `powers` the table of (o + d t)^e,
/// truncated to N coefficients: the callers' products have degree at
/// most N - 1, so nothing is lost. The zeroth power is 1: no product.
#[cfg(test)]
fn add_product<const N: usize>(acc: &mut [f64; N], u: &[f64; N], powers: &[[f64; N]; N], e: u8) {
    if e == 0 {
        for (a, u) in acc.iter_mut().zip(u) {
            *a += u;
        }
        return;
    }
    let v = &powers[usize::from(e)];
    for m in 0..N {
        for k in 0..=m {
            acc[m] += u[k] * v[m - k];
        }
    }
}

/// A univariate polynomial in t on the stack: the accumulators of
/// `substitute_ray`. `len` counts the coefficients in use; an empty one
/// (len 0) stays empty when multiplied, which lets the Horner loop treat a
/// group's first term like any other. `N` slots hold degree N - 1.
struct Acc<const N: usize> {
    c: [f64; N],
    len: usize,
}

impl<const N: usize> Acc<N> {
    fn new() -> Self {
        Acc {
            c: [0.0; N],
            len: 0,
        }
    }

    #[inline]
    fn add_constant(&mut self, f: f64) {
        if self.len == 0 {
            self.c[0] = f;
            self.len = 1;
        } else {
            self.c[0] += f;
        }
    }

    #[inline]
    fn add(&mut self, other: &Self) {
        for k in 0..other.len {
            self.c[k] = if k < self.len {
                self.c[k] + other.c[k]
            } else {
                other.c[k]
            };
        }
        self.len = self.len.max(other.len);
    }

    /// Multiplies by (o + d t)^times. The formal degree grows by `times` even
    /// when d = 0, which keeps the bookkeeping simple; it never passes the
    /// polynomial's total degree.
    #[inline]
    fn mul_linear_pow(&mut self, o: f64, d: f64, times: u8) {
        if self.len == 0 {
            return;
        }
        for _ in 0..times {
            let n = self.len;
            // Upwards, with the old coefficient carried in a register: each
            // load then reads one earlier store whole, where the downward
            // form got vectorised into loads straddling two fresh stores,
            // which stall store forwarding (the whole substitution measured
            // about 1.7x slower that way).
            let mut previous = 0.0;
            for c in &mut self.c[..n] {
                let current = *c;
                *c = current * o + previous * d;
                previous = current;
            }
            self.c[n] = previous * d;
            self.len = n + 1;
        }
    }
}

/// Coefficients in a form the expression parser reads back exactly:
/// Rust's shortest round-trip digits, in exponent form when very large or
/// small.
fn write_number(f: &mut fmt::Formatter<'_>, v: f64) -> fmt::Result {
    let a = v.abs();
    if a != 0.0 && !(1e-4..1e16).contains(&a) {
        write!(f, "{v:e}")
    } else {
        write!(f, "{v}")
    }
}

/// Prints as an expression `parse` accepts, e.g. `x^4 - 5*x^2 + 11.8`, so a
/// polynomial can be shown to people and read back unchanged.
impl fmt::Display for Trivariate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.terms.is_empty() {
            return f.write_str("0");
        }
        for (i, &(e, c)) in self.terms.iter().enumerate() {
            let magnitude = if i == 0 {
                if c < 0.0 {
                    f.write_str("-")?;
                }
                c.abs()
            } else {
                f.write_str(if c < 0.0 { " - " } else { " + " })?;
                c.abs()
            };
            let mut first = true;
            if magnitude != 1.0 || e == [0, 0, 0] {
                write_number(f, magnitude)?;
                first = false;
            }
            for (axis, name) in ["x", "y", "z"].iter().enumerate() {
                if e[axis] == 0 {
                    continue;
                }
                if !first {
                    f.write_str("*")?;
                }
                first = false;
                f.write_str(name)?;
                if e[axis] > 1 {
                    write!(f, "^{}", e[axis])?;
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
pub(crate) mod tests;
