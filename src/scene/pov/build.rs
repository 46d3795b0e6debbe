//! From what a POV-Ray scene's statements gave to a `Scene`: each texture a
//! classic material; each top-level object a shape, a CSG tree or a mesh;
//! each light source POV-Ray's unfading point light (an `area_light` its
//! grid of them); the camera its image plane.
//!
//! Unbounded parts (planes, quadrics, polynomials) are cut by the box of
//! what they are intersected with, where nothing outside can show; what is
//! unbounded as a whole is cut by the world box, [`WORLD`] from the origin
//! (POV-Ray's own rays end at 1e7). Surfaces that let all light through
//! (POV-Ray's `Clear`) become invisible cuts (`Op::Clip`): that is what
//! POV-Ray draws, a cut face that neither shows nor shadows.

use std::path::Path;

use glam::{DAffine3, DMat3, DVec3};

use super::boxes::world_box;
use super::csg::{Context, tree};
use super::object::{BeamKind, CsgOp, Kind, LightSource, Obj, Triangle, clear};
use super::parse::{Loc, Parser};
use super::texture::{Interior, Pigment, Texture, default_texture};
use super::{Globals, Statements};
use crate::error::Result;
use crate::geometry::{Box3, Csg, CsgError, Mesh, Op, Part, Shape, Surface};
use crate::lights::{Beam, Fade, Light, PovBeam, Shadowing};
use crate::math::Vec3;
use crate::poly::solve::Solver;
use crate::scene::{
    Camera, ImagePlane, Integrator, PhotonSettings, RenderSettings, Scene, WorkingGamma,
};
use crate::shading::{Checker, InteriorFade, Mapped, Material, MaterialKind};

/// Half the side of the world box that cuts what is unbounded.
pub const WORLD: f64 = 1e7;

/// CSG nests at most this deep, as in TOML scenes.
pub(super) const MAX_NESTING: usize = 32;

/// A tree being built: leaves with their part, or operations.
pub(super) enum Built {
    Leaf {
        part: Box<Part>,
        /// A solid whose box's faces are surface even alone (a box, a
        /// capped cylinder): alone it needs a tree.
        closed: bool,
        inverse: bool,
        material: u32,
    },
    Op {
        op: Op,
        inverse: bool,
        children: Vec<Built>,
    },
    /// An object with `clipped_by`: a clip whose inverse is the object's
    /// alone, as POV-Ray inverts an object (by `inverse`, or subtracted)
    /// and never its clips.
    Clipped {
        object: Box<Built>,
        clips: Vec<Built>,
    },
    /// A part of a tree with `bounded_by` (see `Node::Gated`).
    Gated { gate: Box<Shape>, child: Box<Built> },
}

/// What building a scene works on: the parser (for errors and warnings at
/// an object's place), the scene being filled, and settings of the whole.
pub(super) struct Builder<'a> {
    pub(super) parser: &'a mut Parser,
    pub(super) scene: &'a mut Scene,
    pub(super) solver: Solver,
    /// `global_settings { ambient_light }`, as a grey.
    ambient: f32,
    /// Whether POV-Ray culls objects by their boxes in this scene: only
    /// with [`BOUNDING_THRESHOLD`] objects or more (see [`frame_objects`]).
    box_culls: bool,
}

/// Debian's `povray.ini` sets `Bounding_Threshold = 3`: with fewer objects
/// in the scene (lights counted), POV-Ray 3.7 builds no bounding slabs
/// (`BoundingTask::Run`), and its renders show no cull by the box that a
/// removed `bounded_by` leaves (docs/povray.md, "How it maps").
const BOUNDING_THRESHOLD: usize = 3;

/// The objects POV-Ray's frame holds (`Parser::Link_To_Frame`): each
/// top-level object and light, with a union that [`split_union`] splits
/// counted by its children.
fn frame_objects(objects: &[Obj]) -> usize {
    objects
        .iter()
        .map(|o| split_union(o).map_or(1, frame_objects))
        .sum()
}

/// The children of a top-level union that POV-Ray links to its frame one
/// by one: one with neither `bounded_by` nor `clipped_by` (a bounded union
/// stays whole, `Split_Unions` being off by default).
fn split_union(obj: &Obj) -> Option<&[Obj]> {
    match &obj.kind {
        Kind::Csg {
            op: CsgOp::Union,
            children,
        } if obj.bounded_by.is_empty() && obj.clipped_by.is_empty() => Some(children),
        _ => None,
    }
}

