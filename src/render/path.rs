//! The path tracer: global illumination by BSDF sampling, next-event
//! estimation (every point and directional light, plus one area light picked
//! by power, the environment among them), multiple importance sampling
//! between the two ways of reaching an area light or the environment, and
//! Russian roulette after a few bounces. The constant background and
//! emissive shapes that are not sampled lights are reached by BSDF sampling
//! alone.
//!
//! With a photon pass, caustics (light → specular → diffuse) come from the
//! photon map, gathered at every vertex that stores photons. A path that
//! leaves such a vertex and reaches a light through mirrors and glass alone is
//! then a caustic the map already counted, so its emission is left out: each
//! path is counted once, and the fireflies such paths cause are gone.

use super::Plan;
use super::photon::{self, PhotonMap};
use super::tally::{Node, RayKind, Tally};
use crate::accel::Accel;
use crate::film::Sample;
use crate::lights::LightRef;
use crate::math::{Frame, Hit, Ray, Ray64, Vec3, offset};
use crate::sampling::mis::power_heuristic;
use crate::sampling::{Deferred, Sampler};
use crate::scene::{Interaction, Scene, fog_along, fog_through};
use crate::shading::{Bsdf, Lobe};

/// Bounces before Russian roulette may end a path.
const ROULETTE_AFTER: u32 = 3;

pub struct PathTracer<'a> {
    pub scene: &'a Scene,
    pub accel: &'a Accel,
    pub plan: Plan,
    /// The caustic photons, when the plan has a photon pass.
    pub caustics: Option<&'a PhotonMap>,
}

/// The numbers one bounce uses, taken together in this order at every
/// vertex whether or not it needs them all (a specular vertex samples no
/// light, roulette waits for a few bounces): so with the Sobol sampler each
/// decision at each depth has its own dimensions in every sample, and its
/// samples stratify it. Roulette's is only reserved, and drawn where a path
/// reaches roulette (`Sampler::defer_1d`): the same number, without the
/// work on the bounces before it.
struct Bounce {
    /// Picks the area light, then the point on it (see `LightPicker::pick`).
    light: [f32; 2],
    /// The BSDF's lobe (u[0]) and direction (u[1], u[2]).
    bsdf: [f32; 3],
    roulette: Deferred,
}

impl Bounce {
    fn draw(sampler: &mut Sampler) -> Bounce {
        let light = sampler.get_2d();
        let lobe = sampler.get_1d();
        let [u1, u2] = sampler.get_2d();
        Bounce {
            light,
            bsdf: [lobe, u1, u2],
            roulette: sampler.defer_1d(),
        }
    }
}

/// The shading point a path is at, as light sampling needs it.
struct Vertex<'v> {
    it: &'v Interaction,
    bsdf: &'v Bsdf,
    frame: &'v Frame,
    wo: Vec3,
    /// Where rays leaving on the normal's side start (see `spawn`).
    above: Vec3,
    depth: u32,
    /// Whether the BSDF-sampled ray from here is traced, so that a light it
    /// meets counts with the other MIS weight. When it is not (the last
    /// vertex), light sampling alone must carry the direct light: weight 1.
    bsdf_continues: bool,
}

