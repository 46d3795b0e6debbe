//! Stratified (jittered) points in the unit square: sample `index` of `count`
//! lies in its own cell of a partition of [0, 1)² into `count` rectangles of
//! equal area, at the position `u` within that cell.
//!
//! The cells come in m = round(√count) rows; a row of c cells has height
//! c/count and cells 1/c wide, so every cell has area 1/count and is close to
//! square (width/height = count/c² ≈ 1). A square count n² gives the n × n
//! grid. For other counts this beats the usual fallbacks: a rank-1 lattice
//! with a Cranley-Patterson rotation needs one shift shared by all of a
//! pixel's samples (a per-sample `u` rotates each point anywhere, which is no
//! stratification at all), and its cells wrap around the square's edges, so
//! on a pixel (a non-periodic integrand) they straddle opposite sides. Here
//! each sample keeps its own `u`, so the generator seeded per (pixel, sample
//! index) is all a caller needs.

use super::ONE_MINUS_EPSILON;

/// Jittered sample `index` of `count` in [0, 1)²: in cell `index % count`
/// (indices past `count` start another round over the same cells; a count of
/// 0 is taken as 1), at `u` within it. O(1), no allocation.
pub fn stratified_2d(index: u32, count: u32, u: [f32; 2]) -> [f32; 2] {
    let cell = Cell::new(index, count);
    let (u0, u1) = (f64::from(u[0]), f64::from(u[1]));
    let x = (f64::from(cell.column) + u0) / f64::from(cell.columns);
    let y = (f64::from(cell.before) + u1 * f64::from(cell.columns)) / f64::from(cell.count);
    [unit(x), unit(y)]
}

/// Where a sample's cell is: in a row of `columns` cells that starts after
/// `before` cells (so it spans [before, before + columns) / count in y), at
/// `column` within that row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Cell {
    count: u32,
    columns: u32,
    before: u32,
    column: u32,
}

impl Cell {
    fn new(index: u32, count: u32) -> Cell {
        let count = count.max(1);
        let k = index % count;
        // Rows: m = round(√count), the first m − extra of q cells and the last
        // `extra` of q + 1, q = ⌊count / m⌋.
        let root = count.isqrt();
        let rows = if u64::from(root) * u64::from(root + 1) < u64::from(count) {
            root + 1
        } else {
            root
        };
        let (q, extra) = (count / rows, count % rows);
        let short_cells = (rows - extra) * q;
        let (columns, before, column) = if k < short_cells {
            (q, k / q * q, k % q)
        } else {
            let j = k - short_cells;
            (q + 1, short_cells + j / (q + 1) * (q + 1), j % (q + 1))
        };
        Cell {
            count,
            columns,
            before,
            column,
        }
    }
}

