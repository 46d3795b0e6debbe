//! The surfaces in their own object space: F, its gradient, Q(s) = F along
//! a ray, and the scale of F's rounding error, for each kind of surface.
//!
//! Inside is where F < 0: a sphere's, ellipsoid's or torus's own volume;
//! for quadrics and algebraic surfaces, the side where the F the user wrote
//! is negative (CSG children may flip it with `inverse`).

use glam::{DMat3, DVec3};

use super::csg::Csg;
use crate::math::smaller;
use crate::poly::trivariate::Trivariate;
use crate::poly::univariate::{PolyN, QUARTIC_SLOTS, SLOTS};

/// A general quadric xᵀA x + b·x + c = 0 with symmetric A.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Quadric {
    pub a: DMat3,
    pub b: DVec3,
    pub c: f64,
}

impl Quadric {
    /// The value c of a quadric that is the constant c ≠ 0 everywhere (A
    /// and b zero): POV-Ray's `box` is one, inside (c < 0) within its box.
    pub(super) fn constant(&self) -> Option<f64> {
        (self.a == DMat3::ZERO && self.b == DVec3::ZERO && self.c != 0.0).then_some(self.c)
    }

    pub(super) fn eval(&self, p: DVec3) -> f64 {
        p.dot(self.a * p) + self.b.dot(p) + self.c
    }

    pub(super) fn gradient(&self, p: DVec3) -> DVec3 {
        2.0 * (self.a * p) + self.b
    }

    /// [c0, c1, c2] of Q(t) = F(o + t·d) = c0 + c1 t + c2 t², in the
    /// line's own t (d not normalised).
    pub(super) fn along_line(&self, o: DVec3, d: DVec3) -> [f64; 3] {
        let ad = self.a * d;
        [self.eval(o), 2.0 * o.dot(ad) + self.b.dot(d), d.dot(ad)]
    }

    /// A with every entry made positive.
    fn abs_a(&self) -> DMat3 {
        DMat3::from_cols(
            self.a.x_axis.abs(),
            self.a.y_axis.abs(),
            self.a.z_axis.abs(),
        )
    }

    /// F at p with every term made positive: the scale of the rounding
    /// error in F's value there.
    pub(super) fn magnitude(&self, p: DVec3) -> f64 {
        let a = p.abs();
        a.dot(self.abs_a() * a) + self.b.abs().dot(a) + self.c.abs()
    }

    /// Whether the whole line o + t·d (object space) certainly misses the
    /// surface: Q(t) = c2 t² + c1 t + c0 has a discriminant below zero by
    /// more than the rounding of its terms could make up (64ε of their
    /// scale, far beyond the few roundings in each), so it keeps one sign
    /// for every t. Lines near a tangent, along an asymptote (c2 ≈ 0), and
    /// every line that hits, answer false and are searched as before. No
    /// unit direction, box clip or trimmed Q: an unbounded quadric is tried
    /// by every ray, and POV-Ray's `Axes` (three thin cylinders) were half
    /// the render time of its steiner.pov sample, nearly all of it misses.
    pub(super) fn misses_line(&self, o: DVec3, d: DVec3) -> bool {
        let [c0, c1, c2] = self.along_line(o, d);
        let abs_a = self.abs_a();
        let pd = d.abs();
        let apd = abs_a * pd;
        let (m2, m1, m0) = (
            pd.dot(apd),
            2.0 * o.abs().dot(apd) + self.b.abs().dot(pd),
            self.magnitude(o),
        );
        let noise = 64.0 * f64::EPSILON * (m1 * m1 + 4.0 * m2 * m0);
        // A NaN (a line at infinity) is no proof: the search decides.
        c1 * c1 - 4.0 * c2 * c0 < -noise
    }
}

/// The surface in its own object space.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub enum Surface {
    Sphere {
        radius: f64,
    },
    Quadric(Quadric),
    /// Around the z axis: major radius R of the tube's centre circle, minor radius r of the tube.
    Torus {
        major: f64,
        minor: f64,
    },
    Algebraic(Box<Trivariate>),
    /// A CSG tree, placed in world space (see `csg`): it has no F of its own.
    Csg(Box<Csg>),
}