impl PathTracer<'_> {
    /// The radiance along a camera ray whose hit was found in f64
    /// (`Accel::intersect_exact`), followed as its f32 rounding.
    pub fn sample(
        &self,
        camera: &Ray64,
        camera_hit: Hit,
        sampler: &mut Sampler,
        tally: &mut Tally,
    ) -> Sample {
        let mut radiance = Vec3::ZERO;
        let mut beta = Vec3::ONE;
        let mut ray = camera.rounded();
        let mut kind = RayKind::Camera;
        let mut first = None;
        // Where the last bounce left from and the BSDF density of its direction,
        // when light sampling there could also have found what the ray hits: the
        // two strategies' MIS weights must then sum to one.
        let mut sampled_from: Option<(Vec3, f32)> = None;
        // Whether the path's last non-specular vertex gathered caustic photons:
        // a light reached from it through specular bounces alone is in the map.
        let mut gathered = false;
        let path = tally.mark();
        for depth in 0..=self.plan.max_depth {
            tally.count(kind, depth);
            let hit = if depth == 0 {
                camera_hit
            } else {
                self.accel.intersect(&ray)
            };
            // Built only when explain records the tree: nothing is allocated per ray.
            let node = tally.open(|| Node::of_hit(self.scene, &hit, kind, depth, beta));
            if !hit.is_hit() {
                let glow = self.fog(&ray, None, &mut beta);
                let add = glow + beta * self.escaped(ray.dir, sampled_from);
                tally.add(node, add);
                radiance += add;
                break;
            }
            let it = self.scene.interaction(&ray, &hit);
            // POV-Ray's fogs on the way through the air (not a solid's inside).
            let glow = if !self.scene.came_through_solid(&hit, it.front) {
                self.fog(&ray, Some((it.p - ray.origin).length()), &mut beta)
            } else {
                Vec3::ZERO
            };
            let u = Bounce::draw(sampler);
            let material = &self.scene.materials[it.material as usize];
            // Out of a fading interior: all the light from here on crossed it.
            if let Some(fade) = material.finish.fade.filter(|_| !it.front) {
                beta *= fade.share((it.p - ray.origin).length());
            }
            let surface = it.surface(material);
            if depth == 0 {
                first = Some((hit.t, it.ns, surface.albedo));
            }
            let mut add = glow;
            // Emitters shine from their front side only.
            if it.front && material.emits() {
                let light = self.scene.light_picker.light_of(hit.geom_id, hit.prim_id);
                if !(gathered && light.is_some()) {
                    let weight = match (sampled_from, light) {
                        (Some((from, bsdf_pdf)), Some((index, picked))) => {
                            let light_pdf = picked * self.scene.lights[index].pdf(from, it.p);
                            power_heuristic(1.0, bsdf_pdf, 1.0, light_pdf)
                        }
                        _ => 1.0,
                    };
                    add += beta * surface.emission * weight;
                }
            }
            let bsdf = Bsdf::at(material, &surface);
            let frame = it.frame();
            let wo = -ray.dir;
            if let Some(map) = self.caustics
                && photon::receives(&bsdf)
            {
                add += beta * map.caustic(it.p, it.n, |wi| bsdf.eval(&frame, wo, wi));
            }
            let samples_lights = self.plan.shadow && !bsdf.is_delta();
            // Found only where a shadow ray will use it: a delta vertex
            // (glass, mirror) spawns just its one bounce.
            let above = samples_lights.then(|| offset(it.p, it.error, it.n, it.n));
            if let Some(above) = above {
                let vertex = Vertex {
                    it: &it,
                    bsdf: &bsdf,
                    frame: &frame,
                    wo,
                    above,
                    depth,
                    // A non-delta BSDF sample is a diffuse or glossy ray:
                    // traced only below the depth limit, if the plan has them.
                    bsdf_continues: depth < self.plan.max_depth && self.plan.diffuse,
                };
                add += beta * self.direct(&vertex, &u, tally);
            }
            tally.add(node, add);
            radiance += add;
            let Some(s) = bsdf.sample(&frame, wo, u.bsdf) else {
                break;
            };
            if !it.leaves_as(s.wi, s.kind.is_transmission()) {
                break;
            }
            kind = match s.kind {
                Lobe::DiffuseReflection | Lobe::GlossyReflection => RayKind::Diffuse,
                Lobe::SpecularReflection => RayKind::Reflection,
                Lobe::SpecularTransmission => RayKind::Refraction,
            };
            let allowed = match kind {
                RayKind::Diffuse => self.plan.diffuse,
                RayKind::Reflection => self.plan.reflection,
                _ => self.plan.refraction,
            };
            if !allowed {
                break;
            }
            sampled_from = (samples_lights && !s.delta).then_some((it.p, s.pdf));
            if !s.delta {
                gathered = self.caustics.is_some() && photon::receives(&bsdf);
            }
            beta *= s.weight;
            if depth >= ROULETTE_AFTER {
                let survive = beta.max_element().min(0.95);
                if sampler.later(u.roulette) >= survive {
                    break;
                }
                beta /= survive;
            }
            ray = Ray::new(spawn(&it, above, s.wi), s.wi);
        }
        tally.close_path(path);
        let (depth, normal, albedo) = first.unwrap_or((f32::INFINITY, Vec3::ZERO, Vec3::ZERO));
        Sample {
            radiance,
            weight: 1.0,
            depth,
            normal,
            albedo,
        }
    }

    /// Next-event estimation: every delta light, and one area light picked by
    /// power, each through a shadow ray. The delta lights ignore the point
    /// `pick.u`, which is the area light's.
    fn direct(&self, v: &Vertex<'_>, u: &Bounce, tally: &mut Tally) -> Vec3 {
        let pick = self.scene.light_picker.pick(u.light);
        let mut sum = Vec3::ZERO;
        for light in pick.delta {
            sum += self.light_sample(v, LightRef::Index(light), 1.0, pick.u, tally);
        }
        if let Some((light, picked)) = pick.area {
            sum += self.light_sample(v, light, picked, pick.u, tally);
        }
        sum
    }

    /// POV-Ray's fogs on the way of `ray`, `length` long (None: to a miss):
    /// the light they add, times the path's weight, which then keeps what
    /// they let through. Nothing where the scene has no fog.
    fn fog(&self, ray: &Ray, length: Option<f32>, beta: &mut Vec3) -> Vec3 {
        if !self.plan.fog {
            return Vec3::ZERO;
        }
        let (added, through) = fog_along(&self.scene.fogs, ray.origin, ray.dir, length);
        let glow = *beta * added;
        *beta *= through;
        glow
    }

    /// The radiance of a ray that left the scene in direction `dir`, weighted
    /// against light sampling's way to the environment when the BSDF sample
    /// from `sampled_from` (see `sample`) could also have been drawn by it.
    fn escaped(&self, dir: Vec3, sampled_from: Option<(Vec3, f32)>) -> Vec3 {
        let radiance = self.scene.escaped(dir);
        let (Some((_, bsdf_pdf)), Some(environment), Some(picked)) = (
            sampled_from,
            &self.scene.environment,
            self.scene.light_picker.environment(),
        ) else {
            return radiance;
        };
        radiance * power_heuristic(1.0, bsdf_pdf, 1.0, picked * environment.pdf(dir))
    }

    /// One sample of `light`, picked with probability `picked`, at `u`.
    fn light_sample(
        &self,
        v: &Vertex<'_>,
        light: LightRef,
        picked: f32,
        u: [f32; 2],
        tally: &mut Tally,
    ) -> Vec3 {
        let it = v.it;
        let Some(incident) = self.scene.incident(light, it.p, u) else {
            return Vec3::ZERO;
        };
        // The geometric side first: no light from behind the true surface.
        let cos = it.ns.dot(incident.wi);
        if !it.leaves_as(incident.wi, false) || cos <= 0.0 {
            return Vec3::ZERO;
        }
        let f = v.bsdf.eval(v.frame, v.wo, incident.wi);
        if f == Vec3::ZERO {
            return Vec3::ZERO;
        }
        let mut shadow = Ray::new(spawn(it, Some(v.above), incident.wi), incident.wi);
        // Stop just short of the light: its own surface must not occlude it.
        shadow.tfar = incident.distance * (1.0 - 1e-4);
        let shadowing = self.scene.shadowing(light);
        if !shadowing.shadowless {
            tally.count(RayKind::Shadow, v.depth);
            if self.accel.occluded(&shadow) {
                return Vec3::ZERO;
            }
        }
        // POV-Ray's light dimmed by the fogs on its way (the path tracer's
        // shadow rays stop at any surface, so the way is all air).
        let mut irradiance = incident.irradiance;
        if shadowing.fogged && self.plan.fog {
            irradiance *= fog_through(&self.scene.fogs, &shadow);
        }
        // Delta lights (pdf 0) only light sampling reaches: weight 1.
        let weight = if incident.pdf > 0.0 && v.bsdf_continues {
            let bsdf_pdf = v.bsdf.pdf(v.frame, v.wo, incident.wi);
            power_heuristic(1.0, picked * incident.pdf, 1.0, bsdf_pdf)
        } else {
            1.0
        };
        f * irradiance * (cos * weight / picked)
    }
}

/// The origin of a ray leaving `it` in direction `w`: `offset`'s point, which
/// is the same for every direction on the normal's side, so that one
/// (`above`, found once a vertex where light sampling needs it) serves the
/// shadow ray and the bounce alike.
fn spawn(it: &Interaction, above: Option<Vec3>, w: Vec3) -> Vec3 {
    match above {
        Some(above) if w.dot(it.n) >= 0.0 => above,
        _ => offset(it.p, it.error, it.n, w),
    }
}
