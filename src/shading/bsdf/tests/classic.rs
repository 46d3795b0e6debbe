//! The classic lobe: the delta fractions come out as the finish gives them,
//! the layers never return more than they receive, and total internal
//! reflection turns the transmitted fraction into reflection.

use super::*;
use crate::shading::Finish;

/// A classic lobe with no diffuse part unless `f` sets one. As the scene
/// loader does, a `reflection_max` left unset takes the value of `reflection`.
pub(super) fn classic(albedo: Vec3, ior: f32, f: impl FnOnce(&mut Finish)) -> Bsdf {
    let mut finish = Finish {
        diffuse: 0.0,
        reflection_max: f32::NAN,
        ..Finish::default()
    };
    f(&mut finish);
    if finish.reflection_max.is_nan() {
        finish.reflection_max = finish.reflection;
    }
    Bsdf::Classic(Classic {
        albedo,
        finish,
        ior,
    })
}

#[test]
fn delta_fractions_keep_all_the_light_they_are_given() {
    // reflection + transmit = 1 and nothing else: every sample carries
    // weight exactly 1 (light transport, no 1/η² scaling), on both sides and
    // beyond the critical angle, where the transmitted part reflects.
    let b = classic(Vec3::ONE, 1.5, |f| {
        f.reflection = 0.4;
        f.transmit = 0.6;
    });
    assert!(b.is_delta() && b.has_specular() && b.has_transmission());
    let frame = tilted();
    let mut r = rng(21);
    for theta in [0.0f32, 30.0, 70.0, 110.0, 150.0, 175.0] {
        let wo = at_angle(&frame, theta, 0.4);
        for _ in 0..200 {
            let s = b
                .sample_with(&frame, wo, u3(&mut r), Transport::Importance)
                .unwrap();
            assert!(s.delta);
            assert!(
                (s.weight - Vec3::ONE).abs().max_element() < 1e-6,
                "{theta}: {s:?}"
            );
            let w = s.f * s.wi.dot(frame.n).abs() / s.pdf;
            assert!((w - s.weight).abs().max_element() < 1e-5, "{w} vs {s:?}");
        }
    }
}

#[test]
fn transmitted_light_reflects_totally_beyond_the_critical_angle() {
    let b = classic(Vec3::ONE, 1.5, |f| f.transmit = 1.0);
    let frame = tilted();
    let critical = (1.0f32 / 1.5).asin().to_degrees();
    // Inside, beyond the critical angle: all of it reflects, back inside.
    let wo = at_angle(&frame, 180.0 - (critical + 1.0), 0.2);
    let s = b.sample(&frame, wo, [0.5, 0.5, 0.5]).unwrap();
    assert_eq!(s.kind, Lobe::SpecularReflection);
    assert_eq!(s.weight, Vec3::ONE);
    assert!(s.wi.dot(frame.n) < 0.0);
    // Inside, within it: refracted out, radiance scaled by η² = (1/1.5)⁻²... seen
    // from inside, η = n_t/n_i = 1/1.5, so the weight is 1/η² = 2.25.
    let wo = at_angle(&frame, 180.0 - (critical - 1.0), 0.2);
    let s = b.sample(&frame, wo, [0.5, 0.5, 0.5]).unwrap();
    assert_eq!(s.kind, Lobe::SpecularTransmission);
    assert!(s.wi.dot(frame.n) > 0.0);
    assert!((s.weight.x - 2.25).abs() < 1e-5, "{s:?}");
}

#[test]
fn fresnel_reflection_head_on_is_the_normal_reflectance() {
    // reflection { 0, 1 fresnel on } with ior n: at normal incidence
    // R = ((n − 1)/(n + 1))², 0.04 for n = 1.5; at grazing it tends to 1.
    let b = classic(Vec3::ONE, 1.5, |f| {
        f.reflection = 0.0;
        f.reflection_max = 1.0;
        f.fresnel = true;
    });
    let frame = tilted();
    let s = b.sample(&frame, frame.n, [0.5, 0.5, 0.5]).unwrap();
    assert!((s.weight.x - 0.04).abs() < 1e-6, "{s:?}");
    let grazing = at_angle(&frame, 89.9, 0.0);
    let s = b.sample(&frame, grazing, [0.5, 0.5, 0.5]).unwrap();
    assert!(s.weight.x > 0.95, "{s:?}");
    // Without fresnel, POV-Ray's linear falloff: min + (max − min)(1 − cos θ).
    let b = classic(Vec3::ONE, 1.5, |f| {
        f.reflection = 0.2;
        f.reflection_max = 0.6;
    });
    let wo = at_angle(&frame, 60.0, 0.0);
    let s = b.sample(&frame, wo, [0.5, 0.5, 0.5]).unwrap();
    assert!((s.weight.x - 0.4).abs() < 1e-5, "{s:?}");
}

