//! The uniform numbers one pixel sample draws, every dimension of its path
//! (pixel position, light choice, light sample, BSDF lobe and direction,
//! roulette), from one of two samplers:
//!
//! - `sobol`: each request (one- or two-dimensional) is the next dimension of
//!   a padded Owen-scrambled Sobol sequence (`sobol`), keyed by (seed, pixel,
//!   dimension) and indexed by the sample: a pixel's first 2^m samples
//!   stratify every one of its dimensions and dimension pairs.
//! - `independent`: a counter-based generator per (seed, pixel, sample), each
//!   number independent of the others; only the pixel position is
//!   stratified (`stratified_2d`).
//!
//! Either way a sample's numbers depend only on (seed, pixel, sample index)
//! and the order of its requests, not on the pass, tile or thread that draws
//! them, nor on the sample count (the Sobol index is the sample index itself,
//! so adaptive rounds and resumed renders go on with the same sequence).
//! With a sample count that is not a power of two, the largest power-of-two
//! prefix is a net and the rest are the start of the next one: still evenly
//! spread, if not exactly one per interval.

use super::rng::{GOLDEN, mix};
use super::{Rng, sobol, stratified_2d};

/// Which sampler a render draws from (`render.sampler`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub enum SamplerKind {
    /// Owen-scrambled Sobol points in every dimension: the default, since it
    /// reaches a lower error at equal samples (docs/integrators.md).
    #[default]
    Sobol,
    /// Independent numbers, stratified in the pixel only.
    Independent,
}

impl SamplerKind {
    /// The name the scene file and the CLI use.
    pub fn name(self) -> &'static str {
        match self {
            SamplerKind::Sobol => "sobol",
            SamplerKind::Independent => "independent",
        }
    }
}

/// The numbers of one pixel sample. Integrators draw them in a fixed order
/// (the pixel first, then each bounce's in the order it uses them), so with
/// the Sobol sampler a dimension means the same decision in every sample.
#[derive(Clone, Debug)]
pub struct Sampler {
    sample: u32,
    source: Source,
}

#[derive(Clone, Debug)]
enum Source {
    Independent(Rng),
    /// The key of (seed, pixel), the sample's index and the next dimension
    /// to draw.
    Sobol {
        key: u64,
        index: sobol::Index,
        dimension: u32,
    },
}

impl Sampler {
    /// The sampler for sample `sample` of pixel `pixel` (its index in the
    /// whole image, so crops and tiles draw what the whole render would).
    pub fn new(kind: SamplerKind, seed: u64, pixel: u64, sample: u32) -> Sampler {
        let source = match kind {
            SamplerKind::Independent => Source::Independent(Rng::for_sample(seed, pixel, sample)),
            SamplerKind::Sobol => Source::Sobol {
                key: mix(mix(seed ^ 0x6a09_e667_f3bc_c908).wrapping_add(pixel)),
                index: sobol::Index::new(sample),
                dimension: 0,
            },
        };
        Sampler { sample, source }
    }

    /// Where in the pixel the sample lies, in [0, 1)², for a pixel taking
    /// `spp` samples a round; the first request. The Sobol points are a net
    /// already; independent ones are jittered over `spp` strata.
    pub fn pixel_2d(&mut self, spp: u32) -> [f32; 2] {
        match &mut self.source {
            Source::Independent(rng) => stratified_2d(self.sample, spp, rng.next_2d()),
            Source::Sobol { .. } => self.get_2d(),
        }
    }

    /// The next dimension: uniform in [0, 1).
    pub fn get_1d(&mut self) -> f32 {
        match &mut self.source {
            Source::Independent(rng) => rng.next_f32(),
            Source::Sobol {
                key,
                index,
                dimension,
            } => sobol::sample_1d(*index, next_key(*key, dimension)),
        }
    }

    /// The next dimension, reserved in its place in the order but drawn
    /// only if `later` is called with it: a decision that is often not
    /// taken (Russian roulette before it may end a path) keeps its own
    /// dimension, and the requests after it theirs, without the work of
    /// drawing it. `later(d)` gives the number `get_1d` would have given.
    pub fn defer_1d(&mut self) -> Deferred {
        match &mut self.source {
            Source::Independent(rng) => Deferred(rng.skip()),
            Source::Sobol { dimension, .. } => {
                let d = *dimension;
                *dimension = d.wrapping_add(1);
                Deferred(u64::from(d))
            }
        }
    }

    /// The number of a dimension `defer_1d` reserved.
    pub fn later(&self, deferred: Deferred) -> f32 {
        match &self.source {
            Source::Independent(_) => Rng::f32_at(deferred.0),
            Source::Sobol { key, index, .. } => {
                let mut d = deferred.0 as u32;
                sobol::sample_1d(*index, next_key(*key, &mut d))
            }
        }
    }

    /// The next two dimensions, a pair stratified together: uniform in [0, 1)².
    pub fn get_2d(&mut self) -> [f32; 2] {
        match &mut self.source {
            Source::Independent(rng) => rng.next_2d(),
            Source::Sobol {
                key,
                index,
                dimension,
            } => sobol::sample_2d(*index, next_key(*key, dimension)),
        }
    }
}

/// A dimension reserved by [`Sampler::defer_1d`]: the generator's state
/// there (independent) or the dimension's index (Sobol).
#[derive(Clone, Copy, Debug)]
pub struct Deferred(u64);

/// The key of dimension `dimension` of the pixel keyed `key`, moving on to
/// the next dimension.
fn next_key(key: u64, dimension: &mut u32) -> u64 {
    let d = *dimension;
    // No sample draws 2^32 numbers; wrapping keeps even that from panicking.
    *dimension = d.wrapping_add(1);
    // The pixel's key is a hash already: one more mix of it with the
    // dimension's own multiple of GOLDEN makes each dimension's.
    mix(key ^ u64::from(d).wrapping_add(1).wrapping_mul(GOLDEN))
}

#[cfg(test)]
mod tests;
