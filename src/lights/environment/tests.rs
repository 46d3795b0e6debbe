use super::*;
use crate::sampling::Rng;

fn source(rotation: f32) -> EnvironmentSource {
    EnvironmentSource {
        file: None,
        sha256: None,
        radiance: None,
        scale: 2.0,
        rotation,
    }
}

/// An 8 × 4 map whose texels all differ, one of them black.
fn map(rotation: f32) -> Environment {
    let mut texels: Vec<[f32; 4]> = (0..32)
        .map(|i| {
            let i = i as f32;
            [
                1.0 + (i * 0.7).sin(),
                0.5 + 0.1 * i,
                (i * 1.3).cos().abs(),
                1.0,
            ]
        })
        .collect();
    texels[13] = [0.0; 4];
    Environment::map(8, &texels, source(rotation))
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

#[test]
fn the_map_is_mitsubas_latitude_longitude_with_y_up() {
    let env = map(0.0);
    assert!(close(env.direction([0.5, 0.5]).0, Vec3::Z));
    assert!(close(env.direction([0.0, 0.5]).0, -Vec3::Z));
    assert!(close(env.direction([0.25, 0.5]).0, Vec3::X));
    assert!(close(env.direction([0.3, 0.0]).0, Vec3::Y));
    // A right-handed quarter turn about +Y takes +Z to +X.
    assert!(close(map(90.0).direction([0.5, 0.5]).0, Vec3::X));
    for rotation in [0.0, 37.0, -120.0] {
        let env = map(rotation);
        for uv in [[0.1, 0.2], [0.6, 0.9], [0.99, 0.5], [0.4, 0.01]] {
            let (dir, sin) = env.direction(uv);
            let (back, sin_back) = env.uv(dir);
            assert!((back[0] - uv[0]).abs() < 1e-4 && (back[1] - uv[1]).abs() < 1e-4);
            assert!((sin - sin_back).abs() < 1e-5);
        }
    }
    // The lookup scales the texel: row 1 (θ in [45°, 90°)), column 2 (φ in [90°, 135°)).
    let (dir, _) = map(0.0).direction([2.5 / 8.0, 1.5 / 4.0]);
    let i = 10.0f32;
    let want = 2.0 * Vec3::new(1.0 + (i * 0.7).sin(), 0.5 + 0.1 * i, (i * 1.3).cos().abs());
    assert!(close(map(0.0).radiance(dir), want));
}

/// ∫ pdf dω over the sphere, by the midpoint rule on a fine θ, φ grid.
fn integral_of_pdf(env: &Environment) -> f64 {
    let (n_theta, n_phi) = (400, 800);
    let mut sum = 0.0f64;
    for i in 0..n_theta {
        let theta = PI * (i as f32 + 0.5) / n_theta as f32;
        for j in 0..n_phi {
            let phi = 2.0 * PI * (j as f32 + 0.5) / n_phi as f32;
            let dir = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            let d_omega = theta.sin() * (PI / n_theta as f32) * (2.0 * PI / n_phi as f32);
            sum += f64::from(env.pdf(dir) * d_omega);
        }
    }
    sum
}

#[test]
fn the_pdf_integrates_to_one() {
    for env in [map(0.0), map(33.0), Environment::constant(Vec3::splat(0.5))] {
        let total = integral_of_pdf(&env);
        assert!((total - 1.0).abs() < 2e-3, "{total}");
    }
}

#[test]
fn sampled_directions_follow_the_pdf() {
    // Chi-square over the texels: each texel's count against the samples
    // times its probability, ∫ pdf dω over the texel = its weight's share.
    let env = map(25.0);
    let count = 100_000;
    let mut seen = [0u32; 32];
    let mut rng = Rng::for_sample(11, 0, 0);
    let mut edges = 0;
    for _ in 0..count {
        // A point on the edge of the black texel can round into it: no sample.
        let Some(inc) = env.incident(rng.next_2d()) else {
            edges += 1;
            continue;
        };
        // The sample's estimate is L / pdf of its own direction.
        let again = env.radiance(inc.wi) / env.pdf(inc.wi);
        assert!((inc.irradiance - again).length() < 1e-3 * again.length());
        let ([u, v], _) = env.uv(inc.wi);
        let cell = ((v * 4.0) as usize).min(3) * 8 + ((u * 8.0) as usize).min(7);
        seen[cell] += 1;
    }
    assert!(edges < 10, "{edges} samples lost on edges");
    let count = count - edges;
    let weights: Vec<f32> = (0..32)
        .map(|cell| {
            let sin = (PI * ((cell / 8) as f32 + 0.5) / 4.0).sin();
            env.texels[cell].dot(LUMINANCE) * sin
        })
        .collect();
    let total: f32 = weights.iter().sum();
    let mut chi2 = 0.0f64;
    for (cell, w) in weights.iter().enumerate() {
        let expected = f64::from(w / total) * f64::from(count);
        if expected == 0.0 {
            assert_eq!(seen[cell], 0, "the black texel is never drawn");
            continue;
        }
        chi2 += (f64::from(seen[cell]) - expected).powi(2) / expected;
    }
    // 30 degrees of freedom (31 drawable cells): the 99.9% quantile is 59.7.
    assert!(chi2 < 59.7, "chi-square {chi2}");
}

#[test]
fn the_estimate_of_the_irradiance_is_right() {
    // A constant sky of radiance L gives an upward surface E = π L.
    let env = Environment::constant(Vec3::splat(1.5));
    let mut rng = Rng::for_sample(5, 0, 0);
    let count = 200_000;
    let mut sum = 0.0f64;
    for _ in 0..count {
        if let Some(inc) = env.incident(rng.next_2d()) {
            sum += f64::from(inc.irradiance.x * inc.wi.y.max(0.0));
        }
    }
    let e = sum / f64::from(count);
    let exact = f64::from(PI * 1.5);
    assert!((e - exact).abs() < 5e-3 * exact, "{e} vs {exact}");
}

#[test]
fn power_is_the_flux_through_the_bounding_disk() {
    let env = Environment::constant(Vec3::ONE);
    let bounds = Bounds {
        min: Vec3::splat(-1.0),
        max: Vec3::ONE,
    };
    let r2 = 3.0;
    let want = PI * r2 * 4.0 * PI;
    let got = env.power(bounds);
    assert!((got.x - want).abs() < 1e-4 * want, "{got} vs {want}");
}
