//! Sampling: the samplers a pixel sample draws its uniform numbers from
//! (Owen-scrambled Sobol points or independent random numbers, each keyed by
//! (seed, pixel, sample index)), stratified pixel samples, warps from the
//! unit square onto the shapes shading and lights need, reconstruction
//! filters sampled by importance (pbrt-v4's filter importance sampling),
//! piecewise-constant 2-D densities (the environment light's), and
//! multiple-importance-sampling weights.
//!
//! Everything here is a pure function of its arguments (of its key, for the
//! samplers), works in f32 at its interface and allocates nothing per sample,
//! so a sample depends only on (seed, pixel, sample index): ARCHITECTURE.md's
//! determinism rule. Inputs called `u` are uniform numbers in [0, 1).

mod discrete;
pub mod filter;
pub mod mis;
mod piecewise;
mod rng;
mod sampler;
mod sobol;
mod stratify;
pub mod warp;

pub use discrete::Discrete;
pub use filter::{Filter, FilterSample, FilterSampler};
pub use piecewise::{Piecewise2D, Sample2D};
pub use rng::Rng;
pub use sampler::{Deferred, Sampler, SamplerKind};
pub use stratify::stratified_2d;

/// The largest f32 below 1 (1 − 2⁻²⁴): results meant to lie in [0, 1) are
/// clamped to it where rounding could otherwise give exactly 1.
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_minus_epsilon_is_the_float_below_one() {
        assert_eq!(ONE_MINUS_EPSILON.next_up(), 1.0);
        assert_eq!(ONE_MINUS_EPSILON.to_bits(), 1.0f32.to_bits() - 1);
        // The generator's largest value is exactly this constant.
        assert_eq!(
            ((1u64 << 24) - 1) as f32 * (1.0 / (1u64 << 24) as f32),
            ONE_MINUS_EPSILON
        );
    }
}
