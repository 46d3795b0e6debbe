//! The photon pass for caustics (Jensen's caustic photon map): photons leave
//! the lights, follow specular bounces only, and are stored where they first
//! reach a diffuse surface after at least one specular bounce (L S+ D paths).
//! Direct light is the shadow rays' job, so photons that reach a diffuse
//! surface straight from a light are not stored. The eye pass gathers the
//! stored photons at its diffuse hits: density estimation over a disk of
//! fixed radius, the scene's or one derived from the photons (`radius`).
//!
//! Photon i draws from its own random stream, keyed by (seed, i) on a stream
//! no camera sample uses, and the map keeps emission order, so it is the same
//! for any thread count.

mod grid;
mod nearest;
mod radius;

use std::f32::consts::PI;

use rayon::prelude::*;

use grid::Grid;
pub use grid::Photon;
pub use radius::{Radius, RadiusFrom};

use super::tally::{RayKind, RayStats, Tally};
use crate::accel::Accel;
use crate::lights::Light;
use crate::math::{Bounds, Ray, Vec3, offset};
use crate::sampling::{Discrete, Rng};
use crate::scene::Scene;
use crate::shading::{Bsdf, Lambert, Plastic, Transport};

/// The "pixel" of the photons' random streams: an index no image reaches, so
/// photon i's stream never meets a camera sample's.
const STREAM: u64 = u64::MAX;

/// Photons traced per parallel task: enough to amortise scheduling.
const CHUNK: u32 = 4096;

/// Whether photons land on a surface with this BSDF: it has a diffuse lobe
/// that reflects something. Glossy-only and specular surfaces do not store.
pub fn receives(bsdf: &Bsdf) -> bool {
    match bsdf {
        Bsdf::Lambert(Lambert { albedo }) | Bsdf::Plastic(Plastic { albedo, .. }) => {
            albedo.max_element() > 0.0
        }
        _ => false,
    }
}

/// The stored caustic photons and their gather radius.
#[derive(Clone, Debug, PartialEq)]
pub struct PhotonMap {
    grid: Grid,
    radius: Radius,
}

/// How the photon pass went, for reports.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PhotonCounts {
    pub emitted: u32,
    pub stored: usize,
    pub rays: RayStats,
}

impl PhotonMap {
    /// Traces `count` photons through `scene`, following at most `max_depth`
    /// specular bounces each, in parallel on the current rayon pool, to be
    /// gathered with `radius` or, without one, the radius the photons call
    /// for. `None` if `stop` says so before every chunk of photons is traced.
    pub fn build(
        scene: &Scene,
        accel: &Accel,
        count: u32,
        radius: Option<f32>,
        max_depth: u32,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Option<(PhotonMap, PhotonCounts)> {
        let bounds = scene.bounds();
        let lights = LightChoice::new(&scene.lights, bounds);
        let tracer = Tracer {
            scene,
            accel,
            bounds,
            lights: &lights,
            count,
            max_depth,
        };
        let chunks: Vec<(Vec<Photon>, RayStats)> = (0..count.div_ceil(CHUNK))
            .into_par_iter()
            // Any chunk to any idle thread, as the render pass's tiles
            // (see `render`): rayon's adaptive splitting may leave a
            // thread's share in pieces no idle thread can take.
            .with_max_len(1)
            .map(|c| {
                if stop() {
                    return None;
                }
                let mut tally = Tally::default();
                let photons = (c * CHUNK..count.min((c + 1) * CHUNK))
                    .filter_map(|i| tracer.trace(i, &mut tally))
                    .collect();
                Some((photons, tally.totals()))
            })
            .collect::<Option<_>>()?;
        let mut rays = RayStats::default();
        let mut photons = Vec::new();
        for (part, stats) in chunks {
            photons.extend(part);
            rays += stats;
        }
        let counts = PhotonCounts {
            emitted: count,
            stored: photons.len(),
            rays,
        };
        let radius = Radius::choose(radius, &photons);
        let map = PhotonMap {
            grid: Grid::new(photons, radius.value),
            radius,
        };
        Some((map, counts))
    }

    /// The caustic radiance leaving a diffuse point p with unit normal n
    /// (facing the viewer) towards the viewer, where `f(wi)` is the BRDF for
    /// light arriving from wi: Σ flux · f(wi) / (π r²) over the photons within
    /// the radius that arrived on n's side.
    pub fn caustic(&self, p: Vec3, n: Vec3, f: impl Fn(Vec3) -> Vec3) -> Vec3 {
        let mut sum = Vec3::ZERO;
        self.grid.for_each_near(p, |ph| {
            // The same side of a thin surface, and light from above it.
            if ph.n.dot(n) > 0.0 && ph.wi.dot(n) > 0.0 {
                sum += ph.flux * f(ph.wi);
            }
        });
        let r = self.radius.value;
        sum / (PI * r * r)
    }

    pub fn radius(&self) -> Radius {
        self.radius
    }

    pub fn len(&self) -> usize {
        self.grid.len()
    }

    pub fn is_empty(&self) -> bool {
        self.grid.is_empty()
    }
}

/// Lights picked in proportion to their power (the sum of its channels).
struct LightChoice<'a> {
    lights: &'a [Light],
    /// The lights by power (the sum of its channels).
    power: Discrete,
}

