//! Intersector micro-benchmarks: per-ray cost of `Shape::intersect` (camera
//! and secondary rays) and `Shape::occluded` (shadow rays) for a sphere, a
//! torus, a thin torus and algebraic surfaces of degree 4, 6 and 10, each
//! under the default root finder and the other methods, on a fixed set of
//! rays aimed at the shape's box (some hit, some graze, some miss).
//!
//! Run: `cargo bench --bench intersect`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use glam::{DAffine3, DVec3};
use sturmray::geometry::{Box3, Shape, Surface};
use sturmray::poly::expr;
use sturmray::poly::solve::{Method, Solver};
use sturmray::sampling::Rng;

/// Rays from a sphere of radius 6 around the origin towards points in the
/// cube of half-size `half`, from a fixed seed, so every run and every
/// shape gets the same directions.
fn rays(n: usize, half: f64) -> Vec<(DVec3, DVec3)> {
    let mut rng = Rng::for_sample(0x2545_f491, 0, 0);
    let mut next = move || f64::from(rng.next_f32());
    (0..n)
        .map(|_| {
            let (u, v) = (std::f64::consts::TAU * next(), 2.0 * next() - 1.0);
            let s = (1.0 - v * v).sqrt();
            let o = 6.0 * DVec3::new(s * u.cos(), s * u.sin(), v);
            let target =
                half * DVec3::new(2.0 * next() - 1.0, 2.0 * next() - 1.0, 2.0 * next() - 1.0);
            (o, (target - o).normalize())
        })
        .collect()
}

fn shapes(solver: Solver) -> Vec<(&'static str, Shape)> {
    let algebraic = |text: &str, half: f64| {
        let f = expr::parse(text, &[]).unwrap();
        let clip = Some(Box3::cube(half));
        Shape::new(
            Surface::Algebraic(Box::new(f)),
            DAffine3::IDENTITY,
            clip,
            0,
            solver,
        )
        .unwrap()
    };
    let plain = |surface| Shape::new(surface, DAffine3::IDENTITY, None, 0, solver).unwrap();
    vec![
        ("sphere", plain(Surface::Sphere { radius: 1.0 })),
        (
            "torus r/R 0.25",
            plain(Surface::Torus {
                major: 1.0,
                minor: 0.25,
            }),
        ),
        (
            "torus r/R 0.01",
            plain(Surface::Torus {
                major: 1.0,
                minor: 0.01,
            }),
        ),
        (
            "goursat (4)",
            algebraic("x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8", 2.2),
        ),
        (
            "heart (6)",
            algebraic(
                "(x^2 + 2.25*y^2 + z^2 - 1)^3 - x^2*z^3 - 0.1125*y^2*z^3",
                1.3,
            ),
        ),
        ("decic (10)", algebraic("x^10 + y^10 + z^10 - 1", 1.1)),
    ]
}

fn intersect(c: &mut Criterion) {
    let rays = rays(1024, 1.2);
    for (name, shape) in shapes(Solver::default()) {
        let mut group = c.benchmark_group(format!("{name}, per ray"));
        group.bench_function("intersect", |bench| {
            let mut i = 0;
            bench.iter(|| {
                i = (i + 1) % rays.len();
                let (o, d) = rays[i];
                black_box(shape.intersect(black_box(o), black_box(d), 0.0, f64::INFINITY))
            })
        });
        group.bench_function("occluded", |bench| {
            let mut i = 0;
            bench.iter(|| {
                i = (i + 1) % rays.len();
                let (o, d) = rays[i];
                black_box(shape.occluded(black_box(o), black_box(d), 0.0, 12.0))
            })
        });
        group.finish();
    }
}

/// The same intersections under each root-finding method at the default
/// tolerance: the renderer's cost of a method, polish and all.
fn methods(c: &mut Criterion) {
    let rays = rays(1024, 1.2);
    let mut group = c.benchmark_group("intersect by method, per ray");
    for &method in Method::ALL {
        let solver = Solver {
            method,
            ..Solver::default()
        };
        for (name, shape) in shapes(solver).into_iter().skip(1) {
            group.bench_function(format!("{name} {}", method.name()), |bench| {
                let mut i = 0;
                bench.iter(|| {
                    i = (i + 1) % rays.len();
                    let (o, d) = rays[i];
                    black_box(shape.intersect(black_box(o), black_box(d), 0.0, f64::INFINITY))
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, intersect, methods);
criterion_main!(benches);
