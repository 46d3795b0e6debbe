use super::*;

const BOTH: [SamplerKind; 2] = [SamplerKind::Sobol, SamplerKind::Independent];

/// The first `n` numbers a sample draws, in the order a path draws them: the
/// pixel, then alternately one and two dimensions.
fn draws(kind: SamplerKind, seed: u64, pixel: u64, sample: u32, n: usize) -> Vec<f32> {
    let mut s = Sampler::new(kind, seed, pixel, sample);
    let mut out = s.pixel_2d(16).to_vec();
    while out.len() < n {
        out.push(s.get_1d());
        out.extend(s.get_2d());
    }
    out.truncate(n);
    out
}

/// Dimension `request` (0 the pixel, then alternately 1D and 2D requests, as
/// `draws` makes them) of sample `sample`: its first coordinate and, for a
/// pair, the second.
fn request(kind: SamplerKind, pixel: u64, sample: u32, request: usize) -> [f32; 2] {
    let mut s = Sampler::new(kind, 7, pixel, sample);
    let mut u = s.pixel_2d(16);
    for r in 1..=request {
        u = if r % 2 == 1 {
            [s.get_1d(), f32::NAN]
        } else {
            s.get_2d()
        };
    }
    u
}

#[test]
fn a_sample_draws_the_same_numbers_every_time_and_others_differ() {
    for kind in BOTH {
        let a = draws(kind, 3, 1000, 5, 40);
        assert_eq!(a, draws(kind, 3, 1000, 5, 40), "{kind:?}");
        for (seed, pixel, sample) in [(4, 1000, 5), (3, 1001, 5), (3, 1000, 6)] {
            let b = draws(kind, seed, pixel, sample, 40);
            let same = a.iter().zip(&b).filter(|(x, y)| x == y).count();
            // 24-bit values: an equal one is a 1-in-16-million coincidence.
            assert!(same <= 1, "{kind:?} {seed} {pixel} {sample}: {same} equal");
        }
    }
}

#[test]
fn every_number_is_in_the_unit_interval() {
    for kind in BOTH {
        for pixel in 0..50 {
            for sample in [0, 1, 2, 3, 255, 256, 65_537, u32::MAX] {
                for u in draws(kind, 11, pixel, sample, 64) {
                    assert!((0.0..1.0).contains(&u), "{kind:?}: {u}");
                }
            }
        }
    }
}

#[test]
fn the_independent_sampler_is_the_counter_based_generator() {
    let (seed, pixel, sample, spp) = (9, 77, 6, 12);
    let mut s = Sampler::new(SamplerKind::Independent, seed, pixel, sample);
    let mut rng = Rng::for_sample(seed, pixel, sample);
    assert_eq!(s.pixel_2d(spp), stratified_2d(sample, spp, rng.next_2d()));
    assert_eq!(s.get_1d(), rng.next_f32());
    assert_eq!(s.get_2d(), rng.next_2d());
}

