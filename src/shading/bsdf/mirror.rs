//! The perfect mirror, a delta lobe.

use super::{BsdfSample, Lobe};
use crate::math::Vec3;

/// A perfect mirror reflecting the fraction `reflectance`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mirror {
    pub reflectance: Vec3,
}

impl Mirror {
    /// Zero: no pair of directions has a finite value; only
    /// [`Mirror::sample`] finds the one direction.
    pub(super) fn eval(&self) -> Vec3 {
        Vec3::ZERO
    }

    /// Zero, as [`Mirror::eval`].
    pub(super) fn pdf(&self) -> f32 {
        0.0
    }

    /// The mirror direction of a local `wo` on either side, with pdf 1 and
    /// weight `reflectance`.
    pub(super) fn sample(&self, wo: Vec3) -> BsdfSample {
        BsdfSample::new(
            reflect(wo),
            self.reflectance / wo.z.abs(),
            1.0,
            self.reflectance,
            Lobe::SpecularReflection,
        )
    }
}

/// The mirror direction of a local `wo` (normal +z), on wo's side.
pub(super) fn reflect(wo: Vec3) -> Vec3 {
    Vec3::new(-wo.x, -wo.y, wo.z)
}
