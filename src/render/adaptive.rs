//! Adaptive supersampling: a pixel takes its base samples, then further
//! rounds of as many while its own samples still disagree, up to a limit.
//! The decision uses nothing but the pixel's own samples, each seeded by
//! (pixel, sample index), so the result does not depend on threads or tiles.

use crate::film::{Pixel, Sample};
use crate::scene::Adaptive;

/// The pixel's samples: `spp` of them, then with `adaptive` more rounds of
/// `spp` while the standard error of the mean luminance exceeds the threshold
/// (relative to the mean, with a floor so near-black pixels count absolutely).
/// `take(k)` traces sample k.
pub fn sample_pixel(
    spp: u32,
    adaptive: Option<&Adaptive>,
    mut take: impl FnMut(u32) -> Sample,
) -> Pixel {
    let mut pixel = Pixel::default();
    let limit = adaptive.map_or(spp, |a| a.max_spp.max(spp));
    let mut k = 0;
    while k < limit {
        for _ in 0..spp.min(limit - k) {
            pixel.add(&take(k));
            k += 1;
        }
        let Some(a) = adaptive else { break };
        let n = f64::from(k);
        // Σy and Σy² are in f64: the variance subtracts them.
        let [sum, sum2] = pixel.luminance;
        let mean = sum / n;
        let variance = ((sum2 - sum * mean) / (n - 1.0)).max(0.0);
        let error = (variance / n).sqrt();
        if error <= f64::from(a.threshold) * mean.abs().max(FLOOR) {
            break;
        }
    }
    pixel
}

/// Below this mean luminance the threshold counts as absolute: a dark pixel's
/// relative error would otherwise ask for samples nobody can see.
const FLOOR: f64 = 0.05;

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

    #[test]
    fn agreeing_samples_stop_at_the_base_count() {
        let pixel = sample_pixel(4, Some(&ADAPTIVE), |_| sample(0.5));
        assert_eq!(pixel.samples, 4);
    }

    #[test]
    fn disagreeing_samples_get_more_up_to_the_limit() {
        // An edge: half the samples see 0, half see 1.
        let pixel = sample_pixel(4, Some(&ADAPTIVE), |k| sample((k % 2) as f32));
        assert_eq!(pixel.samples, 64);
        // A milder disagreement stops in between, at a whole number of rounds.
        let mild = Adaptive {
            threshold: 0.1,
            ..ADAPTIVE
        };
        let pixel = sample_pixel(4, Some(&mild), |k| sample(1.0 + (k % 2) as f32));
        assert!(pixel.samples > 4 && pixel.samples < 64, "{}", pixel.samples);
        assert_eq!(pixel.samples % 4, 0);
    }

    #[test]
    fn without_adaptive_the_count_is_fixed() {
        let pixel = sample_pixel(3, None, |k| sample(k as f32));
        assert_eq!(pixel.samples, 3);
    }
}