/// The scene read from `path`.
pub(super) fn scene(
    path: &Path,
    mut parser: Parser,
    statements: Statements,
    size: (u32, u32),
) -> Result<Scene> {
    let Statements {
        mut objects,
        camera,
        background,
        fogs,
        globals,
    } = statements;
    let render = settings(&globals, parser.version);
    let mut scene = Scene::empty(path, render, background.as_vec3());
    scene.fogs = fogs;
    let resolved = camera
        .resolve()
        .map_err(|m| parser.error_at(camera.loc, m))?;
    if camera.sky_along_view() {
        parser.warn(
            camera.loc,
            "the camera looks along its sky vector: its right vector is kept, as POV-Ray does",
        );
    }
    let plane = ImagePlane {
        direction: resolved.direction,
        right: resolved.right,
        up: resolved.up,
        orthographic: resolved.orthographic,
    };
    scene.camera = Camera::with_plane(resolved.location.as_vec3(), plane, size.0, size.1);
    scene
        .camera
        .check()
        .map_err(|p| parser.error_at(camera.loc, p.message))?;
    let ambient = ((globals.ambient_light.x + globals.ambient_light.y + globals.ambient_light.z)
        / 3.0) as f32;
    let mut builder = Builder {
        parser: &mut parser,
        scene: &mut scene,
        solver: Solver::default(),
        ambient,
        box_culls: frame_objects(&objects) >= BOUNDING_THRESHOLD,
    };
    for obj in &mut objects {
        obj.promote_interior();
        builder.top(obj, DAffine3::IDENTITY, None)?;
    }
    if scene.lights.is_empty() {
        scene.warnings.push(
            "the scene has no light_source: only ambient light shows its objects, as in POV-Ray"
                .into(),
        );
    }
    scene.gather_emitters();
    scene.warnings.extend(parser.warnings.iter().cloned());
    for file in &parser.files[1..] {
        if !scene.sources.contains(file) {
            scene.sources.push(file.clone());
        }
    }
    scene.import = Some(crate::scene::Import {
        read: parser.read,
        skipped: parser.skipped,
    });
    Ok(scene)
}

/// What a `bounded_by` list lets through.
pub(super) enum Bounds {
    /// Every ray (no bound).
    Open,
    /// The rays this gate lets through.
    Gate(Box<Shape>),
    /// No ray: a bound is certainly empty.
    Shut,
}

/// Whether POV-Ray keeps a whole object's `bounded_by`: its parser removes
/// the bound of every object but CSG, `poly` (with `cubic` and `quartic`),
/// text and a quadric whose box it cannot work out, as unnecessary
/// (`Link_To_Frame`, with `Remove_Bounds` on by default), and then draws the
/// object whole. A bound that holds its object changes nothing either way.
fn keeps_bound(kind: &Kind) -> bool {
    match kind {
        Kind::Csg { .. } | Kind::Poly(_) => true,
        Kind::Quadric { a, b, c } => !quadric_boxed(*a, *b, *c),
        _ => false,
    }
}

