//! The distance from a photon to its k-th nearest, for the radius rule: a k-d
//! tree over the photons' positions, split at the median of the widest axis.
//! Built once per photon pass and dropped before the gather grid is; the
//! answers do not depend on how ties were ordered, so neither does the radius.

use crate::math::Vec3;

/// Subtrees of at most this many points are searched by a plain scan.
const LEAF: usize = 8;

pub struct Nearest {
    /// The points, each subtree's in one run, its splitting point in the middle.
    points: Vec<Vec3>,
    /// The splitting axis of the subtree whose middle point is at this index.
    axes: Vec<u8>,
}

impl Nearest {
    pub fn new(mut points: Vec<Vec3>) -> Nearest {
        let mut axes = vec![0; points.len()];
        split(&mut points, &mut axes);
        Nearest { points, axes }
    }

    /// The distance from `q` to its `k`-th nearest point (1 ≤ k ≤ K, at most
    /// the point count), counting a point at `q` itself; K sizes the scratch,
    /// so a query allocates nothing.
    pub fn kth<const K: usize>(&self, q: Vec3, k: usize) -> f32 {
        // The k smallest squared distances so far, in increasing order.
        let mut best = [f32::INFINITY; K];
        self.search(0, self.points.len(), q, &mut best[..k]);
        best[k - 1].sqrt()
    }

    fn search(&self, lo: usize, hi: usize, q: Vec3, best: &mut [f32]) {
        if hi - lo <= LEAF {
            for p in &self.points[lo..hi] {
                offer(best, p.distance_squared(q));
            }
            return;
        }
        let mid = lo + (hi - lo) / 2;
        let split = self.points[mid];
        offer(best, split.distance_squared(q));
        let axis = usize::from(self.axes[mid]);
        let delta = q[axis] - split[axis];
        let (near, far) = if delta < 0.0 {
            ((lo, mid), (mid + 1, hi))
        } else {
            ((mid + 1, hi), (lo, mid))
        };
        self.search(near.0, near.1, q, best);
        // The far side holds nothing nearer than the splitting plane.
        if delta * delta < best[best.len() - 1] {
            self.search(far.0, far.1, q, best);
        }
    }
}

/// Puts `d2` among the sorted `best` if it is smaller than the largest.
fn offer(best: &mut [f32], d2: f32) {
    let last = best.len() - 1;
    if d2 < best[last] {
        let mut i = last;
        while i > 0 && best[i - 1] > d2 {
            best[i] = best[i - 1];
            i -= 1;
        }
        best[i] = d2;
    }
}

/// Orders `points` into a k-d tree in place, recording each split's axis.
fn split(points: &mut [Vec3], axes: &mut [u8]) {
    if points.len() <= LEAF {
        return;
    }
    let (min, max) = points
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    let extent = max - min;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let mid = points.len() / 2;
    points.select_nth_unstable_by(mid, |a, b| a[axis].total_cmp(&b[axis]));
    axes[mid] = axis as u8;
    let (left, rest) = points.split_at_mut(mid);
    let (left_axes, rest_axes) = axes.split_at_mut(mid);
    split(left, left_axes);
    split(&mut rest[1..], &mut rest_axes[1..]);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    fn brute(points: &[Vec3], q: Vec3, k: usize) -> f32 {
        let mut d: Vec<f32> = points.iter().map(|p| p.distance_squared(q)).collect();
        d.sort_by(f32::total_cmp);
        d[k - 1].sqrt()
    }

    #[test]
    fn finds_what_a_brute_force_search_finds() {
        let mut rng = Rng::for_sample(4, 5, 6);
        // A dense cluster, a sparse spread and exact duplicates.
        let mut points: Vec<Vec3> = (0..3000)
            .map(|i| {
                let [a, b] = rng.next_2d();
                let c = rng.next_f32();
                let scale = if i % 3 == 0 { 100.0 } else { 0.1 };
                Vec3::new(a, b, c) * scale
            })
            .collect();
        points.extend(std::iter::repeat_n(Vec3::splat(0.05), 20));
        let tree = Nearest::new(points.clone());
        for (i, &q) in points.iter().enumerate().step_by(37) {
            for k in [1, 2, 7, 16] {
                assert_eq!(
                    tree.kth::<16>(q, k),
                    brute(&points, q, k),
                    "point {i}, k {k}"
                );
            }
        }
        // Away from every point, and among the duplicates.
        for q in [Vec3::splat(-50.0), Vec3::splat(0.05)] {
            assert_eq!(tree.kth::<16>(q, 16), brute(&points, q, 16));
        }
    }

    #[test]
    fn a_few_points_are_one_leaf() {
        let points = vec![Vec3::ZERO, Vec3::X, Vec3::new(0.0, 3.0, 0.0)];
        let tree = Nearest::new(points);
        assert_eq!(tree.kth::<4>(Vec3::ZERO, 1), 0.0);
        assert_eq!(tree.kth::<4>(Vec3::ZERO, 3), 3.0);
    }
}
