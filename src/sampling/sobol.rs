//! Owen-scrambled Sobol points, padded: every dimension a sampler draws is
//! its own randomisation of the first one or two dimensions of Sobol's
//! sequence, which together are a (0,2)-sequence in base 2 (pbrt-v4's
//! `PaddedSobolSampler`, Burley's "Practical Hash-based Owen Scrambling",
//! JCGT 2020). Higher Sobol dimensions are not needed, and lose quality, so
//! they are not used.
//!
//! A (0,2)-sequence's points k·2^m to (k+1)·2^m − 1 form a (0,m,2)-net for
//! every k and m: each elementary interval of area 2^−m (a box of 2^−a by
//! 2^−(m−a)) holds exactly one of them. Two nested scrambles keep that:
//!
//! - the sample index is shuffled by a nested scramble of its bits from the
//!   top, so indices 0..2^m map onto an aligned block of 2^m and every
//!   power-of-two prefix of a pixel's samples stays a net, while each
//!   dimension gets its own order (without it two dimensions scrambled apart
//!   would still share their indices' digits: the first halves of both would
//!   be the same samples, and a path would see the two as correlated);
//! - each coordinate is Owen-scrambled: a random nested permutation of the
//!   elementary intervals, which makes every point uniform on [0, 1) and the
//!   estimator unbiased, while nets stay nets.
//!
//! All of it is hashing of (key, index): no tables but the 32 generator
//! columns, no state, no allocation.

use super::rng::GOLDEN;

/// The generator matrix of Sobol's second dimension, column j being the
/// 32-bit binary fraction that bit j of the index adds (by xor). Computed
/// from the dimension's direction numbers: primitive polynomial x + 1
/// (degree 1), m₁ = 1 and mᵢ = 2·mᵢ₋₁ xor mᵢ₋₁, column i − 1 = mᵢ / 2ⁱ. The
/// first dimension's matrix is the identity read backwards: the index's bits
/// reversed (van der Corput's sequence).
const SECOND: [u32; 32] = second_dimension();

const fn second_dimension() -> [u32; 32] {
    let mut columns = [0u32; 32];
    let mut m: u32 = 1;
    let mut i = 0;
    while i < 32 {
        // mᵢ₊₁ < 2^(i+1), so the shift keeps every bit.
        columns[i] = m << (31 - i);
        m ^= m << 1;
        i += 1;
    }
    columns
}

/// Point `index` of Sobol's second dimension, as a 32-bit fraction: the
/// definition, column by column, which the tests hold the tables to.
#[cfg(test)]
fn second(index: u32) -> u32 {
    (0..32)
        .filter(|&j| index >> j & 1 == 1)
        .fold(0, |value, j| value ^ SECOND[j])
}

/// Sobol's second dimension with its bits reversed, a byte of the index at
/// a time: entry b of table t is the xor of the reversed columns 8t to 8t + 7
/// that the bits of b select. Four lookups instead of up to 32 column steps.
const SECOND_BYTES: [[u32; 256]; 4] = second_bytes();

const fn second_bytes() -> [[u32; 256]; 4] {
    let mut tables = [[0u32; 256]; 4];
    let mut t = 0;
    while t < 4 {
        let mut b = 0;
        while b < 256 {
            let mut bit = 0;
            while bit < 8 {
                if b >> bit & 1 == 1 {
                    tables[t][b] ^= SECOND[8 * t + bit].reverse_bits();
                }
                bit += 1;
            }
            b += 1;
        }
        t += 1;
    }
    tables
}

/// Point `index` of Sobol's second dimension, as a 32-bit fraction with its
/// bits reversed (the form `laine_karras` takes).
fn second_reversed(index: u32) -> u32 {
    let byte = |t: usize| SECOND_BYTES[t][(index >> (8 * t)) as usize & 0xff];
    byte(0) ^ byte(1) ^ byte(2) ^ byte(3)
}

/// Laine and Karras's hash with Burley's constants, as pbrt-v4's
/// `FastOwenScrambler` has them, on a value whose bits are reversed: each
/// step (a multiplication by an even number, xored in; an addition; a
/// multiplication by an odd number) changes a bit only as a function of the
/// bits below it and the seed.
fn laine_karras(mut v: u32, seed: u32) -> u32 {
    v ^= v.wrapping_mul(0x3d20_adea);
    v = v.wrapping_add(seed);
    v = v.wrapping_mul((seed >> 16) | 1);
    v ^= v.wrapping_mul(0x0552_6c56);
    v ^= v.wrapping_mul(0x53a2_2864);
    v
}

/// A nested uniform scramble (Owen's) of the 32-bit binary fraction `v`,
/// chosen by `seed`: each bit is flipped or not by a hash of the bits above
/// it, so points in one elementary interval stay in one. Laine and Karras's
/// hash on the reversed bits, reversed back.
#[cfg(test)]
fn scramble(v: u32, seed: u32) -> u32 {
    scramble_reversed(v.reverse_bits(), seed)
}

/// `scramble` of the fraction whose bits reversed are `reversed`.
fn scramble_reversed(reversed: u32, seed: u32) -> u32 {
    laine_karras(reversed, seed).reverse_bits()
}

