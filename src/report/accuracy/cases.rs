//! The inputs of the accuracy study: sets of polynomials, each solved for
//! its nearest root in (0, hi) as a camera ray's search solves it.
//!
//! Scene sets take the very polynomials the renderer solves
//! ([`Shape::ray_polynomial`]) for camera rays through pixel centres, shape
//! by shape in scanline order, so consecutive cases come from neighbouring
//! rays (what a warm start exploits). Synthetic sets hold clustered and
//! repeated roots, built from their roots in f64, and coefficients at
//! round-off size.

use std::path::Path;

use crate::error::Result;
use crate::geometry::Surface;
use crate::poly::univariate::{Poly, from_roots};
use crate::sampling::Rng;
use crate::scene::Scene;

/// One query: the nearest root of `q` in (0, hi).
#[derive(Clone, Copy, Debug)]
pub struct Case {
    pub q: Poly,
    pub hi: f64,
}

/// A named set of cases; a scene set keeps its scene, resized for the
/// study's reference renders.
#[derive(Clone, Debug)]
pub struct CaseSet {
    pub name: String,
    pub cases: Vec<Case>,
    pub scene: Option<Scene>,
}

/// The scenes the study reads: the gallery's tori and algebraic surfaces
/// (Goursat's tangle cube, Steiner, Kummer, the heart) and the accuracy
/// folder's thin tori and degree 6–10 surfaces.
pub const SCENES: &[&str] = &[
    "scenes/gallery/tori.toml",
    "scenes/gallery/algebraic.toml",
    "scenes/accuracy/thin_tori.toml",
    "scenes/accuracy/high_degree.toml",
];

/// The hard-case scenes, every one of [`SCENES`]: the polynomials of
/// camera rays through the pixel centres of images `width` pixels across.
/// Scene paths are relative to `root`, the repository.
pub fn hard_cases(root: &Path, width: u32) -> Result<Vec<CaseSet>> {
    super::scene_files(root)
        .iter()
        .map(|path| scene_set(path, width))
        .collect()
}

/// Every input of the study: the hard-case scenes and the synthetic sets
/// of `synthetic` polynomials each.
pub fn all_cases(root: &Path, width: u32, synthetic: usize) -> Result<Vec<CaseSet>> {
    let mut sets = hard_cases(root, width)?;
    sets.push(clustered(synthetic));
    sets.push(repeated(synthetic));
    sets.push(noisy(synthetic));
    // A quarter as many: the exact reference costs some 50 times more at
    // degree 35 than at degree 10.
    sets.push(high_degree(synthetic / 4));
    Ok(sets)
}

/// The polynomials of camera rays through the pixel centres of an image
/// `width` pixels across (aspect kept, the scene resized to it) against
/// every torus and algebraic shape of the scene. Spheres and quadrics are
/// left out: their quadratics never reach the root finders.
pub fn scene_set(path: &Path, width: u32) -> Result<CaseSet> {
    let mut scene = Scene::load(path)?;
    let name = format!("scene:{}", scene.name);
    resize(&mut scene, width);
    let frame = scene.camera.frame();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut cases = Vec::new();
    for shape in &scene.shapes {
        if !matches!(shape.surface, Surface::Torus { .. } | Surface::Algebraic(_)) {
            continue;
        }
        for y in 0..h {
            for x in 0..w {
                let ray = frame.ray(x as f32 + 0.5, y as f32 + 0.5);
                let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
                if let Some(r) = shape.ray_polynomial(o, d, 0.0, f64::INFINITY) {
                    cases.push(Case { q: r.q, hi: r.hi });
                }
            }
        }
    }
    Ok(CaseSet {
        name,
        cases,
        scene: Some(scene),
    })
}

/// Sets the camera's width, keeping the aspect ratio (the field of view is
/// vertical, so the view does not change).
fn resize(scene: &mut Scene, width: u32) {
    let c = &mut scene.camera;
    let height = (u64::from(c.height) * u64::from(width) / u64::from(c.width)).max(1);
    (c.width, c.height) = (width, height as u32);
}

