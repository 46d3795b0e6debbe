//! Warps from the unit square onto disks, spheres, hemispheres, cones and
//! triangles, each with the density of its output. Directions are in a local
//! frame with z up (the normal, or a cone's axis); `math::Frame` or the caller
//! rotates them into the world. Inputs `u` are uniform in [0, 1)².
//!
//! Densities are per unit solid angle for directions and per unit area for
//! points, as pbrt's Sample*/ *PDF pairs.

use std::f32::consts::{FRAC_1_PI, FRAC_PI_2, FRAC_PI_4, TAU};

use crate::math::Vec3;

/// 1 / (4π): the density of [`uniform_sphere`].
const INV_4PI: f32 = 0.25 * FRAC_1_PI;
/// 1 / (2π): the density of [`uniform_hemisphere`].
const INV_2PI: f32 = 0.5 * FRAC_1_PI;

/// A point in the unit disk, uniform in area, by Shirley and Chiu's
/// concentric map: squares around the centre go to rings, so strata stay
/// compact and neighbours stay neighbours (unlike the polar map).
pub fn concentric_disk(u: [f32; 2]) -> [f32; 2] {
    let (x, y) = (2.0 * u[0] - 1.0, 2.0 * u[1] - 1.0);
    if x == 0.0 && y == 0.0 {
        return [0.0, 0.0];
    }
    let (r, theta) = if x.abs() > y.abs() {
        (x, FRAC_PI_4 * (y / x))
    } else {
        (y, FRAC_PI_2 - FRAC_PI_4 * (x / y))
    };
    let (sin, cos) = theta.sin_cos();
    [r * cos, r * sin]
}

/// The density of [`concentric_disk`] per unit area: 1/π.
pub const fn concentric_disk_pdf() -> f32 {
    FRAC_1_PI
}

/// A direction in the hemisphere z ≥ 0 with density cos θ / π (Malley's
/// method: a uniform point of the disk lifted onto the hemisphere).
pub fn cosine_hemisphere(u: [f32; 2]) -> Vec3 {
    let [x, y] = concentric_disk(u);
    let z = (1.0 - x * x - y * y).max(0.0).sqrt();
    Vec3::new(x, y, z)
}

/// The density of [`cosine_hemisphere`] for a direction whose cosine with the
/// normal is `cos_theta`: cos θ / π, and 0 below the horizon.
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) * FRAC_1_PI
}

/// A direction uniform over the unit sphere.
pub fn uniform_sphere(u: [f32; 2]) -> Vec3 {
    let z = 1.0 - 2.0 * u[0];
    // 1 − z² as (1 − z)(1 + z) = 4u(1 − u): accurate near the poles.
    let r = (4.0 * u[0] * (1.0 - u[0])).max(0.0).sqrt();
    let (sin, cos) = (TAU * u[1]).sin_cos();
    Vec3::new(r * cos, r * sin, z)
}

/// The density of [`uniform_sphere`]: 1 / (4π).
pub const fn uniform_sphere_pdf() -> f32 {
    INV_4PI
}

/// A direction uniform over the hemisphere z ≥ 0.
pub fn uniform_hemisphere(u: [f32; 2]) -> Vec3 {
    let z = 1.0 - u[0];
    let r = (u[0] * (2.0 - u[0])).max(0.0).sqrt();
    let (sin, cos) = (TAU * u[1]).sin_cos();
    Vec3::new(r * cos, r * sin, z)
}

/// The density of [`uniform_hemisphere`]: 1 / (2π).
pub const fn uniform_hemisphere_pdf() -> f32 {
    INV_2PI
}

/// A direction uniform over the cone of directions within angle θmax of +z,
/// given cos θmax (clamped to [−1, 1]); every result has z ≥ `cos_max`.
/// For a sphere of radius r seen from distance d > r, prefer
/// [`uniform_cone_sin2`] with sin²θmax = r²/d²: 1 − cos θmax formed in f32
/// loses everything for small, distant spheres.
pub fn uniform_cone(u: [f32; 2], cos_max: f32) -> Vec3 {
    let cos_max = cos_max.clamp(-1.0, 1.0);
    cone(u, 1.0 - cos_max, cos_max)
}