/// Whether POV-Ray bounds a quadric by a box of its own (`Quadric::
/// Compute_BBox` then sets `Automatic_Bounds`): it has no mixed terms and,
/// once its linear terms are moved into a shift, is an ellipsoid, cylinder,
/// cone, hyperboloid or paraboloid along an axis. Terms under POV-Ray's
/// EPSILON count as zero, as there.
pub(super) fn quadric_boxed(a: DMat3, b: DVec3, c: f64) -> bool {
    const EPSILON: f64 = 1e-10;
    let zeroed = |v: f64| if v.abs() < EPSILON { 0.0 } else { v };
    if [a.y_axis.x, a.z_axis.x, a.z_axis.y]
        .into_iter()
        .any(|m| zeroed(m) != 0.0)
    {
        return false;
    }
    let square = DVec3::new(a.x_axis.x, a.y_axis.y, a.z_axis.z).map(zeroed);
    let mut linear = (b / 2.0).map(zeroed);
    let mut j = zeroed(c);
    if linear != DVec3::ZERO {
        let shift = DVec3::from_array(std::array::from_fn(|k| {
            if square[k] != 0.0 {
                -linear[k] / square[k]
            } else if linear[k] != 0.0 {
                j / (2.0 * linear[k])
            } else {
                0.0
            }
        }));
        linear += square * shift;
        j -= (shift * (square * shift + 2.0 * linear)).element_sum();
    }
    let (square, linear, j) = if square.x < 0.0 {
        (-square, -linear, -j)
    } else {
        (square, linear, j)
    };
    let signs = [square.x, square.y, square.z, j].map(|v| v.partial_cmp(&0.0));
    use std::cmp::Ordering::{Equal as Z, Greater as P, Less as N};
    // Ellipsoid, cylinders along x, y, z, cones, hyperboloids.
    const FORMS: [[std::cmp::Ordering; 4]; 10] = [
        [P, P, P, N],
        [Z, P, P, N],
        [P, Z, P, N],
        [P, P, Z, N],
        [P, N, N, Z],
        [P, N, P, Z],
        [P, P, N, Z],
        [P, N, N, P],
        [P, N, P, N],
        [P, P, N, N],
    ];
    let paraboloid = |k: usize| {
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        square[k] == 0.0 && linear[k] != 0.0 && square[u] * square[v] > 0.0 && j == 0.0
    };
    FORMS.iter().any(|f| f.map(Some) == signs) || (0..3).any(paraboloid)
}

/// The texture `obj` is drawn with, in its own space: its own, or the one
/// it inherits from its parent (given in the parent's space).
pub(super) fn own_texture(obj: &Obj, inherited: Option<&Texture>) -> Option<Texture> {
    obj.texture.clone().or_else(|| {
        inherited.map(|t| {
            let mut t = t.clone();
            t.transform(obj.transform.inverse());
            t
        })
    })
}

/// The space of a scene's colours: its `assumed_gamma`; without one,
/// POV-Ray 3.7 turns gamma handling off for a scene of an older language
/// version (what it computes goes to the file as it is, which the file's
/// sRGB encoding undoes here) and assumes 1 for a 3.7 scene.
fn working_gamma(assumed: Option<WorkingGamma>, version: f64) -> WorkingGamma {
    assumed.unwrap_or(if version < 3.7 {
        WorkingGamma::Srgb
    } else {
        WorkingGamma::Linear
    })
}

/// POV-Ray's render settings: one ray per pixel through its centre (no
/// anti-aliasing), the Whitted ray tree to `max_trace_level` levels (the
/// camera ray is the first), branches ending below `adc_bailout`, no
/// photon pass (POV-Ray traces photons only when a scene asks), and
/// POV-Ray 3.7's gamma rules for a scene of language `version`.
fn settings(g: &Globals, version: f64) -> RenderSettings {
    let defaults = RenderSettings::default();
    RenderSettings {
        spp: 1,
        integrator: Integrator::Whitted,
        max_depth: g.max_trace_level.saturating_sub(1),
        min_weight: g.adc_bailout as f32,
        photons: PhotonSettings {
            count: 0,
            ..defaults.photons
        },
        working_gamma: working_gamma(g.gamma, version),
        ..defaults
    }
}

