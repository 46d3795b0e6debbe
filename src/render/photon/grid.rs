//! A hashed uniform grid over the stored photons, for fixed-radius gathers:
//! cells twice the gather radius wide, so the sphere around any point lies in
//! the 2 × 2 × 2 cells nearest it. Built once, read by every thread without
//! locks; a query allocates nothing.

use crate::math::Vec3;

/// One photon where it landed: the first diffuse surface after at least one
/// specular bounce.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Photon {
    pub p: Vec3,
    /// Unit direction towards where the photon came from.
    pub wi: Vec3,
    /// The surface's unit normal on the side the photon arrived at.
    pub n: Vec3,
    pub flux: Vec3,
}

/// The largest cell index on each axis, in either direction: its neighbours'
/// are still i32s.
const CELL_LIMIT: i32 = 1 << 30;

#[cfg(test)]
impl Photon {
    /// A photon at `p` from straight above, its flux `p` itself, so a test can
    /// tell which one a gather found.
    pub fn at(p: Vec3) -> Photon {
        Photon {
            p,
            wi: Vec3::Z,
            n: Vec3::Z,
            flux: p,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// 1 / the cell width.
    inv_cell: f32,
    radius: f32,
    /// The photons ordered by bucket, in emission order within one.
    photons: Vec<Photon>,
    /// Bucket b holds photons[starts[b]..starts[b + 1]]; the bucket count is a
    /// power of two, so `mask` picks one from a hash.
    starts: Vec<u32>,
    mask: u32,
}

impl Grid {
    /// The grid over `photons` for gathers of `radius` (> 0). A counting sort
    /// by bucket that keeps emission order: the same photons give the same grid.
    pub fn new(photons: Vec<Photon>, radius: f32) -> Grid {
        let buckets = photons.len().next_power_of_two();
        let mut grid = Grid {
            inv_cell: 0.5 / radius,
            radius,
            photons: Vec::new(),
            starts: vec![0; buckets + 1],
            mask: (buckets - 1) as u32,
        };
        let keys: Vec<u32> = photons
            .iter()
            .map(|ph| grid.bucket(grid.cell(ph.p)))
            .collect();
        for &k in &keys {
            grid.starts[k as usize + 1] += 1;
        }
        for b in 0..buckets {
            grid.starts[b + 1] += grid.starts[b];
        }
        let mut next = grid.starts.clone();
        let mut order = vec![0usize; photons.len()];
        for (i, &k) in keys.iter().enumerate() {
            order[next[k as usize] as usize] = i;
            next[k as usize] += 1;
        }
        grid.photons = order.into_iter().map(|i| photons[i]).collect();
        grid
    }

    pub fn len(&self) -> usize {
        self.photons.len()
    }

    pub fn is_empty(&self) -> bool {
        self.photons.is_empty()
    }

    /// Calls `visit` once for every photon within the radius of `p`.
    pub fn for_each_near(&self, p: Vec3, mut visit: impl FnMut(&Photon)) {
        if self.photons.is_empty() {
            return;
        }
        let scaled = p * self.inv_cell;
        let home = self.cell(p);
        // The neighbour on each axis is the one on the side of the cell's middle
        // that p lies on: the sphere of radius half a cell reaches no further.
        let step = |axis: usize| {
            if scaled[axis] - scaled[axis].floor() < 0.5 {
                -1
            } else {
                1
            }
        };
        let steps = [step(0), step(1), step(2)];
        let r2 = self.radius * self.radius;
        for corner in 0..8 {
            let cell = [0, 1, 2].map(|a| home[a] + if corner >> a & 1 == 1 { steps[a] } else { 0 });
            let b = self.bucket(cell) as usize;
            let range = self.starts[b] as usize..self.starts[b + 1] as usize;
            for ph in &self.photons[range] {
                // Two of the eight cells may share a bucket: take each photon only
                // from its own cell, so none is counted twice.
                if ph.p.distance_squared(p) <= r2 && self.cell(ph.p) == cell {
                    visit(ph);
                }
            }
        }
    }

    fn cell(&self, p: Vec3) -> [i32; 3] {
        // Clamped (and `as` saturates), so a point far outside the scene, or a
        // radius tiny beside the coordinates, still gets a cell whose
        // neighbours' indices do not overflow. The cells at the clamp then
        // hold many photons, which the distance test still sorts out.
        (p * self.inv_cell)
            .floor()
            .to_array()
            .map(|c| (c as i32).clamp(-CELL_LIMIT, CELL_LIMIT))
    }

    /// Teschner et al.'s spatial hash (2003): three large primes, xor-ed.
    fn bucket(&self, [x, y, z]: [i32; 3]) -> u32 {
        let h = (x as u32).wrapping_mul(73_856_093)
            ^ (y as u32).wrapping_mul(19_349_663)
            ^ (z as u32).wrapping_mul(83_492_791);
        h & self.mask
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    #[test]
    fn finds_exactly_the_photons_a_brute_force_search_finds() {
        let mut rng = Rng::for_sample(1, 2, 3);
        let mut point = || Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 4.0 - 2.0;
        let photons: Vec<Photon> = (0..3000).map(|_| Photon::at(point())).collect();
        let radius = 0.3;
        let grid = Grid::new(photons.clone(), radius);
        assert_eq!(grid.len(), photons.len());
        for _ in 0..200 {
            let p = point();
            let mut found = Vec::new();
            grid.for_each_near(p, |ph| found.push(ph.flux.to_array()));
            let mut expected: Vec<[f32; 3]> = photons
                .iter()
                .filter(|ph| ph.p.distance_squared(p) <= radius * radius)
                .map(|ph| ph.flux.to_array())
                .collect();
            found.sort_by(|a, b| a.partial_cmp(b).unwrap());
            expected.sort_by(|a, b| a.partial_cmp(b).unwrap());
            assert_eq!(found, expected, "around {p}");
        }
    }

    #[test]
    fn an_empty_grid_finds_nothing() {
        let grid = Grid::new(Vec::new(), 1.0);
        assert!(grid.is_empty());
        grid.for_each_near(Vec3::ZERO, |_| panic!("no photons"));
    }

    #[test]
    fn a_radius_tiny_beside_the_coordinates_still_gathers() {
        // 3e8 / (2 · 0.01) is far beyond i32: every cell index clamps. The
        // f32 spacing there is 32, so the neighbour lies far outside the radius.
        let p = Vec3::splat(3e8);
        let photons = vec![Photon::at(p), Photon::at(p), Photon::at(p + Vec3::X * 32.0)];
        let grid = Grid::new(photons, 0.01);
        let mut count = 0;
        grid.for_each_near(p, |_| count += 1);
        assert_eq!(count, 2);
        grid.for_each_near(-p, |_| panic!("nothing near the opposite corner"));
    }

    #[test]
    fn a_tiny_table_with_colliding_buckets_counts_each_photon_once() {
        // Two photons: two buckets, so neighbouring cells collide.
        let photons = vec![Photon::at(Vec3::splat(0.1)), Photon::at(Vec3::splat(-0.1))];
        let grid = Grid::new(photons, 1.0);
        let mut count = 0;
        grid.for_each_near(Vec3::ZERO, |_| count += 1);
        assert_eq!(count, 2);
    }
}
