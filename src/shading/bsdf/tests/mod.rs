//! Tests of `Bsdf` as a whole: the helpers every lobe's tests use (independent
//! integrals over the sphere, sampled albedos) and the checks every lobe must
//! pass (sampling agrees with eval and pdf, reciprocity, no NaN, the material
//! mapping). Each lobe's own tests are in the file named after it.

mod classic;
mod dielectric;
mod lambert;
mod metal;
mod mirror;
mod plastic;

use std::f32::consts::TAU;

use super::*;
use crate::sampling::{Rng, warp};
use crate::shading::fresnel;

fn rng(seed: u64) -> Rng {
    Rng::for_sample(seed, 0, 0)
}

fn u3(r: &mut Rng) -> [f32; 3] {
    [r.next_f32(), r.next_f32(), r.next_f32()]
}

/// Uniform direction on the sphere (pdf 1/4π): the independent sampler
/// the integrals below use, so they do not trust `Bsdf::sample`.
fn uniform_sphere(r: &mut Rng) -> Vec3 {
    warp::uniform_sphere([r.next_f32(), r.next_f32()])
}

fn at_angle(frame: &Frame, theta_deg: f32, phi: f32) -> Vec3 {
    let t = theta_deg.to_radians();
    frame.to_world(Vec3::new(t.sin() * phi.cos(), t.sin() * phi.sin(), t.cos()))
}

/// A tilted frame, so the tests exercise to_local/to_world too.
fn tilted() -> Frame {
    Frame::from_normal(Vec3::new(0.3, -0.4, 0.866).normalize())
}

/// Mean and standard error of the mean.
fn mean_se(sum: f64, sum2: f64, n: usize) -> (f64, f64) {
    let n = n as f64;
    let mean = sum / n;
    let var = (sum2 / n - mean * mean).max(0.0);
    (mean, (var / n).sqrt())
}

/// E[weight] over sampled directions (the sampled directional albedo).
fn sampled_albedo(b: &Bsdf, frame: &Frame, wo: Vec3, n: usize, seed: u64) -> (f64, f64) {
    let mut r = rng(seed);
    let (mut s, mut s2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        if let Some(smp) = b.sample_with(frame, wo, u3(&mut r), Transport::Importance) {
            let w = f64::from(smp.weight.max_element());
            s += w;
            s2 += w * w;
        }
    }
    mean_se(s, s2, n)
}

/// The fraction of samples `sample` drops.
fn lost_fraction(b: &Bsdf, frame: &Frame, wo: Vec3, n: usize, seed: u64) -> f64 {
    let mut r = rng(seed);
    let lost = (0..n)
        .filter(|_| b.sample(frame, wo, u3(&mut r)).is_none())
        .count();
    lost as f64 / n as f64
}

/// ∫ f(wo, wi) |cos θi| dωi by uniform sphere sampling (max channel).
fn integrated_albedo(b: &Bsdf, frame: &Frame, wo: Vec3, n: usize, seed: u64) -> (f64, f64) {
    let mut r = rng(seed);
    let (mut s, mut s2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let wi = uniform_sphere(&mut r);
        let v = f64::from(b.eval(frame, wo, wi).max_element() * wi.dot(frame.n).abs())
            * 4.0
            * std::f64::consts::PI;
        s += v;
        s2 += v * v;
    }
    mean_se(s, s2, n)
}

fn glossy_bsdfs() -> Vec<(&'static str, Bsdf)> {
    vec![
        (
            "lambert",
            Bsdf::Lambert(Lambert {
                albedo: Vec3::new(0.8, 0.5, 0.2),
            }),
        ),
        (
            "metal 0.3",
            Bsdf::Metal(Metal {
                f0: Vec3::new(0.95, 0.64, 0.54),
                roughness: 0.3,
            }),
        ),
        (
            "metal 0.7",
            Bsdf::Metal(Metal {
                f0: Vec3::ONE,
                roughness: 0.7,
            }),
        ),
        (
            "plastic 0.3",
            Bsdf::Plastic(Plastic {
                albedo: Vec3::new(0.7, 0.2, 0.2),
                specular: Vec3::splat(0.04),
                roughness: 0.3,
            }),
        ),
        (
            "plastic 0.6",
            Bsdf::Plastic(Plastic {
                albedo: Vec3::splat(0.5),
                specular: Vec3::splat(0.3),
                roughness: 0.6,
            }),
        ),
        (
            "classic",
            classic::classic(Vec3::new(0.8, 0.5, 0.2), 1.5, |f| {
                f.diffuse = 0.7;
                f.specular = 0.4;
                f.roughness = 0.1;
                f.phong = 0.3;
                f.phong_size = 20.0;
                f.metallic = 0.5;
            }),
        ),
    ]
}

