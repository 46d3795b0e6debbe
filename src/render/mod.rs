//! Rendering: the tile loop over rayon, camera sampling, and statistics.

mod batch;
pub mod job;
mod lit;
use lit::{LightProofs, Lit};
pub mod merge;
pub mod order;
mod passes;
mod path;
pub mod photon;
mod plan;
mod tally;
mod whitted;

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::Instant;

use rayon::prelude::*;

pub use path::PathTracer;
pub use photon::PhotonMap;
pub use plan::Plan;
pub use tally::{Node, RayKind, RayStats, Tally};
pub use whitted::Whitted;

use batch::TileCameras;

use crate::accel::ftz::enable_flush_to_zero;
use crate::accel::{Accel, ListBeams, ShapeSet};
use crate::error::{Error, Result};
use crate::film::{Film, Pixel, Pixels, Region, Sample};
use crate::math::{Hit, Ray, Ray64};
use crate::sampling::{FilterSampler, Sampler};
use crate::scene::{CameraFrame, Integrator, PhotonSettings, Scene};

/// How to run a render; the scene says what to render.
#[derive(Clone, Debug, Default)]
pub struct RenderOptions {
    /// Worker threads; `None` uses every core.
    pub threads: Option<usize>,
    /// Overrides the scene's samples per pixel.
    pub spp: Option<u32>,
    /// Shows a progress bar (with rays/s) on a terminal.
    pub progress: bool,
    /// Turns every effect on, whatever the scene calls for (to measure what the plan saves).
    pub all_effects: bool,
    /// Renders only this part of the image (a tile or crop); `None` renders it all.
    pub region: Option<Region>,
    /// Checked before every sample: once set, the render drops the pass under
    /// way (the first, one sample a pixel, only if it has not ended a second
    /// later) and returns the passes it finished.
    pub interrupt: Option<Arc<AtomicBool>>,
}

pub struct RenderOutput {
    pub film: Film,
    pub stats: RayStats,
    pub seconds: f64,
    /// Sample indices 0..samples_done were taken (or, with adaptive sampling,
    /// decided on) for every pixel; less than the target if interrupted.
    pub samples_done: u32,
    /// Whether every pass ran.
    pub complete: bool,
    /// Samples whose radiance was NaN or infinite, counted as black.
    pub nonfinite: u64,
}

/// How long the first pass may go on after an interrupt (see `render`).
const FIRST_PASS_GRACE: std::time::Duration = std::time::Duration::from_secs(1);

/// Tiles are squares of this many pixels a side: small enough to balance two
/// to many threads, large enough that scheduling costs nothing.
const TILE: usize = 16;

/// The tiles of the image's grid (squares of `TILE` from its corner) that
/// meet the region, each cut to the region, row by row of tiles. On the
/// image's grid, not the region's: a tile's camera rays are traced as one
/// stream of the whole grid tile's (`TileCameras`), whatever the region.
fn tiles_of(region: Region) -> Vec<Region> {
    let starts = |from: usize, to: usize| (from / TILE * TILE..to).step_by(TILE);
    starts(region.y0, region.y1)
        .flat_map(|y| {
            starts(region.x0, region.x1).map(move |x| Region {
                x0: x.max(region.x0),
                y0: y.max(region.y0),
                x1: (x + TILE).min(region.x1),
                y1: (y + TILE).min(region.y1),
            })
        })
        .collect()
}

/// The shapes each pixel of `tile` (row by row, `TILE` to a row) may be
/// hit on by its camera rays, whose image positions lie within `reach` of
/// the pixels' centres: what `beams` proves of the whole tile, then of
/// each quarter, for the shapes the tile may hit.
///
/// A shape that the ray through a quarter's middle pixel hits (`probe`:
/// the shape a pixel's camera ray hits first, if any) cannot be proven
/// missed there, nor over the tile, so no proof is tried for it: the same
/// sets, for a ray a quarter. Where a shape covers the tile, the five
/// failed proofs had cost a tile of tcubic.pov some 76,000 instructions
/// each (`valgrind --tool=callgrind`).
fn tile_sets(
    beams: &ListBeams<'_>,
    tile: Region,
    reach: f64,
    mut probe: impl FnMut((usize, usize)) -> Option<usize>,
) -> [ShapeSet; TILE * TILE] {
    let span = |from: usize, to: usize| (from as f64 + 0.5 - reach, to as f64 - 0.5 + reach);
    let rect = |r: &Region| (span(r.x0, r.x1), span(r.y0, r.y1));
    let (xm, ym) = ((tile.x0 + tile.x1) / 2, (tile.y0 + tile.y1) / 2);
    let quarters = [(tile.x0, xm), (xm, tile.x1)]
        .into_iter()
        .flat_map(|(x0, x1)| {
            [(tile.y0, ym), (ym, tile.y1)].map(|(y0, y1)| Region { x0, y0, x1, y1 })
        })
        .filter(|q| q.area() > 0)
        .map(|q| {
            let seen = probe(((q.x0 + q.x1) / 2, (q.y0 + q.y1) / 2));
            (q, seen.map_or(ShapeSet::NONE, ShapeSet::only))
        });
    let quarters: Vec<_> = quarters.collect();
    let seen = (quarters.iter()).fold(ShapeSet::NONE, |all, &(_, seen)| all.with(seen));
    let (xs, ys) = rect(&tile);
    let whole = beams.may_hit(xs, ys, ShapeSet::ALL.minus(seen)).with(seen);
    let mut sets = [whole; TILE * TILE];
    for (quarter, seen) in quarters {
        let (xs, ys) = rect(&quarter);
        let set = beams.may_hit(xs, ys, whole.minus(seen)).with(seen);
        // Then each pixel's own, of the shapes whose box it sees.
        for y in quarter.y0..quarter.y1 {
            let row = (y - tile.y0) * TILE;
            for x in quarter.x0..quarter.x1 {
                sets[row + x - tile.x0] = beams.in_sight(span(x, x + 1), span(y, y + 1), set);
            }
        }
    }
    sets
}

