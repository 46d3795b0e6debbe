//! The Whitted ray tree: local shading with shadow rays at diffuse and plastic
//! surfaces, and recursive specular reflection and Snell refraction at mirrors
//! and dielectrics, and both, by the fractions of POV-Ray's finish, at classic
//! materials, down to a depth limit or until a branch's weight is too small
//! to matter. Which of these rays exist at all is the plan's decision.
//! Caustics come from the photon map, gathered at every diffuse hit of the
//! tree: with the specular chains the tree follows from the eye, that covers
//! L S+ D S* E.

use super::lit::Lit;
use super::tally::{Node, RayKind, Tally};
use super::{PhotonMap, Plan};
use crate::accel::{Accel, ShapeSet};
use crate::film::Sample;
use crate::lights::LightRef;
use crate::math::{Hit, Ray, Ray64, Vec3, offset};
use crate::sampling::Sampler;
use crate::scene::{Interaction, Scene, fog_along, fog_through};
use crate::shading::fresnel;
use crate::shading::{MaterialKind, Surface};

/// How far short of a light its shadow rays stop, as a fraction of their
/// length.
pub(super) const SHADOW_SHORT: f32 = 1e-4;

/// The most surfaces a shadow ray passes filtered (`Whitted::shadow_through`):
/// far more than any glass in a scene puts between a point and a light.
const MAX_FILTERING_SURFACES: u32 = 64;

/// What one sample's walk down the tree carries: the counts and its sampler
/// (area lights pick a point on themselves with it).
struct Walk<'t> {
    tally: &'t mut Tally,
    sampler: &'t mut Sampler,
    /// The shapes the camera hit's shadow rays are offered.
    lit: Lit,
}

pub struct Whitted<'a> {
    pub scene: &'a Scene,
    pub accel: &'a Accel,
    pub plan: Plan,
    /// The caustic photons, when the plan has a photon pass.
    pub caustics: Option<&'a PhotonMap>,
}