/// The density of [`uniform_cone`]: 1 / (2π (1 − cos θmax)); infinite for a
/// cone of zero width (cos θmax = 1), whose only direction is the axis.
pub fn uniform_cone_pdf(cos_max: f32) -> f32 {
    let one_minus_cos = 1.0 - cos_max.clamp(-1.0, 1.0);
    1.0 / (TAU * one_minus_cos)
}

/// [`uniform_cone`] for a cone narrower than a hemisphere given by
/// sin²θmax (clamped to [0, 1]), exact for tiny cones: 1 − cos θmax is
/// formed as sin²θmax / (1 + cos θmax) without cancellation.
pub fn uniform_cone_sin2(u: [f32; 2], sin2_max: f32) -> Vec3 {
    let sin2 = sin2_max.clamp(0.0, 1.0);
    let cos_max = (1.0 - sin2).sqrt();
    cone(u, sin2 / (1.0 + cos_max), cos_max)
}

/// The density of [`uniform_cone_sin2`]: 1 / (2π (1 − cos θmax)).
pub fn uniform_cone_sin2_pdf(sin2_max: f32) -> f32 {
    let sin2 = sin2_max.clamp(0.0, 1.0);
    1.0 / (TAU * (sin2 / (1.0 + (1.0 - sin2).sqrt())))
}

/// The cone sample from 1 − cos θmax, which callers form accurately.
fn cone(u: [f32; 2], one_minus_cos_max: f32, cos_max: f32) -> Vec3 {
    // 1 − cos θ is uniform on [0, 1 − cos θmax]; sin²θ = (1 − cos θ)(1 + cos θ)
    // keeps the small angles that cos θ itself rounds away.
    let one_minus_cos = u[0] * one_minus_cos_max;
    let z = (1.0 - one_minus_cos).max(cos_max);
    let r = (one_minus_cos * (2.0 - one_minus_cos)).max(0.0).sqrt();
    let (sin, cos) = (TAU * u[1]).sin_cos();
    Vec3::new(r * cos, r * sin, z)
}

/// Barycentrics (b0, b1) of a point uniform in area over a triangle, with
/// b2 = 1 − b0 − b1 (Heitz 2019, "A Low-Distortion Map Between Triangle and
/// Square"; one division-free branch, no square root). The density per unit
/// area is 1 / (the triangle's area).
pub fn uniform_triangle(u: [f32; 2]) -> (f32, f32) {
    if u[0] < u[1] {
        let b0 = 0.5 * u[0];
        (b0, u[1] - b0)
    } else {
        let b1 = 0.5 * u[1];
        (u[0] - b1, b1)
    }
}

#[cfg(test)]
mod tests {
    use std::f32::consts::PI;

    use super::*;
    use crate::sampling::Rng;

    const N: usize = 200_000;

    fn uniforms(seed: u64) -> impl Iterator<Item = [f32; 2]> {
        let mut rng = Rng::for_sample(seed, 0, 0);
        std::iter::repeat_with(move || rng.next_2d())
    }

    /// Samples binned in (s, φ) with s ∈ [s_lo, 1] (z for directions, r² for
    /// the disk) in 10 × 8 cells; `density(s, φ)` is the claimed density per
    /// ds dφ (for directions dω = dz dφ, so it is the pdf itself). Expected
    /// counts come from integrating that density over each cell (8 × 8
    /// midpoints), so the test checks the sampler against its own pdf, and the
    /// pdf's integral over the domain against 1.
    ///
    /// χ² over 80 cells has 79 degrees of freedom: mean 79, standard deviation
    /// √158 ≈ 12.6; the bound 145 is over 5 standard deviations. Any cell off
    /// by 10% (expected ≈ 2500, σ ≈ 50) adds about 25 on its own, so a pdf or
    /// sampler that disagrees over a region of the domain fails.
    fn check_density(
        name: &str,
        s_lo: f32,
        samples: impl Iterator<Item = (f32, f32)>,
        density: impl Fn(f32, f32) -> f32,
    ) {
        const NS: usize = 10;
        const NP: usize = 8;
        const SUB: usize = 8;
        let mut observed = [[0u32; NP]; NS];
        for (s, phi) in samples.take(N) {
            let is = (((s - s_lo) / (1.0 - s_lo)) * NS as f32).clamp(0.0, NS as f32 - 1.0);
            let ip = ((phi + PI) / TAU * NP as f32).clamp(0.0, NP as f32 - 1.0);
            observed[is as usize][ip as usize] += 1;
        }
        let (ds, dp) = ((1.0 - s_lo) / NS as f32, TAU / NP as f32);
        let mut total = 0.0f64;
        let mut chi2 = 0.0f64;
        for (is, row) in observed.iter().enumerate() {
            for (ip, &obs) in row.iter().enumerate() {
                let mut mass = 0.0f64;
                for a in 0..SUB {
                    for b in 0..SUB {
                        let s = s_lo + ds * (is as f32 + (a as f32 + 0.5) / SUB as f32);
                        let phi = -PI + dp * (ip as f32 + (b as f32 + 0.5) / SUB as f32);
                        mass += f64::from(density(s, phi));
                    }
                }
                mass *= f64::from(ds * dp) / (SUB * SUB) as f64;
                total += mass;
                let expected = mass * N as f64;
                chi2 += (f64::from(obs) - expected).powi(2) / expected;
            }
        }
        assert!(
            (total - 1.0).abs() < 1e-3,
            "{name}: pdf integrates to {total}"
        );
        assert!(chi2 < 145.0, "{name}: chi² = {chi2} over 80 cells");
    }