impl Surface {
    /// [c0, c1, c2] of Q(t) = F(o + t·d) for a sphere or a quadric, in
    /// the line's own t (d not normalised); None for other surfaces.
    pub(super) fn along_line(&self, o: DVec3, d: DVec3) -> Option<[f64; 3]> {
        match self {
            Surface::Sphere { radius } => Some([
                o.length_squared() - radius * radius,
                2.0 * o.dot(d),
                d.length_squared(),
            ]),
            Surface::Quadric(q) => Some(q.along_line(o, d)),
            _ => None,
        }
    }

    /// A one-line summary for `sturmray info`.
    pub fn describe(&self) -> String {
        match self {
            Surface::Sphere { radius } => format!("sphere r={radius}"),
            Surface::Quadric(_) => "quadric (degree 2)".into(),
            Surface::Torus { major, minor } => format!("torus R={major} r={minor} (degree 4)"),
            Surface::Algebraic(f) => format!(
                "algebraic, degree {}, {} terms",
                f.degree(),
                f.terms().len()
            ),
            Surface::Csg(tree) => format!("csg {}", tree.describe()),
        }
    }

    /// The same surface in coordinates scaled by 2^k (p' = 2^k p), exact: as
    /// a polynomial, F(2^-k p') times a power of two.
    pub(super) fn at_scale_pow2(&self, k: i32) -> Surface {
        let s = 2f64.powi(k);
        match self {
            Surface::Sphere { radius } => Surface::Sphere { radius: radius * s },
            Surface::Torus { major, minor } => Surface::Torus {
                major: major * s,
                minor: minor * s,
            },
            // xᵀAx + b·x + c at x = p'/s, times s².
            Surface::Quadric(q) => Surface::Quadric(Quadric {
                a: q.a,
                b: q.b * s,
                c: q.c * s * s,
            }),
            // F and k·F are one surface: normalised once here, never per ray.
            Surface::Algebraic(f) => {
                // Normalised first, so no coefficient is subnormal when scaled.
                let f = f.normalized().0.at_scale_pow2(-k);
                Surface::Algebraic(Box::new(f.normalized().0))
            }
            // Its leaves are scaled in their own shapes; the tree keeps unit 0.
            Surface::Csg(_) => self.clone(),
        }
    }

    pub(super) fn gradient(&self, p: DVec3) -> DVec3 {
        match self {
            Surface::Sphere { .. } => p,
            Surface::Quadric(q) => q.gradient(p),
            Surface::Torus { major, minor } => torus_gradient(*major, *minor, p),
            Surface::Algebraic(f) => DVec3::from(f.eval_gradient(p.to_array())),
            // Never asked: a tree's normals are its leaves' (see `Csg::intersect`).
            Surface::Csg(_) => DVec3::ZERO,
        }
    }

    /// Whether Q fits the quartic storage (`QUARTIC_SLOTS`): spheres,
    /// quadrics, tori and quartics, whose local Q (`along_in`) then costs no
    /// zeroing or copying of 36 slots. (Those were 10% of the instructions
    /// of POV-Ray's helix.pov, `valgrind --tool=callgrind`.)
    pub(super) fn quartic(&self) -> bool {
        match self {
            Surface::Sphere { .. } | Surface::Quadric(_) | Surface::Torus { .. } => true,
            Surface::Algebraic(f) => f.degree() < QUARTIC_SLOTS,
            Surface::Csg(_) => true,
        }
    }

    /// Q(s) = F(start + s·d) in `S` slots, which must hold the surface's
    /// degree + 1 coefficients. The arithmetic is the same in any storage, so the
    /// coefficients are the same bits.
    pub(super) fn along_in<const S: usize>(&self, start: DVec3, d: DVec3) -> PolyN<S> {
        match self {
            Surface::Sphere { radius } => PolyN::new(&[
                start.length_squared() - radius * radius,
                2.0 * start.dot(d),
                d.length_squared(),
            ]),
            Surface::Quadric(q) => {
                let ad = q.a * d;
                PolyN::new(&[q.eval(start), 2.0 * start.dot(ad) + q.b.dot(d), d.dot(ad)])
            }
            Surface::Torus { major, minor } => torus_polynomial(*major, *minor, start, d),
            Surface::Algebraic(f) => {
                let mut coeffs = [0.0; S];
                let n = f.substitute_ray(start.to_array(), d.to_array(), &mut coeffs);
                // Slots from n on are still zero: built in place, not copied.
                PolyN::from_array(coeffs, n - 1)
            }
            // No F: the constant 1, nowhere zero (a tree is searched by `Csg`).
            Surface::Csg(_) => PolyN::new(&[1.0]),
        }
    }

