//! The ideal diffuse lobe.

use std::f32::consts::FRAC_1_PI;

use super::{BsdfSample, COS_EPS, Lobe};
use crate::math::Vec3;
use crate::sampling::warp;

/// Ideal diffuse: f = albedo/π, sampled by the cosine.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lambert {
    pub albedo: Vec3,
}

impl Lambert {
    /// f, the same for every pair of directions on one side.
    pub(super) fn eval(&self) -> Vec3 {
        self.albedo * FRAC_1_PI
    }

    /// The cosine-weighted density of an upper-hemisphere `wi`.
    pub(super) fn pdf(&self, wi: Vec3) -> f32 {
        wi.z * FRAC_1_PI
    }

    /// A cosine-weighted `wi` in the upper hemisphere (from u[1], u[2]): f
    /// cos/pdf cancels to the albedo exactly.
    pub(super) fn sample(&self, u: [f32; 3]) -> Option<BsdfSample> {
        let wi = warp::cosine_hemisphere([u[1], u[2]]);
        if wi.z < COS_EPS {
            return None;
        }
        Some(BsdfSample::new(
            wi,
            self.eval(),
            self.pdf(wi),
            self.albedo,
            Lobe::DiffuseReflection,
        ))
    }
}
