use super::*;
use crate::sampling::{ONE_MINUS_EPSILON, Rng};

const N: u32 = 200_000;

/// The defaults and a few other parameter choices, among them Mitchell's
/// B-spline (B = 1, C = 0: no negative lobes) and Catmull-Rom (B = 0, C = ½).
fn filters() -> Vec<Filter> {
    vec![
        Filter::BOX,
        Filter::Box { radius: 1.5 },
        Filter::TENT,
        Filter::Tent { radius: 2.0 },
        Filter::GAUSSIAN,
        Filter::Gaussian {
            radius: 2.0,
            sigma: 1.0,
        },
        Filter::MITCHELL,
        Filter::Mitchell {
            radius: 1.5,
            b: 1.0,
            c: 0.0,
        },
        Filter::Mitchell {
            radius: 2.0,
            b: 0.0,
            c: 0.5,
        },
    ]
}

/// N samples of `filter` from a fixed seed.
fn samples(filter: &Filter) -> Vec<FilterSample> {
    let sampler = filter.sampler().unwrap();
    let mut rng = Rng::for_sample(11, 0, 0);
    (0..N).map(|_| sampler.sample(rng.next_2d())).collect()
}

/// ∫ g over [a, b] by Simpson's rule on `n` (even) panels, in f64.
fn simpson(g: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
    let h = (b - a) / n as f64;
    let inner: f64 = (1..n)
        .map(|k| g(a + k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 })
        .sum();
    h / 3.0 * (g(a) + inner + g(b))
}

#[test]
fn names_parse_to_the_defaults() {
    assert_eq!(
        "box".parse::<Filter>().unwrap(),
        Filter::Box { radius: 0.5 }
    );
    assert_eq!(
        "Tent".parse::<Filter>().unwrap(),
        Filter::Tent { radius: 1.0 }
    );
    assert_eq!("triangle".parse::<Filter>().unwrap(), Filter::TENT);
    assert_eq!(
        " gaussian ".parse::<Filter>().unwrap(),
        Filter::Gaussian {
            radius: 1.5,
            sigma: 0.5
        }
    );
    assert_eq!(
        "MITCHELL".parse::<Filter>().unwrap(),
        Filter::Mitchell {
            radius: 2.0,
            b: 1.0 / 3.0,
            c: 1.0 / 3.0
        }
    );
    assert_eq!(Filter::default(), Filter::BOX);
    for f in filters() {
        assert_eq!(f.name().parse::<Filter>().unwrap().name(), f.name());
        assert!(f.to_string().starts_with(f.name()), "{f}");
    }
    let err = "lanczos".parse::<Filter>().unwrap_err();
    assert!(err.is_bad_input());
    let message = err.to_string();
    assert!(
        message.contains("lanczos") && message.contains(NAMES),
        "{message}"
    );
}

#[test]
fn bad_parameters_are_refused() {
    let bad = [
        Filter::Box { radius: 0.0 },
        Filter::Tent { radius: -1.0 },
        Filter::Box { radius: f32::NAN },
        Filter::Tent {
            radius: f32::INFINITY,
        },
        Filter::Gaussian {
            radius: 1.0,
            sigma: 0.0,
        },
        Filter::Gaussian {
            radius: 1.0,
            sigma: f32::NAN,
        },
        Filter::Mitchell {
            radius: 2.0,
            b: f32::NAN,
            c: 0.0,
        },
    ];
    for f in bad {
        let err = f.sampler().unwrap_err();
        assert!(
            err.is_bad_input() && err.to_string().contains(f.name()),
            "{err}"
        );
    }
    for f in filters() {
        f.validate().unwrap();
    }
}