    /// (z, φ) of a direction, after checking it is a unit vector.
    fn polar(d: Vec3) -> (f32, f32) {
        assert!((d.length() - 1.0).abs() < 1e-5, "not unit: {d}");
        (d.z, d.y.atan2(d.x))
    }

    #[test]
    fn concentric_disk_is_uniform_in_the_unit_disk() {
        let samples = uniforms(1).map(|u| {
            let [x, y] = concentric_disk(u);
            let r2 = x * x + y * y;
            assert!(r2 <= 1.0 + 1e-6, "outside the disk: {x} {y}");
            (r2, y.atan2(x))
        });
        // Area element r dr dφ = ½ d(r²) dφ.
        check_density("disk", 0.0, samples, |_, _| 0.5 * concentric_disk_pdf());
        assert_eq!(concentric_disk([0.5, 0.5]), [0.0, 0.0]);
    }

    #[test]
    fn cosine_hemisphere_matches_its_pdf() {
        let samples = uniforms(2).map(|u| {
            let d = cosine_hemisphere(u);
            assert!(d.z >= 0.0, "below the horizon: {d}");
            polar(d)
        });
        check_density("cosine", 0.0, samples, |z, _| cosine_hemisphere_pdf(z));
        assert_eq!(cosine_hemisphere_pdf(-0.5), 0.0);
        assert_eq!(cosine_hemisphere_pdf(1.0), 1.0 / PI);
    }

    #[test]
    fn cosine_hemisphere_mean_cosine_is_two_thirds() {
        // E[cos] = ∫ cos · cos/π dω = 2/3; Var = 1/2 − 4/9 = 1/18, so the
        // standard error over N = 200 000 is 0.236/√N ≈ 5.3e-4; 3e-3 is over 5.
        let mean = uniforms(3)
            .take(N)
            .map(|u| f64::from(cosine_hemisphere(u).z))
            .sum::<f64>()
            / N as f64;
        assert!((mean - 2.0 / 3.0).abs() < 3e-3, "{mean}");
    }

    #[test]
    fn uniform_sphere_matches_its_pdf() {
        let samples = uniforms(4).map(|u| polar(uniform_sphere(u)));
        check_density("sphere", -1.0, samples, |_, _| uniform_sphere_pdf());
    }

    #[test]
    fn uniform_hemisphere_matches_its_pdf() {
        let samples = uniforms(5).map(|u| {
            let d = uniform_hemisphere(u);
            assert!(d.z >= 0.0, "below the horizon: {d}");
            polar(d)
        });
        check_density("hemisphere", 0.0, samples, |_, _| uniform_hemisphere_pdf());
    }