/// The whole tile of the grid of a width × height image that holds `tile`.
fn grid_tile(tile: Region, width: usize, height: usize) -> Region {
    let (x0, y0) = (tile.x0 / TILE * TILE, tile.y0 / TILE * TILE);
    Region {
        x0,
        y0,
        x1: (x0 + TILE).min(width),
        y1: (y0 + TILE).min(height),
    }
}

/// Each tile (of `tiles_of(region)`) as its rows of `pixels` (the region's,
/// row by row): disjoint slices a worker can write while the others write
/// theirs.
fn tile_rows<'a>(
    pixels: &'a mut [Pixel],
    region: Region,
    tiles: &[Region],
) -> Vec<Vec<&'a mut [Pixel]>> {
    let mut rows: Vec<Vec<&mut [Pixel]>> = tiles
        .iter()
        .map(|t| Vec::with_capacity(t.height()))
        .collect();
    // Tiles per row of tiles; a row's pieces end where the grid's columns do.
    let across = (region.x1 - 1) / TILE - region.x0 / TILE + 1;
    for (y, mut row) in (region.y0..).zip(pixels.chunks_mut(region.width())) {
        let first = (y / TILE - region.y0 / TILE) * across;
        let mut x = region.x0;
        for tile in &mut rows[first..] {
            let end = ((x / TILE + 1) * TILE).min(region.x1);
            let (piece, rest) = row.split_at_mut(end - x);
            tile.push(piece);
            (row, x) = (rest, end);
            if row.is_empty() {
                break;
            }
        }
    }
    rows
}

/// A rayon pool whose threads all run with FTZ/DAZ, as Embree asks.
pub fn thread_pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .start_handler(|_| enable_flush_to_zero())
        .build()
        .map_err(|e| Error::Internal(format!("cannot start worker threads: {e}")))
}

pub fn render(scene: &Scene, accel: &Accel, options: &RenderOptions) -> Result<RenderOutput> {
    render_from(scene, accel, options, None)
}