impl<'a> LightChoice<'a> {
    fn new(lights: &'a [Light], bounds: Bounds) -> LightChoice<'a> {
        let power = Discrete::new(lights.iter().map(|l| l.power(bounds).element_sum()));
        LightChoice { lights, power }
    }

    /// The light for uniform `u` and the probability of picking it; None if
    /// no light emits anything.
    fn pick(&self, u: f32) -> Option<(&'a Light, f32)> {
        let (i, p) = self.power.sample(u)?;
        Some((&self.lights[i], p))
    }
}

struct Tracer<'a> {
    scene: &'a Scene,
    accel: &'a Accel,
    bounds: Bounds,
    lights: &'a LightChoice<'a>,
    count: u32,
    max_depth: u32,
}

impl Tracer<'_> {
    /// Photon `index`: where it is stored, if it makes a caustic.
    fn trace(&self, index: u32, tally: &mut Tally) -> Option<Photon> {
        let mut rng = Rng::for_sample(self.scene.render.seed, STREAM, index);
        let (light, probability) = self.lights.pick(rng.next_f32())?;
        let [a, b] = rng.next_2d();
        let [c, d] = rng.next_2d();
        let e = light.emit([a, b, c, d], self.bounds)?;
        // Each photon stands for 1/count of the light's share of the emission.
        let mut flux = e.flux / (probability * self.count as f32);
        let mut ray = Ray::new(offset(e.origin, e.error, e.normal, e.dir), e.dir);
        let mut depth = 0;
        loop {
            tally.count(RayKind::Photon, depth);
            let hit = self.accel.intersect(&ray);
            if !hit.is_hit() {
                return None;
            }
            // Only a specular first hit can start a caustic; anything else is
            // direct light, dropped before the work of an interaction (most
            // photons, where a small glass ball sits over a wide floor).
            if depth == 0 {
                let material = &self.scene.materials[self.scene.material_of(&hit) as usize];
                if !Bsdf::from_material(material).is_delta() {
                    return None;
                }
            }
            let it = self.scene.interaction(&ray, &hit);
            let material = &self.scene.materials[it.material as usize];
            let bsdf = Bsdf::at(material, &it.surface(material));
            let wo = -ray.dir;
            if receives(&bsdf) {
                // Straight from the light (depth 0) is direct light: not a caustic.
                return (depth > 0).then_some(Photon {
                    p: it.p,
                    wi: wo,
                    n: it.n,
                    flux,
                });
            }
            if !bsdf.is_delta() || depth >= self.max_depth {
                return None;
            }
            let frame = it.frame();
            let u = [rng.next_f32(), rng.next_f32(), rng.next_f32()];
            // Glass picks reflection or refraction by Fresnel; flux is not
            // rescaled by refraction (importance transport).
            let s = bsdf.sample_with(&frame, wo, u, Transport::Importance)?;
            if !it.leaves_as(s.wi, s.kind.is_transmission()) {
                return None;
            }
            flux *= s.weight;
            if flux.max_element() <= 0.0 {
                return None;
            }
            ray = Ray::new(offset(it.p, it.error, it.n, s.wi), s.wi);
            depth += 1;
        }
    }
}
