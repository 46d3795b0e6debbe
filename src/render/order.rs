//! The order a batch of rays is traced in: neighbours in space and direction
//! next to each other.
//!
//! Rays handed to `trace` or to the Python module come in the caller's
//! order, which for random rays through a large mesh means each ray walks
//! BVH nodes and triangles the previous one did not, and the traversal
//! waits on memory. Traced in the order of a Morton (Z-order) key of their
//! origins, then of their directions, consecutive rays visit the same nodes
//! while they are still in cache, as in the ray-reordering literature
//! (Pharr et al. 1997; Moon et al. 2010). Each ray's answer does not depend
//! on the order, so the hits are the same bytes; they are put back in the
//! caller's order before anyone sees them.

use rayon::prelude::*;

use crate::math::{Ray, Vec3};

/// Bits of the key per axis of the origin: 2^24 cells over the batch's
/// bounding box, about one per ray at 16M rays.
const ORIGIN_BITS: u32 = 8;
/// Bits per axis of the direction, below the origin's: rays from one point
/// (a camera, a light) are ordered by where they go, in 64 cones.
const DIRECTION_BITS: u32 = 2;

/// A permutation of a ray batch: `order[i]` is the caller's index of the
/// i-th ray to trace.
pub struct CoherentOrder {
    /// None: the caller's own order (a batch of more than 2^32 rays, whose
    /// indices do not fit beside the key).
    order: Option<Vec<u32>>,
}