/// `render`, continuing from a film state when `resume` holds one (the film
/// and its samples done): its samples are kept, the render takes the rest.
/// It must hold `region` and `samples_done` full passes. The film is taken,
/// not copied, so the render holds at most two buffers of sums
/// (`film::RENDER_BYTES_PER_PIXEL`).
pub fn render_from(
    scene: &Scene,
    accel: &Accel,
    options: &RenderOptions,
    resume: Option<(Film, u32)>,
) -> Result<RenderOutput> {
    let start = Instant::now();
    let (width, height) = (scene.camera.width as usize, scene.camera.height as usize);
    let spp = options.spp.unwrap_or(scene.render.spp);
    if spp == 0 {
        return Err(Error::Input("--spp must be at least 1".into()));
    }
    let region = options.region.unwrap_or(Region::whole(width, height));
    if !region.fits(width, height) {
        return Err(Error::Input(format!(
            "the region [{}, {}) x [{}, {}) is empty or outside the {width}x{height} image",
            region.x0, region.x1, region.y0, region.y1
        )));
    }
    let frame = scene.camera.frame();
    let filter = scene.render.filter.sampler()?;
    let adaptive = scene.render.adaptive.as_ref();
    if adaptive.is_some_and(|a| spp < 2 || a.max_spp < spp) {
        return Err(Error::Input(format!(
            "--spp {spp}: adaptive sampling needs at least 2 samples per round, \
             and no more than the scene's max_spp"
        )));
    }
    // A fresh render has no film until its first pass ends: that pass
    // starts every pixel from `Pixel::default()` and writes the film whole.
    let (mut film, from) = match resume {
        Some((film, done)) => (Some(film), done),
        None => (None, 0),
    };
    if let Some(film) = &film
        && (film.width, film.height, film.region) != (width, height, region)
    {
        return Err(Error::Input(
            "the film state to resume holds another image size or region".into(),
        ));
    }
    let plan = plan(scene, options.all_effects);
    let pool = thread_pool(options.threads)?;
    // Checked for every sample and photon chunk, so an interrupt is honoured
    // within moments whatever the pass size.
    let stop = || {
        options
            .interrupt
            .as_ref()
            .is_some_and(|i| i.load(Ordering::Relaxed))
    };
    // The first pass (one sample a pixel) may run on for a second after the
    // signal, so a render stopped early still keeps some work; later passes,
    // and a first one that takes longer, stop at once.
    // A panic caught in a query stops every worker at its next sample (no
    // grace: the render has failed), and the check after the pass reports it.
    let noticed = std::sync::OnceLock::new();
    let cut = |first: bool| {
        accel.panicked()
            || stop() && (!first || noticed.get_or_init(Instant::now).elapsed() > FIRST_PASS_GRACE)
    };
    let photons_stop = || stop() || accel.panicked();
    let (caustics, photon_rays) =
        pool.install(|| photon_pass(scene, accel, &plan, options.progress, &photons_stop))?;
    accel.check()?;
    // An interrupted photon pass leaves no map: no pass can run without it.
    let photons_cut = plan.photon && caustics.is_none();
    let integrator = Tracer::new(scene, accel, plan, caustics.as_ref());
    let light_proofs = integrator.light_proofs();
    let tiles = tiles_of(region);
    // Rectangles of camera rays proven to miss a shape skip it (see
    // `ListBeams`); a sample lies within the filter's radius of its
    // pixel's centre, its f32 position a rounding or so further.
    let beams = frame.pinhole().and_then(|p| accel.camera_beams(&p));
    let reach = match spp {
        1 => 0.0,
        _ => f64::from(scene.render.filter.radius()) + 0.01,
    };
    // Each tile's sets, proven in the first pass that reaches the tile and
    // kept for the passes after it.
    let shapes_geom_id = scene.shapes_geom_id();
    let tile_proofs: Vec<OnceLock<[ShapeSet; TILE * TILE]>> =
        tiles.iter().map(|_| OnceLock::new()).collect();
    // A pixel whose centre ray the sets offer no shape (each proven missed
    // or its box unseen) misses, and where every miss gives one sample,
    // the pixel takes it untraced. Over the background of POV-Ray's
    // quartic samples a camera ray had cost some 800 instructions
    // (`valgrind --tool=callgrind`).
    let untraced = (spp == 1 && beams.is_some())
        .then(|| integrator.constant_miss(&frame))
        .flatten();
    let blank = untraced.is_some();
    // In a pass that starts every pixel afresh (no film before it), such a
    // pixel is one value, added up once.
    let untraced_pixel = untraced.map(|sample| {
        let mut pixel = Pixel::default();
        let bad = passes::add(&mut pixel, sample);
        (pixel, bad)
    });

    let passes = passes::passes(spp, adaptive, from);
    let total = passes
        .iter()
        .map(|r| u64::from(r.end - r.start))
        .sum::<u64>();
    let progress = progress_bar(options.progress, total * region.area() as u64);
    let rays_done = AtomicU64::new(photon_rays.total());
    let mut stats = photon_rays;
    let (mut samples_done, mut nonfinite) = (from, 0);
    // Each pass writes its pixels in place into a second buffer, read from
    // the film, and the two swap when the pass ends: a pass an interrupt
    // cuts short is then dropped whole without a copy, and no pass gathers
    // tiles to copy them over one by one. Copying 50 MB of 800x600 pixels
    // on one thread, and filling a fresh film with defaults before, were
    // 15% of the render time of POV-Ray's torus.pov at 1 spp on 2 threads.
    let mut spare: Option<Pixels> = None;
    for range in passes {
        // A pass an interrupt cuts short is dropped whole: the film keeps
        // only complete passes, which is what its state can describe.
        if stop() && (!passes::is_first(&range) || photons_cut) {
            break;
        }
        let first = passes::is_first(&range);
        // Zero bytes the kernel maps on first write, from every thread at
        // once (see `Pixels`); each pixel is overwritten before anything
        // reads it.
        let mut next = spare
            .take()
            .unwrap_or_else(|| Pixels::zeroed(region.area()));
        let rows = tile_rows(&mut next, region, &tiles);
        let prev = film.as_ref();
        let results: Option<Vec<(RayStats, u64)>> = pool.install(|| {
            tiles
                .par_iter()
                .zip(rows)
                .zip(&tile_proofs)
                // At most four tiles a piece rayon may hand to an idle
                // thread. Its adaptive splitting (a piece is cut again only
                // when another thread steals it) had given each thread half
                // the tiles in pieces it ran one after the other, and where
                // the image's work sits in one half (POV-Ray's bicube.pov)
                // one thread idled for a third of the pass. Pieces of one
                // tile balanced as well but cost glass_torus.toml and
                // metals.toml 3-4% more time than pieces of four. Each
                // tile's pixels and its place in the results are its own
                // whichever thread takes it.
                .with_max_len(4)
                .map(|((tile, mut rows), proofs)| {
                    let mut tally = Tally::default();
                    let mut bad = 0;
                    for (y, row) in (tile.y0..tile.y1).zip(rows.iter_mut()) {
                        for (x, out) in (tile.x0..tile.x1).zip(row.iter_mut()) {
                            *out = prev.map_or_else(Pixel::default, |f| *f.pixel(x, y));
                        }
                    }
                    let camera = |at, k| camera_ray(scene, &frame, &filter, at, k, spp);
                    // Sample a pixel's next sample, from its camera ray's
                    // hit, or as `untraced` where it was left untraced.
                    let mut sample = |pixel: &mut Pixel,
                                      traced: Option<(&Ray64, Hit, f32, &mut Sampler)>,
                                      lit| {
                        if cut(first) {
                            return None;
                        }
                        let sample = match traced {
                            Some((ray, hit, weight, sampler)) => Sample {
                                weight,
                                ..integrator.sample(ray, hit, sampler, &mut tally, lit)
                            },
                            // Left untraced only where `untraced` is known.
                            None => {
                                tally.count(RayKind::Camera, 0);
                                if let (None, Some((fresh, fresh_bad))) = (prev, untraced_pixel) {
                                    (*pixel, bad) = (fresh, bad + fresh_bad);
                                    return Some(());
                                }
                                untraced?
                            }
                        };
                        bad += passes::add(pixel, sample);
                        Some(())
                    };
                    if accel.streams() && passes::every_pixel_takes(&range, spp, adaptive) {
                        // Sample k of the whole grid tile as one stream,
                        // its hits the same whatever the region or pass.
                        let grid = grid_tile(*tile, width, height);
                        let mut cameras = TileCameras::new();
                        for k in range.clone() {
                            cameras.trace(accel, grid, |at| camera(at, k));
                            for (y, row) in (tile.y0..tile.y1).zip(rows.iter_mut()) {
                                for (x, pixel) in (tile.x0..tile.x1).zip(row.iter_mut()) {
                                    sample(pixel, cameras.get(grid, (x, y)), Lit::NONE)?;
                                }
                            }
                        }
                    } else {
                        // Backends without streams, each ray offered the
                        // shapes its rectangle may hit.
                        // The probes' hits are their pixels' sample 0 (the
                        // sets offer those pixels every shape that may be
                        // hit, so the nearest is the same): kept, not traced
                        // twice, where the tile's sets are proven now.
                        let mut probed = [None; 4];
                        let mut probe = |at| {
                            let hit = accel.intersect_exact_among(&camera(at, 0).0, ShapeSet::ALL);
                            if let Some(slot) = probed.iter_mut().find(|p| p.is_none()) {
                                *slot = Some((at, hit));
                            }
                            (hit.is_hit() && hit.geom_id == shapes_geom_id)
                                .then_some(hit.prim_id as usize)
                        };
                        let sets = (beams.as_ref())
                            .map(|b| proofs.get_or_init(|| tile_sets(b, *tile, reach, &mut probe)));
                        let known = |at, k| {
                            let probed = probed.iter().flatten().filter(|_| k == 0);
                            probed
                                .into_iter()
                                .find(|(p, _)| *p == at)
                                .map(|(_, hit)| *hit)
                        };
                        let among = |(x, y): (usize, usize)| {
                            sets.as_ref()
                                .map_or(ShapeSet::ALL, |s| s[(y - tile.y0) * TILE + x - tile.x0])
                        };
                        match &light_proofs {
                            Some(light_proofs)
                                if passes::every_pixel_takes(&range, spp, adaptive) =>
                            {
                                // Sample k of the whole tile traced first,
                                // for the proofs that spare its shadow rays.
                                let (mut cameras, mut lit) = (TileCameras::new(), Vec::new());
                                for k in range.clone() {
                                    let camera = |at| camera(at, k);
                                    let hit = |at, ray: &Ray64, set| {
                                        known(at, k).unwrap_or_else(|| {
                                            accel.intersect_exact_among(ray, set)
                                        })
                                    };
                                    cameras.trace_among(*tile, camera, among, hit, blank);
                                    light_proofs.prove(&cameras, *tile, &mut lit);
                                    let pixels = (tile.y0..tile.y1).zip(rows.iter_mut()).flat_map(
                                        |(y, row)| {
                                            (tile.x0..tile.x1)
                                                .zip(row.iter_mut())
                                                .map(move |(x, p)| ((x, y), p))
                                        },
                                    );
                                    for ((at, pixel), lit) in pixels.zip(&lit) {
                                        sample(pixel, cameras.get(*tile, at), *lit)?;
                                    }
                                }
                            }
                            // Adaptive rounds (the pixels that take them):
                            // one ray at a time.
                            _ => {
                                for (y, row) in (tile.y0..tile.y1).zip(rows.iter_mut()) {
                                    for (x, pixel) in (tile.x0..tile.x1).zip(row.iter_mut()) {
                                        if !passes::takes(pixel, &range, spp, adaptive) {
                                            continue;
                                        }
                                        for k in range.clone() {
                                            let set = among((x, y));
                                            if blank && set == ShapeSet::NONE {
                                                sample(pixel, None, Lit::NONE)?;
                                                continue;
                                            }
                                            let (ray, weight, mut sampler) = camera((x, y), k);
                                            let hit = known((x, y), k).unwrap_or_else(|| {
                                                accel.intersect_exact_among(&ray, set)
                                            });
                                            let traced = (&ray, hit, weight, &mut sampler);
                                            sample(pixel, Some(traced), Lit::NONE)?;
                                        }
                                    }
                                }
                            }
                        }
                    }
                    let stats = tally.totals();
                    let done =
                        rays_done.fetch_add(stats.total(), Ordering::Relaxed) + stats.total();
                    if let Some(bar) = &progress {
                        bar.inc(tile.area() as u64 * u64::from(range.end - range.start));
                        let mrays = done as f64 / start.elapsed().as_secs_f64() / 1e6;
                        bar.set_message(format!("{mrays:.2} Mrays/s"));
                    }
                    Some((stats, bad))
                })
                .collect()
        });
        accel.check()?;
        let Some(results) = results else {
            break;
        };
        for (tile_stats, bad) in results {
            stats += tile_stats;
            nonfinite += bad;
        }
        let done = Film {
            width,
            height,
            region,
            pixels: next,
        };
        spare = film.replace(done).map(|f| f.pixels);
        samples_done = range.end;
    }
    let film = film.unwrap_or_else(|| Film::of_region(width, height, region));
    if let Some(bar) = progress {
        bar.finish_and_clear();
    }
    let target = passes::target(spp, adaptive);
    Ok(RenderOutput {
        film,
        stats,
        seconds: start.elapsed().as_secs_f64(),
        samples_done,
        complete: samples_done == target,
        nonfinite,
    })
}

