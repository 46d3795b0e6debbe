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

use glam::{DAffine3, DVec3};

use super::object::{CsgOp, Kind, LightSource, Obj, clear};
use super::parse::{Loc, Parser};
use super::texture::{Pigment, Texture, default_texture};
use super::{Globals, Statements};
use crate::error::{Error, Result};
use crate::geometry::{Box3, Csg, Leaf, Mesh, Node, Op, Part, Shape, Surface};
use crate::lights::Light;
use crate::math::Vec3;
use crate::poly::solve::Solver;
use crate::scene::solids::{axis_frame, linear, round};
use crate::scene::{Camera, ImagePlane, Integrator, PhotonSettings, RenderSettings, Scene};
use crate::shading::{Material, MaterialKind};

/// Half the side of the world box that cuts what is unbounded.
pub const WORLD: f64 = 1e7;

/// CSG nests at most this deep, as in TOML scenes.
const MAX_NESTING: usize = 32;

/// A tree being built: leaves with their part, or operations.
enum Built {
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
}

struct Builder<'a> {
    parser: &'a mut Parser,
    scene: &'a mut Scene,
    solver: Solver,
    ambient: f32,
}

/// The scene read from `path`.
pub(super) fn scene(
    path: &Path,
    mut parser: Parser,
    statements: Statements,
    size: (u32, u32),
) -> Result<Scene> {
    let Statements {
        objects,
        camera,
        background,
        globals,
    } = statements;
    let render = settings(&globals);
    let mut scene = Scene::empty(path, render, background.as_vec3());
    let resolved = camera
        .resolve()
        .map_err(|m| parser.error_at(camera.loc, m))?;
    let plane = ImagePlane {
        direction: resolved.direction.as_vec3(),
        right: resolved.right.as_vec3(),
        up: resolved.up.as_vec3(),
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
    };
    for obj in &objects {
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
        read: parser.read.clone(),
        skipped: parser.skipped.iter().fold(
            Default::default(),
            |mut m: std::collections::BTreeMap<String, usize>, k| {
                *m.entry(k.clone()).or_default() += 1;
                m
            },
        ),
    });
    Ok(scene)
}

/// POV-Ray's render settings: one ray per pixel through its centre (no
/// anti-aliasing), the Whitted ray tree to `max_trace_level` levels (the
/// camera ray is the first), branches ending below `adc_bailout`, and no
/// photon pass (POV-Ray traces photons only when a scene asks).
fn settings(g: &Globals) -> RenderSettings {
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
        ..defaults
    }
}