/// Degree 4 to 10 with a cluster of 2 to 4 roots, 1e-2 to 1e-9 apart (a ray
/// through a thin shell or grazing a fold), among other roots in (0, 4).
pub fn clustered(n: usize) -> CaseSet {
    synthetic("clustered", 0x0c10_57e5, n, |rng, _| {
        let degree = 4 + (rng.next_u64() % 7) as usize;
        let size = 2 + (rng.next_u64() % 3) as usize;
        let gap = 10f64.powf(-2.0 - 7.0 * f64::from(rng.next_f32()));
        let centre = 0.2 + 3.0 * f64::from(rng.next_f32());
        let mut roots: Vec<f64> = (0..size).map(|k| centre + gap * k as f64).collect();
        while roots.len() < degree {
            roots.push(-1.0 + 6.0 * f64::from(rng.next_f32()));
        }
        from_roots(lead(rng), &roots)
    })
}

/// Degree 2 to 10 with one root of multiplicity 2 to 4 (a tangent ray, a
/// node, a surface like the cubed sphere), half of them at values f64
/// represents exactly (the polynomial then has the multiple root itself),
/// half at decimals (rounding splits the root into a cluster or a complex
/// pair: the exact reference decides which).
pub fn repeated(n: usize) -> CaseSet {
    synthetic("repeated", 0x4e9, n, |rng, i| {
        let multiplicity = 2 + (rng.next_u64() % 3) as usize;
        let others = (rng.next_u64() % 7) as usize;
        let step = (1 + rng.next_u64() % 15) as f64;
        let root = if i % 2 == 0 { step / 4.0 } else { step / 5.0 };
        let mut roots = vec![root; multiplicity];
        for _ in 0..others {
            roots.push(-1.0 + 6.0 * f64::from(rng.next_f32()));
        }
        from_roots(lead(rng), &roots)
    })
}

/// Degree 3 to 10, random coefficients of 0.1 to 10 in size times a
/// leading scale, where each lower one is, with odds of 1 in 3, at
/// round-off size instead (1e-12 to 1e-8 of the largest): a coefficient
/// that is zero in exact arithmetic, such as an odd one for a ray through a
/// torus's centre, but not after rounding. Such terms push remainders of
/// the f64 chain down to their own noise.
pub fn noisy(n: usize) -> CaseSet {
    synthetic("noisy", 0x0015e, n, |rng, _| {
        let degree = 3 + (rng.next_u64() % 8) as usize;
        let scale = lead(rng);
        let mut c: Vec<f64> = (0..=degree)
            .map(|_| scale * 10f64.powf(2.0 * f64::from(rng.next_f32()) - 1.0))
            .collect();
        let largest = c.iter().fold(0.0, |m: f64, x| m.max(x.abs()));
        for ci in &mut c[..degree] {
            if rng.next_u64().is_multiple_of(3) {
                *ci = largest * 10f64.powf(-12.0 + 4.0 * f64::from(rng.next_f32()));
            }
            if rng.next_u64().is_multiple_of(2) {
                *ci = -*ci;
            }
        }
        Poly::new(&c)
    })
}

/// Degree 20 to 35 (POV-Ray's `poly` limit), three kinds by turns:
/// Chebyshev-spaced simple roots 2 + 2cos((2k − 1)π / 2n), crowding
/// towards both ends of (0, 4); equally spaced ones (Wilkinson's
/// polynomial, scaled into (0, 4)), whose rounded coefficients move the
/// upper roots far or make them complex; and a cluster of 2 to 4 roots
/// 1e-3 to 1e-9 apart among equally spaced others in (-1, 5). Built from
/// their roots in f64 like the other sets, so what is measured is the
/// roots of the rounded polynomial, which the exact reference gives.
pub fn high_degree(n: usize) -> CaseSet {
    synthetic("high-degree", 0x0035, n, |rng, i| {
        let degree = 20 + (rng.next_u64() % 16) as usize;
        high_degree_poly(rng, i, degree)
    })
}

/// `n` polynomials of each degree in `degrees`, built as [`high_degree`]
/// builds its (the kind cycling with the index), each solved on (0, 4].
pub fn by_degree(degrees: std::ops::RangeInclusive<usize>, n: usize) -> Vec<(usize, CaseSet)> {
    degrees
        .map(|degree| {
            let set = synthetic("by-degree", 0x1700 + degree as u64, n, |rng, i| {
                high_degree_poly(rng, i, degree)
            });
            (degree, set)
        })
        .collect()
}

