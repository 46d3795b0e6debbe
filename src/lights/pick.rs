//! Which lights a shading point samples: every point and directional light
//! (they are cheap and noiseless), plus one area light picked in proportion to
//! its power, so a mesh with ten thousand emissive triangles costs one shadow
//! ray, not ten thousand, and the bright ones get the samples. The
//! environment light, when the scene has one, is one more area light to pick,
//! by the flux it sends through the scene's bounding disk.

use std::collections::HashMap;

use super::Light;
use crate::math::{Bounds, LUMINANCE};
use crate::sampling::Discrete;

/// A light to sample: one of the scene's lights, or its environment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightRef {
    /// Light i of the scene's lights.
    Index(usize),
    Environment,
}

impl std::fmt::Display for LightRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LightRef::Index(i) => write!(f, "light {i}"),
            LightRef::Environment => f.write_str("environment"),
        }
    }
}

/// The lights of one shading point's estimate.
pub struct LightPick {
    /// The point and directional lights: each is sampled with probability 1.
    pub delta: std::ops::Range<usize>,
    /// One area light and the probability it was picked with.
    pub area: Option<(LightRef, f32)>,
    /// The point the area light samples itself with: the `u` the pick was
    /// made with, its first number reused (see [`Discrete::sample_reused`]).
    pub u: [f32; 2],
}

/// Light selection for a scene whose lights list the delta lights first.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LightPicker {
    deltas: usize,
    /// The area lights, which follow the deltas, by power; then the
    /// environment, if there is one.
    area: Discrete,
    environment: bool,
    /// The area light each emissive primitive is, by (geom_id, prim_id).
    emitters: HashMap<(u32, u32), u32>,
}

impl LightPicker {
    /// `lights` holds the delta lights first, then the area lights;
    /// `emitters` names the geometry of each area light; `environment` is
    /// the environment light's power (its luminance), if the scene has one.
    pub fn new(
        lights: &[Light],
        emitters: HashMap<(u32, u32), u32>,
        environment: Option<f32>,
    ) -> LightPicker {
        let deltas = lights.iter().take_while(|l| l.is_delta()).count();
        // An area light's power does not depend on the scene's bounds.
        let area = Discrete::new(
            lights[deltas..]
                .iter()
                .map(|l| l.power(Bounds::EMPTY).dot(LUMINANCE))
                .chain(environment),
        );
        LightPicker {
            deltas,
            area,
            environment: environment.is_some(),
            emitters,
        }
    }

    /// The light of the area distribution's item i.
    fn area_light(&self, i: usize) -> LightRef {
        if self.environment && i + 1 == self.area.len() {
            LightRef::Environment
        } else {
            LightRef::Index(self.deltas + i)
        }
    }

    /// The lights to sample, picking the area light with `u[0]` in [0, 1)
    /// and reusing it for the light's point: with stratified `u`, the points
    /// are stratified over all the area lights together (the two triangles
    /// of a quad panel, a mesh's thousands), not only over the choice.
    pub fn pick(&self, u: [f32; 2]) -> LightPick {
        let picked = self.area.sample_reused(u[0]);
        LightPick {
            delta: 0..self.deltas,
            area: picked.map(|(i, p, _)| (self.area_light(i), p)),
            u: [picked.map_or(u[0], |(.., reused)| reused), u[1]],
        }
    }

    /// Whether `pick` uses its `u`: not where the scene has no area light
    /// and no environment, whose points it would sample.
    pub fn uses_u(&self) -> bool {
        !self.area.is_empty()
    }

    /// The light a hit on primitive (geom_id, prim_id) found, with the
    /// probability [`LightPicker::pick`] picks it; None for geometry that is no
    /// sampled light.
    pub fn light_of(&self, geom_id: u32, prim_id: u32) -> Option<(usize, f32)> {
        let &light = self.emitters.get(&(geom_id, prim_id))?;
        let light = light as usize;
        Some((light, self.area.probability(light - self.deltas)))
    }

    /// The probability [`LightPicker::pick`] picks the environment; None
    /// when the scene has none.
    pub fn environment(&self) -> Option<f32> {
        self.environment
            .then(|| self.area.probability(self.area.len() - 1))
    }

