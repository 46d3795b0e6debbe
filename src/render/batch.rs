//! A tile's camera rays traced together: sample k through every pixel of a
//! tile of the image's grid, as one coherent stream (Embree's
//! `rtcIntersect1M`, which sorts them into packets and traverses them
//! together). On the Cornell box a camera ray costs 0.35x of one
//! `rtcIntersect1` call that way (`make embree-modes`); see ARCHITECTURE.md,
//! "Camera rays as streams", for what renders gained.
//!
//! A packet may break a tie (two primitives hit at the same t, as at a
//! shared edge) otherwise than one ray alone would, so the stream is
//! always the same: the whole grid tile's rays, in row order, for one
//! sample index. A pixel's sample k is then the same whatever the region
//! rendered (a crop's edge tile traces its grid tile's other pixels too,
//! and drops them), the passes, the threads or a resume.

use super::TILE;
use crate::accel::{Accel, ShapeSet};
use crate::film::Region;
use crate::math::{DVec3, Hit, Ray64};
use crate::sampling::Sampler;

/// The camera rays of one grid tile for one sample index, with their hits,
/// filter weights and the samplers the integrator goes on drawing from,
/// pixel by pixel, row by row. Its buffers are made once, for every
/// sample index and pass of the tile.
pub(super) struct TileCameras {
    rays: Vec<Ray64>,
    hits: Vec<Hit>,
    /// Each pixel's filter weight and sampler; None for a pixel left
    /// untraced (`trace_among`'s `untraced`).
    samples: Vec<Option<(f32, Sampler)>>,
}

impl TileCameras {
    /// Buffers for a whole tile's rays, made once: grown a push at a time
    /// they were 2% of bicube.pov's render loop (`valgrind --tool=callgrind`,
    /// `RawVec::grow_one`).
    pub(super) fn new() -> TileCameras {
        TileCameras {
            rays: Vec::with_capacity(TILE * TILE),
            hits: Vec::with_capacity(TILE * TILE),
            samples: Vec::with_capacity(TILE * TILE),
        }
    }

    /// Traces `camera`'s ray (with its weight and sampler) through every
    /// pixel of `grid`, a tile of the image's grid.
    pub(super) fn trace(
        &mut self,
        accel: &Accel,
        grid: Region,
        camera: impl Fn((usize, usize)) -> (Ray64, f32, Sampler),
    ) {
        self.gather(grid, camera);
        self.hits.resize(self.rays.len(), Hit::MISS);
        accel.intersect_exact_batch(&self.rays, &mut self.hits);
    }

    /// `trace`, one ray at a time, each offered the shapes `among` gives
    /// its pixel: `hit` finds its nearest hit among them (see
    /// `Accel::intersect_exact_among`). A pixel offered none where
    /// `untraced` holds gets no ray at all: a miss, whose sample the
    /// caller knows without one (`get` gives None).
    pub(super) fn trace_among(
        &mut self,
        grid: Region,
        camera: impl Fn((usize, usize)) -> (Ray64, f32, Sampler),
        among: impl Fn((usize, usize)) -> ShapeSet,
        mut hit: impl FnMut((usize, usize), &Ray64, ShapeSet) -> Hit,
        untraced: bool,
    ) {
        self.rays.clear();
        self.samples.clear();
        self.hits.clear();
        for y in grid.y0..grid.y1 {
            for x in grid.x0..grid.x1 {
                let set = among((x, y));
                if untraced && set == ShapeSet::NONE {
                    self.rays.push(Ray64 {
                        origin: DVec3::ZERO,
                        dir: DVec3::ZERO,
                    });
                    self.samples.push(None);
                    self.hits.push(Hit::MISS);
                    continue;
                }
                let (ray, weight, sampler) = camera((x, y));
                self.hits.push(hit((x, y), &ray, set));
                self.rays.push(ray);
                self.samples.push(Some((weight, sampler)));
            }
        }
    }

    fn gather(&mut self, grid: Region, camera: impl Fn((usize, usize)) -> (Ray64, f32, Sampler)) {
        self.rays.clear();
        self.samples.clear();
        for y in grid.y0..grid.y1 {
            for x in grid.x0..grid.x1 {
                let (ray, weight, sampler) = camera((x, y));
                self.rays.push(ray);
                self.samples.push(Some((weight, sampler)));
            }
        }
    }

    /// Pixel i's ray (row by row), as last traced.
    pub(super) fn ray(&self, i: usize) -> &Ray64 {
        &self.rays[i]
    }

    /// Each pixel's ray and hit, row by row, as last traced.
    pub(super) fn hits(&self) -> impl Iterator<Item = (&Ray64, &Hit)> {
        self.rays.iter().zip(&self.hits)
    }

    /// Pixel (x, y)'s ray, hit, weight and sampler, of `grid` as last
    /// traced; None for a pixel left untraced.
    pub(super) fn get(
        &mut self,
        grid: Region,
        (x, y): (usize, usize),
    ) -> Option<(&Ray64, Hit, f32, &mut Sampler)> {
        let i = (y - grid.y0) * grid.width() + (x - grid.x0);
        let (weight, sampler) = self.samples[i].as_mut()?;
        Some((&self.rays[i], self.hits[i], *weight, sampler))
    }
}