#[test]
fn sampled_values_match_eval_and_pdf() {
    let frame = tilted();
    for (name, b) in glossy_bsdfs() {
        for theta in [10.0f32, 50.0, 80.0, 130.0] {
            let wo = at_angle(&frame, theta, 0.3);
            let mut r = rng(7);
            for _ in 0..2000 {
                let Some(s) = b.sample(&frame, wo, u3(&mut r)) else {
                    continue;
                };
                assert!(!s.delta);
                let f = b.eval(&frame, wo, s.wi);
                let pdf = b.pdf(&frame, wo, s.wi);
                let rel = |a: f32, b: f32| (a - b).abs() <= 1e-3 * a.abs().max(b.abs()) + 1e-6;
                assert!(rel(pdf, s.pdf), "{name} θ {theta}: {pdf} vs {}", s.pdf);
                for c in 0..3 {
                    assert!(rel(f[c], s.f[c]), "{name} θ {theta}: {f} vs {}", s.f);
                    let w = s.f[c] * s.wi.dot(frame.n).abs() / s.pdf;
                    assert!(rel(w, s.weight[c]), "{name}: {w} vs {}", s.weight);
                }
                // Reflection stays on wo's side.
                assert!(s.wi.dot(frame.n) * wo.dot(frame.n) > 0.0);
            }
        }
    }
}

/// The chi-square-style check: bin sampled directions over the sphere
/// (equal-area bins in cos θ and φ) and compare the counts with N·∫pdf
/// over each bin, integrated numerically from `Bsdf::pdf`. The samples
/// `sample` drops (below the horizon) form one more bin, whose expected
/// count is N(1 − ∫pdf): so this also checks that ∫pdf = 1 − P(None).
#[test]
fn sampled_directions_follow_the_pdf() {
    const NZ: usize = 32;
    const NPHI: usize = 64;
    const SUB: usize = 12;
    const N: usize = 200_000;
    let frame = Frame::from_normal(Vec3::Z);
    let mut report = Vec::new();
    for (name, b) in glossy_bsdfs() {
        for theta in [0.0f32, 40.0, 75.0] {
            let wo = at_angle(&frame, theta, 0.3);
            let mut observed = vec![0u32; NZ * NPHI + 1];
            let mut r = rng(8);
            for _ in 0..N {
                let bin = match b.sample(&frame, wo, u3(&mut r)) {
                    None => NZ * NPHI,
                    Some(s) => {
                        let z = ((s.wi.z + 1.0) * 0.5 * NZ as f32) as usize;
                        let phi = s.wi.y.atan2(s.wi.x).rem_euclid(TAU);
                        let p = (phi / TAU * NPHI as f32) as usize;
                        z.min(NZ - 1) * NPHI + p.min(NPHI - 1)
                    }
                };
                observed[bin] += 1;
            }
            let mut expected = vec![0f64; NZ * NPHI + 1];
            let (dz, dphi) = (2.0 / NZ as f64, TAU as f64 / NPHI as f64);
            let cell = dz * dphi / (SUB * SUB) as f64;
            let mut total = 0.0;
            for iz in 0..NZ {
                for ip in 0..NPHI {
                    let mut sum = 0.0;
                    for a in 0..SUB {
                        for c in 0..SUB {
                            let z = -1.0 + dz * (iz as f64 + (a as f64 + 0.5) / SUB as f64);
                            let phi = dphi * (ip as f64 + (c as f64 + 0.5) / SUB as f64);
                            let s = (1.0 - z * z).max(0.0).sqrt();
                            let wi =
                                Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, z as f32);
                            sum += f64::from(b.pdf(&frame, wo, wi)) * cell;
                        }
                    }
                    expected[iz * NPHI + ip] = sum * N as f64;
                    total += sum;
                }
            }
            expected[NZ * NPHI] = (1.0 - total).max(0.0) * N as f64;
            let lost = f64::from(observed[NZ * NPHI]) / N as f64;
            // ∫pdf + P(None) = 1: quadrature error of the peaked lobes
            // and the binomial noise of P(None) (≤ 0.1%) stay below 1%.
            assert!(
                (total + lost - 1.0).abs() < 0.01,
                "{name} θ {theta}: ∫pdf {total} + lost {lost}"
            );
            // Pool bins expecting fewer than 5 (chi-square's usual rule).
            let (mut chi2, mut dof, mut pool_o, mut pool_e) = (0.0, 0usize, 0.0, 0.0);
            for (o, e) in observed.iter().zip(&expected) {
                if *e < 5.0 {
                    pool_o += f64::from(*o);
                    pool_e += e;
                } else {
                    chi2 += (f64::from(*o) - e).powi(2) / e;
                    dof += 1;
                }
            }
            if pool_e >= 5.0 {
                chi2 += (pool_o - pool_e).powi(2) / pool_e;
                dof += 1;
            } else {
                assert!(pool_o <= 20.0, "{name} θ {theta}: {pool_o} in empty bins");
            }
            let dof = dof.saturating_sub(1).max(1) as f64;
            // For a right pdf, chi² ≈ dof ± √(2 dof); allow 6σ of noise.
            // A wrong pdf (e.g. a factor missing) gives chi² in the
            // thousands at this sample count.
            report.push((name, theta, chi2 / dof, lost));
            assert!(
                chi2 < dof + 6.0 * (2.0 * dof).sqrt(),
                "{name} θ {theta}: chi² {chi2} for {dof} dof"
            );
        }
    }
    eprintln!("(bsdf, θo, chi²/dof, P(lost)): {report:?}");
}

