//! Measuring one root finder at one tolerance on one set of cases: time per
//! ray, root error and missed and false hits against the exact reference,
//! and the image error of a render against a reference render.

use std::time::Instant;

use crate::accel::{Accel, Backend};
use crate::error::Result;
use crate::poly::exact::exact_roots;
use crate::poly::solve::{Method, Solver};
use crate::render::{RenderOptions, render};
use crate::report::accuracy::cases::Case;
use crate::scene::Scene;

/// A root finder under study.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Finder {
    /// `Solver::nearest` with this method, as the renderer calls it.
    Cold(Method),
    /// `Solver::nearest_from` (sturm-newton), warm-started from the root the
    /// previous case of the set gave: Newton alone when the guess holds,
    /// Sturm counts only to prove it.
    Warm,
}

impl Finder {
    pub const ALL: [Finder; 6] = [
        Finder::Cold(Method::SturmBisect),
        Finder::Cold(Method::SturmNewton),
        Finder::Cold(Method::SturmIllinois),
        Finder::Cold(Method::Closed),
        Finder::Cold(Method::Yuksel),
        Finder::Warm,
    ];

    /// The method's stable name; the warm start is "newton-warm".
    pub fn name(self) -> &'static str {
        match self {
            Finder::Cold(m) => m.name(),
            Finder::Warm => "newton-warm",
        }
    }

    pub fn solver(self, tolerance: f64) -> Solver {
        let method = match self {
            Finder::Cold(m) => m,
            Finder::Warm => Method::SturmNewton,
        };
        Solver {
            method,
            tolerance,
            ..Solver::default()
        }
    }

    /// The nearest root of every case, in order.
    pub fn solve(self, tolerance: f64, cases: &[Case]) -> Vec<Option<f64>> {
        let solver = self.solver(tolerance);
        let mut guess = f64::NAN;
        cases
            .iter()
            .map(|c| {
                let t = match self {
                    Finder::Cold(_) => solver.nearest(&c.q, 0.0, c.hi),
                    Finder::Warm => solver.nearest_from(&c.q, 0.0, c.hi, guess),
                };
                guess = t.unwrap_or(guess);
                t
            })
            .collect()
    }
}

/// The exact nearest root of each case in (0, hi): the correctly rounded
/// f64 of the first root [`exact_roots`] finds in (0, hi].
pub fn reference(cases: &[Case]) -> Vec<Option<f64>> {
    cases
        .iter()
        .map(|c| {
            exact_roots(c.q.coeffs(), 0.0, c.hi, 0.0)
                .and_then(|roots| roots.into_iter().find(|&t| t < c.hi))
        })
        .collect()
}

/// Wall time of one pass of `finder` over the cases, in seconds.
pub fn time(finder: Finder, tolerance: f64, cases: &[Case]) -> f64 {
    let start = Instant::now();
    std::hint::black_box(finder.solve(tolerance, std::hint::black_box(cases)));
    start.elapsed().as_secs_f64()
}

/// How found roots compare with the reference.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Errors {
    /// |t − t_ref| / max(1, |t_ref|) for each case both hit (the solver's
    /// own tolerance measure).
    pub root: Vec<f64>,
    /// The reference hits, the finder does not.
    pub missed: usize,
    /// The finder hits, the reference does not.
    pub false_hits: usize,
}

impl Errors {
    pub fn compare(found: &[Option<f64>], reference: &[Option<f64>]) -> Errors {
        let mut e = Errors::default();
        for (f, r) in found.iter().zip(reference) {
            match (f, r) {
                (Some(t), Some(r)) => e.root.push((t - r).abs() / r.abs().max(1.0)),
                (None, Some(_)) => e.missed += 1,
                (Some(_), None) => e.false_hits += 1,
                (None, None) => {}
            }
        }
        e
    }

    /// Pools another set's errors into these.
    pub fn extend(&mut self, other: &Errors) {
        self.root.extend_from_slice(&other.root);
        self.missed += other.missed;
        self.false_hits += other.false_hits;
    }

    /// The q-quantile (0..=1) of the root errors, 0 when there are none.
    pub fn quantile(&self, q: f64) -> f64 {
        let mut sorted = self.root.clone();
        sorted.sort_by(f64::total_cmp);
        match sorted.len() {
            0 => 0.0,
            n => sorted[((n - 1) as f64 * q).round() as usize],
        }
    }
}