#[test]
fn offsets_lie_within_the_radius() {
    for f in filters() {
        let r = f.radius();
        let sampler = f.sampler().unwrap();
        let corners = [0.0, 0.25, 0.5, ONE_MINUS_EPSILON];
        let extremes = corners
            .iter()
            .flat_map(|&a| corners.map(|b| sampler.sample([a, b])));
        for s in samples(&f).into_iter().chain(extremes) {
            assert!(s.offset.iter().all(|o| o.abs() <= r), "{f}: {s:?}");
            assert!(s.weight.is_finite(), "{f}: {s:?}");
        }
        // The extremes of u reach the edges of the support.
        let edge = sampler.sample([ONE_MINUS_EPSILON, 0.0]).offset;
        assert!(edge[0] > 0.95 * r && edge[1] < -0.95 * r, "{f}: {edge:?}");
    }
}

#[test]
fn weighted_marginals_match_the_normalised_filter() {
    // 20 bins across [−r, r] per axis. A bin's weighted share of N samples
    // estimates ∫_bin f₁ / ∫ f₁; its standard error is √((E[w² 1_bin] −
    // share²) / N), estimated from the samples (binomial √(p(1 − p)/N) ≤
    // 0.0011 when every weight is 1). Each bin must agree within 5 standard
    // errors (+1e-5 for the quadrature); a misplaced lobe or a wrong
    // inverse CDF moves several bins by far more.
    const BINS: usize = 20;
    for f in filters() {
        let r = f64::from(f.radius());
        let total = f.integral_1d();
        let samples = samples(&f);
        for axis in 0..2 {
            let mut sum = [0.0f64; BINS];
            let mut sum2 = [0.0f64; BINS];
            for s in &samples {
                let t = (f64::from(s.offset[axis]) + r) / (2.0 * r) * BINS as f64;
                let bin = (t as usize).min(BINS - 1);
                let w = f64::from(s.weight);
                sum[bin] += w;
                sum2[bin] += w * w;
            }
            for bin in 0..BINS {
                let a = -r + 2.0 * r * bin as f64 / BINS as f64;
                let b = a + 2.0 * r / BINS as f64;
                let expected = simpson(|x| f.eval_1d(x), a, b, 200) / total;
                let n = f64::from(N);
                let share = sum[bin] / n;
                let se = ((sum2[bin] / n - share * share).max(0.0) / n).sqrt();
                assert!(
                    (share - expected).abs() <= 5.0 * se + 1e-5,
                    "{f}, axis {axis}, bin {bin}: {share} vs {expected} (se {se})"
                );
            }
        }
    }
}

#[test]
fn mean_weight_is_one() {
    for f in filters() {
        let samples = samples(&f);
        if !matches!(f, Filter::Mitchell { .. }) {
            assert!(samples.iter().all(|s| s.weight == 1.0), "{f}");
            continue;
        }
        // Standard error of the mean weight from the samples' spread; the
        // mean must be within 5 of them of 1, and the test must be sharp.
        let n = f64::from(N);
        let mean = samples.iter().map(|s| f64::from(s.weight)).sum::<f64>() / n;
        let var = samples
            .iter()
            .map(|s| (f64::from(s.weight) - mean).powi(2))
            .sum::<f64>()
            / (n - 1.0);
        let se = (var / n).sqrt();
        assert!(se < 0.005, "{f}: standard error {se}");
        assert!(
            (mean - 1.0).abs() < 5.0 * se,
            "{f}: mean weight {mean} ± {se}"
        );
    }
}

