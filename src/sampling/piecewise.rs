//! A piecewise-constant density on the unit square over a grid of cells
//! (pbrt-v4's `PiecewiseConstant2D`): a marginal distribution over the rows
//! and a conditional one over each row's cells. Both are [`Discrete`]
//! distributions whose reused number places the point within the picked
//! cell, so the continuous sample is (cell + reused) / cells along each axis.

use super::Discrete;

/// A density proportional to the cells' weights on [0, 1)², row by row.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Piecewise2D {
    width: usize,
    rows: Discrete,
    cells: Vec<Discrete>,
}

/// A point drawn from a [`Piecewise2D`] and the density there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample2D {
    /// (x, y) in [0, 1)²: x along a row, y down the rows.
    pub point: [f32; 2],
    /// The density with respect to area on the unit square.
    pub pdf: f32,
}

impl Piecewise2D {
    /// `weights` has `width` cells a row, rows from y = 0; negative and NaN
    /// weights count as zero.
    pub fn new(weights: &[f32], width: usize) -> Piecewise2D {
        let cells: Vec<Discrete> = weights
            .chunks(width.max(1))
            .map(|row| Discrete::new(row.iter().copied()))
            .collect();
        let rows = Discrete::new(
            weights
                .chunks(width.max(1))
                .map(|row| row.iter().filter(|w| **w > 0.0).sum::<f32>()),
        );
        Piecewise2D { width, rows, cells }
    }

    /// The point for uniform `u` in [0, 1)²; None if every weight is zero.
    pub fn sample(&self, u: [f32; 2]) -> Option<Sample2D> {
        let (row, p_row, y) = self.rows.sample_reused(u[1])?;
        let (cell, p_cell, x) = self.cells[row].sample_reused(u[0])?;
        let (w, h) = (self.width as f32, self.cells.len() as f32);
        Some(Sample2D {
            point: [(cell as f32 + x) / w, (row as f32 + y) / h],
            pdf: p_row * p_cell * w * h,
        })
    }

    /// The density at `point` in [0, 1]² (edges clamp into the grid).
    pub fn pdf(&self, point: [f32; 2]) -> f32 {
        let h = self.cells.len();
        if h == 0 {
            return 0.0;
        }
        let index = |t: f32, n: usize| ((t * n as f32) as usize).min(n - 1);
        let (cell, row) = (index(point[0], self.width), index(point[1], h));
        self.rows.probability(row) * self.cells[row].probability(cell) * (self.width * h) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_density_follows_the_weights_and_integrates_to_one() {
        // 3 × 2 cells; the zero cell is never drawn.
        let d = Piecewise2D::new(&[1.0, 0.0, 3.0, 2.0, 2.0, 4.0], 3);
        // Total 12 over area 1: cell weight w has density 6 w / 12.
        assert!((d.pdf([0.1, 0.2]) - 0.5).abs() < 1e-6);
        assert_eq!(d.pdf([0.5, 0.2]), 0.0);
        assert!((d.pdf([0.9, 0.9]) - 2.0).abs() < 1e-6);
        assert!((d.pdf([1.0, 1.0]) - 2.0).abs() < 1e-6);
        // A multiple of both grid sides: the midpoint rule is then exact.
        let n = 66u32;
        let mut integral = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let p = [(i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32];
                integral += f64::from(d.pdf(p)) / f64::from(n * n);
                let s = d.sample(p).unwrap();
                assert!(s.point.iter().all(|t| (0.0..1.0).contains(t)), "{s:?}");
                assert!(s.pdf > 0.0 && (s.pdf - d.pdf(s.point)).abs() < 1e-5);
            }
        }
        assert!((integral - 1.0).abs() < 1e-5, "{integral}");
        assert_eq!(Piecewise2D::new(&[0.0; 4], 2).sample([0.5, 0.5]), None);
    }
}
