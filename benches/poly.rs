//! Root-finder micro-benchmarks: per-call cost of the queries a ray makes
//! (nearest for camera and secondary rays, any for shadow rays) on torus
//! quartics from a fixed set of rays, of the building blocks, and of the
//! exact count that certifies `roots`.
//!
//! Run: `cargo bench --bench poly`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use sturmray::poly::MAX_DEGREE;
use sturmray::poly::closed;
use sturmray::poly::exact::exact_count;
use sturmray::poly::solve::{Method, Solver};
use sturmray::poly::sturm::SturmSequence;
use sturmray::poly::univariate::{Poly, SmallPoly};
use sturmray::sampling::Rng;

/// Q(t) of the ray o + t d (|d| = 1) against the torus about z with radii
/// (major, minor): (|x|^2 + R^2 - r^2)^2 - 4 R^2 (x^2 + y^2).
fn torus(major: f64, minor: f64, o: [f64; 3], d: [f64; 3]) -> Poly {
    let dot = |u: [f64; 3], v: [f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    let (b, c) = (dot(o, d), dot(o, o));
    let k = c + major * major - minor * minor;
    let e2 = d[0] * d[0] + d[1] * d[1];
    let e1 = o[0] * d[0] + o[1] * d[1];
    let e0 = o[0] * o[0] + o[1] * o[1];
    let r4 = 4.0 * major * major;
    Poly::new(&[
        k * k - r4 * e0,
        4.0 * b * k - 2.0 * r4 * e1,
        4.0 * b * b + 2.0 * k - r4 * e2,
        4.0 * b,
        1.0,
    ])
}

/// A deterministic spread of rays from a sphere of radius 4 towards points
/// near the torus (R = 1, r = 0.3): about two thirds hit it, with 2 or 4
/// roots; the rest miss.
fn torus_rays(n: usize) -> Vec<Poly> {
    let mut rng = Rng::for_sample(0x9e37_79b9, 0, 0);
    let mut next = move || f64::from(rng.next_f32());
    (0..n)
        .map(|_| {
            let (u, v) = (2.0 * std::f64::consts::PI * next(), 2.0 * next() - 1.0);
            let s = (1.0 - v * v).sqrt();
            let o = [4.0 * s * u.cos(), 4.0 * s * u.sin(), 4.0 * v];
            let (w, radius) = (2.0 * std::f64::consts::PI * next(), 1.4 * next());
            let target = [radius * w.cos(), radius * w.sin(), 0.6 * next() - 0.3];
            let d = [target[0] - o[0], target[1] - o[1], target[2] - o[2]];
            let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            torus(1.0, 0.3, o, [d[0] / len, d[1] / len, d[2] / len])
        })
        .collect()
}

fn queries(c: &mut Criterion) {
    let rays = torus_rays(1024);
    let mut group = c.benchmark_group("torus quartic, per call");
    for &method in Method::ALL {
        let solver = Solver {
            method,
            ..Solver::default()
        };
        group.bench_function(format!("nearest {}", method.name()), |bench| {
            let mut i = 0;
            bench.iter(|| {
                i = (i + 1) % rays.len();
                black_box(solver.nearest(black_box(&rays[i]), 0.0, 10.0))
            })
        });
    }
    let solver = Solver::default();
    group.bench_function("any (shadow)", |bench| {
        let mut i = 0;
        bench.iter(|| {
            i = (i + 1) % rays.len();
            black_box(solver.any(black_box(&rays[i]), 0.0, 10.0))
        })
    });
    group.bench_function("nearest_from (warm start)", |bench| {
        let mut i = 0;
        let mut last = 4.0;
        bench.iter(|| {
            i = (i + 1) % rays.len();
            let t = solver.nearest_from(black_box(&rays[i]), 0.0, 10.0, last);
            last = t.unwrap_or(last);
            black_box(t)
        })
    });
    group.bench_function("roots", |bench| {
        let mut i = 0;
        let mut out = [0.0; MAX_DEGREE];
        bench.iter(|| {
            i = (i + 1) % rays.len();
            black_box(solver.roots(black_box(&rays[i]), 0.0, 10.0, &mut out))
        })
    });
    // In the small instantiation, as a ray's query builds it.
    let small: Vec<SmallPoly> = rays.iter().map(|p| p.resized().unwrap()).collect();
    group.bench_function("SturmSequence::new", |bench| {
        let mut i = 0;
        bench.iter(|| {
            i = (i + 1) % small.len();
            black_box(SturmSequence::new(black_box(&small[i])))
        })
    });
    group.bench_function("closed::quartic", |bench| {
        let mut i = 0;
        let mut out = [0.0; 4];
        bench.iter(|| {
            i = (i + 1) % rays.len();
            let c = rays[i].coeffs();
            black_box(closed::quartic([c[0], c[1], c[2], c[3], c[4]], &mut out))
        })
    });
    group.finish();
}

fn high_degree(c: &mut Criterion) {
    let mut coeffs = vec![1.0];
    for r in 1..=10 {
        let mut next = vec![0.0; coeffs.len() + 1];
        for (i, &ci) in coeffs.iter().enumerate() {
            next[i + 1] += ci;
            next[i] -= f64::from(r) * ci;
        }
        coeffs = next;
    }
    let p = Poly::new(&coeffs);
    let solver = Solver::default();
    let mut group = c.benchmark_group("roots 1..10 (degree 10)");
    group.bench_function("nearest", |bench| {
        bench.iter(|| black_box(solver.nearest(black_box(&p), 0.0, 11.0)))
    });
    group.bench_function("roots", |bench| {
        let mut out = [0.0; MAX_DEGREE];
        bench.iter(|| black_box(solver.roots(black_box(&p), 0.0, 11.0, &mut out)))
    });
    group.finish();
    // Chebyshev's T_35 (35 simple roots in (-1, 1), integer coefficients
    // exact in f64): the limit's cost.
    let (mut prev, mut t35) = (vec![1.0], vec![0.0, 1.0]);
    for _ in 1..35 {
        let mut next: Vec<f64> = std::iter::once(0.0)
            .chain(t35.iter().map(|c| 2.0 * c))
            .collect();
        for (n, p) in next.iter_mut().zip(&prev) {
            *n -= p;
        }
        (prev, t35) = (t35, next);
    }
    let p = Poly::new(&t35);
    let mut group = c.benchmark_group("Chebyshev T_35 (degree 35)");
    group.bench_function("nearest", |bench| {
        bench.iter(|| black_box(solver.nearest(black_box(&p), -2.0, 2.0)))
    });
    group.bench_function("roots", |bench| {
        let mut out = [0.0; MAX_DEGREE];
        bench.iter(|| black_box(solver.roots(black_box(&p), -2.0, 2.0, &mut out)))
    });
    group.finish();
}

/// The exact path that certifies `roots` (issue 17): random coefficients
/// of up to 1e3 in size with all 53 bits of mantissa in use (as computed ray
/// polynomials have; the rationals' size, hence the cost, grows with them),
/// at degree 8, 16, 35 (the f64 path's limit) and 100 (where the exact path
/// answers alone). `exact_count` is the count the renderer's `roots` checks
/// against; `certified` is the whole answer of `sturmray roots` on (−MAX,
/// MAX], certificate included. Run: `cargo bench --bench poly -- exact`.
fn exact_certificate(c: &mut Criterion) {
    let mut rng = Rng::for_sample(0xce27, 0, 0);
    let mut unit = move || f64::from(rng.next_f32()) + f64::from(rng.next_f32()) * 2f64.powi(-24);
    let solver = Solver::default();
    for degree in [8, 16, 35, 100] {
        let polys: Vec<Vec<f64>> = (0..16)
            .map(|_| (0..=degree).map(|_| 2e3 * unit() - 1e3).collect())
            .collect();
        let mut group = c.benchmark_group(format!("exact, degree {degree}, per call"));
        if degree > 35 {
            group.sample_size(10);
        }
        group.bench_function("exact_count", |bench| {
            let mut i = 0;
            bench.iter(|| {
                i = (i + 1) % polys.len();
                black_box(exact_count(black_box(&polys[i]), -3.7, 2.9))
            })
        });
        group.bench_function("certified", |bench| {
            let mut i = 0;
            bench.iter(|| {
                i = (i + 1) % polys.len();
                black_box(solver.certified(black_box(&polys[i]), -f64::MAX, f64::MAX))
            })
        });
        group.finish();
    }
}

criterion_group!(benches, queries, high_degree, exact_certificate);
criterion_main!(benches);