/// `x` (in [0, 1] up to rounding) as an f32 in [0, 1).
fn unit(x: f64) -> f32 {
    (x as f32).clamp(0.0, ONE_MINUS_EPSILON)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// Cell `index`'s rectangle [x0, x1) × [y0, y1).
    fn bounds(index: u32, count: u32) -> [f64; 4] {
        let c = Cell::new(index, count);
        let (n, w) = (f64::from(c.count), f64::from(c.columns));
        [
            f64::from(c.column) / w,
            f64::from(c.column + 1) / w,
            f64::from(c.before) / n,
            f64::from(c.before + c.columns) / n,
        ]
    }

    #[test]
    fn square_counts_put_one_sample_in_every_grid_cell() {
        for n in [1u32, 2, 3, 4, 8, 16] {
            let count = n * n;
            for pixel in 0..20 {
                let mut seen = vec![0u32; count as usize];
                for k in 0..count {
                    let p = stratified_2d(k, count, Rng::for_sample(1, pixel, k).next_2d());
                    assert!(p.iter().all(|c| (0.0..1.0).contains(c)), "{p:?}");
                    let (i, j) = ((p[0] * n as f32) as u32, (p[1] * n as f32) as u32);
                    seen[(j * n + i) as usize] += 1;
                }
                assert!(seen.iter().all(|&c| c == 1), "n = {n}: {seen:?}");
            }
        }
    }

    #[test]
    fn every_count_partitions_the_square_into_equal_near_square_cells() {
        for count in 1..=150 {
            let cells: Vec<[f64; 4]> = (0..count).map(|k| bounds(k, count)).collect();
            for (k, b) in cells.iter().enumerate() {
                let area = (b[1] - b[0]) * (b[3] - b[2]);
                assert!(
                    (area * f64::from(count) - 1.0).abs() < 1e-12,
                    "{count}/{k}: {b:?}"
                );
                assert!(b[0] >= 0.0 && b[1] <= 1.0 && b[2] >= 0.0 && b[3] <= 1.0 + 1e-12);
                // Longer side over shorter: at most 2 (3 for count 3, where
                // rectangles in rows cannot do better), where strips would
                // reach `count`.
                let aspect = (b[1] - b[0]) / (b[3] - b[2]);
                let worst = if count == 3 { 3.0 } else { 2.0 };
                assert!(
                    aspect.max(1.0 / aspect) <= worst + 1e-12,
                    "{count}: {aspect}"
                );
            }
            // Equal areas summing to 1 tile the square if no two overlap: probe
            // a grid of points, each in exactly one cell.
            for a in 0..37 {
                for b in 0..41 {
                    let (x, y) = ((f64::from(a) + 0.5) / 37.0, (f64::from(b) + 0.5) / 41.0);
                    let inside = cells
                        .iter()
                        .filter(|c| c[0] <= x && x < c[1] && c[2] <= y && y < c[3])
                        .count();
                    assert_eq!(inside, 1, "count {count}: ({x}, {y})");
                }
            }
        }
    }

    #[test]
    fn each_sample_lies_in_its_own_cell() {
        for count in 1..=70 {
            for pixel in 0..5 {
                for k in 0..count {
                    let p = stratified_2d(k, count, Rng::for_sample(2, pixel, k).next_2d());
                    let [x0, x1, y0, y1] = bounds(k, count);
                    let (x, y) = (f64::from(p[0]), f64::from(p[1]));
                    // f32 rounding may land a hair outside: allow one f32 ulp.
                    let e = 1e-7;
                    assert!(
                        x0 - e <= x && x < x1 + e && y0 - e <= y && y < y1 + e,
                        "count {count}, sample {k}: {p:?} not in {:?}",
                        [x0, x1, y0, y1]
                    );
                }
            }
        }
    }

    #[test]
    fn extreme_jitter_stays_in_the_unit_square() {
        for count in [1, 2, 3, 7, 9, 12, 100, 1000, u32::MAX] {
            for k in [0, 1, count / 2, count - 1] {
                for u in [[0.0, 0.0], [ONE_MINUS_EPSILON; 2], [0.0, ONE_MINUS_EPSILON]] {
                    let p = stratified_2d(k, count, u);
                    assert!(
                        p.iter().all(|c| (0.0..1.0).contains(c)),
                        "{count} {k} {p:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn indices_past_count_start_another_round() {
        for count in [4, 7] {
            let u = [0.3, 0.8];
            assert_eq!(
                stratified_2d(count + 2, count, u),
                stratified_2d(2, count, u)
            );
        }
        assert_eq!(stratified_2d(5, 0, [0.25, 0.5]), [0.25, 0.5]);
        assert_eq!(stratified_2d(0, 1, [0.25, 0.5]), [0.25, 0.5]);
    }

    #[test]
    fn points_average_to_the_centre() {
        // 4000 pixels × count points. Independent uniform points would have a
        // mean with standard error 0.2887/√(4000·count) ≤ 0.0023 per axis;
        // stratified ones vary less. 0.01 is over 4 such standard errors.
        for count in [7, 12, 16] {
            let (mut sx, mut sy) = (0.0f64, 0.0f64);
            for pixel in 0..4000 {
                for k in 0..count {
                    let p = stratified_2d(k, count, Rng::for_sample(3, pixel, k).next_2d());
                    sx += f64::from(p[0]);
                    sy += f64::from(p[1]);
                }
            }
            let total = 4000.0 * f64::from(count);
            let (mx, my) = (sx / total, sy / total);
            assert!(
                (mx - 0.5).abs() < 0.01 && (my - 0.5).abs() < 0.01,
                "{count}: {mx} {my}"
            );
        }
    }

    #[test]
    fn stratification_beats_independent_points_on_a_smooth_integrand() {
        // ∫∫ x·y + x² over the unit square = 1/4 + 1/3. Per pixel, the mean of
        // `count` values estimates it; over 2000 pixels compare the mean
        // squared error with that of independent points (same uniforms).
        // Jittering makes it fall like count⁻² rather than count⁻¹ for smooth
        // integrands, so the ratio of the two is about 1/count (measured:
        // count × ratio between 0.7 and 1.3; each MSE has a relative standard
        // error of about √(2/2000) ≈ 3%). Bound: count × ratio < 1.6, which
        // independent points (ratio 1) fail from count 2 on.
        let f = |p: [f32; 2]| f64::from(p[0] * p[1] + p[0] * p[0]);
        let exact = 0.25 + 1.0 / 3.0;
        for count in [2, 3, 5, 7, 12, 16, 30] {
            let (mut e_strat, mut e_iid) = (0.0f64, 0.0f64);
            for pixel in 0..2000 {
                let (mut a, mut b) = (0.0, 0.0);
                for k in 0..count {
                    let u = Rng::for_sample(4, pixel, k).next_2d();
                    a += f(stratified_2d(k, count, u));
                    b += f(u);
                }
                e_strat += (a / f64::from(count) - exact).powi(2);
                e_iid += (b / f64::from(count) - exact).powi(2);
            }
            assert!(
                e_strat * f64::from(count) < 1.6 * e_iid,
                "count {count}: {e_strat} vs {e_iid}"
            );
        }
    }
}