/// The caustic photon map when the plan calls for it, and the photon rays it
/// took; run on the render's pool. With `report`, says on stderr what it built.
/// Once `stop` says so, the map is left unfinished (`None`).
fn photon_pass(
    scene: &Scene,
    accel: &Accel,
    plan: &Plan,
    report: bool,
    stop: &(dyn Fn() -> bool + Sync),
) -> Result<(Option<PhotonMap>, RayStats)> {
    if !plan.photon {
        return Ok((None, RayStats::default()));
    }
    let start = Instant::now();
    let settings = scene.render.photons;
    // The count may come from --photons as well as the scene.
    PhotonSettings::check_count(settings.count)
        .map_err(|e| Error::Input(format!("photons (--photons or render.photons.count): {e}")))?;
    let Some((map, counts)) = PhotonMap::build(
        scene,
        accel,
        settings.count,
        settings.radius,
        plan.max_depth,
        stop,
    ) else {
        return Ok((None, RayStats::default()));
    };
    if report {
        crate::io::console::note(format_args!(
            "photon map: {} of {} photons stored, radius {:.3e} ({}), {:.2} s",
            counts.stored,
            counts.emitted,
            map.radius().value,
            map.radius().from,
            start.elapsed().as_secs_f64()
        ));
    }
    Ok((Some(map), counts.rays))
}