/// One polynomial of [`high_degree`]'s kind `i % 3` at this degree.
fn high_degree_poly(rng: &mut Rng, i: usize, degree: usize) -> Poly {
    let spaced = |k: usize, from: f64, to: f64| from + (to - from) * k as f64 / degree as f64;
    let roots: Vec<f64> = match i % 3 {
        0 => (1..=degree)
            .map(|k| {
                let angle = (2 * k - 1) as f64 * std::f64::consts::PI / (2 * degree) as f64;
                2.0 + 2.0 * angle.cos()
            })
            .collect(),
        1 => (1..=degree)
            .map(|k| spaced(k, 0.0, 4.0 * degree as f64 / (degree + 1) as f64))
            .collect(),
        _ => {
            let size = 2 + (rng.next_u64() % 3) as usize;
            let gap = 10f64.powf(-3.0 - 6.0 * f64::from(rng.next_f32()));
            let centre = 0.2 + 3.0 * f64::from(rng.next_f32());
            let cluster = (0..size).map(|k| centre + gap * k as f64);
            cluster
                .chain((size..degree).map(|k| spaced(k, -1.0, 5.0)))
                .collect()
        }
    };
    from_roots(lead(rng), &roots)
}

/// A synthetic set of `n` polynomials from `make(rng, index)`, each solved
/// on (0, 4), drawn from a generator seeded by `seed` so every run of the
/// study sees the same cases.
fn synthetic(
    name: &str,
    seed: u64,
    n: usize,
    mut make: impl FnMut(&mut Rng, usize) -> Poly,
) -> CaseSet {
    let mut rng = Rng::for_sample(seed, 0, 0);
    let cases = (0..n)
        .map(|i| Case {
            q: make(&mut rng, i),
            hi: 4.0,
        })
        .collect();
    CaseSet {
        name: name.into(),
        cases,
        scene: None,
    }
}

/// A leading coefficient of either sign, 1e-3 to 1e3 in size.
fn lead(rng: &mut Rng) -> f64 {
    let size = 10f64.powf(6.0 * f64::from(rng.next_f32()) - 3.0);
    if rng.next_u64().is_multiple_of(2) {
        size
    } else {
        -size
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::poly::exact::exact_count;
    use crate::poly::sturm::SturmSequence;

    #[test]
    fn synthetic_sets_have_their_roots_in_the_interval() {
        for set in [clustered(50), repeated(50)] {
            assert_eq!(set.cases.len(), 50, "{}", set.name);
            for c in &set.cases {
                assert!(c.q.degree() >= 2, "{}: {:?}", set.name, c.q);
                // Every case was built with a root in (0, 4).
                assert!(
                    SturmSequence::new(&c.q).count(0.0, c.hi) > 0,
                    "{}",
                    set.name
                );
            }
        }
        let noisy = noisy(50);
        assert_eq!(noisy.cases.len(), 50);
        let tiny = |c: &Case| {
            let largest = c.q.max_abs_coeff();
            c.q.coeffs().iter().any(|x| x.abs() < 1e-7 * largest)
        };
        assert!(noisy.cases.iter().all(|c| (3..=10).contains(&c.q.degree())));
        assert!(noisy.cases.iter().filter(|c| tiny(c)).count() > 25);
    }

    #[test]
    fn the_high_degree_set_spans_degree_20_to_35() {
        let set = high_degree(60);
        assert_eq!(set.cases.len(), 60);
        let degrees: Vec<usize> = set.cases.iter().map(|c| c.q.degree()).collect();
        assert!(degrees.iter().all(|d| (20..=35).contains(d)), "{degrees:?}");
        assert!(
            degrees.contains(&20) || degrees.contains(&35),
            "{degrees:?}"
        );
        for c in &set.cases {
            // Every case was built with roots in (0, 4); rounding keeps some.
            let n = exact_count(c.q.coeffs(), 0.0, c.hi).expect("finite");
            assert!(n > 0, "{:?}", c.q);
        }
    }

    #[test]
    fn scene_sets_take_the_renderers_polynomials() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let set = scene_set(&root.join("scenes/accuracy/thin_tori.toml"), 16).unwrap();
        assert_eq!(set.name, "scene:thin_tori");
        assert_eq!(set.scene.as_ref().unwrap().camera.width, 16);
        assert_eq!(set.scene.as_ref().unwrap().camera.height, 10);
        assert!(!set.cases.is_empty());
        assert!(set.cases.iter().all(|c| c.q.degree() == 4 && c.hi > 0.0));
    }
}
