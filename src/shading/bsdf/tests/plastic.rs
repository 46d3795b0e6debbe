//! Tests of the plastic lobe, through `Bsdf`.

use super::*;
use crate::shading::bsdf::plastic::coat_transmission;

#[test]
fn plastic_never_reflects_more_than_it_receives() {
    let frame = tilted();
    let mut worst = 0.0f64;
    for specular in [0.0f32, 0.04, 0.5, 1.0] {
        for alpha in [0.05f32, 0.3, 1.0] {
            let b = Bsdf::Plastic(Plastic {
                albedo: Vec3::ONE,
                specular: Vec3::splat(specular),
                roughness: alpha,
            });
            for theta in [0.0f32, 45.0, 75.0, 89.0] {
                let wo = at_angle(&frame, theta, 2.0);
                let (albedo, se) = sampled_albedo(&b, &frame, wo, 100_000, 6);
                worst = worst.max(albedo);
                assert!(
                    albedo < 1.0 + 4.0 * se,
                    "F0 {specular} α {alpha} θ {theta}: {albedo}"
                );
                // The coupled diffuse alone has the closed-form albedo
                // (1 − F0)(1 − (1 − cos/2)^5); the coat only adds to it.
                let c = theta.to_radians().cos();
                let diffuse = f64::from((1.0 - specular) * coat_transmission(c));
                assert!(
                    albedo > diffuse - 4.0 * se,
                    "F0 {specular} α {alpha} θ {theta}: {albedo} < {diffuse}"
                );
            }
        }
    }
    eprintln!("plastic worst directional albedo: {worst}");
}