/// A sample index, held with its bits reversed: the form the index's
/// shuffle takes, computed once for all the dimensions a sample draws (x86
/// has no instruction that reverses bits; each reversal is a dozen).
#[derive(Clone, Copy, Debug)]
pub struct Index {
    reversed: u32,
}

impl Index {
    pub fn new(index: u32) -> Index {
        Index {
            reversed: index.reverse_bits(),
        }
    }
}

/// A 32-bit fraction as an f32 in [0, 1): its top 24 bits, exactly, so the
/// largest value is `ONE_MINUS_EPSILON` and 1 never comes.
fn unit(v: u32) -> f32 {
    (v >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// The three scrambles of one dimension, from its 64-bit key: the index's
/// shuffle and the two coordinates'. The key is a hash already, so its
/// halves and the high half of its product with an odd constant serve.
fn seeds(key: u64) -> [u32; 3] {
    let more = (key.wrapping_mul(GOLDEN) >> 32) as u32;
    [key as u32, (key >> 32) as u32, more]
}

/// Sample `index` of the one-dimensional sequence `key` names: van der
/// Corput's, shuffled and scrambled. Its first 2^m samples put one in each
/// interval [i/2^m, (i+1)/2^m).
pub fn sample_1d(index: Index, key: u64) -> f32 {
    let [shuffle, x, _] = seeds(key);
    let i = scramble_reversed(index.reversed, shuffle);
    // Van der Corput's point is i reversed, which its scramble reverses back.
    unit(laine_karras(i, x).reverse_bits())
}

/// Sample `index` of the two-dimensional sequence `key` names: Sobol's first
/// two dimensions, shuffled and scrambled. Its first 2^m samples are a
/// (0,m,2)-net.
pub fn sample_2d(index: Index, key: u64) -> [f32; 2] {
    let [shuffle, x, y] = seeds(key);
    let i = scramble_reversed(index.reversed, shuffle);
    [
        unit(laine_karras(i, x).reverse_bits()),
        unit(laine_karras(second_reversed(i), y).reverse_bits()),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_second_dimension_matches_its_published_columns() {
        // Joe and Kuo's dimension 2 (the Pascal matrix mod 2), as pbrt-v4's
        // SobolMatrices32 lists it.
        assert_eq!(
            SECOND[..8],
            [
                0x8000_0000,
                0xc000_0000,
                0xa000_0000,
                0xf000_0000,
                0x8800_0000,
                0xcc00_0000,
                0xaa00_0000,
                0xff00_0000
            ]
        );
        assert_eq!(SECOND[31], 0xffff_ffff);
        // The first points: 0, 1/2, 3/4, 1/4, 5/8, 1/8, 3/8, 7/8.
        let first: Vec<u32> = (0..8).map(|i| second(i) >> 29).collect();
        assert_eq!(first, [0, 4, 6, 2, 5, 1, 3, 7]);
    }

    #[test]
    fn the_byte_tables_are_the_second_dimension_reversed() {
        let mut index = 0x9e37_79b9u32;
        for _ in 0..10_000 {
            assert_eq!(second_reversed(index), second(index).reverse_bits());
            index = index.wrapping_mul(0x2c92_77b5).wrapping_add(0xac56_4b05);
        }
        for index in [0, 1, 2, 255, 256, u32::MAX] {
            assert_eq!(second_reversed(index), second(index).reverse_bits());
        }
    }

    #[test]
    fn unscrambled_blocks_are_nets() {
        // Before any scrambling, every aligned block of 2^m points is a
        // (0,m,2)-net: the property the shuffle relies on.
        for m in 0..=8u32 {
            for block in [0u32, 1, 5, 1000] {
                let points = (0..1u32 << m).map(|j| {
                    let i = (block << m) + j;
                    (i.reverse_bits(), second(i))
                });
                assert!(is_net(points, m), "m {m}, block {block}");
            }
        }
    }

    /// Whether the 2^m points (as 32-bit fractions) put one point in every
    /// elementary interval of area 2^−m.
    fn is_net(points: impl Iterator<Item = (u32, u32)> + Clone, m: u32) -> bool {
        (0..=m).all(|a| {
            let mut seen = vec![false; 1 << m];
            points.clone().all(|(x, y)| {
                let cell = |v: u32, bits: u32| if bits == 0 { 0 } else { v >> (32 - bits) };
                let c = ((cell(x, a) << (m - a)) | cell(y, m - a)) as usize;
                !std::mem::replace(&mut seen[c], true)
            })
        })
    }

    #[test]
    fn scrambling_is_nested() {
        // Points sharing their top b bits share them after the scramble too,
        // and the scramble is a bijection (checked on 16 bits, all inputs).
        for seed in [0u32, 1, 0xdead_beef, 0x8000_0001] {
            let mut images = vec![false; 1 << 16];
            for v in 0..1u32 << 16 {
                let w = scramble(v << 16, seed);
                assert!(!std::mem::replace(&mut images[(w >> 16) as usize], true));
                // Changing only the low bits keeps the top bits' image.
                assert_eq!(scramble((v << 16) | 0xffff, seed) >> 16, w >> 16);
                for b in [1u32, 4, 9] {
                    let sibling = (v << 16) ^ (1 << (32 - b - 1));
                    let same = scramble(sibling, seed) >> (32 - b);
                    assert_eq!(same, w >> (32 - b), "seed {seed:#x}, b {b}");
                }
            }
        }
    }
}