#[test]
fn reflection_lobes_are_reciprocal() {
    let frame = tilted();
    let mut r = rng(9);
    for (name, b) in glossy_bsdfs() {
        let mut nonzero = 0;
        for _ in 0..5000 {
            let (wo, wi) = (uniform_sphere(&mut r), uniform_sphere(&mut r));
            let (a, c) = (b.eval(&frame, wo, wi), b.eval(&frame, wi, wo));
            assert!(
                (a - c).abs().max_element() <= 1e-4 * a.max_element().max(1.0),
                "{name}: {a} vs {c}"
            );
            nonzero += usize::from(a.max_element() > 0.0);
        }
        // About half the pairs lie on one side; those must be nonzero.
        assert!(nonzero > 2000, "{name}: {nonzero}");
    }
}

#[test]
fn every_materials_sampled_albedo_is_at_most_one() {
    // Issue 4 §10: white materials at their brightest settings.
    let frame = tilted();
    let all = [
        Bsdf::Lambert(Lambert { albedo: Vec3::ONE }),
        Bsdf::Plastic(Plastic {
            albedo: Vec3::ONE,
            specular: Vec3::splat(0.04),
            roughness: 0.2,
        }),
        Bsdf::Mirror(Mirror {
            reflectance: Vec3::ONE,
        }),
        Bsdf::Metal(Metal {
            f0: Vec3::ONE,
            roughness: 0.4,
        }),
        Bsdf::Dielectric(Dielectric {
            ior: 1.5,
            tint: Vec3::ONE,
        }),
        classic::classic(Vec3::ONE, 1.5, |f| {
            f.diffuse = 1.0;
            f.specular = 1.0;
            f.phong = 1.0;
            f.reflection = 1.0;
            f.transmit = 1.0;
        }),
    ];
    for b in all {
        for theta in [0.0f32, 60.0, 88.0, 150.0] {
            let wo = at_angle(&frame, theta, 0.0);
            let (albedo, se) = sampled_albedo(&b, &frame, wo, 50_000, 12);
            assert!(
                albedo <= 1.0 + 4.0 * se + 1e-6,
                "{b:?} θ {theta}: {albedo} ± {se}"
            );
        }
    }
}