    /// F evaluated with every term made positive: the scale of the rounding
    /// error in F's value at p (its terms cancel on the surface).
    pub(super) fn magnitude(&self, p: DVec3) -> f64 {
        let a = p.abs();
        match self {
            Surface::Sphere { radius } => a.length_squared() + radius * radius,
            Surface::Quadric(q) => q.magnitude(p),
            Surface::Torus { major, minor } => {
                let s = a.length_squared() + major * major + minor * minor;
                s * s + 4.0 * major * major * (a.x * a.x + a.y * a.y)
            }
            // Three powi per term were 4% of the instructions of POV-Ray's
            // torus.pov (`valgrind --tool=callgrind`); a quartic has at most
            // 35 terms but 5 powers per axis. Each power is still taken by
            // powi, and the sum runs in the same order: the same bits.
            Surface::Algebraic(f) if f.degree() < QUARTIC_SLOTS => {
                let powers =
                    |x: f64| -> [f64; QUARTIC_SLOTS] { std::array::from_fn(|k| x.powi(k as i32)) };
                let (x, y, z) = (powers(a.x), powers(a.y), powers(a.z));
                f.terms()
                    .iter()
                    .map(|&([i, j, k], c)| {
                        c.abs() * x[usize::from(i)] * y[usize::from(j)] * z[usize::from(k)]
                    })
                    .sum()
            }
            Surface::Algebraic(f) => algebraic_magnitude(f, a),
            Surface::Csg(_) => 1.0,
        }
    }
}

/// Σ |c| |x|^i |y|^j |z|^k over F's terms at a = |p|, each power by powi.
fn algebraic_magnitude(f: &Trivariate, a: DVec3) -> f64 {
    f.terms()
        .iter()
        .map(|&([i, j, k], c)| {
            c.abs() * a.x.powi(i.into()) * a.y.powi(j.into()) * a.z.powi(k.into())
        })
        .sum()
}

/// How far a root moves when the polynomial's value is perturbed by `noise`, from
/// its Taylor coefficients c at the root: min over k ≥ 1 of (noise / |c_k|)^(1/k).
pub(super) fn root_uncertainty(c: &[f64], noise: f64) -> f64 {
    let mut least = f64::INFINITY;
    for (k, ck) in c.iter().enumerate().skip(1) {
        if *ck == 0.0 {
            continue;
        }
        let ratio = noise / ck.abs();
        // pow is most of this function's cost, and at a simple root the
        // first term is the least: a k-th root that cannot come out below
        // the least so far (ratio above least^k, with a margin far above the
        // roundings of powi and pow) is not taken. The minimum, and so every
        // bit of the result, is unchanged (a NaN ratio, skipped too, never
        // was the minimum). pow(x, 1) is x exactly.
        if k == 1 {
            least = smaller(least, ratio);
        } else if ratio <= least.powi(k as i32) * (1.0 + 1e-9) {
            least = smaller(least, ratio.powf(1.0 / k as f64));
        }
    }
    least
}

impl Surface {
    /// How far a root at p of F(p + h·d) may be from the true one: rounding
    /// perturbs the value by about `noise`, which moves a root by about
    /// min over k ≥ 1 of (noise / |c_k|)^(1/k) for the Taylor coefficients c_k at p:
    /// noise / |Q'| for a simple root, but its square or cube root where the ray
    /// grazes the surface or F's gradient vanishes.
    pub(super) fn uncertainty(&self, p: DVec3, d: DVec3) -> f64 {
        if self.quartic() {
            self.uncertainty_in::<QUARTIC_SLOTS>(p, d)
        } else {
            self.uncertainty_in::<SLOTS>(p, d)
        }
    }