    #[test]
    fn uniform_cone_stays_inside_and_matches_its_pdf() {
        for cos_max in [0.9f32, 0.3, -0.4] {
            let samples = uniforms(6).map(|u| {
                let d = uniform_cone(u, cos_max);
                assert!(d.z >= cos_max, "outside the cone {cos_max}: {d}");
                polar(d)
            });
            let pdf = uniform_cone_pdf(cos_max);
            check_density("cone", cos_max, samples, |_, _| pdf);
        }
        // The whole sphere at cos θmax = −1, the hemisphere at 0.
        let close = |a: f32, b: f32| (a / b - 1.0).abs() < 1e-6;
        assert!(close(uniform_cone_pdf(-1.0), uniform_sphere_pdf()));
        assert!(close(uniform_cone_pdf(0.0), uniform_hemisphere_pdf()));
        assert_eq!(uniform_cone([0.7, 0.2], 1.0), Vec3::Z);
    }

    #[test]
    fn cone_from_sin2_agrees_and_keeps_tiny_cones() {
        // A moderate cone: the same directions as from the cosine.
        let sin2 = 0.19f32;
        for u in uniforms(7).take(1000) {
            let (a, b) = (
                uniform_cone_sin2(u, sin2),
                uniform_cone(u, (1.0 - sin2).sqrt()),
            );
            assert!((a - b).length() < 1e-5, "{a} {b}");
        }
        let rel = uniform_cone_sin2_pdf(sin2) / uniform_cone_pdf((1.0 - sin2).sqrt()) - 1.0;
        assert!(rel.abs() < 1e-5, "{rel}");
        // A sphere of radius 1 at distance 1e5: θmax = 1e-5, so 1 − cos θmax =
        // 5e-11 is zero in f32 and cone sampling from the cosine collapses
        // onto the axis. From sin² the directions still fill the cone.
        let sin2 = 1e-10f32;
        let mut widest = 0.0f32;
        for u in uniforms(8).take(1000) {
            let d = uniform_cone_sin2(u, sin2);
            let sin_theta = d.x.hypot(d.y);
            assert!(sin_theta <= 1e-5 * (1.0 + 1e-5), "{d}");
            widest = widest.max(sin_theta);
        }
        assert!(widest > 0.9e-5, "{widest}");
        let pdf = uniform_cone_sin2_pdf(sin2);
        let expected = 1.0 / (TAU * 5e-11);
        assert!((pdf / expected - 1.0).abs() < 1e-5, "{pdf} vs {expected}");
        assert!(uniform_cone_pdf((1.0 - sin2).sqrt()).is_infinite());
    }

    #[test]
    fn uniform_triangle_is_uniform_over_sub_triangles() {
        // Split the triangle into 16 congruent sub-triangles (4 per edge): each
        // expects N/16 = 12 500, binomial σ ≈ 108; χ² over 16 cells has 15
        // degrees of freedom (mean 15, σ ≈ 5.5), bound 45 (> 5σ).
        let mut cells = [0u32; 16];
        let mut sums = [0.0f64; 3];
        for u in uniforms(9).take(N) {
            let (b0, b1) = uniform_triangle(u);
            let b2 = 1.0 - b0 - b1;
            assert!(b0 >= 0.0 && b1 >= 0.0 && b2 >= 0.0, "{b0} {b1} {b2}");
            for (s, b) in sums.iter_mut().zip([b0, b1, b2]) {
                *s += f64::from(b);
            }
            let (i, j, k) = (
                (b0 * 4.0) as u32,
                (b1 * 4.0) as u32,
                (b2 * 4.0).min(3.0) as u32,
            );
            // Upright sub-triangles have i + j + k = 3, inverted ones 2; (i, j)
            // and the orientation name one of 10 + 6 = 16 cells.
            let upright = i + j + k >= 3;
            let index = if upright {
                [0, 4, 7, 9][j as usize] + i
            } else {
                10 + [0, 3, 5][j as usize] + i
            };
            cells[index.min(15) as usize] += 1;
        }
        let expected = N as f64 / 16.0;
        let chi2: f64 = cells
            .iter()
            .map(|&c| (f64::from(c) - expected).powi(2) / expected)
            .sum();
        assert!(chi2 < 45.0, "χ² = {chi2}: {cells:?}");
        // Each barycentric is Beta(1, 2): mean 1/3, σ = √(1/18) ≈ 0.236, so
        // the standard error of a mean is 5.3e-4; 3e-3 is over 5 of them.
        for s in sums {
            assert!((s / N as f64 - 1.0 / 3.0).abs() < 3e-3, "{sums:?}");
        }
    }
}
