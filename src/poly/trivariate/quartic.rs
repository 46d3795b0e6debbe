//! Q(t) = F(o + t d) for F of degree 4 or less, the surfaces POV-Ray's
//! `quartic`, `cubic` and `poly` of order ≤ 4 give, with every loop bound a
//! constant.
//!
//! F's coefficients sit in a table indexed by their exponents, zeros
//! included, with a flag for each group of terms sharing x's and y's
//! exponents (a, b) and for each row sharing a. The substitution walks the
//! groups as the sorted term list does (a, then b, then c descending),
//! skips the empty ones, and multiplies each polynomial in t only up to its
//! own degree: a group's inner sum s has degree ≤ D − a − b, a row's sum
//! degree ≤ D − a. The term list's walk (`Trivariate::substitute_sparse`,
//! kept as the tests' reference) spent much of its work matching exponents
//! and multiplying by the zeros above each polynomial's degree: about 790
//! instructions a call on POV-Ray's partorus.pov against some 420 here
//! (`valgrind --tool=callgrind`). The products left here are the nonzero
//! ones, in the same order, so Q's coefficients are the same bits (only the
//! sign of a zero could differ, where a zero product is no longer added to
//! it).

use std::fmt;

/// Q's coefficients in `N` slots, from the walk over F's groups in the
/// term list's order: for each row a (one line of the macro, x's exponent
/// first, then y's exponents b in order), the row's sum of groups times
/// (o_x + d_x t)^a added to q.
macro_rules! walk {
    ($table:expr, $o:expr, $d:expr, $n:ident; $($a:literal: $($b:literal)+;)+) => {{
        let [x, y, z] = std::array::from_fn(|axis| linear_powers::<$n>($o[axis], $d[axis]));
        let mut q = [0.0; $n];
        $(
            if $table.row[$a] {
                let mut t = [0.0; $n];
                $( $table.group::<$n, $a, $b>(&z, &y, &mut t); )+
                add_product::<$n, $a>(&mut q, &t, $n - 1 - $a, &x);
            }
        )+
        q
    }};
}

/// Slots of a degree-4 polynomial in t.
const SLOTS: usize = 5;

/// F's coefficients by exponent, for degree ≤ 4.
#[derive(Clone, PartialEq)]
pub struct Quartic {
    /// `coef[a][b][c]`: the coefficient of x^a y^b z^c (0 where absent).
    coef: [[[f64; SLOTS]; SLOTS]; SLOTS],
    /// Whether some term has x^a y^b.
    group: [[bool; SLOTS]; SLOTS],
    /// Whether some term has x^a.
    row: [bool; SLOTS],
    degree: usize,
}

impl fmt::Debug for Quartic {
    // The table repeats the terms, which `Trivariate`'s own output shows.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Quartic").finish_non_exhaustive()
    }
}

impl Quartic {
    /// The table of F's terms, when F's degree is 4 or less.
    pub fn of(terms: &[([u8; 3], f64)], degree: usize) -> Option<Box<Quartic>> {
        if degree >= SLOTS {
            return None;
        }
        let mut table = Box::new(Quartic {
            coef: [[[0.0; SLOTS]; SLOTS]; SLOTS],
            group: [[false; SLOTS]; SLOTS],
            row: [false; SLOTS],
            degree,
        });
        for &([a, b, c], f) in terms {
            let [a, b, c] = [a, b, c].map(usize::from);
            table.coef[a][b][c] = f;
            table.group[a][b] = true;
            table.row[a] = true;
        }
        Some(table)
    }

    /// Q's coefficients, lowest degree first, into `out[..=degree]`;
    /// returns degree + 1. A cubic takes four slots, every other degree
    /// five (the slot count the solver's quartic path uses).
    pub fn substitute(&self, o: [f64; 3], d: [f64; 3], out: &mut [f64]) -> usize {
        let n = self.degree + 1;
        assert!(
            out.len() >= n,
            "substitute_ray needs {n} output coefficients, got {}",
            out.len()
        );
        if self.degree == 3 {
            let q = self.walk_cubic(o, d);
            out[..n].copy_from_slice(&q[..n]);
        } else {
            let q = self.walk_quartic(o, d);
            out[..n].copy_from_slice(&q[..n]);
        }
        n
    }

    fn walk_quartic(&self, o: [f64; 3], d: [f64; 3]) -> [f64; SLOTS] {
        const N: usize = SLOTS;
        walk!(self, o, d, N;
            4: 0;
            3: 1 0;
            2: 2 1 0;
            1: 3 2 1 0;
            0: 4 3 2 1 0;
        )
    }

    fn walk_cubic(&self, o: [f64; 3], d: [f64; 3]) -> [f64; 4] {
        const N: usize = 4;
        walk!(self, o, d, N;
            3: 0;
            2: 1 0;
            1: 2 1 0;
            0: 3 2 1 0;
        )
    }

    /// acc += Σ_c f_abc (o_z + d_z t)^c, times (o_y + d_y t)^b: one group's
    /// share of its row, with D = N − 1 the degree the walk is sized for.
    #[inline(always)]
    fn group<const N: usize, const A: usize, const B: usize>(
        &self,
        z: &[[f64; N]; N],
        y: &[[f64; N]; N],
        acc: &mut [f64; N],
    ) {
        if !self.group[A][B] {
            return;
        }
        let top = N - 1 - A - B;
        let mut s = [0.0; N];
        for c in (0..top + 1).rev() {
            let f = self.coef[A][B][c];
            for k in 0..c + 1 {
                s[k] += f * z[c][k];
            }
        }
        add_product::<N, B>(acc, &s, top, y);
    }
}

/// acc += u·(o + d t)^E, with `u` of degree at most `top` and the table
/// `powers` of (o + d t)^e (row e of degree e). Each slot m adds the
/// products u[k]·v[m − k] in ascending k, as the full convolution does,
/// without the ones where either factor is above its degree (zeros).
#[inline(always)]
fn add_product<const N: usize, const E: usize>(
    acc: &mut [f64; N],
    u: &[f64; N],
    top: usize,
    powers: &[[f64; N]; N],
) {
    if E == 0 {
        for m in 0..top + 1 {
            acc[m] += u[m];
        }
        return;
    }
    let v = &powers[E];
    // Exclusive ranges: an inclusive one's end flag keeps loops from unrolling.
    for m in 0..(top + E).min(N - 1) + 1 {
        for k in m.saturating_sub(E)..m.min(top) + 1 {
            acc[m] += u[k] * v[m - k];
        }
    }
}

/// (o + d t)^e for e < N, each as its N coefficients in t (zero above
/// t^e).
///
/// Row e is filled only up to t^e, where the full loop over all N slots
/// added products with the zeros above it: a sum that gains a zero product
/// is unchanged, so the entries are the same bits (only a zero's sign
/// could differ), and `substitute_ray` took 6% fewer instructions on
/// POV-Ray's bicube.pov (`valgrind --tool=callgrind`).
pub(super) fn linear_powers<const N: usize>(o: f64, d: f64) -> [[f64; N]; N] {
    let mut p = [[0.0; N]; N];
    p[0][0] = 1.0;
    for e in 1..N {
        let previous = p[e - 1];
        p[e][0] = previous[0] * o;
        for k in 1..e {
            p[e][k] = previous[k] * o + previous[k - 1] * d;
        }
        p[e][e] = previous[e - 1] * d;
    }
    p
}