/// The integrator the scene asks for.
enum Tracer<'a> {
    Whitted(Whitted<'a>),
    Path(PathTracer<'a>),
}

impl<'a> Tracer<'a> {
    fn new(
        scene: &'a Scene,
        accel: &'a Accel,
        plan: Plan,
        caustics: Option<&'a PhotonMap>,
    ) -> Tracer<'a> {
        match scene.render.integrator {
            Integrator::Whitted => Tracer::Whitted(Whitted {
                scene,
                accel,
                plan,
                caustics,
            }),
            Integrator::Path => Tracer::Path(PathTracer {
                scene,
                accel,
                plan,
                caustics,
            }),
        }
    }

    /// The proofs that spare shadow rays (`lit`), for the Whitted tracer
    /// where no surface filters shadows: the path tracer's shadow rays
    /// start at sampled points, not at the camera's hits alone.
    fn light_proofs(&self) -> Option<LightProofs<'a>> {
        match self {
            Tracer::Whitted(w) if w.plan.shadow => LightProofs::new(w.scene, w.accel),
            _ => None,
        }
    }

    /// The sample of a camera ray through a pixel's centre (weight 1) that
    /// meets nothing, where that is one sample whatever the ray: without an
    /// environment or fog, a ray that leaves the scene brings back the
    /// background and draws no number. Pixels whose ray is known to meet
    /// no box take it untraced (`render_from`). None elsewhere.
    fn constant_miss(&self, frame: &CameraFrame) -> Option<Sample> {
        let (scene, plan) = match self {
            Tracer::Whitted(w) => (w.scene, &w.plan),
            Tracer::Path(p) => (p.scene, &p.plan),
        };
        if plan.fog || scene.environment.is_some() {
            return None;
        }
        let mut sampler = Sampler::new(scene.render.sampler, scene.render.seed, 0, 0);
        let ray = frame.ray64(0.5, 0.5);
        let mut tally = Tally::default();
        Some(self.sample(&ray, Hit::MISS, &mut sampler, &mut tally, Lit::NONE))
    }

    /// A camera sample's radiance as linear light: the integrators work in
    /// the scene's colour space (`WorkingGamma`), decoded here.
    /// `lit` is `Lit::NONE` but for the Whitted tracer (`light_proofs`).
    fn sample(
        &self,
        camera: &Ray64,
        hit: Hit,
        sampler: &mut Sampler,
        tally: &mut Tally,
        lit: Lit,
    ) -> Sample {
        let (mut sample, scene) = match self {
            Tracer::Whitted(w) => (w.sample(camera, hit, sampler, tally, lit), w.scene),
            Tracer::Path(p) => (p.sample(camera, hit, sampler, tally), p.scene),
        };
        sample.radiance = scene.render.working_gamma.to_linear(sample.radiance);
        sample
    }
}

fn plan(scene: &Scene, all_effects: bool) -> Plan {
    if all_effects {
        Plan::everything(scene.render.max_depth)
    } else {
        Plan::for_scene(scene)
    }
}

