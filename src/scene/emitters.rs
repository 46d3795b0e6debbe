//! The scene's area lights, found in its geometry: every emissive triangle and
//! every emissive whole sphere is a light that next-event estimation samples.
//! Other emissive analytic shapes (tori, quadrics, algebraic surfaces) have no
//! area sampling: bounces still find them, and they light the scene that way.
//! The environment light is picked among the area lights by its power.

use std::collections::HashMap;

use super::Scene;
use crate::lights::{EmissionMap, Incident, Light, LightPicker, LightRef, Shadowing};
use crate::math::Vec3;

impl Scene {
    /// Appends a light for each emissive primitive, after the point and
    /// directional lights, and builds the light picker. Called once, when the
    /// scene is loaded.
    pub(crate) fn gather_emitters(&mut self) {
        let emissive = |m: u32| self.materials[m as usize].emits();
        // Each emission map's mean, found once per material.
        let means: Vec<Option<Vec3>> = (self.materials.iter())
            .map(|m| m.maps.emission.as_ref().map(|t| t.image.mean()))
            .collect();
        let mut emitters = HashMap::new();
        let mut found = Vec::new();
        for (geom, mesh) in self.meshes.iter().enumerate() {
            for (prim, (tri, &m)) in mesh.triangles.iter().zip(&mesh.materials).enumerate() {
                let [p0, p1, p2] = tri.map(|i| mesh.positions[i as usize]);
                let (edge1, edge2) = (p1 - p0, p2 - p0);
                if !emissive(m) || edge1.cross(edge2).length_squared() == 0.0 {
                    continue;
                }
                let material = &self.materials[m as usize];
                let map = (material.maps.emission.as_ref())
                    .zip(means[m as usize])
                    .zip(mesh.uv(prim as u32, 0.0, 0.0))
                    .map(|((texture, mean), uv0)| {
                        let corner = |b1, b2| mesh.uv(prim as u32, b1, b2).unwrap_or(uv0) - uv0;
                        Box::new(EmissionMap {
                            texture: texture.clone(),
                            uv0,
                            du: corner(1.0, 0.0),
                            dv: corner(0.0, 1.0),
                            mean,
                        })
                    });
                // A map black everywhere leaves nothing to sample.
                if map.as_ref().is_some_and(|m| m.mean.max_element() <= 0.0) {
                    continue;
                }
                emitters.insert((geom as u32, prim as u32), found.len());
                found.push(Light::Triangle {
                    p0,
                    edge1,
                    edge2,
                    radiance: material.emission,
                    map,
                });
            }
        }
        let shapes = self.shapes_geom_id();
        for (prim, shape) in self.shapes.iter().enumerate() {
            let Some((center, radius)) = shape.world_sphere() else {
                continue;
            };
            if !emissive(shape.material) {
                continue;
            }
            emitters.insert((shapes, prim as u32), found.len());
            found.push(Light::Sphere {
                center: center.as_vec3(),
                radius: radius as f32,
                radiance: self.materials[shape.material as usize].emission,
            });
        }
        // Delta lights first: the picker samples them all and picks among the rest.
        self.lights.retain(Light::is_delta);
        let first = self.lights.len() as u32;
        self.lights.extend(found);
        let emitters = emitters
            .into_iter()
            .map(|(k, i)| (k, first + i as u32))
            .collect();
        let environment =
            (self.environment.as_ref()).map(|e| e.power(self.bounds()).dot(crate::math::LUMINANCE));
        self.light_picker = LightPicker::new(&self.lights, emitters, environment);
    }

    /// Light `light` as seen from p, sampled with `u` (see [`Light::incident`]).
    pub fn incident(&self, light: LightRef, p: Vec3, u: [f32; 2]) -> Option<Incident> {
        match light {
            LightRef::Index(i) => self.lights[i].incident(p, u),
            LightRef::Environment => self.environment.as_ref()?.incident(u),
        }
    }

    /// What `light` does with what lies on its way (see [`Shadowing`]).
    pub fn shadowing(&self, light: LightRef) -> Shadowing {
        match light {
            LightRef::Index(i) => self.lights[i].shadowing(),
            LightRef::Environment => Shadowing::default(),
        }
    }

    /// The radiance a ray that leaves the scene in the unit direction `dir`
    /// brings back: the environment's, or the constant background.
    pub fn escaped(&self, dir: Vec3) -> Vec3 {
        match &self.environment {
            Some(environment) => environment.radiance(dir),
            None => self.background,
        }
    }

    /// Emissive shapes that only bounces can find (no area sampling for their kind).
    pub fn unsampled_emitters(&self) -> usize {
        self.shapes
            .iter()
            .filter(|s| self.materials[s.material as usize].emits() && s.world_sphere().is_none())
            .count()
    }
}