    fn uncertainty_in<const S: usize>(&self, p: DVec3, d: DVec3) -> f64 {
        let q = self.along_in::<S>(p, d);
        let c = q.coeffs();
        let noise = f64::EPSILON * (4 * c.len()) as f64 * self.magnitude(p);
        root_uncertainty(c, noise)
    }
}

/// Q(s) for the torus (x²+y²+z²+R²−r²)² − 4R²(x²+y²) along start + s·d.
fn torus_polynomial<const S: usize>(major: f64, minor: f64, o: DVec3, d: DVec3) -> PolyN<S> {
    let r2 = major * major;
    let k = r2 - minor * minor;
    // |p|² + R² − r² = a s² + b s + c
    let (a, b, c) = (d.length_squared(), 2.0 * o.dot(d), o.length_squared() + k);
    // x² + y² = e s² + f s + g
    let (e, f, g) = (
        d.x * d.x + d.y * d.y,
        2.0 * (o.x * d.x + o.y * d.y),
        o.x * o.x + o.y * o.y,
    );
    let four_r2 = 4.0 * r2;
    PolyN::new(&[
        c * c - four_r2 * g,
        2.0 * b * c - four_r2 * f,
        b * b + 2.0 * a * c - four_r2 * e,
        2.0 * a * b,
        a * a,
    ])
}

fn torus_gradient(major: f64, minor: f64, p: DVec3) -> DVec3 {
    let s = p.length_squared() + major * major - minor * minor;
    let r = 4.0 * s * p;
    DVec3::new(
        r.x - 8.0 * major * major * p.x,
        r.y - 8.0 * major * major * p.y,
        r.z,
    )
}

#[cfg(test)]
mod tests {
    use super::{Surface, algebraic_magnitude, root_uncertainty};
    use crate::poly::trivariate::Trivariate;
    use glam::DVec3;
    use proptest::prelude::*;

    /// The plain formula, every k-th root taken.
    fn every_root(c: &[f64], noise: f64) -> f64 {
        c.iter()
            .enumerate()
            .skip(1)
            .filter(|(_, ck)| **ck != 0.0)
            .map(|(k, ck)| (noise / ck.abs()).powf(1.0 / k as f64))
            .fold(f64::INFINITY, f64::min)
    }

    proptest! {
        /// A quartic's magnitude from the table of powers is the per-term
        /// formula's, bit for bit: every monomial of degree <= 4 (35 of
        /// them), coefficients and points over many orders of magnitude.
        #[test]
        fn quartic_magnitude_from_the_table_is_the_plain_sum(
            c in proptest::collection::vec((-8i32..8, -1.0f64..1.0), 35),
            p in (-6i32..6, -1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0),
        ) {
            let mut monomials = Vec::new();
            for i in 0..=4u8 {
                for j in 0..=4 - i {
                    for k in 0..=4 - i - j {
                        monomials.push([i, j, k]);
                    }
                }
            }
            let terms = monomials.into_iter().zip(c.iter().map(|&(e, m)| m * 10f64.powi(e)));
            let f = Trivariate::from_terms(terms);
            let scale = 10f64.powi(p.0);
            let point = DVec3::new(p.1, p.2, p.3) * scale;
            let plain = algebraic_magnitude(&f, point.abs());
            let surface = Surface::Algebraic(Box::new(f));
            prop_assert_eq!(surface.magnitude(point).to_bits(), plain.to_bits());
        }

        /// Skipping the k-th roots that cannot be the least changes no bit:
        /// Taylor coefficients over 60 orders of magnitude, zeros among them,
        /// so that each k in turn gives the least.
        #[test]
        fn skipped_roots_leave_the_same_bits(
            c in proptest::collection::vec((-30i32..30, -1.0f64..1.0, any::<bool>()), 2..8),
            noise in 1e-20f64..1e-5,
        ) {
            let c: Vec<f64> = c
                .into_iter()
                .map(|(e, m, zero)| if zero { 0.0 } else { m * 10f64.powi(e) })
                .collect();
            prop_assert_eq!(
                root_uncertainty(&c, noise).to_bits(),
                every_root(&c, noise).to_bits()
            );
        }
    }
}