impl Builder<'_> {
    /// A top-level object (or a child of a top-level union, which is the
    /// same as its children side by side) placed by `parent`.
    fn top(&mut self, obj: &Obj, parent: DAffine3, texture: Option<&Texture>) -> Result<()> {
        let to_world = parent * obj.transform;
        let texture = obj.texture.as_ref().or(texture);
        match &obj.kind {
            Kind::Light(light) => {
                self.light(light, parent);
                return Ok(());
            }
            Kind::Csg {
                op: CsgOp::Union,
                children,
            } if obj.bounded_by.is_empty() && obj.clipped_by.is_empty() => {
                for child in children {
                    self.top(child, to_world, texture)?;
                }
                return Ok(());
            }
            Kind::Mesh(triangles) => {
                if !obj.clipped_by.is_empty() {
                    self.parser.warn(
                        obj.loc,
                        "a clipped mesh is drawn whole (clipped_by applies to analytic shapes)",
                    );
                }
                return self.mesh(triangles, to_world, texture, obj.ior);
            }
            _ => {}
        }
        if texture.is_some_and(|t| clear(&t.pigment)) {
            return Ok(());
        }
        self.csg_lights(obj, parent);
        let world = Box3::cube(WORLD);
        let Some(built) = self.node(obj, parent, texture, world, 0)? else {
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
        let mut shape = self.shape(built, obj.loc)?;
        if let Some(bound) = obj.bounded_by.first()
            && let Some(gate) = self.gate(bound, to_world)?
        {
            shape.set_gate(gate);
        }
        if obj.no_shadow {
            self.parser
                .skip_warning(obj.loc, "no_shadow", "the object casts shadows");
        }
        self.scene.shapes.push(shape);
        Ok(())
    }

    /// The shape of a `bounded_by` object, placed in the world.
    fn gate(&mut self, bound: &Obj, to_world: DAffine3) -> Result<Option<Shape>> {
        let Some(built) = self.node(bound, to_world, None, Box3::cube(WORLD), 0)? else {
            return Ok(None);
        };
        Ok(Some(self.shape(built, bound.loc)?))
    }

    /// The scene shape of a node: a surface alone as it is, anything else
    /// (a closed solid, whose box's faces are surface too, or an operation)
    /// as a tree.
    fn shape(&mut self, built: Built, loc: Loc) -> Result<Shape> {
        let built = match built {
            Built::Leaf {
                part,
                closed: false,
                inverse: false,
                material,
            } => match *part {
                Part::Solid(shape) | Part::Sheet(shape) => return Ok(shape),
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
        let tree = Csg::new(root, leaves).map_err(|e| self.parser.error_at(loc, e))?;
        Shape::new(
            Surface::Csg(Box::new(tree)),
            DAffine3::IDENTITY,
            None,
            material,
            self.solver,
        )
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

    /// POV-Ray's light: unfading, and a grid of lights for an `area_light`.
    fn light(&mut self, light: &LightSource, to_world: DAffine3) {
        let position = to_world.transform_point3(light.position);
        // π: a light of colour 1 gives POV-Ray's unit diffuse shading (see
        // `Finish::local_brdf`).
        let colour = light.colour * std::f64::consts::PI;
        let Some((a, b, n1, n2)) = light.area else {
            self.scene.lights.push(Light::Unfading {
                position: position.as_vec3(),
                irradiance: colour.as_vec3(),
            });
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
        let share = colour / f64::from(n1 * n2);
        for i in 0..n1 {
            for j in 0..n2 {
                self.scene.lights.push(Light::Unfading {
                    position: (position + step(i, n1) * a + step(j, n2) * b).as_vec3(),
                    irradiance: share.as_vec3(),
                });
            }
        }
    }

    /// The scene's material for `texture` (POV-Ray's default where there is
    /// none) with an interior's `ior`.
    fn material(&mut self, texture: Option<&Texture>, ior: Option<f64>) -> u32 {
        let fallback = default_texture();
        let texture = texture.unwrap_or(&fallback);
        let c = match &texture.pigment {
            Pigment::Colour(c) => *c,
            Pigment::Checker { colours, .. } => {
                let [a, b] = colours;
                std::array::from_fn(|i| 0.5 * (a[i] + b[i]))
            }
        };
        let mut finish = texture.finish;
        finish.transmit = (c[3] + c[4]).clamp(0.0, 1.0) as f32;
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
        let material = Material {
            name: format!("pov {}", self.scene.materials.len()),
            kind: MaterialKind::Classic,
            albedo: DVec3::new(c[0], c[1], c[2])
                .max(DVec3::ZERO)
                .as_vec3()
                .min(Vec3::splat(crate::scene::MAX_COLOUR)),
            specular: Vec3::ZERO,
            shininess: 50.0,
            roughness: finish.roughness,
            ior: ior.unwrap_or(1.0).clamp(1e-3, 100.0) as f32,
            emission: Vec3::ZERO,
            finish,
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
    fn node(
        &mut self,
        obj: &Obj,
        parent: DAffine3,
        inherited: Option<&Texture>,
        context: Box3,
        depth: usize,
    ) -> Result<Option<Built>> {
        if depth > MAX_NESTING {
            return Err(self.parser.error_at(
                obj.loc,
                format!("CSG nests deeper than {MAX_NESTING} levels"),
            ));
        }
        // Nothing of it shows outside its own box either.
        let context = context.intersection(&world_box(obj, parent));
        if context.is_empty() {
            // Cut away by what it is intersected with: nothing of it shows.
            return Ok(None);
        }
        let to_world = parent * obj.transform;
        let texture = obj.texture.as_ref().or(inherited);
        // A clipped object: as a solid, the object and its clips; seen, only the object.
        if !obj.clipped_by.is_empty() {
            let mut inner = obj.clone();
            inner.clipped_by.clear();
            inner.inverse = false;
            let mut children = Vec::new();
            let Some(first) = self.node(&inner, parent, inherited, context, depth + 1)? else {
                return Ok(None);
            };
            children.push(first);
            for c in &obj.clipped_by {
                if let Some(n) = self.node(c, to_world, texture, context, depth + 1)? {
                    children.push(n);
                }
            }
            return Ok(Some(Built::Op {
                op: Op::Clip,
                inverse: obj.inverse,
                children,
            }));
        }
        let material = self.material(texture, obj.ior);
        let leaf = |part: Part, closed: bool| {
            Some(Built::Leaf {
                part: Box::new(part),
                closed,
                inverse: obj.inverse,
                material,
            })
        };
        let solver = self.solver;
        let shape = |this: &Self, surface: Surface, frame: DAffine3, clip: Option<Box3>| {
            Shape::new(surface, to_world * frame, clip, material, solver)
                .map_err(|e| this.parser.error_at(obj.loc, e))
        };
        // An unbounded surface, cut to its context: its crossings are then
        // searched from near the ray, not from a box entry far away.
        let unbounded = |this: &Self, surface: Surface| {
            let mut s = Shape::unclipped(surface, to_world, material, solver)
                .map_err(|e| this.parser.error_at(obj.loc, e))?;
            s.clip_to(&context)
                .map_err(|e| this.parser.error_at(obj.loc, e))?;
            Ok::<Shape, Error>(s)
        };
        Ok(match &obj.kind {
            Kind::Light(_) => None,
            Kind::Sphere { center, radius } => {
                let s = shape(
                    self,
                    Surface::Sphere { radius: *radius },
                    DAffine3::from_translation(*center),
                    None,
                )?;
                leaf(Part::Solid(s), false)
            }
            Kind::Torus { major, minor } => {
                // POV-Ray's torus turns about y; sturmray's about z.
                let frame = DAffine3::from_rotation_x(-std::f64::consts::FRAC_PI_2);
                let s = shape(
                    self,
                    Surface::Torus {
                        major: *major,
                        minor: *minor,
                    },
                    frame,
                    None,
                )?;
                leaf(Part::Solid(s), false)
            }
            Kind::Box { a, b } => {
                let clip = Box3 {
                    min: a.min(*b),
                    max: a.max(*b),
                };
                if clip.min.cmpge(clip.max).any() {
                    self.parser.warn(
                        obj.loc,
                        "a flat box (two corners share a coordinate) is left out",
                    );
                    return Ok(None);
                }
                let inside = crate::geometry::Surface::Quadric(crate::geometry::Quadric {
                    a: glam::DMat3::ZERO,
                    b: DVec3::ZERO,
                    c: -1.0,
                });
                let s = shape(self, inside, DAffine3::IDENTITY, Some(clip))?;
                leaf(Part::Solid(s), true)
            }
            Kind::Round {
                base,
                cap,
                r0,
                r1,
                open,
            } => {
                let (surface, clip) = round(*r0, *r1, (*cap - *base).length());
                let s = shape(self, surface, axis_frame(*base, *cap - *base), Some(clip))?;
                if *open {
                    leaf(Part::Sheet(s), false)
                } else {
                    leaf(Part::Solid(s), true)
                }
            }
            Kind::Disc {
                center,
                normal,
                radius,
                hole,
            } => leaf(
                Part::Disc {
                    to_object: (to_world * axis_frame(*center, *normal)).inverse(),
                    radius: *radius,
                    hole: *hole,
                },
                true,
            ),
            Kind::Plane { normal, distance } => {
                let n = normal.normalize();
                if depth > 0 {
                    // n·p < d in object space is n'·q < n'·M(p0) in the world.
                    let world = to_world.inverse().matrix3.transpose() * n;
                    let p0 = to_world.transform_point3(*distance * n);
                    leaf(
                        Part::Plane {
                            normal: world,
                            offset: world.dot(p0),
                        },
                        false,
                    )
                } else {
                    let s = unbounded(self, linear(n, *distance))?;
                    leaf(Part::Solid(s), false)
                }
            }
            Kind::Quadric { a, b, c } => {
                let surface = Surface::Quadric(crate::geometry::Quadric {
                    a: *a,
                    b: *b,
                    c: *c,
                });
                let s = unbounded(self, surface)?;
                leaf(Part::Solid(s), false)
            }
            Kind::Poly(poly) => {
                if poly.degree() > crate::poly::MAX_DEGREE {
                    return Err(self
                        .parser
                        .error_at(obj.loc, "the polynomial's degree is above 35"));
                }
                let surface = Surface::Algebraic(Box::new(poly.clone()));
                let s = unbounded(self, surface)?;
                leaf(Part::Solid(s), false)
            }
            Kind::Mesh(_) => {
                self.parser.warn(
                    obj.loc,
                    "a mesh inside CSG is left out: it has no inside here",
                );
                None
            }
            Kind::Csg { op, children } => {
                self.operation(obj, *op, children, to_world, texture, context, depth)?
            }
        })
    }

    /// A CSG operation's node. Children that let all light through are
    /// invisible cuts: an intersection with them clips, a difference clips
    /// by their outside, a union or merge leaves them out.
    #[allow(clippy::too_many_arguments)]
    fn operation(
        &mut self,
        obj: &Obj,
        op: CsgOp,
        children: &[Obj],
        to_world: DAffine3,
        texture: Option<&Texture>,
        context: Box3,
        depth: usize,
    ) -> Result<Option<Built>> {
        let is_clear = |c: &Obj| {
            c.texture
                .as_ref()
                .or(texture)
                .is_some_and(|t| clear(&t.pigment))
        };
        let solids: Vec<&Obj> = children
            .iter()
            .filter(|c| !matches!(c.kind, Kind::Light(_)))
            .collect();
        if solids.is_empty() {
            return Ok(None);
        }
        // What bounds the operation: where its children can show.
        let inner = match op {
            CsgOp::Intersection => solids
                .iter()
                .map(|c| world_box(c, to_world))
                .fold(context, |b, c| b.intersection(&c)),
            CsgOp::Difference => world_box(solids[0], to_world).intersection(&context),
            CsgOp::Union | CsgOp::Merge => context,
        };
        let mut shown = Vec::new();
        let mut cuts = Vec::new();
        for (i, child) in solids.iter().enumerate() {
            let Some(node) = self.node(child, to_world, texture, inner, depth + 1)? else {
                // An empty part empties an intersection, and the first part
                // of a difference is all there is.
                if op == CsgOp::Intersection || (op == CsgOp::Difference && i == 0) {
                    return Ok(None);
                }
                continue;
            };
            if is_clear(child) && (op != CsgOp::Difference || i > 0) {
                match op {
                    CsgOp::Intersection => cuts.push(node),
                    CsgOp::Difference => cuts.push(flip(node)),
                    // A clear part of a union shows nothing.
                    CsgOp::Union | CsgOp::Merge => {}
                }
            } else {
                shown.push(node);
            }
        }
        if shown.is_empty() {
            return Ok(None);
        }
        let op = match op {
            CsgOp::Union => Op::Union,
            CsgOp::Intersection => Op::Intersection,
            CsgOp::Difference => Op::Difference,
            CsgOp::Merge => Op::Merge,
        };
        let visible = if shown.len() == 1 && op != Op::Difference {
            shown.pop().expect("one child")
        } else {
            Built::Op {
                op,
                inverse: false,
                children: shown,
            }
        };
        let node = if cuts.is_empty() {
            visible
        } else {
            let mut children = vec![visible];
            children.extend(cuts);
            Built::Op {
                op: Op::Clip,
                inverse: false,
                children,
            }
        };
        Ok(Some(if obj.inverse { flip(node) } else { node }))
    }

    /// A mesh's triangles in the world, each with its texture's material.
    fn mesh(
        &mut self,
        triangles: &[([DVec3; 3], Option<Texture>)],
        to_world: DAffine3,
        texture: Option<&Texture>,
        ior: Option<f64>,
    ) -> Result<()> {
        let mut mesh = Mesh {
            name: format!("mesh {}", self.scene.meshes.len()),
            ..Mesh::default()
        };
        for (corners, own) in triangles {
            let material = self.material(own.as_ref().or(texture), ior);
            let first = mesh.positions.len() as u32;
            for p in corners {
                mesh.positions.push(to_world.transform_point3(*p).as_vec3());
            }
            mesh.triangles.push([first, first + 1, first + 2]);
            mesh.materials.push(material);
        }
        self.scene.meshes.push(mesh);
        Ok(())
    }
}

/// `node` with its inside flipped.
fn flip(node: Built) -> Built {
    match node {
        Built::Leaf {
            part,
            closed,
            inverse,
            material,
        } => Built::Leaf {
            part,
            closed,
            inverse: !inverse,
            material,
        },
        Built::Op {
            op,
            inverse,
            children,
        } => Built::Op {
            op,
            inverse: !inverse,
            children,
        },
    }
}

/// The geometry tree of `built`, its leaves appended to `leaves`.
fn tree(built: Built, leaves: &mut Vec<Leaf>) -> Node {
    match built {
        Built::Leaf {
            part,
            inverse,
            material,
            ..
        } => {
            leaves.push(Leaf {
                part: *part,
                inverse,
                material,
            });
            Node::Leaf(leaves.len() as u32 - 1)
        }
        Built::Op {
            op,
            inverse,
            children,
        } => Node::Op {
            op,
            inverse,
            children: children.into_iter().map(|c| tree(c, leaves)).collect(),
        },
    }
}

/// The world box of an object placed by `parent`: where its inside can be,
/// infinite along the axes it does not bound (a half-space bounds one side
/// of one axis, a quadric cylinder the axes across it), so that the
/// intersections of unbounded parts can still be finite.
fn world_box(obj: &Obj, parent: DAffine3) -> Box3 {
    let to_world = parent * obj.transform;
    let everywhere = Box3 {
        min: DVec3::NEG_INFINITY,
        max: DVec3::INFINITY,
    };
    if obj.inverse {
        return everywhere;
    }
    let local = match &obj.kind {
        Kind::Sphere { center, radius } => Box3 {
            min: *center - *radius,
            max: *center + *radius,
        },
        Kind::Box { a, b } => Box3 {
            min: a.min(*b),
            max: a.max(*b),
        },
        Kind::Torus { major, minor } => Box3 {
            min: DVec3::new(-(major + minor), -minor, -(major + minor)),
            max: DVec3::new(major + minor, *minor, major + minor),
        },
        Kind::Round {
            base, cap, r0, r1, ..
        } => {
            let r = r0.max(*r1);
            Box3 {
                min: base.min(*cap) - r,
                max: base.max(*cap) + r,
            }
        }
        Kind::Disc { center, radius, .. } => Box3 {
            min: *center - *radius,
            max: *center + *radius,
        },
        Kind::Mesh(triangles) => {
            let mut b = Box3 {
                min: DVec3::INFINITY,
                max: DVec3::NEG_INFINITY,
            };
            for (corners, _) in triangles {
                for p in corners {
                    b.min = b.min.min(*p);
                    b.max = b.max.max(*p);
                }
            }
            b
        }
        Kind::Plane { normal, distance } => half_space(*normal, *distance).unwrap_or(everywhere),
        Kind::Quadric { a, b, c } => quadric_box(a, *b, *c).unwrap_or(everywhere),
        Kind::Poly(_) | Kind::Light(_) => everywhere,
        Kind::Csg { op, children } => {
            let mut boxes = children
                .iter()
                .filter(|c| !matches!(c.kind, Kind::Light(_)))
                .map(|c| world_box(c, DAffine3::IDENTITY));
            match op {
                CsgOp::Union | CsgOp::Merge => boxes
                    .reduce(|a, c| Box3 {
                        min: a.min.min(c.min),
                        max: a.max.max(c.max),
                    })
                    .unwrap_or(everywhere),
                CsgOp::Intersection => boxes.fold(everywhere, |a, c| a.intersection(&c)),
                CsgOp::Difference => boxes.next().unwrap_or(everywhere),
            }
        }
    };
    let clipped = obj
        .clipped_by
        .iter()
        .map(|c| world_box(c, DAffine3::IDENTITY))
        .fold(local, |b, c| b.intersection(&c));
    transform_box(&clipped, to_world)
}

/// The half-space n·p < d bounds one side of an axis when n is along it.
fn half_space(normal: DVec3, distance: f64) -> Option<Box3> {
    let n = normal.normalize();
    let axis = (0..3).find(|&i| n[i].abs() == 1.0)?;
    let mut b = Box3 {
        min: DVec3::NEG_INFINITY,
        max: DVec3::INFINITY,
    };
    if n[axis] > 0.0 {
        b.max[axis] = distance;
    } else {
        b.min[axis] = -distance;
    }
    Some(b)
}

/// The inside of Σ aᵢ xᵢ² + b·x + c < 0 with a diagonal, aᵢ ≥ 0 (an
/// ellipsoid, or a cylinder along the axes with aᵢ = 0 and bᵢ = 0): on each
/// axis with aᵢ > 0, |xᵢ + bᵢ/2aᵢ| ≤ √(R/aᵢ), R = Σ bⱼ²/4aⱼ − c.
fn quadric_box(a: &glam::DMat3, b: DVec3, c: f64) -> Option<Box3> {
    let d = DVec3::new(a.x_axis.x, a.y_axis.y, a.z_axis.z);
    let off = [
        a.x_axis.y, a.x_axis.z, a.y_axis.z, a.y_axis.x, a.z_axis.x, a.z_axis.y,
    ];
    if off.iter().any(|v| *v != 0.0) || d.min_element() < 0.0 || d.max_element() <= 0.0 {
        return None;
    }
    if (0..3).any(|i| d[i] == 0.0 && b[i] != 0.0) {
        return None;
    }
    let r = (0..3)
        .filter(|&i| d[i] > 0.0)
        .map(|i| b[i] * b[i] / (4.0 * d[i]))
        .sum::<f64>()
        - c;
    let mut out = Box3 {
        min: DVec3::NEG_INFINITY,
        max: DVec3::INFINITY,
    };
    for i in (0..3).filter(|&i| d[i] > 0.0) {
        let (centre, half) = (-b[i] / (2.0 * d[i]), (r.max(0.0) / d[i]).sqrt());
        out.min[i] = centre - half;
        out.max[i] = centre + half;
    }
    Some(out)
}

/// The box of `b` moved by `m`, by interval arithmetic so that infinite
/// sides stay infinite only along the axes they reach; finite boxes are
/// padded by a millionth of their size so that no surface lies on a face.
fn transform_box(b: &Box3, m: DAffine3) -> Box3 {
    let mut out = Box3 {
        min: m.translation,
        max: m.translation,
    };
    for k in 0..3 {
        for j in 0..3 {
            let f = m.matrix3.col(j)[k];
            if f == 0.0 {
                continue;
            }
            let (p, q) = (f * b.min[j], f * b.max[j]);
            out.min[k] += p.min(q);
            out.max[k] += p.max(q);
        }
    }
    let finite = (out.max - out.min)
        .to_array()
        .into_iter()
        .filter(|v| v.is_finite());
    let pad = 1e-6 * finite.fold(0.0, f64::max).max(1e-300);
    Box3 {
        min: out.min - pad,
        max: out.max + pad,
    }
}
