//! Whether F may vanish in a box: certified enclosures of F's values
//! there, for finding the box around a surface's own points
//! (`geometry::analytic`'s `surface_box`).
//!
//! Two, as they suit different boxes. The centred form re-expands F about
//! the box's centre c in units of its half-widths r, G(u) = F(c + r∘u) =
//! Σ g_α u^α with u ∈ [−1, 1]³, so that |G(u) − g_0| ≤ Σ_{α≠0} |g_α|: tight
//! for boxes small beside their distance from F's features, and it bounds
//! F from below, as the leading form's bound needs. The Bernstein form
//! re-expands F over the box [lo, lo + w] in the tensor Bernstein basis of
//! degree n per axis, whose coefficients enclose F's values there (their
//! convex hull holds the graph): it excludes boxes near the origin of a
//! far larger search, where the centred form cannot.

use super::{MAX_DEGREE, Trivariate};

/// F's coefficients in a dense cube of side degree + 1, for re-expanding
/// it over many boxes without rebuilding term lists.
#[derive(Clone, Debug)]
pub struct Dense {
    n: usize,
    coeffs: Vec<f64>,
    /// The sparse terms, for the magnitude that bounds the rounding.
    terms: Vec<([u8; 3], f64)>,
    /// Scratch for the re-expansion, the size of `coeffs`.
    work: Vec<f64>,
    /// Power to Bernstein basis of degree n on [0, 1]: b_i = Σ_{j ≤ i}
    /// w_ij a_j, with weights w_ij = C(i, j) / C(n, j) in [0, 1] at
    /// [i · (n + 1) + j].
    to_bernstein: Vec<f64>,
}

impl Trivariate {
    /// F in dense form (see [`Dense`]).
    pub fn dense(&self) -> Dense {
        let n = self.degree;
        let side = n + 1;
        let mut coeffs = vec![0.0; side * side * side];
        for &(e, c) in &self.terms {
            let [i, j, k] = e.map(usize::from);
            coeffs[(i * side + j) * side + k] = c;
        }
        let binomial =
            |a: usize, b: usize| (0..b).fold(1.0, |c, k| c * (a - k) as f64 / (k + 1) as f64);
        let to_bernstein = (0..side * side)
            .map(|k| {
                let (i, j) = (k / side, k % side);
                if j <= i {
                    binomial(i, j) / binomial(n, j)
                } else {
                    0.0
                }
            })
            .collect();
        Dense {
            n,
            work: coeffs.clone(),
            coeffs,
            terms: self.terms.clone(),
            to_bernstein,
        }
    }
}

impl Dense {
    /// Whether F certainly has no zero in the box `centre` ± `half`
    /// (half-widths ≥ 0, all finite), by the centred form. False answers
    /// "perhaps".
    pub fn excludes_zero(&mut self, centre: [f64; 3], half: [f64; 3]) -> bool {
        let (value, spread) = self.enclose(centre, half);
        value.abs() > spread
    }

    /// F at `centre` and how far F may stray from it within `centre` ±
    /// `half`, the expansion's rounding included: every value of F there
    /// lies within value ± spread.
    pub fn enclose(&mut self, centre: [f64; 3], half: [f64; 3]) -> (f64, f64) {
        self.reexpand(centre, half);
        let rest: f64 = self.work[1..].iter().map(|g| g.abs()).sum();
        (self.work[0], rest + self.rounding(centre, half))
    }

