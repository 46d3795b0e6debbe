//! Tests of the Lambert lobe, through `Bsdf`.

use super::*;

#[test]
fn lambert_reflects_its_albedo() {
    let albedo = Vec3::new(0.9, 0.5, 0.1);
    let b = Bsdf::Lambert(Lambert { albedo });
    let frame = tilted();
    for theta in [0.0, 45.0, 85.0] {
        let wo = at_angle(&frame, theta, 0.4);
        // Independent: uniform-sphere integral of f cos. Per-sample sd is
        // √(5/3)·a ≈ 1.3a, so 400k samples give a standard error of 0.2%:
        // the 1% bound is 5σ.
        let (got, se) = integrated_albedo(&b, &frame, wo, 400_000, 2);
        assert!((got - 0.9).abs() < 0.009, "{theta}: {got} ± {se}");
        // Importance sampling cancels exactly: every weight is the albedo.
        let mut r = rng(3);
        for _ in 0..1000 {
            let s = b.sample(&frame, wo, u3(&mut r)).unwrap();
            assert!((s.weight - albedo).abs().max_element() < 1e-6);
            assert!(
                (s.f * s.wi.dot(frame.n) / s.pdf - albedo)
                    .abs()
                    .max_element()
                    < 1e-4
            );
            assert_eq!(s.kind, Lobe::DiffuseReflection);
        }
    }
    // Seen from the back, it reflects into the back hemisphere.
    let wo = at_angle(&frame, 160.0, 0.0);
    let s = b.sample(&frame, wo, [0.5, 0.3, 0.7]).unwrap();
    assert!(s.wi.dot(frame.n) < 0.0);
}