#[test]
fn every_power_of_two_prefix_stratifies_each_dimension_and_pair() {
    // For every m, the first 2^m samples of a pixel put one point in each
    // elementary interval of every 2D request (a (0,m,2)-net: boxes of
    // 2^-a by 2^-(m-a)), and one in each 1/2^m of every 1D request; deep
    // requests (a path's later bounces) as well as the first.
    for pixel in [0, 1, 12_345] {
        for r in [0, 1, 2, 7, 8, 41, 42] {
            let points: Vec<[f32; 2]> = (0..256)
                .map(|k| request(SamplerKind::Sobol, pixel, k, r))
                .collect();
            for m in 0..=8u32 {
                let prefix = &points[..1 << m];
                let pair = !prefix[0][1].is_nan();
                for a in if pair { 0..=m } else { m..=m } {
                    let mut seen = vec![false; 1 << m];
                    for p in prefix {
                        let x = (p[0] * (1u32 << a) as f32) as usize;
                        let y = if pair {
                            (p[1] * (1u32 << (m - a)) as f32) as usize
                        } else {
                            0
                        };
                        let cell = (x << (m - a)) | y;
                        assert!(
                            !std::mem::replace(&mut seen[cell], true),
                            "pixel {pixel}, request {r}, m {m}, a {a}: two in one interval"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn the_independent_sampler_does_not_stratify_past_the_pixel() {
    // The contrast that shows the test above can fail: 16 independent
    // numbers leave some of 16 strata empty, all but surely.
    let empty = (0..20u64)
        .filter(|&pixel| {
            let mut seen = [false; 16];
            for k in 0..16 {
                seen[(request(SamplerKind::Independent, pixel, k, 1)[0] * 16.0) as usize] = true;
            }
            seen.contains(&false)
        })
        .count();
    assert!(empty >= 19, "{empty}");
}

/// Pearson's correlation of two equally long series.
fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let cov: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let va: f64 = a.iter().map(|x| (x - ma).powi(2)).sum();
    let vb: f64 = b.iter().map(|y| (y - mb).powi(2)).sum();
    cov / (va * vb).sqrt()
}

#[test]
fn pixels_and_dimensions_are_uncorrelated() {
    // Over 1024 samples, a dimension of one pixel against the same dimension
    // of its neighbour, and against another dimension of the same pixel
    // (where unshuffled padding would share the index's digits: the top bits
    // would agree in every sample, a correlation near ±1 in the first
    // digit). Uncorrelated series have r with standard error 1/√1024 ≈
    // 0.031; the bound is 5 of those, and is asserted over many pairs.
    let n = 1024;
    let series = |pixel: u64, r: usize, coordinate: usize| -> Vec<f64> {
        (0..n)
            .map(|k| f64::from(request(SamplerKind::Sobol, pixel, k, r)[coordinate]))
            .collect()
    };
    let bit = |v: &[f64]| -> Vec<f64> { v.iter().map(|x| f64::from(*x >= 0.5)).collect() };
    for pixel in [0u64, 31, 4096] {
        for r in [0, 1, 2, 5] {
            let a = series(pixel, r, 0);
            let neighbour = series(pixel + 1, r, 0);
            assert!(correlation(&a, &neighbour).abs() < 0.16, "{pixel} {r}");
            for other in [r + 1, r + 2, r + 9] {
                let b = series(pixel, other, 0);
                let rho = correlation(&a, &b);
                let top = correlation(&bit(&a), &bit(&b));
                assert!(rho.abs() < 0.16, "{pixel}: {r} vs {other}: {rho}");
                assert!(top.abs() < 0.16, "{pixel}: {r} vs {other}: top bits {top}");
            }
        }
    }
}

#[test]
fn sobol_beats_independent_numbers_on_a_smooth_path_like_integrand() {
    // A smooth function of eight dimensions drawn as a path draws them (the
    // pixel pair, then 1D and 2D requests): a smooth term per dimension and
    // one per pair, as a path's radiance is mostly made of (the pixel
    // position, a light sample's two coordinates). Integrated per pixel with
    // 64 samples over 400 pixels; its exact integral is known, so each
    // sampler's mean squared error is measured, not estimated from its
    // spread. Measured: sobol's MSE is 1/1500 of independent's. Bound:
    // 1/100, far above that and far below the 1 of equal samplers (each MSE
    // has a relative standard error near √(2/400) ≈ 7%).
    let pairs = [(0, 1), (3, 4), (6, 7)];
    let f = |u: &[f32]| -> f64 {
        let u: Vec<f64> = u.iter().map(|&x| f64::from(x)).collect();
        // ∫₀¹ 3x² dx = 1 and ∫∫ 4xy = 1.
        u.iter().map(|x| 3.0 * x * x).sum::<f64>()
            + pairs.iter().map(|&(i, j)| 4.0 * u[i] * u[j]).sum::<f64>()
    };
    let exact = 8.0 + pairs.len() as f64;
    let mse = |kind: SamplerKind| -> f64 {
        (0..400u64)
            .map(|pixel| {
                let mean = (0..64)
                    .map(|k| f(&draws(kind, 5, pixel, k, 8)))
                    .sum::<f64>()
                    / 64.0;
                (mean - exact).powi(2)
            })
            .sum::<f64>()
            / 400.0
    };
    let (sobol, independent) = (mse(SamplerKind::Sobol), mse(SamplerKind::Independent));
    assert!(sobol < independent / 100.0, "{sobol} vs {independent}");
}

#[test]
fn a_deferred_dimension_is_the_number_drawn_in_its_place() {
    for kind in BOTH {
        for sample in [0, 1, 5, 1000] {
            // In order: pixel, 1D, 2D, 1D, 2D.
            let mut a = Sampler::new(kind, 5, 321, sample);
            let (pa, xa, ya, za, wa) = (
                a.pixel_2d(4),
                a.get_1d(),
                a.get_2d(),
                a.get_1d(),
                a.get_2d(),
            );
            // The same with the two 1D requests reserved, drawn late or not
            // at all: every other request keeps its number.
            let mut b = Sampler::new(kind, 5, 321, sample);
            let pb = b.pixel_2d(4);
            let x = b.defer_1d();
            let yb = b.get_2d();
            let skipped = b.defer_1d();
            let wb = b.get_2d();
            assert_eq!((pa, ya, wa), (pb, yb, wb), "{kind:?}");
            assert_eq!(b.later(x).to_bits(), xa.to_bits(), "{kind:?}");
            assert_eq!(b.later(skipped).to_bits(), za.to_bits(), "{kind:?}");
        }
    }
}