#[test]
fn no_nan_anywhere() {
    let mut r = rng(13);
    let frame = tilted();
    let bsdfs = [
        Bsdf::Lambert(Lambert { albedo: Vec3::ONE }),
        Bsdf::Plastic(Plastic {
            albedo: Vec3::ONE,
            specular: Vec3::splat(0.04),
            roughness: 0.0,
        }),
        Bsdf::Plastic(Plastic {
            albedo: Vec3::ZERO,
            specular: Vec3::ZERO,
            roughness: f32::NAN,
        }),
        Bsdf::Mirror(Mirror {
            reflectance: Vec3::ONE,
        }),
        Bsdf::Metal(Metal {
            f0: Vec3::ONE,
            roughness: 0.0,
        }),
        Bsdf::Metal(Metal {
            f0: Vec3::splat(0.5),
            roughness: 1.0,
        }),
        Bsdf::Dielectric(Dielectric {
            ior: 1.5,
            tint: Vec3::ONE,
        }),
        Bsdf::Dielectric(Dielectric {
            ior: 1.0,
            tint: Vec3::ONE,
        }),
        classic::classic(Vec3::ONE, 1.5, |f| {
            f.diffuse = 0.5;
            f.specular = 1.0;
            f.roughness = 0.0005;
            f.phong = 1.0;
            f.phong_size = 1e6;
            f.reflection = 0.2;
            f.transmit = 0.3;
        }),
        classic::classic(Vec3::ZERO, 1.0, |_| {}),
    ];
    let n = frame.n;
    let tangent = frame.s;
    let mut dirs = vec![
        n,
        -n,
        tangent,
        -tangent,
        (n * 1e-7 + tangent).normalize(),
        (-n * 1e-7 + tangent).normalize(),
        (n + tangent * 1e-7).normalize(),
    ];
    dirs.extend((0..300).map(|_| uniform_sphere(&mut r)));
    let us = [
        [0.0, 0.0, 0.0],
        [0.999_999_9, 0.999_999_9, 0.999_999_9],
        [0.5, 0.5, 0.0],
        [0.0, 0.999_999_9, 0.5],
    ];
    for b in bsdfs {
        for &wo in &dirs {
            for &wi in dirs.iter().take(40) {
                let f = b.eval(&frame, wo, wi);
                let p = b.pdf(&frame, wo, wi);
                assert!(
                    f.is_finite() && f.min_element() >= 0.0,
                    "{b:?} {wo} {wi}: {f}"
                );
                assert!(p.is_finite() && p >= 0.0, "{b:?} {wo} {wi}: {p}");
            }
            let random = [u3(&mut r), u3(&mut r)];
            for u in us.iter().chain(&random) {
                if let Some(s) = b.sample(&frame, wo, *u) {
                    assert!(s.pdf > 0.0 && s.pdf.is_finite(), "{b:?} {wo} {u:?}: {s:?}");
                    assert!(s.f.is_finite() && s.weight.is_finite(), "{b:?} {wo}: {s:?}");
                    assert!((s.wi.length() - 1.0).abs() < 1e-4, "{b:?} {wo}: {s:?}");
                }
            }
        }
    }
}

#[test]
fn materials_map_onto_bsdfs() {
    let mut m = Material::diffuse("d", Vec3::splat(0.5));
    assert_eq!(
        Bsdf::from_material(&m),
        Bsdf::Lambert(Lambert {
            albedo: Vec3::splat(0.5)
        })
    );
    m.kind = MaterialKind::Plastic;
    m.specular = Vec3::splat(0.04);
    m.shininess = 98.0;
    let Bsdf::Plastic(Plastic { roughness, .. }) = Bsdf::from_material(&m) else {
        panic!()
    };
    // α = √(2/(98 + 2)) = √0.02.
    assert!((roughness - 0.02f32.sqrt()).abs() < 1e-6);
    assert_eq!(shininess_to_alpha(0.0), 1.0);
    assert_eq!(shininess_to_alpha(1e12), MIN_ALPHA);
    m.kind = MaterialKind::Mirror;
    assert_eq!(
        Bsdf::from_material(&m),
        Bsdf::Mirror(Mirror {
            reflectance: Vec3::splat(0.04)
        })
    );
    m.specular = Vec3::ZERO;
    assert_eq!(
        Bsdf::from_material(&m),
        Bsdf::Mirror(Mirror {
            reflectance: Vec3::splat(0.5)
        })
    );
    m.kind = MaterialKind::Dielectric;
    m.ior = 1.33;
    let glass = Bsdf::from_material(&m);
    assert_eq!(
        glass,
        Bsdf::Dielectric(Dielectric {
            ior: 1.33,
            tint: Vec3::ONE
        })
    );
    assert!(glass.is_delta() && glass.has_transmission() && glass.has_specular());
    m.ior = f32::NAN;
    assert!(
        matches!(Bsdf::from_material(&m), Bsdf::Dielectric(Dielectric { ior, .. }) if ior == 1.5)
    );
    m.kind = MaterialKind::Emissive;
    assert!(matches!(
        Bsdf::from_material(&m),
        Bsdf::Lambert(Lambert { .. })
    ));
    let metal = Bsdf::Metal(Metal {
        f0: Vec3::ONE,
        roughness: 0.1,
    });
    assert!(!metal.is_delta() && metal.has_glossy() && !metal.has_specular());
    assert!(!metal.has_transmission());
}
