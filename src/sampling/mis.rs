//! Multiple-importance-sampling weights (Veach's balance and power
//! heuristics) for two strategies f and g that took `nf` and `ng` samples.
//!
//! The weight of a sample drawn by f is `heuristic(nf, f_pdf, ng, g_pdf)`; the
//! same sample seen from g gets `heuristic(ng, g_pdf, nf, f_pdf)`, and the two
//! sum to 1 whenever either density is positive. No input gives NaN: a density
//! that is zero, negative or NaN counts as zero (that strategy cannot produce
//! the sample), an infinite one (a delta) takes the whole weight, and two
//! infinite ones share it equally. Ratios instead of squares keep large and
//! tiny densities from overflowing or underflowing.

/// The balance heuristic nf·f_pdf / (nf·f_pdf + ng·g_pdf).
pub fn balance_heuristic(nf: f32, f_pdf: f32, ng: f32, g_pdf: f32) -> f32 {
    weight(nf * f_pdf, ng * g_pdf, |r| r)
}

/// The power heuristic with exponent 2: (nf·f_pdf)² / ((nf·f_pdf)² + (ng·g_pdf)²).
pub fn power_heuristic(nf: f32, f_pdf: f32, ng: f32, g_pdf: f32) -> f32 {
    weight(nf * f_pdf, ng * g_pdf, |r| r * r)
}

/// h(f) / (h(f) + h(g)) for h(x) = x^β (β ≥ 1), where `ratio_power(r)` gives
/// r^β; computed as 1 / (1 + h(g/f)) or h(f/g) / (1 + h(f/g)), so the
/// smaller of the two ratios is the one raised to the power.
fn weight(f: f32, g: f32, ratio_power: impl Fn(f32) -> f32) -> f32 {
    if f.is_nan() || f <= 0.0 {
        return 0.0;
    }
    if g.is_nan() || g <= 0.0 {
        return 1.0;
    }
    if f == f32::INFINITY && g == f32::INFINITY {
        return 0.5;
    }
    if f >= g {
        1.0 / (1.0 + ratio_power(g / f))
    } else {
        let h = ratio_power(f / g);
        h / (1.0 + h)
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    type Heuristic = fn(f32, f32, f32, f32) -> f32;
    const BOTH: [(&str, Heuristic); 2] =
        [("balance", balance_heuristic), ("power", power_heuristic)];

    fn close(a: f32, b: f32) -> bool {
        (a - b).abs() <= 1e-6
    }

    #[test]
    fn known_values() {
        assert!(close(balance_heuristic(1.0, 3.0, 1.0, 1.0), 0.75));
        assert!(close(power_heuristic(1.0, 3.0, 1.0, 1.0), 0.9));
        assert!(close(power_heuristic(1.0, 1.0, 1.0, 3.0), 0.1));
        // Sample counts scale the densities: 2 samples at 1 against 1 at 2.
        assert!(close(balance_heuristic(2.0, 1.0, 1.0, 2.0), 0.5));
        assert!(close(power_heuristic(1.0, 2.0, 4.0, 1.0), 0.2));
        assert!(close(power_heuristic(1.0, 0.5, 1.0, 0.5), 0.5));
    }

    #[test]
    fn zeros_infinities_and_nans_give_no_nan() {
        let inf = f32::INFINITY;
        for (name, h) in BOTH {
            let cases = [
                (1.0, 0.0, 1.0, 2.0, 0.0),
                (1.0, 2.0, 1.0, 0.0, 1.0),
                (1.0, 0.0, 1.0, 0.0, 0.0),
                (0.0, 2.0, 1.0, 2.0, 0.0),
                (1.0, inf, 1.0, 5.0, 1.0),
                (1.0, 5.0, 1.0, inf, 0.0),
                (1.0, inf, 1.0, inf, 0.5),
                (1.0, inf, 1.0, 0.0, 1.0),
                (1.0, f32::NAN, 1.0, 1.0, 0.0),
                (1.0, 1.0, 1.0, f32::NAN, 1.0),
                (1.0, -1.0, 1.0, 1.0, 0.0),
                // Squares of these overflow (1e60) or underflow (1e-60) in f32.
                (1.0, 1e30, 1.0, 1e30, 0.5),
                (1.0, 1e-30, 1.0, 1e-30, 0.5),
                (1.0, 1e30, 1.0, 1.0, 1.0),
                (1.0, 1e-30, 1.0, 1.0, 0.0),
            ];
            for (nf, fp, ng, gp, want) in cases {
                let w = h(nf, fp, ng, gp);
                assert!(
                    close(w, want),
                    "{name}({nf}, {fp}, {ng}, {gp}) = {w}, not {want}"
                );
            }
        }
    }

    fn density() -> impl Strategy<Value = f32> {
        prop_oneof![
            Just(0.0f32),
            Just(f32::INFINITY),
            Just(f32::MIN_POSITIVE),
            Just(f32::MAX),
            (-40.0f32..40.0).prop_map(|e| 10f32.powf(e)),
        ]
    }

    proptest! {
        #[test]
        fn two_strategies_sum_to_one(
            nf in 1u32..64, ng in 1u32..64, fp in density(), gp in density()
        ) {
            let (nf, ng) = (nf as f32, ng as f32);
            for (name, h) in BOTH {
                let (a, b) = (h(nf, fp, ng, gp), h(ng, gp, nf, fp));
                prop_assert!((0.0..=1.0).contains(&a), "{} {}", name, a);
                prop_assert!((0.0..=1.0).contains(&b), "{} {}", name, b);
                if nf * fp > 0.0 || ng * gp > 0.0 {
                    // Each weight is rounded once or twice: a few ulps of 1.
                    prop_assert!((a + b - 1.0).abs() <= 4.0 * f32::EPSILON, "{} {} + {}", name, a, b);
                } else {
                    prop_assert_eq!((a, b), (0.0, 0.0));
                }
            }
        }

        #[test]
        fn power_favours_the_larger_density_more_than_balance(
            fp in 1e-3f32..1e3, gp in 1e-3f32..1e3
        ) {
            let (p, b) = (power_heuristic(1.0, fp, 1.0, gp), balance_heuristic(1.0, fp, 1.0, gp));
            if fp > gp {
                prop_assert!(p >= b);
            } else {
                prop_assert!(p <= b);
            }
        }
    }
}