    /// Whether F certainly has no zero in the box from `lo` by `width`
    /// (all ≥ 0 and finite), by the Bernstein form: its coefficients all
    /// of one sign, clear of their rounding.
    pub fn bernstein_excludes(&mut self, lo: [f64; 3], width: [f64; 3]) -> bool {
        self.reexpand(lo, width);
        let side = self.n + 1;
        let mut line = [0.0; MAX_DEGREE + 1];
        for axis in 0..3 {
            let stride = side.pow(2 - axis as u32);
            for p in 0..side {
                for q in 0..side {
                    let base = match axis {
                        0 => p * side + q,
                        1 => p * side * side + q,
                        _ => (p * side + q) * side,
                    };
                    for (m, a) in line[..side].iter_mut().enumerate() {
                        *a = self.work[base + m * stride];
                    }
                    for i in 0..side {
                        let weights = &self.to_bernstein[i * side..=i * side + i];
                        let b: f64 = weights.iter().zip(&line).map(|(w, a)| w * a).sum();
                        self.work[base + i * stride] = b;
                    }
                }
            }
        }
        // Each Bernstein coefficient is a sum of the re-expansion's, with
        // weights in [0, 1]: its error is at most theirs added up, which
        // `rounding` bounds, plus the conversion's own few roundings.
        let rounding = 4.0 * self.rounding(lo, width);
        let (low, high) = self
            .work
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &b| {
                (l.min(b), h.max(b))
            });
        low > rounding || high < -rounding
    }

    /// `work` = F(origin + scale∘u) in powers of u.
    fn reexpand(&mut self, origin: [f64; 3], scale: [f64; 3]) {
        let (n, side) = (self.n, self.n + 1);
        self.work.copy_from_slice(&self.coeffs);
        let at = |i: usize, j: usize, k: usize| (i * side + j) * side + k;
        // One axis at a time: each line of coefficients along it is a
        // polynomial in that variable, shifted to the origin (synthetic
        // division) and scaled. Total degree ≤ n bounds each line's length.
        for axis in 0..3 {
            let (c, r) = (origin[axis], scale[axis]);
            for p in 0..side {
                for q in 0..side - p {
                    let len = n - p - q;
                    let index = |m: usize| match axis {
                        0 => at(m, p, q),
                        1 => at(p, m, q),
                        _ => at(p, q, m),
                    };
                    for i in 0..len {
                        for m in (i..len).rev() {
                            self.work[index(m)] += c * self.work[index(m + 1)];
                        }
                    }
                    let mut power = 1.0;
                    for m in 0..=len {
                        self.work[index(m)] *= power;
                        power *= r;
                    }
                }
            }
        }
    }

    /// A bound on the rounding of any one coefficient of `reexpand`'s
    /// result: each is rounded at most 3(n + 1) times over a sum whose
    /// terms, made positive, add up (over all of them) to F's terms made
    /// positive at |origin| + scale; every rounding is bounded by that
    /// total, with room to spare.
    fn rounding(&self, origin: [f64; 3], scale: [f64; 3]) -> f64 {
        let magnitude: f64 = self
            .terms
            .iter()
            .map(|&(e, f)| {
                (0..3).fold(f.abs(), |m, axis| {
                    m * (origin[axis].abs() + scale[axis].abs()).powi(i32::from(e[axis]))
                })
            })
            .sum();
        64.0 * (self.n + 1) as f64 * f64::EPSILON * magnitude
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sphere() -> Trivariate {
        // x² + y² + z² − 1
        Trivariate::from_terms([
            ([2, 0, 0], 1.0),
            ([0, 2, 0], 1.0),
            ([0, 0, 2], 1.0),
            ([0, 0, 0], -1.0),
        ])
    }

    #[test]
    fn a_box_away_from_the_sphere_is_excluded_and_one_across_it_is_not() {
        let mut f = sphere().dense();
        assert!(f.excludes_zero([3.0, 0.0, 0.0], [0.5; 3]));
        assert!(f.excludes_zero([0.0; 3], [0.2; 3]));
        assert!(!f.excludes_zero([1.0, 0.0, 0.0], [0.1; 3]));
        // Touching the surface at one corner only: never excluded.
        assert!(!f.excludes_zero([1.1, 0.1, 0.1], [0.1, 0.1, 0.1]));
    }

    #[test]
    fn the_bernstein_form_excludes_a_large_box_the_centred_form_cannot() {
        // The torus R = 2, r = 0.5, and a box from near it out to 1000:
        // the centred form's spread is as large as F there, the Bernstein
        // coefficients are all positive.
        let torus =
            crate::poly::expr::parse("(x^2 + y^2 + z^2 + 3.75)^2 - 16*(x^2 + y^2)", &[]).unwrap();
        let mut f = torus.dense();
        let (lo, width) = ([10.0, 0.0, 0.0], [990.0, 1000.0, 1000.0]);
        let centre = [505.0, 500.0, 500.0];
        assert!(!f.excludes_zero(centre, [495.0, 500.0, 500.0]));
        assert!(f.bernstein_excludes(lo, width));
        // Across the tube, neither form may exclude.
        assert!(!f.bernstein_excludes([1.0, -1.0, -1.0], [2.0, 2.0, 2.0]));
    }

    #[test]
    fn the_re_expansion_is_f_about_the_centre() {
        // A quartic with mixed terms: g_0 is F(c), and the sum of all g_α
        // is F at the box's +++ corner.
        let f = Trivariate::from_terms([
            ([4, 0, 0], 1.0),
            ([1, 2, 1], -3.0),
            ([0, 1, 2], 2.5),
            ([0, 0, 1], 0.75),
            ([0, 0, 0], -2.0),
        ]);
        let mut dense = f.dense();
        let (c, r) = ([0.3, -1.2, 0.7], [0.25, 0.5, 0.125]);
        dense.excludes_zero(c, r);
        assert!((dense.work[0] - f.eval(c)).abs() < 1e-12);
        let corner = [c[0] + r[0], c[1] + r[1], c[2] + r[2]];
        let sum: f64 = dense.work.iter().sum();
        assert!((sum - f.eval(corner)).abs() < 1e-12, "{sum}");
    }
}