/// Camera ray `k` through pixel (x, y), with its filter weight and the
/// sample's sampler (which the integrator goes on drawing from): through the
/// pixel's centre when the pixel takes one sample; otherwise at the
/// sampler's pixel position (stratified over each round of `spp` samples),
/// warped by the reconstruction filter (filter importance sampling); from
/// the sampler's lens point when the camera has a lens. Keyed
/// by (seed, pixel, k), so it is the same whoever renders it. In f64: the
/// integrators trace it with `Accel::intersect_exact`.
fn camera_ray(
    scene: &Scene,
    frame: &CameraFrame,
    filter: &FilterSampler,
    (x, y): (usize, usize),
    k: u32,
    spp: u32,
) -> (Ray64, f32, Sampler) {
    let centre = (x as f32 + 0.5, y as f32 + 0.5);
    let index = (y * scene.camera.width as usize + x) as u64;
    let mut sampler = Sampler::new(scene.render.sampler, scene.render.seed, index, k);
    let (x, y, weight) = if spp == 1 {
        (centre.0, centre.1, 1.0)
    } else {
        let s = filter.sample(sampler.pixel_2d(spp));
        (centre.0 + s.offset[0], centre.1 + s.offset[1], s.weight)
    };
    // The lens point is the pair after the pixel's (drawn only by a lens, so
    // a pinhole's dimensions are what they were): stratified with the
    // Sobol sampler as the pixel position is.
    let ray = if frame.has_lens() {
        frame.lens_ray64(x, y, sampler.get_2d())
    } else {
        frame.ray64(x, y)
    };
    (ray, weight, sampler)
}

/// The camera ray and the ray tree of one pixel sample, for `sturmray explain`.
pub fn explain(
    scene: &Scene,
    accel: &Accel,
    pixel: (usize, usize),
    sample: u32,
    all_effects: bool,
) -> Result<(Sample, Ray, Vec<Node>)> {
    let (w, h) = (scene.camera.width as usize, scene.camera.height as usize);
    if pixel.0 >= w || pixel.1 >= h {
        return Err(Error::Input(format!(
            "--pixel {},{} is outside the {w}x{h} image",
            pixel.0, pixel.1
        )));
    }
    let most = scene
        .render
        .adaptive
        .as_ref()
        .map_or(scene.render.spp, |a| a.max_spp);
    if sample >= most {
        return Err(Error::Input(format!(
            "--sample {sample}: the scene takes at most {most} samples per pixel (0 to {})",
            most - 1
        )));
    }
    let plan = plan(scene, all_effects);
    let (caustics, _) =
        thread_pool(None)?.install(|| photon_pass(scene, accel, &plan, false, &|| false))?;
    let integrator = Tracer::new(scene, accel, plan, caustics.as_ref());
    let filter = scene.render.filter.sampler()?;
    let frame = scene.camera.frame();
    let spp = scene.render.spp;
    let camera = |at| camera_ray(scene, &frame, &filter, at, sample, spp);
    let mut tally = Tally {
        tree: Some(Vec::new()),
        ..Tally::default()
    };
    // The camera ray's hit as the render finds it (see `batch`).
    let adaptive = scene.render.adaptive.as_ref();
    let mut cameras = TileCameras::new();
    let streamed = (accel.streams()
        && passes::every_pixel_takes(&(sample..sample + 1), spp, adaptive))
    .then(|| {
        let at = Region {
            x0: pixel.0,
            y0: pixel.1,
            x1: pixel.0 + 1,
            y1: pixel.1 + 1,
        };
        let grid = grid_tile(at, w, h);
        cameras.trace(accel, grid, camera);
        let (ray, hit, weight, sampler) = cameras.get(grid, pixel)?;
        Some((*ray, hit, weight, sampler.clone()))
    });
    let (ray, hit, weight, mut sampler) = streamed.flatten().unwrap_or_else(|| {
        let (ray, weight, sampler) = camera(pixel);
        (ray, accel.intersect_exact(&ray), weight, sampler)
    });
    let mut result = integrator.sample(&ray, hit, &mut sampler, &mut tally, Lit::NONE);
    result.weight = weight;
    accel.check()?;
    Ok((result, ray.rounded(), tally.tree.unwrap_or_default()))
}

/// A progress bar on stderr when it is a terminal; none otherwise.
fn progress_bar(wanted: bool, pixels: u64) -> Option<indicatif::ProgressBar> {
    use std::io::IsTerminal;
    if !wanted || !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = indicatif::ProgressBar::new(pixels);
    let style = indicatif::ProgressStyle::with_template(
        "{spinner} [{elapsed_precise}] {wide_bar} {percent:>3}% eta {eta} {msg}",
    )
    .ok()?;
    bar.set_style(style);
    Some(bar)
}

/// Rays one parallel task traces: enough that scheduling costs nothing.
const TRACE_CHUNK: usize = 4096;

/// Traces every ray to its nearest hit, in parallel chunks through the batch
/// path, in coherent order (`order`); the hits come back in the rays' order.
pub fn trace_all(accel: &Accel, rays: &[Ray], threads: Option<usize>) -> Result<Vec<Hit>> {
    crate::accel::check_rays(rays)?;
    thread_pool(threads)?
        .install(|| in_coherent_order(rays, Hit::MISS, |rays, hits| trace_batch(accel, rays, hits)))
}

