//! Fresnel reflectance, Snell refraction and mirror reflection.
//!
//! Conventions shared by every function here, so callers never have to guess:
//!
//! - `n` is the surface's *outward* normal (pointing out of the material, into
//!   the medium the surface faces), never flipped toward the viewer. Which side
//!   a direction lies on is read from the sign of its cosine with `n`: that is
//!   how a dielectric knows whether light enters or leaves it.
//! - `ior` is the material's index of refraction relative to the outside
//!   medium, i.e. η = n_transmitted / n_incident for light *entering* the
//!   material. Light leaving it sees 1/ior.
//! - Directions are unit vectors. `wo` points away from the surface (toward
//!   the viewer), as in pbrt; `reflect` alone takes a ray direction travelling
//!   *toward* the surface, matching the textbook V_o = V_i − 2(V_i·N)N.

use crate::math::Vec3;

/// Fresnel reflectance of a smooth dielectric interface for unpolarised light.
///
/// `cos_i` is the cosine between the direction light arrives from (pointing
/// away from the surface) and the outward normal: positive on the outside,
/// negative when the light arrives from inside the material. `ior` is the
/// material's index relative to the outside (see the module notes). Beyond
/// the critical angle (only possible from the denser side) the result is 1:
/// total internal reflection. The result lies in [0, 1] for any finite input
/// with `ior > 0`.
pub fn dielectric(cos_i: f32, ior: f32) -> f32 {
    // Inside the material the roles swap: the "incident" index is ior and the
    // transmitted one is 1, so the relative index is 1/ior.
    let (cos_i, eta) = if cos_i < 0.0 {
        (-cos_i, 1.0 / ior)
    } else {
        (cos_i, ior)
    };
    let cos_i = cos_i.min(1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    // NaN comes only from a degenerate ior: reflect everything rather than
    // propagate it.
    if sin2_t >= 1.0 || sin2_t.is_nan() {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    // Both denominators are > 0: cos_t > 0 here and eta > 0.
    let r_parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (r_parallel * r_parallel + r_perpendicular * r_perpendicular)
}

/// Snell refraction: the transmitted direction for light leaving along `wo`.
///
/// `wo` points away from the surface on the side it lies on; `n` is the
/// outward normal; `ior` as in [`dielectric`]. The side is chosen by the sign
/// of `wo·n`: positive means `wo` is outside and the result points into the
/// material (relative index `ior`), negative means `wo` is inside and the
/// result points out (relative index `1/ior`). Returns the unit transmitted
/// direction (pointing away from the surface on the other side), or `None`
/// under total internal reflection. Light paths are reversible, so the same
/// function serves camera paths (wo toward the eye) and light paths.
pub fn refract(wo: Vec3, n: Vec3, ior: f32) -> Option<Vec3> {
    let cos_o = wo.dot(n);
    let (n, eta, cos_o) = if cos_o < 0.0 {
        (-n, 1.0 / ior, -cos_o)
    } else {
        (n, ior, cos_o)
    };
    let cos_o = cos_o.min(1.0);
    let sin2_t = (1.0 - cos_o * cos_o) / (eta * eta);
    if sin2_t >= 1.0 || sin2_t.is_nan() {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    // pbrt's form: the tangential part scales by 1/eta, the normal part is
    // rebuilt from cos_t on the far side. Unit length up to rounding;
    // normalise so repeated refractions do not drift.
    Some((-wo / eta + (cos_o / eta - cos_t) * n).normalize())
}

/// Mirror reflection V_o = V_i − 2(V_i·N)N.
///
/// `v` is a ray direction travelling *toward* the surface (V_i, e.g. the
/// incoming ray's `dir`) and the result travels away from it; either
/// orientation of `n` gives the same answer. For a `wo` pointing away from
/// the surface the mirror direction is `reflect(-wo, n)`. Angle and length
/// are preserved: `reflect(v, n)·n = −v·n`.
pub fn reflect(v: Vec3, n: Vec3) -> Vec3 {
    v - 2.0 * v.dot(n) * n
}

/// Schlick's approximation F0 + (1 − F0)(1 − cos)^5 of the Fresnel
/// reflectance, per colour channel.
///
/// Used for metals (F0 their colour at normal incidence) and the plastic
/// coat, where an exact conductor Fresnel would need complex indices that
/// scenes do not provide. `cos` is the cosine between the light direction and
/// the (micro)normal; it is clamped to [0, 1], so a slightly negative cosine
/// from rounding gives F = 1, not a value above 1.
pub fn schlick(f0: Vec3, cos: f32) -> Vec3 {
    let m = (1.0 - cos.clamp(0.0, 1.0)).powi(5);
    f0 + (Vec3::ONE - f0) * m
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The exact Fresnel equations in their angle form (Born & Wolf):
    /// R_s = sin²(θi−θt)/sin²(θi+θt), R_p = tan²(θi−θt)/tan²(θi+θt), with θt
    /// from Snell's law by `asin`. Independent of the cosine form above.
    fn fresnel_by_angles(theta_i: f64, n_i: f64, n_t: f64) -> f64 {
        let s = n_i / n_t * theta_i.sin();
        if s >= 1.0 {
            return 1.0;
        }
        let theta_t = s.asin();
        let rs = ((theta_i - theta_t).sin() / (theta_i + theta_t).sin()).powi(2);
        let rp = ((theta_i - theta_t).tan() / (theta_i + theta_t).tan()).powi(2);
        0.5 * (rs + rp)
    }

    fn direction(theta: f32, phi: f32) -> Vec3 {
        Vec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        )
    }

    #[test]
    fn normal_incidence_gives_the_textbook_value_from_either_side() {
        for n in [1.0f32, 1.33, 1.5, 2.42] {
            let expected = ((n - 1.0) / (n + 1.0)).powi(2);
            let outside = dielectric(1.0, n);
            let inside = dielectric(-1.0, n);
            assert!((outside - expected).abs() < 1e-6, "{n}: {outside}");
            assert!((inside - expected).abs() < 1e-6, "{n}: {inside}");
        }
        // Glass: 4% is the number every optics text quotes.
        assert!((dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
    }

    #[test]
    fn grazing_incidence_reflects_everything() {
        for n in [1.1f32, 1.5, 2.42] {
            assert_eq!(dielectric(0.0, n), 1.0);
            assert!(dielectric(1e-4, n) > 0.999, "{}", dielectric(1e-4, n));
            // Reflectance rises monotonically toward grazing on the outside.
            let mut last = 0.0;
            for k in 0..=100 {
                let r = dielectric(1.0 - k as f32 / 100.0, n);
                assert!(r >= last - 1e-6, "{n} at step {k}: {r} < {last}");
                last = r;
            }
        }
    }

    #[test]
    fn matches_the_angle_form_from_both_sides() {
        for n in [1.33f32, 1.5, 2.42] {
            for k in 0..90 {
                let theta = (k as f64 + 0.5).to_radians();
                let out = dielectric(theta.cos() as f32, n);
                let inside = dielectric(-theta.cos() as f32, n);
                let want_out = fresnel_by_angles(theta, 1.0, f64::from(n));
                let want_in = fresnel_by_angles(theta, f64::from(n), 1.0);
                assert!((f64::from(out) - want_out).abs() < 2e-5, "{n} {k}°");
                assert!((f64::from(inside) - want_in).abs() < 2e-5, "{n} {k}° in");
            }
        }
    }

    #[test]
    fn reflectance_is_the_same_for_both_ends_of_a_refracted_ray() {
        // Stokes: light crossing at (θi outside, θt inside) reflects the same
        // fraction whichever way it travels.
        let n = 1.5f32;
        for k in 1..89 {
            let theta_i = (k as f32).to_radians();
            let theta_t = (theta_i.sin() / n).asin();
            let a = dielectric(theta_i.cos(), n);
            let b = dielectric(-theta_t.cos(), n);
            // f32 cosines near grazing carry ~1e-5 of rounding into F.
            assert!((a - b).abs() < 3e-5, "{k}°: {a} vs {b}");
        }
    }

    #[test]
    fn brewster_angle_leaves_only_the_s_polarised_half() {
        // At tan θB = n, θi + θt = 90° so R_p = 0 and R = R_s / 2 = sin²(θi−θt)/2.
        let n = 1.5f32;
        let theta_b = n.atan();
        let theta_t = std::f32::consts::FRAC_PI_2 - theta_b;
        let want = 0.5 * (theta_b - theta_t).sin().powi(2);
        let got = dielectric(theta_b.cos(), n);
        assert!((got - want).abs() < 1e-6, "{got} vs {want}");
    }

    #[test]
    fn total_internal_reflection_beyond_the_critical_angle() {
        let n = 1.5f32;
        let critical = (1.0 / n).asin(); // 41.81°
        let normal = Vec3::Z;
        for (delta, tir) in [
            (-0.01f32, false),
            (-0.001, false),
            (0.001, true),
            (0.2, true),
        ] {
            let theta = critical + delta;
            // Inside the glass: the direction lies below the outward normal.
            let wo = -direction(theta, 0.7);
            let r = dielectric(wo.dot(normal), n);
            let t = refract(wo, normal, n);
            if tir {
                assert_eq!(r, 1.0, "{delta}");
                assert!(t.is_none(), "{delta}");
            } else {
                assert!(r < 1.0, "{delta}: {r}");
                assert!(t.is_some(), "{delta}");
            }
        }
        // From outside there is no critical angle.
        for k in 0..=90 {
            let wo = direction((k as f32).min(89.99).to_radians(), 0.3);
            assert!(refract(wo, normal, n).is_some(), "{k}");
        }
    }

    #[test]
    fn refraction_obeys_snells_law() {
        let n_glass = 1.5f32;
        let normal = Vec3::new(0.3, -0.5, 0.8).normalize();
        let mut state = 12345u32;
        let mut next = || {
            state = state.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
            (state >> 8) as f32 / (1u32 << 24) as f32
        };
        let mut tested = 0;
        for _ in 0..2000 {
            let z = 2.0 * next() - 1.0;
            let phi = std::f32::consts::TAU * next();
            let r = (1.0 - z * z).max(0.0).sqrt();
            let wo = Vec3::new(r * phi.cos(), r * phi.sin(), z).normalize();
            let cos_o = wo.dot(normal);
            if cos_o.abs() < 1e-3 {
                continue;
            }
            let (n_o, n_t) = if cos_o > 0.0 {
                (1.0, n_glass)
            } else {
                (n_glass, 1.0)
            };
            let Some(wt) = refract(wo, normal, n_glass) else {
                // Only allowed from inside beyond the critical angle.
                let sin_o = (1.0 - cos_o * cos_o).sqrt();
                assert!(cos_o < 0.0 && n_o * sin_o >= n_t * 0.999, "{wo} {cos_o}");
                continue;
            };
            tested += 1;
            let cos_t = wt.dot(normal);
            assert!((wt.length() - 1.0).abs() < 1e-5);
            // Crosses to the other side.
            assert!(cos_t * cos_o < 0.0, "{wo} -> {wt}");
            // n_o sin θo = n_t sin θt.
            let sin_o = wo.cross(normal).length();
            let sin_t = wt.cross(normal).length();
            assert!((n_o * sin_o - n_t * sin_t).abs() < 1e-4, "{wo} -> {wt}");
            // In the plane of incidence, on the far side of the normal.
            let plane = wo.cross(normal);
            assert!(wt.dot(plane).abs() < 1e-4);
            let tangent_o = wo - cos_o * normal;
            let tangent_t = wt - cos_t * normal;
            assert!(tangent_o.dot(tangent_t) <= 1e-6);
        }
        // Uniform directions: all 1000-odd from outside refract, and from
        // inside only those within the critical cone (cos > 0.745, a quarter).
        assert!(tested > 1150, "{tested}");
    }

    #[test]
    fn refraction_is_reversible() {
        let normal = Vec3::Z;
        for k in 0..89 {
            let wo = direction((k as f32).to_radians(), 1.1);
            let wt = refract(wo, normal, 1.5).unwrap();
            let back = refract(wt, normal, 1.5).unwrap();
            assert!((back - wo).length() < 1e-5, "{k}: {back} vs {wo}");
        }
    }

    #[test]
    fn reflection_preserves_the_angle() {
        let n = Vec3::new(1.0, 2.0, 2.0) / 3.0;
        for v in [
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::new(0.6, -0.8, 0.0),
            Vec3::new(-0.48, 0.6, -0.64),
        ] {
            let r = reflect(v, n);
            assert!((r.dot(n) + v.dot(n)).abs() < 1e-6, "{v}");
            assert!((r.length() - v.length()).abs() < 1e-6);
            // Coplanar with v and n, and the tangential part kept.
            assert!(r.dot(v.cross(n)).abs() < 1e-6);
            assert!(((r - r.dot(n) * n) - (v - v.dot(n) * n)).length() < 1e-6);
            assert!((reflect(r, n) - v).length() < 1e-6);
            // The normal's orientation does not matter.
            assert!((reflect(v, -n) - r).length() < 1e-6);
        }
        // A ray going straight down comes straight back up.
        assert_eq!(reflect(Vec3::NEG_Z, Vec3::Z), Vec3::Z);
    }

    #[test]
    fn schlick_is_exact_at_both_ends_and_close_for_glass() {
        let f0 = Vec3::new(0.04, 0.5, 0.95);
        assert_eq!(schlick(f0, 1.0), f0);
        assert_eq!(schlick(f0, 0.0), Vec3::ONE);
        assert_eq!(schlick(f0, -0.1), Vec3::ONE);
        // Against the exact dielectric for n = 1.5 (F0 = 0.04), with the
        // errors computed separately in f64: under 0.004 up to 37° (cos 0.8),
        // 0.019 at 60° and worst, 0.0357, near 85°.
        let mut worst = 0.0f32;
        for k in 0..=1000 {
            let c = k as f32 / 1000.0;
            let err = (schlick(Vec3::splat(0.04), c).x - dielectric(c, 1.5)).abs();
            if c >= 0.8 {
                assert!(err < 0.004, "cos {c}: {err}");
            }
            worst = worst.max(err);
        }
        assert!((0.035..0.037).contains(&worst), "{worst}");
    }

    #[test]
    fn degenerate_inputs_give_numbers_not_nan() {
        for c in [-1.0f32, -0.5, -0.0, 0.0, 0.5, 1.0, 1.0 + 1e-6, -1.0 - 1e-6] {
            for n in [1.0f32, 1.5, 0.5, 1e-6, 1e6] {
                let r = dielectric(c, n);
                assert!((0.0..=1.0).contains(&r), "{c} {n}: {r}");
            }
        }
        for wo in [Vec3::Z, Vec3::NEG_Z, Vec3::X, Vec3::new(0.6, 0.0, -0.8)] {
            if let Some(wt) = refract(wo, Vec3::Z, 1.5) {
                assert!(wt.is_finite(), "{wo}");
            }
        }
    }
}
