//! Tests of the mirror lobe, through `Bsdf`.

use super::*;

#[test]
fn mirror_reflects_at_the_equal_angle() {
    let reflectance = Vec3::new(0.9, 0.8, 0.7);
    let b = Bsdf::Mirror(Mirror { reflectance });
    let frame = tilted();
    for theta in [0.0f32, 30.0, 89.0, 120.0, 180.0] {
        let wo = at_angle(&frame, theta, 0.9);
        let s = b.sample(&frame, wo, [0.1, 0.2, 0.3]).unwrap();
        assert!(s.delta && s.kind == Lobe::SpecularReflection);
        let want = fresnel::reflect(-wo, frame.n);
        assert!((s.wi - want).length() < 1e-5, "{theta}: {} vs {want}", s.wi);
        assert!((s.wi.dot(frame.n) - wo.dot(frame.n)).abs() < 1e-5);
        assert_eq!(s.weight, reflectance);
        let w = s.f * s.wi.dot(frame.n).abs() / s.pdf;
        assert!((w - reflectance).abs().max_element() < 1e-5);
        assert_eq!(b.eval(&frame, wo, s.wi), Vec3::ZERO);
        assert_eq!(b.pdf(&frame, wo, s.wi), 0.0);
    }
}
