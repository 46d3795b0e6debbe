//! The render plan: which rays and passes a scene calls for. A diffuse scene
//! spawns no reflection or refraction rays, a scene without lights no shadow
//! rays (the environment light counts as a light), a scene without a light →
//! specular → diffuse path no photon pass (the environment emits no photons);
//! `sturmray info` prints the plan and `--stats` counts prove it.

use std::fmt;

use crate::geometry::Shape;
use crate::scene::{Integrator, Scene};
use crate::shading::{Bsdf, Finish, Material, MaterialKind};

use super::photon;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Plan {
    /// Shadow rays towards lights, from surfaces that shade locally.
    pub shadow: bool,
    /// Shadow rays pass transparent classic surfaces, filtered by each (as
    /// POV-Ray's do): only where some classic material transmits, since
    /// each such ray then finds every surface on its way, not just one.
    pub filtered_shadows: bool,
    /// Specular reflection rays, from mirrors, dielectrics and classic
    /// materials with a reflection (or a transmission that can reflect totally).
    pub reflection: bool,
    /// Refraction rays, through dielectrics and classic materials that transmit.
    pub refraction: bool,
    /// Diffuse and glossy bounces: global illumination, by the path tracer.
    pub diffuse: bool,
    /// The photon pass for caustics: photons from the lights through specular
    /// surfaces to diffuse ones, gathered where the eye's rays meet them.
    pub photon: bool,
    /// POV-Ray's fogs, on every ray's way through the air (a `.pov`
    /// scene's `fog`).
    pub fog: bool,
    /// The depth limit of the ray tree.
    pub max_depth: u32,
    /// Every effect forced on: reflection and refraction rays from every surface,
    /// as a renderer without a plan would trace them. They add nothing to the
    /// image; they only cost time.
    pub forced: bool,
}

impl Plan {
    /// The effects the scene calls for: only materials some geometry uses count.
    pub fn for_scene(scene: &Scene) -> Plan {
        let mut used = vec![false; scene.materials.len()];
        let meshes = scene
            .meshes
            .iter()
            .flat_map(|m| m.materials.iter().copied());
        for m in meshes.chain(scene.shapes.iter().flat_map(Shape::materials)) {
            used[m as usize] = true;
        }
        // A prototype's own materials count once if any instance keeps them.
        let mut kept = vec![false; scene.prototypes.len()];
        for instance in &scene.instances {
            match instance.material {
                Some(m) => used[m as usize] = true,
                None => kept[instance.prototype as usize] = true,
            }
        }
        for (prototype, _) in scene.prototypes.iter().zip(kept).filter(|(_, k)| *k) {
            let meshes = prototype.meshes.iter().flat_map(|m| m.materials.iter());
            for m in meshes
                .copied()
                .chain(prototype.shapes.iter().flat_map(Shape::materials))
            {
                used[m as usize] = true;
            }
        }
        let uses_where = |test: &dyn Fn(&Material) -> bool| {
            scene
                .materials
                .iter()
                .zip(&used)
                .any(|(m, &u)| u && test(m))
        };
        let uses = |kinds: &[MaterialKind]| uses_where(&|m| kinds.contains(&m.kind));
        // A classic material calls for each effect only if its finish has it.
        let classic = |effect: &dyn Fn(&Finish, f32) -> bool| {
            uses_where(&|m| m.kind == MaterialKind::Classic && effect(&m.finish, m.ior))
        };
        let classic_local = classic(&|f, _| f.shades_locally());
        let local = classic_local
            || uses(&[
                MaterialKind::Diffuse,
                MaterialKind::Plastic,
                MaterialKind::Metal,
            ]);
        let deep = scene.render.max_depth > 0;
        // The environment is a light too: shadow rays sample it.
        let shadow = local && (!scene.lights.is_empty() || scene.environment.is_some());
        Plan {
            shadow,
            filtered_shadows: shadow && classic(&|f, _| f.transmits()),
            reflection: deep
                && (uses(&[MaterialKind::Mirror, MaterialKind::Dielectric])
                    || classic(&|f, ior| f.reflects(ior))),
            refraction: deep
                && (uses(&[MaterialKind::Dielectric]) || classic(&|f, _| f.transmits())),
            diffuse: deep
                && scene.render.integrator == Integrator::Path
                && (classic_local
                    || uses(&[
                        MaterialKind::Diffuse,
                        MaterialKind::Plastic,
                        MaterialKind::Metal,
                        MaterialKind::Emissive,
                    ])),
            // A caustic needs a light, a specular surface to bend its light and a
            // diffuse one to catch it.
            photon: deep
                && !scene.lights.is_empty()
                && scene.render.photons.count > 0
                && uses_where(&|m| Bsdf::from_material(m).has_specular())
                && uses_where(&|m| photon::receives(&Bsdf::from_material(m))),
            fog: !scene.fogs.is_empty(),
            max_depth: scene.render.max_depth,
            forced: false,
        }
    }

    /// Every effect on, whatever the scene needs: for measuring what the plan saves.
    pub fn everything(max_depth: u32) -> Plan {
        // (The path tracer has no zero-weight branches to force; `diffuse` only
        // lets it bounce wherever it can.)
        Plan {
            shadow: true,
            filtered_shadows: true,
            reflection: true,
            refraction: true,
            diffuse: true,
            photon: true,
            fog: true,
            max_depth,
            forced: true,
        }
    }
}

impl fmt::Display for Plan {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let on = |b: bool| if b { "yes" } else { "no" };
        let forced = if self.forced {
            ", every effect forced"
        } else {
            ""
        };
        write!(
            f,
            "{} (depth {}{forced}): shadow rays {}{}, reflection rays {}, refraction rays {}, \
             diffuse bounces {}, photon pass {}{}",
            if self.diffuse { "path" } else { "whitted" },
            self.max_depth,
            on(self.shadow),
            if self.filtered_shadows && self.shadow {
                " (filtered by transparent surfaces)"
            } else {
                ""
            },
            on(self.reflection),
            on(self.refraction),
            on(self.diffuse),
            on(self.photon),
            // Only where a scene has one, so other plans read as before.
            if self.fog { ", fog yes" } else { "" }
        )
    }
}
