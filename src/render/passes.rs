//! A render runs in progressive passes, each taking a range of sample indices
//! for every pixel, so an interrupted render can stop between passes and
//! resume where it stopped. A pixel sums its samples in index order whatever
//! the passes, so the split never changes the image.
//!
//! With adaptive supersampling a pass is one round of `spp` samples: after
//! its base samples a pixel takes further rounds while its own samples
//! disagree (the standard error of their mean luminance above the threshold
//! times the mean), up to `max_spp`. The decision uses nothing but the
//! pixel's own sums, which the film state keeps, so it does not depend on
//! threads, tiles or interruptions.

use std::ops::Range;

use crate::film::{Pixel, Sample};
use crate::scene::Adaptive;

/// Below this mean luminance the threshold counts as absolute: a dark pixel's
/// relative error would otherwise ask for samples nobody can see.
const FLOOR: f64 = 0.05;

/// How many passes a render without adaptive sampling is split into (fewer
/// when it has fewer samples): enough that an interrupt loses little work.
const PASSES: u32 = 8;

/// The sample ranges of a render's passes, from sample `from` on. The first
/// pass is one sample per pixel, quick at any spp: an interrupt lets it end
/// (within a grace period), so a render stopped early keeps some work.
pub fn passes(spp: u32, adaptive: Option<&Adaptive>, from: u32) -> Vec<Range<u32>> {
    let limit = target(spp, adaptive);
    let step = match adaptive {
        Some(_) => spp,
        None => spp.div_ceil(PASSES).max(1),
    };
    (0..limit)
        .step_by(step as usize)
        .flat_map(|k| {
            let end = (k + step).min(limit);
            // Adaptive decisions come after a whole round, so splitting the
            // first one changes nothing.
            let split = if k == 0 { 1 } else { k };
            [k..split, split..end]
        })
        .filter(|r| !r.is_empty() && r.start >= from)
        .collect()
}

/// The most samples a pixel takes: `spp`, or with adaptive sampling `max_spp`.
pub fn target(spp: u32, adaptive: Option<&Adaptive>) -> u32 {
    adaptive.map_or(spp, |a| a.max_spp.max(spp))
}

/// Whether this is a render's first pass (one sample per pixel).
pub fn is_first(range: &Range<u32>) -> bool {
    range.start == 0
}

/// Whether a pixel takes samples `range`: always, unless adaptive
/// sampling finds it has converged, or it stopped in an earlier pass. The
/// pixel's state before the pass decides it.
pub fn takes(pixel: &Pixel, range: &Range<u32>, spp: u32, adaptive: Option<&Adaptive>) -> bool {
    every_pixel_takes(range, spp, adaptive)
        || adaptive.is_some_and(|a| pixel.samples >= range.start && !converged(pixel, a))
}

/// Whether every pixel takes samples `range`: without adaptive sampling,
/// and in its base round.
pub fn every_pixel_takes(range: &Range<u32>, spp: u32, adaptive: Option<&Adaptive>) -> bool {
    adaptive.is_none() || range.start < spp
}

/// Adds a sample to its pixel (the pixel's next in index order); returns 1
/// if its radiance was non-finite (counted as black), else 0.
pub fn add(pixel: &mut Pixel, mut sample: Sample) -> u64 {
    let nonfinite = u64::from(sample.sanitize());
    pixel.add(&sample);
    nonfinite
}

/// Whether a pixel's samples agree well enough to stop.
fn converged(pixel: &Pixel, a: &Adaptive) -> bool {
    let n = f64::from(pixel.samples);
    // Σy and Σy² are in f64: the variance subtracts them.
    let [sum, sum2] = pixel.luminance;
    let mean = sum / n;
    let variance = ((sum2 - sum * mean) / (n - 1.0)).max(0.0);
    (variance / n).sqrt() <= f64::from(a.threshold) * mean.abs().max(FLOOR)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    fn sample(y: f32) -> Sample {
        Sample {
            radiance: Vec3::splat(y),
            weight: 1.0,
            depth: 1.0,
            normal: Vec3::Z,
            albedo: Vec3::ONE,
        }
    }

    const ADAPTIVE: Adaptive = Adaptive {
        max_spp: 64,
        threshold: 0.01,
    };

    /// Every pass of a render over one pixel.
    fn run(spp: u32, adaptive: Option<&Adaptive>, take: impl Fn(u32) -> Sample) -> Pixel {
        let mut pixel = Pixel::default();
        for range in passes(spp, adaptive, 0) {
            if takes(&pixel, &range, spp, adaptive) {
                for k in range {
                    add(&mut pixel, take(k));
                }
            }
        }
        pixel
    }

    #[test]
    fn passes_cover_every_sample_once() {
        assert_eq!(passes(3, None, 0), vec![0..1, 1..2, 2..3]);
        assert_eq!(
            passes(20, None, 0),
            vec![0..1, 1..3, 3..6, 6..9, 9..12, 12..15, 15..18, 18..20]
        );
        assert_eq!(passes(20, None, 9), vec![9..12, 12..15, 15..18, 18..20]);
        assert_eq!(passes(20, None, 1)[0], 1..3);
        assert_eq!(passes(4, Some(&ADAPTIVE), 0).len(), 17);
        assert_eq!(passes(4_000_000_000, None, 0)[..2], [0..1, 1..500_000_000]);
        assert_eq!(passes(4, Some(&ADAPTIVE), 60), vec![60..64]);
    }

    #[test]
    fn agreeing_samples_stop_at_the_base_count() {
        assert_eq!(run(4, Some(&ADAPTIVE), |_| sample(0.5)).samples, 4);
    }

    #[test]
    fn disagreeing_samples_get_more_up_to_the_limit() {
        // An edge: half the samples see 0, half see 1.
        assert_eq!(
            run(4, Some(&ADAPTIVE), |k| sample((k % 2) as f32)).samples,
            64
        );
        // A milder disagreement stops in between, at a whole number of rounds.
        let mild = Adaptive {
            threshold: 0.1,
            ..ADAPTIVE
        };
        let pixel = run(4, Some(&mild), |k| sample(1.0 + (k % 2) as f32));
        assert!(pixel.samples > 4 && pixel.samples < 64, "{}", pixel.samples);
        assert_eq!(pixel.samples % 4, 0);
    }

    #[test]
    fn without_adaptive_every_sample_is_taken_in_order() {
        let pixel = run(5, None, |k| sample(k as f32));
        assert_eq!(pixel.samples, 5);
        let mut direct = Pixel::default();
        (0..5).for_each(|k| direct.add(&sample(k as f32)));
        assert_eq!(pixel, direct);
    }

    #[test]
    fn non_finite_radiance_is_counted_and_kept_off_the_film() {
        let mut pixel = Pixel::default();
        let bad: u64 = [f32::NAN, f32::INFINITY, 1.0, 2.0]
            .into_iter()
            .map(|y| add(&mut pixel, sample(y)))
            .sum();
        assert_eq!(bad, 2);
        assert_eq!(pixel.samples, 4);
        assert!(pixel.radiance.iter().all(|c| c.is_finite()));
        assert_eq!(pixel.radiance[0], 3.0);
    }
}
