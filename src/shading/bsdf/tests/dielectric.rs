//! Tests of the glass lobes, through `Bsdf`.

use super::*;

#[test]
fn glass_splits_by_fresnel_and_conserves_energy() {
    let ior = 1.5;
    let b = Bsdf::Dielectric(Dielectric {
        ior,
        tint: Vec3::ONE,
    });
    let frame = tilted();
    for theta in [0.0f32, 30.0, 60.0, 85.0, 100.0, 140.0, 170.0, 180.0] {
        let wo = at_angle(&frame, theta, 0.5);
        let cos_o = wo.dot(frame.n);
        let fresnel_r = fresnel::dielectric(cos_o, ior);
        // The two lobes' probabilities: u just below F picks reflection
        // with pdf F; u just above picks refraction with pdf 1 − F.
        let lo = b.sample(&frame, wo, [fresnel_r * 0.999, 0.5, 0.5]).unwrap();
        assert_eq!(lo.kind, Lobe::SpecularReflection);
        assert!((lo.pdf - fresnel_r).abs() < 1e-6);
        if fresnel_r < 1.0 {
            let u0 = (fresnel_r + 1e-4).min(0.999_999);
            let hi = b.sample(&frame, wo, [u0, 0.5, 0.5]).unwrap();
            assert_eq!(hi.kind, Lobe::SpecularTransmission);
            assert!((lo.pdf + hi.pdf - 1.0).abs() < 1e-6, "{theta}");
            // Snell in world space, on the far side.
            let cos_t = hi.wi.dot(frame.n);
            assert!(cos_t * cos_o < 0.0);
            let (ni, nt) = if cos_o > 0.0 { (1.0, ior) } else { (ior, 1.0) };
            let (si, st) = (wo.cross(frame.n).length(), hi.wi.cross(frame.n).length());
            assert!((ni * si - nt * st).abs() < 1e-4, "{theta}");
        }
        // Monte Carlo: the reflected fraction is F (binomial, 5σ) and,
        // without the 1/η² radiance factor, every weight is exactly 1,
        // so E[f cos / pdf] = 1 with zero variance.
        let n = 20_000;
        let mut r = rng(10);
        let mut reflected = 0;
        for _ in 0..n {
            let s = b
                .sample_with(&frame, wo, u3(&mut r), Transport::Importance)
                .unwrap();
            reflected += usize::from(s.kind.is_reflection());
            assert_eq!(s.weight, Vec3::ONE);
            let w = s.f * s.wi.dot(frame.n).abs() / s.pdf;
            assert!((w - Vec3::ONE).abs().max_element() < 1e-4, "{theta}: {w}");
        }
        let p = f64::from(fresnel_r);
        let sigma = (p * (1.0 - p) / n as f64).sqrt();
        let got = reflected as f64 / n as f64;
        assert!(
            (got - p).abs() <= 5.0 * sigma + 1e-9,
            "{theta}: {got} vs {p}"
        );
        assert_eq!(b.eval(&frame, wo, lo.wi), Vec3::ZERO);
        assert_eq!(b.pdf(&frame, wo, lo.wi), 0.0);
    }
}

#[test]
fn glass_scales_radiance_by_eta_squared_and_a_crossing_pair_cancels() {
    let ior = 1.5;
    let tint = Vec3::new(1.0, 0.9, 0.8);
    let b = Bsdf::Dielectric(Dielectric { ior, tint });
    let frame = tilted();
    let wo = at_angle(&frame, 35.0, 1.0);
    // u[0] = 0.999 > F: refraction. Camera outside looking in.
    let into = b.sample(&frame, wo, [0.999, 0.0, 0.0]).unwrap();
    assert!((into.weight - tint / (ior * ior)).abs().max_element() < 1e-6);
    // Continue along the refracted ray to the slab's parallel far face,
    // whose outward normal is −n; there wo = −into.wi lies inside.
    let far = Frame::from_normal(-frame.n);
    let out = b.sample(&far, -into.wi, [0.999, 0.0, 0.0]).unwrap();
    assert!((out.weight - tint * ior * ior).abs().max_element() < 1e-4);
    // A glass slab in a furnace: in × out = tint², no radiance gain.
    let both = into.weight * out.weight;
    assert!((both - tint * tint).abs().max_element() < 1e-5, "{both}");
    // And the exit direction is parallel to the entry (a slab shifts, not bends).
    assert!((out.wi + wo).length() < 1e-5);
    let photon = b
        .sample_with(&frame, wo, [0.999, 0.0, 0.0], Transport::Importance)
        .unwrap();
    assert_eq!(photon.weight, tint);
}

#[test]
fn glass_reflects_totally_beyond_the_critical_angle() {
    let ior = 1.5f32;
    let b = Bsdf::Dielectric(Dielectric {
        ior,
        tint: Vec3::ONE,
    });
    let frame = tilted();
    let critical = (1.0 / ior).asin().to_degrees(); // 41.8°
    let mut r = rng(11);
    for theta in [critical + 0.5, 60.0, 89.0] {
        // Inside: below the outward normal.
        let wo = at_angle(&frame, 180.0 - theta, 0.2);
        for _ in 0..1000 {
            let s = b.sample(&frame, wo, u3(&mut r)).unwrap();
            assert_eq!(s.kind, Lobe::SpecularReflection, "{theta}");
            assert_eq!(s.pdf, 1.0);
            assert_eq!(s.weight, Vec3::ONE);
            assert!(s.wi.dot(frame.n) < 0.0);
        }
    }
    // Just inside the critical angle some light still escapes.
    let wo = at_angle(&frame, 180.0 - (critical - 0.5), 0.2);
    let s = b.sample(&frame, wo, [0.999_99, 0.5, 0.5]).unwrap();
    assert_eq!(s.kind, Lobe::SpecularTransmission);
}