/// Whether anything blocks each ray, as `trace_all` traces.
pub fn occluded_all(accel: &Accel, rays: &[Ray], threads: Option<usize>) -> Result<Vec<bool>> {
    crate::accel::check_rays(rays)?;
    thread_pool(threads)?.install(|| {
        in_coherent_order(rays, false, |rays, blocked| {
            occluded_batch(accel, rays, blocked)
        })
    })
}

/// One result per ray from `trace`, which is given the rays in their
/// coherent order; the results come back in the caller's order.
fn in_coherent_order<T: Copy + Send + Sync>(
    rays: &[Ray],
    empty: T,
    trace: impl FnOnce(&[Ray], &mut [T]) -> Result<()>,
) -> Result<Vec<T>> {
    let order = order::CoherentOrder::new(rays);
    let mut sorted = vec![empty; rays.len()];
    trace(&order.gather(rays), &mut sorted)?;
    let mut results = vec![empty; rays.len()];
    order.scatter(&sorted, &mut results);
    Ok(results)
}

/// Nearest hits on the current rayon pool, into `hits`. The rays are
/// checked by the caller (`accel::check_rays`), once for all batches.
pub fn trace_batch(accel: &Accel, rays: &[Ray], hits: &mut [Hit]) -> Result<()> {
    rays.par_chunks(TRACE_CHUNK)
        .zip(hits.par_chunks_mut(TRACE_CHUNK))
        .try_for_each(|(rays, hits)| accel.intersect_batch(rays, hits, false))
}

/// Whether anything blocks each ray, on the current rayon pool, into `blocked`.
pub fn occluded_batch(accel: &Accel, rays: &[Ray], blocked: &mut [bool]) -> Result<()> {
    rays.par_chunks(TRACE_CHUNK)
        .zip(blocked.par_chunks_mut(TRACE_CHUNK))
        .for_each(|(rays, blocked)| {
            for (b, ray) in blocked.iter_mut().zip(rays) {
                *b = accel.occluded(ray);
            }
        });
    accel.check()
}

/// Every hit of many rays: ray i's are `hits[offsets[i]..offsets[i + 1]]`,
/// nearest first (see `Accel::intersect_all`).
#[derive(Clone, Debug, PartialEq)]
pub struct AllHits {
    pub hits: Vec<Hit>,
    pub offsets: Vec<u64>,
}

impl Default for AllHits {
    fn default() -> AllHits {
        AllHits {
            hits: Vec::new(),
            offsets: vec![0],
        }
    }
}