/// A render's beauty and which pixels saw any surface.
pub struct Image {
    beauty: Vec<[f32; 3]>,
    covered: Vec<bool>,
}

/// How far an image is from the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageError {
    /// Root mean square of the beauty's difference over all channels and pixels.
    pub rmse: f64,
    /// Pixels that hit a surface in one image and nothing in the other.
    pub coverage: usize,
}

/// Renders `scene` at one sample per pixel with every analytic shape using
/// `solver`. Deterministic: one sample per pixel, seeded per pixel.
pub fn render_with(scene: &Scene, solver: Solver) -> Result<Image> {
    let mut scene = scene.clone();
    for shape in &mut scene.shapes {
        shape.set_solver(solver);
    }
    let accel = Accel::build(&scene, Backend::Embree, None)?;
    let options = RenderOptions {
        spp: Some(1),
        ..RenderOptions::default()
    };
    let layers = render(&scene, &accel, &options)?.film.layers();
    Ok(Image {
        covered: layers.depth.iter().map(|d| d.is_finite()).collect(),
        beauty: layers.beauty,
    })
}

impl Image {
    pub fn error_from(&self, reference: &Image) -> ImageError {
        let squares: f64 = self
            .beauty
            .iter()
            .zip(&reference.beauty)
            .flat_map(|(a, b)| (0..3).map(move |k| f64::from(a[k] - b[k]).powi(2)))
            .sum();
        let coverage = self
            .covered
            .iter()
            .zip(&reference.covered)
            .filter(|(a, b)| a != b)
            .count();
        ImageError {
            rmse: (squares / (3 * self.beauty.len().max(1)) as f64).sqrt(),
            coverage,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::poly::univariate::{Poly, from_roots};

    #[test]
    fn errors_count_misses_false_hits_and_relative_error() {
        let found = [Some(2.0 + 2e-9), None, Some(0.5), None, Some(0.25 + 1e-9)];
        let reference = [Some(2.0), Some(1.0), None, None, Some(0.25)];
        let e = Errors::compare(&found, &reference);
        assert_eq!((e.missed, e.false_hits), (1, 1));
        assert_eq!(e.root.len(), 2);
        // Relative above 1, absolute below.
        assert!((e.root[0] - 1e-9).abs() < 1e-15, "{:?}", e.root);
        assert!((e.root[1] - 1e-9).abs() < 1e-15, "{:?}", e.root);
        assert_eq!(e.quantile(1.0), e.root.iter().copied().fold(0.0, f64::max));
        assert_eq!(Errors::default().quantile(0.5), 0.0);
    }

    #[test]
    fn reference_is_the_exact_nearest_root_in_the_open_interval() {
        let cases = [
            Case {
                q: from_roots(1.0, &[-1.0, 0.5, 3.0]),
                hi: 4.0,
            },
            // The only root is at hi: not in (0, hi).
            Case {
                q: from_roots(-2.0, &[4.0]),
                hi: 4.0,
            },
            // (t − 1/3)³ rounded: the exact path decides what its roots are.
            Case {
                q: Poly::new(&[-1.0, 9.0, -27.0, 27.0]),
                hi: 1.0,
            },
        ];
        let r = reference(&cases);
        assert_eq!(r[0], Some(0.5));
        assert_eq!(r[1], None);
        assert!(r[2].is_some_and(|t| (t - 1.0 / 3.0).abs() < 1e-5), "{r:?}");
    }

    #[test]
    fn every_finder_agrees_with_the_reference_on_separated_roots() {
        let cases: Vec<Case> = (1..=20)
            .map(|k| Case {
                q: from_roots(1.5, &[-0.5, 0.1 * f64::from(k), 2.5]),
                hi: 3.0,
            })
            .collect();
        let reference = reference(&cases);
        for finder in Finder::ALL {
            let e = Errors::compare(&finder.solve(1e-12, &cases), &reference);
            assert_eq!((e.missed, e.false_hits), (0, 0), "{}", finder.name());
            assert!(e.quantile(1.0) <= 1e-12, "{}: {:?}", finder.name(), e.root);
        }
    }
}