    /// How many area lights there are, the environment not counted.
    pub fn area_lights(&self) -> usize {
        self.area.len() - usize::from(self.environment)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    fn sphere(radius: f32) -> Light {
        Light::Sphere {
            center: Vec3::ZERO,
            radius,
            radiance: Vec3::ONE,
        }
    }

    #[test]
    fn area_lights_are_picked_by_power() {
        let point = Light::Point {
            position: Vec3::ZERO,
            intensity: Vec3::ONE,
        };
        // Powers 1 : 3 (radii 1 and √3).
        let lights = [point, sphere(1.0), sphere(3f32.sqrt())];
        let emitters = HashMap::from([((4, 0), 1), ((4, 1), 2)]);
        let picker = LightPicker::new(&lights, emitters, None);
        assert_eq!(picker.area_lights(), 2);
        assert_eq!(picker.environment(), None);
        let pick = picker.pick([0.1, 0.3]);
        assert_eq!(pick.delta, 0..1);
        let (light, p) = pick.area.unwrap();
        assert_eq!(light, LightRef::Index(1));
        assert!((p - 0.25).abs() < 1e-6, "{p}");
        // The pick's number is reused within the light's share, [0, 0.25).
        assert!(
            (pick.u[0] - 0.4).abs() < 1e-6 && pick.u[1] == 0.3,
            "{:?}",
            pick.u
        );
        let pick = picker.pick([0.9, 0.3]);
        let (light, p) = pick.area.unwrap();
        assert_eq!(light, LightRef::Index(2));
        assert!((p - 0.75).abs() < 1e-6, "{p}");
        assert!((pick.u[0] - 0.65 / 0.75).abs() < 1e-6, "{:?}", pick.u);
        // The lookup from geometry gives the same probabilities.
        assert_eq!(
            picker.light_of(4, 1).map(|(i, p)| (LightRef::Index(i), p)),
            picker.pick([0.9, 0.5]).area
        );
        assert_eq!(picker.light_of(4, 7), None);
        // u just below 1 stays in range.
        let top = picker.pick([0.999_999_9, 0.5]);
        assert!(
            top.area.unwrap().0 == LightRef::Index(2) && top.u[0] < 1.0,
            "{:?}",
            top.u
        );
    }

    /// Point lights alone leave the pick's number unused (the Whitted
    /// tracer then draws none); an area light or an environment uses it.
    #[test]
    fn the_pick_uses_its_number_only_for_an_area_light_or_environment() {
        let point = Light::Point {
            position: Vec3::ZERO,
            intensity: Vec3::ONE,
        };
        let points = LightPicker::new(&[point.clone(), point.clone()], HashMap::new(), None);
        assert!(!points.uses_u());
        assert_eq!(points.pick([0.1, 0.2]).area, None);
        let with_area = LightPicker::new(&[point, sphere(1.0)], HashMap::new(), None);
        assert!(with_area.uses_u());
        assert!(LightPicker::new(&[], HashMap::new(), Some(1.0)).uses_u());
    }

    #[test]
    fn the_environment_is_picked_by_its_power_after_the_area_lights() {
        // Powers 1 : 3 : the environment's 4 (in luminance; radius 1: power 4π²).
        let lights = [sphere(1.0), sphere(3f32.sqrt())];
        let unit = sphere(1.0).power(Bounds::EMPTY).dot(LUMINANCE);
        let picker = LightPicker::new(&lights, HashMap::new(), Some(4.0 * unit));
        assert_eq!(picker.area_lights(), 2);
        let (light, p) = picker.pick([0.3, 0.5]).area.unwrap();
        assert_eq!(light, LightRef::Index(1));
        assert!((p - 3.0 / 8.0).abs() < 1e-6, "{p}");
        let (light, p) = picker.pick([0.6, 0.5]).area.unwrap();
        assert_eq!(light, LightRef::Environment);
        assert!((p - 0.5).abs() < 1e-6, "{p}");
        assert_eq!(picker.environment(), Some(p));
        // Alone, it is always picked.
        let alone = LightPicker::new(&[], HashMap::new(), Some(1.0));
        assert_eq!(
            alone.pick([0.9, 0.1]).area,
            Some((LightRef::Environment, 1.0))
        );
        assert_eq!(alone.area_lights(), 0);
    }

    #[test]
    fn no_area_lights_picks_none() {
        let picker = LightPicker::new(&[], HashMap::new(), None);
        let pick = picker.pick([0.5, 0.25]);
        assert!(pick.area.is_none());
        assert_eq!(pick.delta, 0..0);
        assert_eq!(pick.u, [0.5, 0.25]);
    }
}