/// Every hit of each ray (the nearest `max_hits` if given), appended to
/// `all`, on the current rayon pool; the rays are checked by the caller.
pub fn all_hits_batch(
    accel: &Accel,
    rays: &[Ray],
    max_hits: Option<usize>,
    all: &mut AllHits,
) -> Result<()> {
    let parts: Vec<(Vec<Hit>, Vec<u64>)> = rays
        .par_chunks(TRACE_CHUNK)
        .map(|rays| {
            let (mut hits, mut counts) = (Vec::new(), Vec::with_capacity(rays.len()));
            for ray in rays {
                let first = hits.len();
                accel.intersect_all(ray, &mut hits);
                hits.truncate(first + max_hits.unwrap_or(usize::MAX).min(hits.len() - first));
                counts.push((hits.len() - first) as u64);
            }
            (hits, counts)
        })
        .collect();
    accel.check()?;
    for (hits, counts) in parts {
        for count in counts {
            let last = all.offsets.last().copied().unwrap_or(0);
            all.offsets.push(last + count);
        }
        all.hits.extend(hits);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::Backend;
    use crate::scene::LoadOptions;

    /// The probes only spare proofs that would fail: each tile's sets are
    /// those proven without them. A torus (a Bernstein proof) and a ball
    /// (a discriminant), each covering some tiles, missed by others.
    #[test]
    fn probed_tile_sets_are_the_sets_proven_without_probes() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("probe.pov");
        let text = "camera { location <0.3, 1.2, -10> look_at <0, 0, 0> angle 40 }\n\
             light_source { <20, 30, -40> color rgb 1 }\n\
             torus { 2, 0.6 rotate 60*x pigment { rgb 1 } }\n\
             sphere { <2.5, -1, 1>, 1 pigment { rgb 1 } }\n";
        std::fs::write(&path, text).unwrap();
        let options = LoadOptions {
            size: Some((96, 72)),
            ..LoadOptions::default()
        };
        let scene = Scene::load_with(&path, &options).unwrap();
        let accel = Accel::build(&scene, Backend::Embree, Some(1)).unwrap();
        let frame = scene.camera.frame();
        let beams = frame
            .pinhole()
            .and_then(|p| accel.camera_beams(&p))
            .expect("a list scene under a pinhole");
        let filter = scene.render.filter.sampler().unwrap();
        let probe = |at| {
            let ray = camera_ray(&scene, &frame, &filter, at, 0, 1).0;
            let hit = accel.intersect_exact_among(&ray, ShapeSet::ALL);
            (hit.is_hit() && hit.geom_id == scene.shapes_geom_id()).then_some(hit.prim_id as usize)
        };
        let (mut hit, mut proven) = (std::cell::Cell::new(0), 0);
        let counted = |at| {
            let shape = probe(at);
            hit.set(hit.get() + usize::from(shape.is_some()));
            shape
        };
        for tile in tiles_of(Region::whole(96, 72)) {
            let blind = tile_sets(&beams, tile, 0.0, |_| None);
            assert_eq!(tile_sets(&beams, tile, 0.0, counted), blind, "{tile:?}");
            proven += usize::from(blind.iter().any(|s| *s != beams.listed()));
        }
        // Probes met the shapes, and proofs held elsewhere.
        assert!(*hit.get_mut() > 0 && proven > 0);
    }

    /// A missed camera ray's sample is one whatever the ray and its
    /// sampler, with either integrator and in a scene's working gamma,
    /// where `constant_miss` says so; with fog or an environment, it says
    /// nothing.
    #[test]
    fn a_constant_miss_is_every_missed_camera_ray_s_sample() {
        let dir = tempfile::tempdir().unwrap();
        let pov = |name: &str, extra: &str| {
            let text = format!(
                "global_settings {{ assumed_gamma 2.2 }}
                 camera {{ location <0, 0, -10> look_at <0, 0, 0> angle 40 }}
                 light_source {{ <20, 30, -40> color rgb 1 }}
                 background {{ color rgb <0.2, 0.4, 0.7> }}
                 sphere {{ 0, 1 pigment {{ rgb 1 }} }}
{extra}"
            );
            let path = dir.path().join(name);
            std::fs::write(&path, text).unwrap();
            Scene::load(&path).unwrap()
        };
        let toml = |name: &str, sky: &str| {
            let text = format!(
                r#"{sky}
[camera]
eye = [0, 0, -5]
look_at = [0, 0, 0]
fov = 60
width = 8
height = 8
[render]
integrator = "path"
[materials.grey]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]
[[objects]]
type = "sphere"
radius = 1
material = "grey"
"#
            );
            let path = dir.path().join(name);
            std::fs::write(&path, text).unwrap();
            Scene::load(&path).unwrap()
        };
        let scenes = [
            (pov("plain.pov", ""), true),
            (pov("fog.pov", "fog { distance 20 color rgb 0.5 }"), false),
            (toml("plain.toml", "background = [0.3, 0.2, 0.1]"), true),
            (
                toml("sky.toml", "[environment]\nradiance = [1, 1, 1]"),
                false,
            ),
        ];
        for (i, (scene, constant)) in scenes.iter().enumerate() {
            let accel = Accel::build(scene, Backend::Embree, Some(1)).unwrap();
            let tracer = Tracer::new(scene, &accel, Plan::for_scene(scene), None);
            let (frame, filter) = (scene.camera.frame(), scene.render.filter.sampler().unwrap());
            let Some(miss) = tracer.constant_miss(&frame) else {
                assert!(!constant, "scene {i}: no constant miss");
                continue;
            };
            assert!(
                *constant,
                "scene {i}: a constant miss where rays see fog or a sky"
            );
            assert!(
                miss.radiance.max_element() > 0.0,
                "scene {i}: a black background"
            );
            let (w, h) = (scene.camera.width, scene.camera.height);
            for (x, y) in [(0, 0), (w - 1, 0), (3, h - 1), (w / 2, 1)] {
                let pixel = (x as usize, y as usize);
                let (ray, weight, mut sampler) = camera_ray(scene, &frame, &filter, pixel, 0, 1);
                let hit = accel.intersect_exact(&ray);
                assert!(!hit.is_hit(), "scene {i}: pixel {pixel:?} meets the sphere");
                let mut tally = Tally::default();
                let sample = tracer.sample(&ray, hit, &mut sampler, &mut tally, Lit::NONE);
                assert_eq!(
                    Sample { weight, ..sample },
                    miss,
                    "scene {i}: pixel {pixel:?}"
                );
            }
        }
    }

    #[test]
    fn tile_rows_hand_out_every_pixel_once_to_its_tile() {
        // Neither side a multiple of the tile, and not at the image's corner.
        let region = Region {
            x0: 3,
            y0: 5,
            x1: 3 + 2 * TILE + 7,
            y1: 5 + TILE + 1,
        };
        let tiles = tiles_of(region);
        let mut pixels = vec![Pixel::default(); region.area()];
        for (tile, rows) in tiles.iter().zip(tile_rows(&mut pixels, region, &tiles)) {
            // Each is the part in the region of one tile of the image's grid.
            let grid = grid_tile(*tile, 100, 100);
            assert_eq!((grid.x0 % TILE, grid.y0 % TILE), (0, 0));
            assert_eq!(tile.x0, grid.x0.max(region.x0));
            assert_eq!(tile.x1, grid.x1.min(region.x1));
            assert_eq!(tile.y0, grid.y0.max(region.y0));
            assert_eq!(tile.y1, grid.y1.min(region.y1));
            assert_eq!(rows.len(), tile.height());
            for (y, row) in (tile.y0..tile.y1).zip(rows) {
                assert_eq!(row.len(), tile.width());
                for (x, p) in (tile.x0..tile.x1).zip(row) {
                    p.samples += 1;
                    p.depth = (y * 1000 + x) as f32;
                }
            }
        }
        let film = Film {
            width: 100,
            height: 100,
            region,
            pixels: pixels.into(),
        };
        for y in region.y0..region.y1 {
            for x in region.x0..region.x1 {
                let p = film.pixel(x, y);
                assert_eq!((p.samples, p.depth), (1, (y * 1000 + x) as f32));
            }
        }
    }
}