#[test]
fn fractions_that_fit_pass_unchanged_and_others_shrink_to_one() {
    let frame = tilted();
    let wo = at_angle(&frame, 35.0, 0.0);
    // diffuse 0.4 (white) + reflection 0.5 fit: the albedo is their sum.
    let fits = classic(Vec3::ONE, 1.0, |f| {
        f.diffuse = 0.4;
        f.reflection = 0.5;
    });
    let (albedo, se) = sampled_albedo(&fits, &frame, wo, 100_000, 22);
    assert!((albedo - 0.9).abs() < 4.0 * se + 1e-6, "{albedo} ± {se}");
    // diffuse 1 + reflection 0.5 ask for 1.5: the diffuse keeps what is left.
    let shrinks = classic(Vec3::ONE, 1.0, |f| {
        f.diffuse = 1.0;
        f.reflection = 0.5;
    });
    let (albedo, se) = sampled_albedo(&shrinks, &frame, wo, 100_000, 23);
    assert!((albedo - 1.0).abs() < 4.0 * se + 1e-6, "{albedo} ± {se}");
    // The diffuse part by itself, through eval: 0.5/π for a white pigment.
    let f = shrinks.eval(&frame, wo, at_angle(&frame, 20.0, 2.0));
    assert!((f.x - 0.5 / std::f32::consts::PI).abs() < 1e-6, "{f}");
}

#[test]
fn a_finish_at_its_maximum_never_gains_energy() {
    // Every knob at its top, singly and together, on both sides.
    let all: [fn(&mut Finish); 5] = [
        |f| {
            f.diffuse = 1.0;
            f.specular = 1.0;
            f.phong = 1.0;
            f.roughness = 1.0;
            f.phong_size = 1.0;
        },
        |f| {
            f.diffuse = 1.0;
            f.specular = 1.0;
            f.phong = 1.0;
            f.reflection = 0.3;
            f.reflection_max = 1.0;
            f.fresnel = true;
            f.transmit = 0.5;
        },
        |f| {
            f.diffuse = 1.0;
            f.reflection = 1.0;
            f.transmit = 1.0;
        },
        |f| {
            f.specular = 1.0;
            f.roughness = 0.0005;
            f.metallic = 1.0;
        },
        |f| {
            f.diffuse = 1.0;
            f.phong = 1.0;
            f.phong_size = 1000.0;
            f.transmit = 1.0;
        },
    ];
    let frame = tilted();
    for (i, set) in all.into_iter().enumerate() {
        let b = classic(Vec3::ONE, 1.5, set);
        for theta in [0.0f32, 45.0, 85.0, 120.0, 178.0] {
            let wo = at_angle(&frame, theta, 0.7);
            let (albedo, se) = sampled_albedo(&b, &frame, wo, 50_000, 24);
            assert!(
                albedo <= 1.0 + 4.0 * se + 1e-6,
                "finish {i} θ {theta}: {albedo} ± {se}"
            );
        }
    }
}

#[test]
fn metallic_tints_highlights_and_reflection_by_the_pigment() {
    let gold = Vec3::new(1.0, 0.5, 0.25);
    let b = classic(gold, 1.0, |f| {
        f.reflection = 0.8;
        f.metallic = 1.0;
    });
    let frame = tilted();
    let s = b.sample(&frame, frame.n, [0.5, 0.5, 0.5]).unwrap();
    assert!((s.weight - gold * 0.8).abs().max_element() < 1e-6, "{s:?}");
    let white = classic(gold, 1.0, |f| f.reflection = 0.8);
    let s = white.sample(&frame, frame.n, [0.5, 0.5, 0.5]).unwrap();
    assert!(
        (s.weight - Vec3::splat(0.8)).abs().max_element() < 1e-6,
        "{s:?}"
    );
}