impl Whitted<'_> {
    /// The radiance along a camera ray, with the first hit's AOVs. The ray's
    /// `hit` was found in f64 (`Accel::intersect_exact`); it is followed as
    /// its f32 rounding. Its shadow rays towards a light `lit` names skip
    /// the shape proven to cast no shadow on the hit.
    pub fn sample(
        &self,
        camera: &Ray64,
        hit: Hit,
        sampler: &mut Sampler,
        tally: &mut Tally,
        lit: Lit,
    ) -> Sample {
        let walk = &mut Walk {
            tally,
            sampler,
            lit,
        };
        let ray = &camera.rounded();
        // Once for the ray tree and the AOVs: an analytic hit's error bound
        // costs a substitution of the ray into its polynomial.
        let it = hit.is_hit().then(|| self.scene.interaction(ray, &hit));
        let radiance = self.follow_from(
            ray,
            (&hit, it.as_ref()),
            RayKind::Camera,
            0,
            Vec3::ONE,
            walk,
        );
        let Some(it) = it else {
            return Sample {
                radiance,
                weight: 1.0,
                depth: f32::INFINITY,
                normal: Vec3::ZERO,
                albedo: Vec3::ZERO,
            };
        };
        Sample {
            radiance,
            weight: 1.0,
            depth: hit.t,
            normal: it.ns,
            albedo: it
                .surface(&self.scene.materials[it.material as usize])
                .albedo,
        }
    }

    /// The radiance a ray of the tree brings back from `hit`.
    fn follow(
        &self,
        ray: &Ray,
        hit: &Hit,
        kind: RayKind,
        depth: u32,
        weight: Vec3,
        walk: &mut Walk<'_>,
    ) -> Vec3 {
        let it = hit.is_hit().then(|| self.scene.interaction(ray, hit));
        self.follow_from(ray, (hit, it.as_ref()), kind, depth, weight, walk)
    }

    /// `follow`, with the hit's interaction (`None` for a miss) already known.
    fn follow_from(
        &self,
        ray: &Ray,
        (hit, it): (&Hit, Option<&Interaction>),
        kind: RayKind,
        depth: u32,
        weight: Vec3,
        walk: &mut Walk<'_>,
    ) -> Vec3 {
        walk.tally.count(kind, depth);
        let node = walk
            .tally
            .open(|| Node::of_hit(self.scene, hit, kind, depth, weight));
        let radiance = match it {
            Some(it) => self.shade(ray, it, depth, weight, walk),
            None => self.scene.escaped(ray.dir),
        };
        let radiance = self.fogged(ray, (hit, it), radiance);
        walk.tally.finish(node, radiance);
        radiance
    }

    /// `radiance` come back along `ray` through POV-Ray's fogs, where the
    /// way was through the air: not where it ends on a solid's inside.
    fn fogged(&self, ray: &Ray, (hit, it): (&Hit, Option<&Interaction>), radiance: Vec3) -> Vec3 {
        if !self.plan.fog || it.is_some_and(|it| self.scene.came_through_solid(hit, it.front)) {
            return radiance;
        }
        let length = it.map(|it| (it.p - ray.origin).length());
        let (added, through) = fog_along(&self.scene.fogs, ray.origin, ray.dir, length);
        added + through * radiance
    }

    fn shade(
        &self,
        ray: &Ray,
        it: &Interaction,
        depth: u32,
        weight: Vec3,
        walk: &mut Walk<'_>,
    ) -> Vec3 {
        let material = &self.scene.materials[it.material as usize];
        let wo = -ray.dir;
        let surface = it.surface(material);
        // Emitters shine from their front side only.
        let mut radiance = if it.front {
            surface.emission
        } else {
            Vec3::ZERO
        };
        match material.kind {
            MaterialKind::Mirror => {
                if self.plan.reflection {
                    let r = material.reflectance(&surface);
                    let dir = fresnel::reflect(ray.dir, it.ns);
                    radiance +=
                        r * self.spawn(it, dir, depth, weight * r, RayKind::Reflection, walk);
                }
            }
            MaterialKind::Dielectric => {
                // Snell and Fresnel need to know which side the ray comes from: the
                // interaction's normal faces the ray, `front` says whether that is outside.
                let outward = it.outward();
                let f = fresnel::dielectric(wo.dot(outward), material.ior);
                if self.plan.reflection {
                    let dir = fresnel::reflect(ray.dir, it.ns);
                    radiance +=
                        f * self.spawn(it, dir, depth, weight * f, RayKind::Reflection, walk);
                }
                if self.plan.refraction
                    && f < 1.0
                    && let Some(dir) = fresnel::refract(wo, outward, material.ior)
                {
                    let t = 1.0 - f;
                    radiance +=
                        t * self.spawn(it, dir, depth, weight * t, RayKind::Refraction, walk);
                }
            }
            MaterialKind::Diffuse
            | MaterialKind::Plastic
            | MaterialKind::Metal
            | MaterialKind::Emissive => {
                let brdf = |wi| material.local_brdf(&surface, it.ns, wo, wi);
                if self.plan.shadow {
                    radiance += self.direct(it, brdf, depth, weight, walk);
                }
                if let Some(map) = self.caustics {
                    radiance += map.caustic(it.p, it.n, brdf);
                }
                self.force(ray, it, depth, weight, [true, true], walk);
            }
            MaterialKind::Classic => {
                radiance += self.classic(ray, it, &surface, depth, weight, walk);
            }
        }
        radiance
    }

    /// What a renderer without a plan pays where the material has no such
    /// branch: the reflected and refracted rays `missing` names, weighted by zero.
    fn force(
        &self,
        ray: &Ray,
        it: &Interaction,
        depth: u32,
        weight: Vec3,
        missing: [bool; 2],
        walk: &mut Walk<'_>,
    ) {
        if !self.plan.forced {
            return;
        }
        if missing[0] {
            let mirror = fresnel::reflect(ray.dir, it.n);
            let _ = self.spawn(it, mirror, depth, weight, RayKind::Reflection, walk);
        }
        if missing[1] {
            let _ = self.spawn(it, ray.dir, depth, weight, RayKind::Refraction, walk);
        }
    }

    /// POV-Ray's finish as a ray tree: ambient, and the lights through shadow
    /// rays, for the part of the pigment that does not transmit; a reflected
    /// branch weighted by the reflected fraction (tinted by `metallic`); a
    /// refracted branch weighted by `transmit`, which total internal
    /// reflection adds to the reflected one.
    fn classic(
        &self,
        ray: &Ray,
        it: &Interaction,
        surface: &Surface,
        depth: u32,
        weight: Vec3,
        walk: &mut Walk<'_>,
    ) -> Vec3 {
        let material = &self.scene.materials[it.material as usize];
        let finish = &material.finish;
        let wo = -ray.dir;
        let albedo = surface.albedo;
        let mut radiance = finish.ambient_colour(albedo);
        if self.plan.shadow {
            let brdf = |wi| material.local_brdf(surface, it.ns, wo, wi);
            radiance += self.direct(it, brdf, depth, weight, walk);
        }
        let outward = it.outward();
        // A ray that leaves a fading interior brings light faded by its way
        // inside (POV-Ray applies it to what comes through the surface).
        let fade = finish
            .fade
            .filter(|_| !it.front)
            .map_or(Vec3::ONE, |f| f.share((it.p - ray.origin).length()));
        // POV-Ray's colour × filter + transmit, the pigment tinting the filter.
        let t = finish.transmitted(albedo) * fade;
        let refracted = if finish.transmits() {
            fresnel::refract(wo, outward, material.ior)
        } else {
            None
        };
        // Under total internal reflection POV-Ray 3.7 traces the mirrored
        // ray with all of the light, faded but neither filtered nor tinted,
        // in place of the surface's own reflection (its
        // `ComputeLightedTexture`).
        let r = if finish.transmits() && refracted.is_none() {
            fade
        } else {
            finish.tint(albedo) * finish.reflectance(wo.dot(outward), material.ior)
        };
        if self.plan.reflection && r.max_element() > 0.0 {
            let dir = fresnel::reflect(ray.dir, it.ns);
            radiance += r * self.spawn(it, dir, depth, weight * r, RayKind::Reflection, walk);
        }
        if self.plan.refraction
            && let Some(dir) = refracted
        {
            radiance += t * self.spawn(it, dir, depth, weight * t, RayKind::Refraction, walk);
        }
        self.force(
            ray,
            it,
            depth,
            weight,
            [r.max_element() == 0.0, refracted.is_none()],
            walk,
        );
        radiance
    }

    /// The light a shadow ray lets through: none past an opaque surface, all
    /// where nothing is in its way. Where the scene has transparent classic
    /// materials (`Plan::filtered_shadows`), POV-Ray's shadows: each surface
    /// of one the ray crosses, going in and coming out, lets through its
    /// colour × filter + transmit, without bending the ray.
    /// `among`: the shapes that may block it (see `Lit`). Past a surface
    /// that filters it, the ray goes on from a point off its line, which
    /// the proof did not cover, and every shape is offered.
    fn shadow_through(&self, shadow: &Ray, fogged: bool, among: ShapeSet) -> Vec3 {
        if !self.plan.filtered_shadows {
            return if self.accel.occluded_among(shadow, among) {
                Vec3::ZERO
            } else if fogged {
                fog_through(&self.scene.fogs, shadow)
            } else {
                Vec3::ONE
            };
        }
        let mut ray = *shadow;
        let mut through = Vec3::ONE;
        for surface in 0..MAX_FILTERING_SURFACES {
            let among = if surface == 0 { among } else { ShapeSet::ALL };
            let hit = self.accel.intersect_among(&ray, among);
            if !hit.is_hit() {
                return if fogged {
                    through * fog_through(&self.scene.fogs, &ray)
                } else {
                    through
                };
            }
            let it = self.scene.interaction(&ray, &hit);
            // The fog on the way to this surface, if that way was through
            // the air (not a solid's inside, as for the camera's rays).
            if fogged && !self.scene.came_through_solid(&hit, it.front) {
                let mut part = ray;
                part.tfar = hit.t;
                through *= fog_through(&self.scene.fogs, &part);
            }
            if self.scene.casts_shadow(&hit) {
                let material = &self.scene.materials[it.material as usize];
                let finish = &material.finish;
                if material.kind != MaterialKind::Classic || !finish.transmits() {
                    return Vec3::ZERO;
                }
                through *= finish.transmitted(it.surface(material).albedo);
                // Leaving an interior: faded by the way through it.
                if let Some(fade) = finish.fade.filter(|_| !it.front) {
                    through *= fade.shadow_share((it.p - ray.origin).length());
                }
                if through.max_element() < self.scene.render.min_weight {
                    return Vec3::ZERO;
                }
            }
            // On from just past the surface, to the same end (a directional
            // light's is at infinity, where o + t·d has no finite point).
            let origin = offset(it.p, it.error, it.n, ray.dir);
            let tfar = if ray.tfar.is_finite() {
                (ray.at(ray.tfar) - origin).dot(ray.dir) / ray.dir.length_squared()
            } else {
                f32::INFINITY
            };
            // Not past the end (nor NaN, which no ray may carry).
            if tfar.is_nan() || tfar <= 0.0 {
                return through;
            }
            ray = Ray::new(origin, ray.dir);
            ray.tfar = tfar;
        }
        // More surfaces than any glass needs: as dark as their light would be.
        Vec3::ZERO
    }

    /// A secondary ray from `it` along `dir`, if the depth limit and the branch's
    /// weight allow it.
    fn spawn(
        &self,
        it: &Interaction,
        dir: Vec3,
        depth: u32,
        weight: Vec3,
        kind: RayKind,
        walk: &mut Walk<'_>,
    ) -> Vec3 {
        if depth >= self.plan.max_depth || weight.max_element() < self.scene.render.min_weight {
            return Vec3::ZERO;
        }
        // A shading normal may send the ray through the surface: no leak.
        if !it.leaves_as(dir, kind == RayKind::Refraction) {
            return Vec3::ZERO;
        }
        let ray = Ray::new(offset(it.p, it.error, it.n, dir), dir);
        let hit = self.accel.intersect(&ray);
        self.follow(&ray, &hit, kind, depth + 1, weight, walk)
    }

    /// Local shading from every point and directional light and one area light
    /// picked by power, each tested with a shadow ray; `brdf` is the
    /// material's local reflection model at the hit, a function of the
    /// direction towards the light. Each shading point draws one request in
    /// the order the tree is walked, which picks the area light and then
    /// the point on it (the delta lights ignore it).
    fn direct(
        &self,
        it: &Interaction,
        brdf: impl Fn(Vec3) -> Vec3,
        depth: u32,
        weight: Vec3,
        walk: &mut Walk<'_>,
    ) -> Vec3 {
        // No number is drawn where the pick would not use it (some 130
        // instructions a shading point): the tracer draws none after it,
        // so no later number moves.
        let picker = &self.scene.light_picker;
        let u = if picker.uses_u() {
            walk.sampler.get_2d()
        } else {
            [0.5; 2]
        };
        let pick = picker.pick(u);
        let area = pick.area.into_iter();
        let mut radiance = Vec3::ZERO;
        let deltas = pick.delta.map(|i| (LightRef::Index(i), 1.0));
        for (light, picked) in deltas.chain(area) {
            let Some(incident) = self.scene.incident(light, it.p, pick.u) else {
                continue;
            };
            // The geometric side first: no light from behind the true surface.
            let cos = it.ns.dot(incident.wi);
            if !it.leaves_as(incident.wi, false) || cos <= 0.0 {
                continue;
            }
            let shadow = || {
                let mut shadow = Ray::new(offset(it.p, it.error, it.n, incident.wi), incident.wi);
                // Stop just short of the light: its own surface must not occlude it.
                shadow.tfar = incident.distance * (1.0 - SHADOW_SHORT);
                shadow
            };
            let shadowing = self.scene.shadowing(light);
            let fogged = shadowing.fogged && self.plan.fog;
            let through = if shadowing.shadowless {
                // No shadow ray: only the fog, over the whole way.
                if fogged {
                    fog_through(&self.scene.fogs, &shadow())
                } else {
                    Vec3::ONE
                }
            } else {
                walk.tally.count(RayKind::Shadow, depth);
                let among = match light {
                    LightRef::Index(i) if depth == 0 => walk.lit.among(i),
                    _ => ShapeSet::ALL,
                };
                // A shadow ray proven clear of every shape (`Lit`) meets
                // nothing: unfogged, it is not made.
                if among == ShapeSet::NONE && !fogged {
                    Vec3::ONE
                } else {
                    self.shadow_through(&shadow(), fogged, among)
                }
            };
            let contribution = if through == Vec3::ZERO {
                Vec3::ZERO
            } else {
                brdf(incident.wi) * incident.irradiance * through * (cos / picked)
            };
            walk.tally.open(|| Node {
                depth,
                kind: RayKind::Shadow,
                hit: format!(
                    "{light}: {}",
                    match through {
                        Vec3::ZERO => "blocked",
                        Vec3::ONE => "visible",
                        _ => "filtered",
                    }
                ),
                t: shadow().tfar,
                material: None,
                weight: weight.to_array(),
                radiance: contribution.to_array(),
            });
            radiance += contribution;
        }
        radiance
    }
}
