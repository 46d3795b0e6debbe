//! Random numbers seeded per (seed, pixel, sample index), so every sample is
//! reproducible whatever thread or tile computes it.

/// splitmix64's output function: a bijective 64-bit mixer.
pub(super) fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A small counter-based generator (splitmix64 over a hashed start).
#[derive(Clone, Debug)]
pub struct Rng {
    state: u64,
}

/// 2⁶⁴ over the golden ratio: splitmix64's increment, which visits every
/// state, and a spread-out step for keys.
pub(super) const GOLDEN: u64 = 0x9e37_79b9_7f4a_7c15;

impl Rng {
    /// The generator for one pixel sample.
    pub fn for_sample(seed: u64, pixel: u64, sample: u32) -> Rng {
        let start =
            mix(mix(seed ^ GOLDEN).wrapping_add(pixel) ^ mix(u64::from(sample) ^ 0x5851_f42d));
        Rng { state: start }
    }

    pub fn next_u64(&mut self) -> u64 {
        mix(self.skip())
    }

    /// Uniform in [0, 1): the top 24 bits as a float, so 1.0 is never returned.
    pub fn next_f32(&mut self) -> f32 {
        Rng::f32_at(self.skip())
    }

    /// Moves on past one number without drawing it, and returns the state
    /// that number is drawn from (`f32_at`): a counter step, no mixing.
    pub fn skip(&mut self) -> u64 {
        self.state = self.state.wrapping_add(GOLDEN);
        self.state
    }

    /// The `next_f32` of the step that reached `state`.
    pub fn f32_at(state: u64) -> f32 {
        (mix(state) >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
    }

    /// Two uniforms in [0, 1), in the order two `next_f32` calls give them:
    /// the `u` that the warps, filters and stratification take.
    pub fn next_2d(&mut self) -> [f32; 2] {
        let x = self.next_f32();
        [x, self.next_f32()]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_key_same_stream_different_key_different_stream() {
        let a: Vec<u64> = (0..4)
            .map(|_| 0)
            .scan(Rng::for_sample(1, 2, 3), |r, _: u64| Some(r.next_u64()))
            .collect();
        let b: Vec<u64> = (0..4)
            .map(|_| 0)
            .scan(Rng::for_sample(1, 2, 3), |r, _: u64| Some(r.next_u64()))
            .collect();
        assert_eq!(a, b);
        let keys = [(1, 2, 4), (1, 3, 3), (2, 2, 3), (0, 0, 0)];
        for (s, p, k) in keys {
            assert_ne!(Rng::for_sample(s, p, k).next_u64(), a[0], "{s} {p} {k}");
        }
    }

    #[test]
    fn next_2d_is_two_next_f32_in_order() {
        let (mut a, mut b) = (Rng::for_sample(3, 4, 5), Rng::for_sample(3, 4, 5));
        for _ in 0..8 {
            let [x, y] = a.next_2d();
            assert_eq!(
                (x.to_bits(), y.to_bits()),
                (b.next_f32().to_bits(), b.next_f32().to_bits())
            );
        }
    }

    #[test]
    fn floats_are_uniform_in_unit_interval() {
        let mut r = Rng::for_sample(7, 0, 0);
        let n = 100_000;
        let mut buckets = [0u32; 10];
        for _ in 0..n {
            let x = r.next_f32();
            assert!((0.0..1.0).contains(&x));
            buckets[(x * 10.0) as usize] += 1;
        }
        // Each bucket expects 10 000 with standard deviation ~95; 6σ bounds.
        for b in buckets {
            assert!((9_430..=10_570).contains(&b), "{buckets:?}");
        }
    }
}