#[test]
fn mitchell_weights_are_sign_times_normalisation() {
    for f in filters()
        .into_iter()
        .filter(|f| matches!(f, Filter::Mitchell { .. }))
    {
        let r = f64::from(f.radius());
        let abs = simpson(|x| f.eval_1d(x).abs(), -r, r, 4000);
        let norm = (abs / f.integral_1d()).powi(2);
        let samples = samples(&f);
        let mut near = 0;
        let mut negative = 0;
        for s in &samples {
            let w = f64::from(s.weight);
            let value = f.evaluate(s.offset);
            // The weight's sign is the filter's where it is not ~0.
            if value.abs() > 1e-4 {
                assert_eq!(w < 0.0, value < 0.0, "{f}: {s:?} where f = {value}");
            }
            // Within a table cell |f| varies; near a zero crossing the
            // value is at most about twice the cell's mean per axis.
            assert!(w.abs() <= 4.5 * norm, "{f}: {s:?}, norm {norm}");
            near += usize::from((w.abs() / norm - 1.0).abs() < 0.05);
            negative += usize::from(w < 0.0);
        }
        // With 256 cells 97.5% (B = C = 1/3), 99.8% (B-spline) and 97.5%
        // (Catmull-Rom) are within 5%; 128 cells would give 90%, 96%, 89%.
        assert!(
            near as f64 > 0.95 * f64::from(N),
            "{f}: only {near} within 5%"
        );
        let (b, c) = match f {
            Filter::Mitchell { b, c, .. } => (b, c),
            _ => unreachable!(),
        };
        // B = 1, C = 0 is the cubic B-spline, positive everywhere.
        assert_eq!(
            negative == 0,
            b == 1.0 && c == 0.0,
            "{f}: {negative} negative"
        );
    }
}

#[test]
fn box_of_half_a_pixel_is_plain_jitter() {
    let sampler = Filter::BOX.sampler().unwrap();
    let mut rng = Rng::for_sample(5, 1, 2);
    for _ in 0..10_000 {
        let u = rng.next_2d();
        let s = sampler.sample(u);
        assert_eq!(
            s.offset.map(f32::to_bits),
            [u[0] - 0.5, u[1] - 0.5].map(f32::to_bits)
        );
        assert_eq!(s.weight, 1.0);
    }
}

#[test]
fn values_and_integrals() {
    // Mitchell B = C = 1/3 at the centre (6 − 2B)/6 = 8/9, at its knot B/6.
    let m = Filter::MITCHELL;
    let close = |a: f32, b: f32| (a - b).abs() < 1e-6;
    assert!(close(m.evaluate([0.0, 0.0]), (8.0f32 / 9.0).powi(2)));
    assert!(close(m.evaluate([1.0, 0.0]), 8.0 / 9.0 / 18.0));
    assert_eq!(m.evaluate([2.1, 0.0]), 0.0);
    assert!(close(Filter::TENT.evaluate([0.5, -0.25]), 0.5 * 0.75));
    assert_eq!(Filter::BOX.evaluate([0.6, 0.0]), 0.0);
    assert!(close(
        Filter::GAUSSIAN.evaluate([0.5, 0.0]),
        (-0.5f32).exp()
    ));
    // The closed-form integrals agree with quadrature of evaluate's axes.
    for f in filters() {
        let r = f64::from(f.radius());
        let i1 = simpson(|x| f.eval_1d(x), -r, r, 4000);
        let rel = f64::from(f.integral()) / (i1 * i1) - 1.0;
        assert!(rel.abs() < 1e-5, "{f}: {rel}");
    }
    // Mitchell's B-spline and Catmull-Rom members stay partitions of unity.
    assert!(close(Filter::BOX.integral(), 1.0));
    assert!(close(Filter::MITCHELL.integral(), 1.0));
}

#[test]
fn erf_and_its_inverse() {
    // Reference values of erf (to 1e-10).
    for (x, want) in [
        (0.0, 0.0),
        (0.5, 0.520_499_877_8),
        (1.0, 0.842_700_792_9),
        (2.0, 0.995_322_265_0),
        (-1.5, -0.966_105_146_5),
    ] {
        assert!((erf(x) - want).abs() < 2e-7, "erf({x}) = {}", erf(x));
    }
    for k in -99..=99 {
        let y = f64::from(k) / 100.0;
        let x = erf_inv(y);
        assert!((erf(x) - y).abs() < 4e-7, "erf(erf_inv({y})) = {}", erf(x));
    }
}