impl Builder<'_> {
    /// A top-level object (or a child of a top-level union, which is the
    /// same as its children side by side) placed by `parent`.
    fn top(&mut self, obj: &Obj, parent: DAffine3, inherited: Option<&Texture>) -> Result<()> {
        let to_world = parent * obj.transform;
        let own = own_texture(obj, inherited);
        let texture = own.as_ref();
        if let Some(children) = split_union(obj) {
            // The union's `no_shadow` and `hollow` are its parts' too.
            for child in children {
                if (obj.no_shadow && !child.no_shadow) || (obj.hollow && !child.hollow) {
                    let mut child = child.clone();
                    child.no_shadow |= obj.no_shadow;
                    child.hollow |= obj.hollow;
                    self.top(&child, to_world, texture)?;
                } else {
                    self.top(child, to_world, texture)?;
                }
            }
            return Ok(());
        }
        match &obj.kind {
            Kind::Light(light) => {
                self.light(light, parent);
                return Ok(());
            }
            // A bounded union's meshes and triangles have no inside for a
            // tree to hold: drawn beside it, as they would be unbounded (a
            // bound is meant to hold what it bounds), and the rest gated.
            Kind::Csg {
                op: CsgOp::Union,
                children,
            } if obj.clipped_by.is_empty()
                && children.iter().any(|c| matches!(c.kind, Kind::Mesh(_))) =>
            {
                let (meshes, rest): (Vec<Obj>, Vec<Obj>) = children
                    .iter()
                    .cloned()
                    .partition(|c| matches!(c.kind, Kind::Mesh(_)));
                for mut mesh in meshes {
                    mesh.no_shadow |= obj.no_shadow;
                    self.top(&mesh, to_world, texture)?;
                }
                if rest.is_empty() {
                    return Ok(());
                }
                let mut others = obj.clone();
                others.kind = Kind::Csg {
                    op: CsgOp::Union,
                    children: rest,
                };
                return self.top(&others, parent, inherited);
            }
            Kind::Mesh(triangles) => {
                if !obj.clipped_by.is_empty() {
                    self.parser.warn(
                        obj.loc,
                        "a clipped mesh is drawn whole (clipped_by applies to analytic shapes)",
                    );
                }
                if obj.no_shadow {
                    self.parser
                        .skip_warning(obj.loc, "no_shadow", "a mesh casts shadows");
                }
                return self.mesh(triangles, to_world, texture, obj.interior.as_ref());
            }
            _ => {}
        }
        if texture.is_some_and(|t| clear(&t.pigment)) {
            return Ok(());
        }
        self.csg_lights(obj, parent);
        let world = Box3::cube(WORLD);
        let Some(built) = self.node(obj, parent, inherited, Context::world(world), 0)? else {
            return Ok(());
        };
        // `inverse` on an object alone changes nothing POV-Ray draws.
        let built = match built {
            Built::Leaf {
                part,
                closed,
                material,
                ..
            } => Built::Leaf {
                part,
                closed,
                inverse: false,
                material,
            },
            op => op,
        };
        let Some(mut shape) = self.shape(built, obj.loc)? else {
            return Ok(());
        };
        // A bound that is the object's own clip holds every point the clip
        // lets show, so every ray with a hit passes it: the clip's span,
        // found first on every ray, already decides what the gate would.
        // helix.pov's gates were a fifth of its render-loop instructions.
        if !obj.bound_is_clip {
            match self.whole_gate(obj, parent)? {
                Bounds::Gate(gate) => {
                    if shape.needs_gate(&gate) {
                        shape.set_gate(*gate);
                    }
                }
                Bounds::Shut => {
                    self.parser.warn(
                        obj.loc,
                        "no ray can pass this object's bounded_by (a bound is empty, or \
                         their boxes do not overlap): it is left out, as POV-Ray draws \
                         nothing of it",
                    );
                    return Ok(());
                }
                Bounds::Open => {}
            }
        }
        if obj.no_shadow {
            shape.set_no_shadow();
        }
        if obj.hollow {
            shape.set_hollow();
        }
        self.scene.shapes.push(shape);
        Ok(())
    }

    /// The gate of a whole object's `bounded_by`, as POV-Ray draws it: the
    /// bounds themselves where it keeps
    /// them (`keeps_bound`), and the box of their boxes where that is
    /// smaller than the object's own box, since POV-Ray culls the object by
    /// it (`Intersect_BBox`). The box adds nothing to one kept bound, which
    /// every ray that meets it meets. Below POV-Ray's bounding threshold
    /// there is no box test (`box_culls`). `Shut` where no ray can pass:
    /// a bound that is certainly empty, or bounds whose boxes are apart.
    fn whole_gate(&mut self, obj: &Obj, parent: DAffine3) -> Result<Bounds> {
        let to_world = parent * obj.transform;
        let kept = keeps_bound(&obj.kind);
        let bounds = if kept {
            self.gates(&obj.bounded_by, to_world)?
        } else {
            Bounds::Open
        };
        if !self.box_culls {
            return Ok(bounds);
        }
        let everywhere = Box3::cube(f64::INFINITY);
        let boxed = obj
            .bounded_by
            .iter()
            .filter(|b| !b.inverse)
            .map(|b| world_box(b, to_world))
            .fold(everywhere, |a, b| a.intersection(&b));
        if boxed.is_empty() {
            return Ok(Bounds::Shut);
        }
        let volume = |b: &Box3| (b.max - b.min).max(DVec3::ZERO).element_product();
        let culls = (!kept || obj.bounded_by.len() > 1)
            && boxed.min.is_finite()
            && boxed.max.is_finite()
            && volume(&boxed) < volume(&world_box(obj, parent));
        let cull = if culls {
            let cube = Obj::new(
                Kind::Box {
                    a: boxed.min,
                    b: boxed.max,
                },
                obj.loc,
            );
            self.gates(&[cube], DAffine3::IDENTITY)?
        } else {
            Bounds::Open
        };
        Ok(match (cull, bounds) {
            (Bounds::Shut, _) | (_, Bounds::Shut) => Bounds::Shut,
            (Bounds::Gate(mut cull), Bounds::Gate(bounds)) => {
                cull.set_gate(*bounds);
                Bounds::Gate(cull)
            }
            (Bounds::Gate(gate), Bounds::Open) | (Bounds::Open, Bounds::Gate(gate)) => {
                Bounds::Gate(gate)
            }
            (Bounds::Open, Bounds::Open) => Bounds::Open,
        })
    }

    /// The gate of a `bounded_by` list, placed in the world: each object's
    /// shape gated by the next's, since POV-Ray lets a ray through only if it
    /// meets every bound (`Ray_In_Bound`). `Open` for an empty list, `Shut`
    /// where a bound is certainly empty (an intersection of objects apart),
    /// which no ray meets.
    pub(super) fn gates(&mut self, bounds: &[Obj], to_world: DAffine3) -> Result<Bounds> {
        let mut chain = None;
        for bound in bounds.iter().rev() {
            let Some(built) =
                self.node(bound, to_world, None, Context::world(Box3::cube(WORLD)), 0)?
            else {
                return Ok(Bounds::Shut);
            };
            let Some(mut gate) = self.shape(built, bound.loc)? else {
                return Ok(Bounds::Shut);
            };
            if let Some(next) = chain.take() {
                gate.set_gate(next);
            }
            chain = Some(gate);
        }
        Ok(chain.map_or(Bounds::Open, |gate| Bounds::Gate(Box::new(gate))))
    }

    /// The scene shape of a node: a surface alone as it is, anything else
    /// (a closed solid, whose box's faces are surface too, or an operation)
    /// as a tree; None, with a warning, for a tree that is certainly empty
    /// (an intersection of objects apart), which POV-Ray draws as nothing.
    fn shape(&mut self, built: Built, loc: Loc) -> Result<Option<Shape>> {
        let built = match built {
            Built::Leaf {
                part,
                closed: false,
                inverse: false,
                material,
            } => match *part {
                Part::Solid(shape) | Part::Sheet(shape) => return Ok(Some(shape)),
                part => Built::Leaf {
                    part: Box::new(part),
                    closed: false,
                    inverse: false,
                    material,
                },
            },
            built => built,
        };
        let mut leaves = Vec::new();
        let root = tree(built, &mut leaves);
        let material = leaves.first().map_or(0, |l| l.material);
        let tree = match Csg::within(root, leaves, Box3::cube(WORLD)) {
            Ok(tree) => tree,
            Err(CsgError::Empty) => {
                self.parser.warn(
                    loc,
                    "this object is empty (its parts do not overlap): it is left out, \
                     as POV-Ray draws nothing of it",
                );
                return Ok(None);
            }
            Err(e) => return Err(self.parser.error_at(loc, e.to_string())),
        };
        Shape::new(
            Surface::Csg(Box::new(tree)),
            DAffine3::IDENTITY,
            None,
            material,
            self.solver,
        )
        .map(Some)
        .map_err(|e| self.parser.error_at(loc, e))
    }

    /// Lights inside a CSG tree, which light the scene from where they are.
    fn csg_lights(&mut self, obj: &Obj, parent: DAffine3) {
        let to_world = parent * obj.transform;
        if let Kind::Csg { children, .. } = &obj.kind {
            for child in children {
                match &child.kind {
                    Kind::Light(l) => self.light(l, to_world),
                    Kind::Csg { .. } => self.csg_lights(child, to_world),
                    _ => {}
                }
            }
        }
    }

    /// POV-Ray's light: unfading unless it has a fade, and a grid of
    /// lights for an `area_light`.
    fn light(&mut self, light: &LightSource, to_world: DAffine3) {
        let position = to_world.transform_point3(light.position);
        // π: a light of colour 1 gives POV-Ray's unit diffuse shading (see
        // `Finish::local_brdf`).
        let colour = light.colour * std::f64::consts::PI;
        // One axis, from the centre, for every light of a grid (POV-Ray's).
        let direction = (to_world.transform_point3(light.point_at) - position).normalize_or_zero();
        // Every light of a grid fades from the centre, as POV-Ray's area
        // light does (without `area_illumination`).
        let fade = Fade::new(light.fade_distance, light.fade_power, position.as_vec3());
        let shadowing = Shadowing {
            shadowless: light.shadowless,
            fogged: light.media_attenuation && light.media_interaction,
        };
        let one = |position: DVec3, irradiance: DVec3| match beam(light) {
            None => Light::PovPoint {
                position: position.as_vec3(),
                irradiance: irradiance.as_vec3(),
                fade,
                shadowing,
            },
            Some(beam) => Light::PovBeam(PovBeam {
                position: position.as_vec3(),
                direction: direction.as_vec3(),
                irradiance: irradiance.as_vec3(),
                beam,
                parallel: light.parallel,
                fade,
                shadowing,
            }),
        };
        let Some((a, b, n1, n2)) = light.area else {
            self.scene.lights.push(one(position, colour));
            return;
        };
        let (a, b) = (to_world.transform_vector3(a), to_world.transform_vector3(b));
        let step = |i: u32, n: u32| {
            if n > 1 {
                f64::from(i) / f64::from(n - 1) - 0.5
            } else {
                0.0
            }
        };
        // POV-Ray's `circular` grid: each square ring of the grid moved
        // onto the circle inside it, from a centre 0.001 off the grid's own
        // (POV-Ray's, which also keeps the middle point from 0 / 0). With
        // one light along an edge POV-Ray divides by zero; here the grid
        // then stays a line.
        let bend = |(u, v): (f64, f64)| {
            if !light.circular || n1 < 2 || n2 < 2 {
                return (u, v);
            }
            let (u, v) = (u + 0.001, v + 0.001);
            let k = u.abs().max(v.abs()) / u.hypot(v);
            (u * k, v * k)
        };
        let share = colour / f64::from(n1 * n2);
        for i in 0..n1 {
            for j in 0..n2 {
                let (u, v) = bend((step(i, n1), step(j, n2)));
                self.scene.lights.push(one(position + u * a + v * b, share));
            }
        }
    }

    /// The scene's material for `texture` (POV-Ray's default where there is
    /// none) with an interior's ior and fade.
    pub(super) fn material(
        &mut self,
        texture: Option<&Texture>,
        interior: Option<&Interior>,
        to_world: DAffine3,
    ) -> u32 {
        let fallback = default_texture();
        let texture = texture.unwrap_or(&fallback);
        let rgb = |c: &[f64; 5]| {
            let v = DVec3::new(c[0], c[1], c[2]).as_vec3();
            v.clamp(Vec3::ZERO, Vec3::splat(crate::scene::MAX_COLOUR))
        };
        let mut mapped = None;
        let (c, checker) = match &texture.pigment {
            Pigment::Colour(c) => (*c, None),
            // The albedo where the pattern is not drawn (a mesh's uv) and
            // filter and transmit are the map's mean (POV-Ray's vary with
            // the pattern).
            Pigment::Mapped { spec, to_owner } => {
                mapped = Some(Mapped {
                    kind: spec.kind,
                    wave: spec.wave,
                    frequency: spec.frequency,
                    phase: spec.phase,
                    map: spec.map.iter().map(|(v, c)| (*v, rgb(c))).collect(),
                    to_pattern: (to_world * *to_owner).inverse(),
                });
                (texture.pigment.mean_colour(), None)
            }
            // Filter and transmit are the first colour's (POV-Ray's are per
            // cube; the subset's checkered floors are opaque).
            Pigment::Checker { colours, to_owner } => (
                colours[0],
                Some(Checker {
                    colours: [rgb(&colours[0]), rgb(&colours[1])],
                    to_pattern: (to_world * *to_owner).inverse(),
                }),
            ),
        };
        let mut finish = texture.finish;
        finish.transmit = (c[3] + c[4]).clamp(0.0, 1.0) as f32;
        finish.filter = (c[3].max(0.0) as f32).min(finish.transmit);
        finish.ambient *= self.ambient;
        for v in [
            &mut finish.diffuse,
            &mut finish.ambient,
            &mut finish.specular,
            &mut finish.phong,
            &mut finish.reflection,
            &mut finish.reflection_max,
            &mut finish.metallic,
        ] {
            *v = v.clamp(0.0, 1.0);
        }
        finish.roughness = finish.roughness.clamp(1e-4, 1.0);
        finish.phong_size = finish.phong_size.max(1e-3);
        // 0 lights a surface evenly; far above POV-Ray's own 1-10 only
        // overflows the power.
        finish.brilliance = finish.brilliance.clamp(0.0, 1000.0);
        let interior = interior.copied().unwrap_or_default();
        finish.fade = InteriorFade::new(
            interior.fade_distance,
            interior.fade_power,
            DVec3::from(interior.fade_colour).as_vec3(),
        );
        let material = Material {
            name: format!("pov {}", self.scene.materials.len()),
            kind: MaterialKind::Classic,
            albedo: rgb(&c),
            specular: Vec3::ZERO,
            shininess: 50.0,
            roughness: finish.roughness,
            ior: interior.ior.clamp(1e-3, 100.0) as f32,
            emission: Vec3::ZERO,
            finish,
            checker,
            mapped,
            albedo_map: None,
            maps: Default::default(),
        };
        let same = |m: &Material| Material {
            name: String::new(),
            ..m.clone()
        };
        let key = same(&material);
        if let Some(i) = self.scene.materials.iter().position(|m| same(m) == key) {
            return i as u32;
        }
        self.scene.materials.push(material);
        self.scene.materials.len() as u32 - 1
    }

    /// The tree node of `obj`, placed by `parent`, in `context` (a world
    /// box outside which nothing of it can show): None for what draws
    /// nothing (a light).
    /// A mesh's triangles in the world, each with its texture's material;
    /// a `smooth_triangle`'s corners with their normals, the others' with
    /// none (zero: shaded flat), if any triangle is smooth.
    fn mesh(
        &mut self,
        triangles: &[Triangle],
        to_world: DAffine3,
        texture: Option<&Texture>,
        interior: Option<&Interior>,
    ) -> Result<()> {
        let mut mesh = Mesh {
            name: format!("mesh {}", self.scene.meshes.len()),
            ..Mesh::default()
        };
        let smooth = triangles.iter().any(|t| t.normals.is_some());
        // Normals map by the inverse transpose, so they stay normal to
        // the surface under a scale.
        let normal_map = to_world.matrix3.inverse().transpose();
        for triangle in triangles {
            let material = self.material(triangle.texture.as_ref().or(texture), interior, to_world);
            let first = mesh.positions.len() as u32;
            for p in triangle.corners {
                mesh.positions.push(to_world.transform_point3(p).as_vec3());
            }
            if smooth {
                let normals = triangle.normals.unwrap_or([DVec3::ZERO; 3]);
                for n in normals {
                    mesh.normals
                        .push((normal_map * n).normalize_or_zero().as_vec3());
                }
            }
            mesh.triangles.push([first, first + 1, first + 2]);
            mesh.materials.push(material);
        }
        self.scene.meshes.push(mesh);
        Ok(())
    }
}

/// A POV-Ray light's beam; None for a plain point light, which is
/// `Light::PovPoint`.
fn beam(light: &LightSource) -> Option<Beam> {
    let (radius, falloff, tightness) = (
        light.radius as f32,
        light.falloff as f32,
        light.tightness as f32,
    );
    match light.beam {
        BeamKind::Point => light.parallel.then_some(Beam::Round),
        BeamKind::Spot => Some(Beam::Spot {
            cos_radius: light.radius.to_radians().cos() as f32,
            cos_falloff: light.falloff.to_radians().cos() as f32,
            tightness,
        }),
        BeamKind::Cylinder => Some(Beam::Cylinder {
            radius,
            falloff,
            tightness,
        }),
    }
}