impl CoherentOrder {
    /// The order of `rays`: by the Morton key of the origin in the batch's
    /// bounding box, then of the direction, then by index (so the order is
    /// the same whatever the thread count). Rays that are not finite get
    /// some place: the caller checks them (`accel::check_rays`).
    pub fn new(rays: &[Ray]) -> CoherentOrder {
        if u32::try_from(rays.len()).is_err() {
            return CoherentOrder { order: None };
        }
        let (lo, hi) = rays
            .par_iter()
            .fold(
                || (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
                |(lo, hi), r| (lo.min(r.origin), hi.max(r.origin)),
            )
            .reduce(
                || (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
                |a, b| (a.0.min(b.0), a.1.max(b.1)),
            );
        let origin_scale = cell_scale(hi - lo, ORIGIN_BITS);
        let direction_scale = cell_scale(Vec3::splat(2.0), DIRECTION_BITS);
        // The 30-bit key above the index, in one u64: sorting plain integers
        // is several times cheaper than sorting pairs.
        let mut keyed: Vec<u64> = rays
            .par_iter()
            .enumerate()
            .map(|(i, r)| {
                let origin = morton(cells(r.origin - lo, origin_scale, ORIGIN_BITS));
                let dir = r.dir.normalize_or_zero() + Vec3::ONE;
                let direction = morton(cells(dir, direction_scale, DIRECTION_BITS));
                let key = (origin << (3 * DIRECTION_BITS)) | direction;
                (key << 32) | i as u64
            })
            .collect();
        keyed.par_sort_unstable();
        CoherentOrder {
            order: Some(keyed.into_iter().map(|k| k as u32).collect()),
        }
    }

    /// The items in this order (the rays themselves, or anything per ray).
    pub fn gather<T: Copy + Send + Sync>(&self, items: &[T]) -> Vec<T> {
        match &self.order {
            Some(order) => order.par_iter().map(|&i| items[i as usize]).collect(),
            None => items.to_vec(),
        }
    }

    /// Puts results made in this order back in the caller's: `out[order[i]]
    /// = sorted[i]`.
    pub fn scatter<T: Copy>(&self, sorted: &[T], out: &mut [T]) {
        match &self.order {
            Some(order) => {
                for (&i, &item) in order.iter().zip(sorted) {
                    out[i as usize] = item;
                }
            }
            None => out.copy_from_slice(sorted),
        }
    }
}

/// Per axis, cells per unit so that `extent` spans 2^bits cells (a flat
/// axis has one cell).
fn cell_scale(extent: Vec3, bits: u32) -> Vec3 {
    let cells = (1u32 << bits) as f32;
    Vec3::select(extent.cmpgt(Vec3::ZERO), cells / extent, Vec3::ZERO)
}

/// The cell of `p` (measured from the box's corner) on each axis.
fn cells(p: Vec3, scale: Vec3, bits: u32) -> [u64; 3] {
    let top = ((1u32 << bits) - 1) as f32;
    (p * scale)
        .clamp(Vec3::ZERO, Vec3::splat(top))
        .to_array()
        .map(|c| c as u64)
}

/// Interleaves the bits of three cell indices of at most 10 bits (x lowest).
fn morton(c: [u64; 3]) -> u64 {
    let spread = |v: u64| {
        let mut x = v & 0x3ff;
        x = (x | (x << 16)) & 0x0300_00ff;
        x = (x | (x << 8)) & 0x0300_f00f;
        x = (x | (x << 4)) & 0x030c_30c3;
        (x | (x << 2)) & 0x0924_9249
    };
    spread(c[0]) | (spread(c[1]) << 1) | (spread(c[2]) << 2)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rays(n: usize) -> Vec<Ray> {
        // A fixed scatter of origins and directions (a Weyl sequence).
        (0..n)
            .map(|i| {
                let f = |k: f32| ((i as f32 + 1.0) * k).fract() * 6.0 - 3.0;
                Ray::new(
                    Vec3::new(f(0.618_034), f(0.414_214), f(0.732_051)),
                    Vec3::new(f(0.236_068), f(0.316_625), f(0.645_751)),
                )
            })
            .collect()
    }

    #[test]
    fn the_order_is_a_permutation_and_scatter_undoes_gather() {
        let rays = rays(10_000);
        let order = CoherentOrder::new(&rays);
        let mut seen = vec![false; rays.len()];
        for &i in order.order.as_ref().unwrap() {
            assert!(!std::mem::replace(&mut seen[i as usize], true), "{i} twice");
        }
        let ids: Vec<u32> = (0..rays.len() as u32).collect();
        let mut back = vec![u32::MAX; ids.len()];
        order.scatter(&order.gather(&ids), &mut back);
        assert_eq!(back, ids);
    }

    #[test]
    fn neighbours_in_the_order_are_near_in_space() {
        let rays = rays(1 << 14);
        let step = |rays: &[Ray]| -> f32 {
            rays.windows(2)
                .map(|w| w[0].origin.distance(w[1].origin))
                .sum::<f32>()
                / (rays.len() - 1) as f32
        };
        let sorted = CoherentOrder::new(&rays).gather(&rays);
        // Random points in a 6-unit cube are ~3 apart; 2^14 of them along a
        // Z-order curve are a few cell widths (6 / 2^(14/3) ≈ 0.23) apart.
        assert!(step(&rays) > 2.0, "the input is scattered: {}", step(&rays));
        assert!(
            step(&sorted) < 0.5,
            "the order walks far: {}",
            step(&sorted)
        );
    }

    #[test]
    fn rays_from_one_point_keep_their_order_within_a_direction_cell() {
        let rays: Vec<Ray> = (0..64)
            .map(|i| Ray::new(Vec3::ONE, Vec3::new(1.0, 0.0, 1e-4 * i as f32)))
            .collect();
        // One origin, one direction cell: ties are broken by index.
        let order = CoherentOrder::new(&rays).order;
        assert_eq!(order, Some((0..64).collect::<Vec<u32>>()));
    }

    #[test]
    fn morton_interleaves_x_lowest() {
        assert_eq!(morton([1, 0, 0]), 0b001);
        assert_eq!(morton([0, 1, 0]), 0b010);
        assert_eq!(morton([0, 0, 1]), 0b100);
        assert_eq!(morton([3, 0, 0]), 0b001_001);
        let top = (1 << 10) - 1;
        assert_eq!(morton([top, top, top]), (1 << 30) - 1);
    }
}
