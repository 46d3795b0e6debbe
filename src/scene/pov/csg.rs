//! The CSG trees of a POV-Ray scene: each object a node (a leaf with its
//! part, or an operation), placed by its parents, cut to its context (the
//! world box where it can show), and clear parts turned into invisible cuts.

use glam::{DAffine3, DVec3};

use super::boxes::{framed_box, world_box};
use super::build::{Bounds, Builder, Built, MAX_NESTING, own_texture};
use super::object::{CsgOp, Kind, Obj, clear};
use super::texture::Texture;
use crate::error::{Error, Result};
use crate::geometry::{Box3, Leaf, Node, Op, Part, Shape, Surface};
use crate::scene::solids::{axis_frame, linear, round};

/// Where a node can show: a world box, and the box of the nearest object
/// above it (or itself) whose own box is finite, in that object's space.
/// An unbounded surface is cut to both: mapped into the surface's space, a
/// world box widens under every rotation on the way (helix.pov's clipped
/// quartics, turned twice, got boxes three times as wide as their clips),
/// while a box in the frame the surface shares with its clip does not.
/// `inverted`: whether the node's inside ends up inverted (by `inverse`
/// or by being subtracted) an odd number of times.
#[derive(Clone, Copy)]
pub(super) struct Context {
    world: Box3,
    framed: Option<(Box3, DAffine3)>,
    inverted: bool,
}

impl Context {
    pub(super) fn world(world: Box3) -> Context {
        Context {
            world,
            framed: None,
            inverted: false,
        }
    }
}

impl Builder<'_> {
    pub(super) fn node(
        &mut self,
        obj: &Obj,
        parent: DAffine3,
        inherited: Option<&Texture>,
        context: Context,
        depth: usize,
    ) -> Result<Option<Built>> {
        if depth > MAX_NESTING {
            return Err(self.parser.error_at(
                obj.loc,
                format!("CSG nests deeper than {MAX_NESTING} levels"),
            ));
        }
        let to_world = parent * obj.transform;
        // A part's bound gates the part (a whole object's gates the shape,
        // see `Builder::top`); one copied from its clip decides nothing.
        if depth > 0 && !obj.bounded_by.is_empty() && !obj.bound_is_clip {
            let mut inner = obj.clone();
            inner.bounded_by.clear();
            let Some(child) = self.node(&inner, parent, inherited, context, depth)? else {
                return Ok(None);
            };
            return Ok(Some(match self.gates(&obj.bounded_by, to_world)? {
                Bounds::Gate(gate) => Built::Gated {
                    gate,
                    child: Box::new(child),
                },
                // A bound no ray passes hides the part's surface, which
                // `operation` decides (`bound_shut`).
                Bounds::Open | Bounds::Shut => child,
            }));
        }
        // Nothing of it shows outside its own box either.
        let own = framed_box(obj);
        let outer = context;
        let context = Context {
            world: context.world.intersection(&world_box(obj, parent)),
            framed: if own.min.is_finite() && own.max.is_finite() {
                Some((own, to_world))
            } else {
                context.framed
            },
            inverted: context.inverted,
        };
        if context.world.is_empty() {
            // Cut away by what it is intersected with: nothing of it shows.
            return Ok(None);
        }
        let own = own_texture(obj, inherited);
        let texture = own.as_ref();
        // A clipped object: as a solid, the object and its clips; seen, only
        // the object. Inverted, it is the object inverted within its clips
        // (see `Built::Clipped`).
        if !obj.clipped_by.is_empty() {
            // Its bound, if any, gates the whole object: above (see `top`),
            // or at the top of this function.
            let mut inner = obj.clone();
            inner.clipped_by.clear();
            inner.bounded_by.clear();
            let Some(object) = self.node(&inner, parent, inherited, context, depth + 1)? else {
                return Ok(None);
            };
            // Inverted, the object within its clips reaches past its own
            // box: the clips are cut only to where its parent can show.
            let within = if context.inverted != obj.inverse {
                Context {
                    inverted: false,
                    ..outer
                }
            } else {
                Context {
                    inverted: false,
                    ..context
                }
            };
            let mut clips = Vec::new();
            for c in &obj.clipped_by {
                if let Some(n) = self.node(c, to_world, texture, within, depth + 1)? {
                    clips.push(n);
                }
            }
            return Ok(Some(Built::Clipped {
                object: Box::new(object),
                clips,
            }));
        }
        let material = self.material(texture, obj.interior.as_ref(), to_world);
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
        // searched from near the ray, not from a box entry far away. The
        // context's boxes are finite, so a cut that fails leaves nothing:
        // none of it can show (an ellipsoid apart from what it is
        // intersected with).
        let unbounded = |this: &Self, surface: Surface| {
            let mut s = Shape::unclipped(surface, to_world, material, solver)
                .map_err(|e| this.parser.error_at(obj.loc, e))?;
            let framed = context
                .framed
                .is_none_or(|(b, frame)| s.clip_within(&b, frame).is_ok());
            let kept = framed && s.clip_to(&context.world).is_ok();
            Ok::<Option<Shape>, Error>(kept.then_some(s))
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
                let inside = crate::geometry::Surface::Quadric(crate::geometry::Quadric {
                    a: glam::DMat3::ZERO,
                    b: DVec3::ZERO,
                    c: -1.0,
                });
                let flat: Vec<usize> = (0..3).filter(|&i| clip.min[i] >= clip.max[i]).collect();
                match flat[..] {
                    [] => {
                        let s = shape(self, inside, DAffine3::IDENTITY, Some(clip))?;
                        leaf(Part::Solid(s), true)
                    }
                    // Alone, a box flat along one axis is the rectangle
                    // POV-Ray draws: the plane there, clipped to the box
                    // made deep along that axis (whose faces are not seen).
                    [axis] if depth == 0 => {
                        let mut deep = clip;
                        deep.min[axis] -= 1.0;
                        deep.max[axis] += 1.0;
                        let s = shape(self, inside, DAffine3::IDENTITY, Some(deep))?;
                        let part = |part: Part, closed: bool| Built::Leaf {
                            part: Box::new(part),
                            closed,
                            inverse: false,
                            material,
                        };
                        Some(Built::Op {
                            op: Op::Clip,
                            inverse: false,
                            children: vec![
                                part(half_space(to_world, DVec3::AXES[axis], clip.min), false),
                                part(Part::Solid(s), true),
                            ],
                        })
                    }
                    _ => {
                        self.parser.warn(
                            obj.loc,
                            "a flat box is left out: in CSG it has no inside, and flat along \
                             two axes it is a line",
                        );
                        return Ok(None);
                    }
                }
            }
            Kind::Round {
                base,
                cap,
                r0,
                r1,
                open,
            } => {
                let length = (*cap - *base).length();
                let (surface, clip) = round(*r0, *r1, length);
                let frame = axis_frame(*base, *cap - *base);
                if !*open {
                    let s = shape(self, surface, frame, Some(clip))?;
                    leaf(Part::Solid(s), true)
                } else if depth == 0 {
                    // Alone, only its surface counts: a tube with no inside.
                    let s = shape(self, surface, frame, Some(clip))?;
                    leaf(Part::Sheet(s), false)
                } else {
                    // In CSG, POV-Ray's open tube keeps the capped solid's
                    // inside and shows no caps: the solid a little longer,
                    // clipped to the slab between the caps' planes, whose
                    // faces are never seen (see `open_tube`).
                    let (longer, [below, above]) = open_tube(clip, *r0, *r1, to_world * frame);
                    let s = shape(self, surface, frame, Some(longer))?;
                    let plane = |part: Part| Built::Leaf {
                        part: Box::new(part),
                        closed: false,
                        inverse: false,
                        material,
                    };
                    Some(Built::Op {
                        op: Op::Clip,
                        inverse: obj.inverse,
                        children: vec![
                            Built::Leaf {
                                part: Box::new(Part::Solid(s)),
                                closed: true,
                                inverse: false,
                                material,
                            },
                            plane(below),
                            plane(above),
                        ],
                    })
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
                    // In CSG, POV-Ray's disc is inside behind its plane.
                    half_space: depth > 0,
                },
                true,
            ),
            Kind::Plane { normal, distance } => {
                let n = normal.normalize();
                if depth > 0 {
                    leaf(half_space(to_world, n, *distance * n), false)
                } else {
                    let Some(s) = unbounded(self, linear(n, *distance))? else {
                        return Ok(None);
                    };
                    leaf(Part::Solid(s), false)
                }
            }
            Kind::Quadric { a, b, c } => {
                let surface = Surface::Quadric(crate::geometry::Quadric {
                    a: *a,
                    b: *b,
                    c: *c,
                });
                let Some(s) = unbounded(self, surface)? else {
                    return Ok(None);
                };
                leaf(Part::Solid(s), false)
            }
            Kind::Poly(poly) => {
                if poly.degree() > crate::poly::MAX_DEGREE {
                    return Err(self
                        .parser
                        .error_at(obj.loc, "the polynomial's degree is above 35"));
                }
                let surface = Surface::Algebraic(Box::new(poly.clone()));
                let Some(s) = unbounded(self, surface)? else {
                    return Ok(None);
                };
                leaf(Part::Solid(s), false)
            }
            Kind::Mesh(_) => {
                self.parser.warn(
                    obj.loc,
                    "a mesh or triangle inside CSG is left out: it has no inside here",
                );
                None
            }
            Kind::Csg { op, children } => {
                self.operation(obj, *op, children, to_world, texture, context, depth)?
            }
        })
    }

    /// Whether a part's own `bounded_by` lets no ray through (a bound that
    /// is certainly empty). POV-Ray then never intersects the part, but
    /// still asks whether points are inside it (`Inside_Object` ignores
    /// bounds), so the part is an invisible cut, as a clear one is.
    fn bound_shut(&mut self, obj: &Obj, parent: DAffine3) -> Result<bool> {
        Ok(!obj.bounded_by.is_empty()
            && !obj.bound_is_clip
            && matches!(
                self.gates(&obj.bounded_by, parent * obj.transform)?,
                Bounds::Shut
            ))
    }

    /// A CSG operation's node. Children that let all light through, or
    /// whose bound no ray passes, are invisible cuts: an intersection with
    /// them clips, a difference clips by their outside, a union or merge
    /// leaves them out.
    #[allow(clippy::too_many_arguments)]
    fn operation(
        &mut self,
        obj: &Obj,
        mut op: CsgOp,
        children: &[Obj],
        to_world: DAffine3,
        texture: Option<&Texture>,
        context: Context,
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
        let world = match op {
            CsgOp::Intersection => solids
                .iter()
                .map(|c| world_box(c, to_world))
                .fold(context.world, |b, c| b.intersection(&c)),
            CsgOp::Difference => world_box(solids[0], to_world).intersection(&context.world),
            CsgOp::Union | CsgOp::Merge => context.world,
        };
        let inner = Context { world, ..context };
        let mut shown = Vec::new();
        let mut cuts = Vec::new();
        for (i, child) in solids.iter().enumerate() {
            let subtracted = op == CsgOp::Difference && i > 0;
            let inner = Context {
                inverted: (context.inverted != obj.inverse) != subtracted,
                ..inner
            };
            let hidden = self.bound_shut(child, to_world)?;
            let Some(node) = self.node(child, to_world, texture, inner, depth + 1)? else {
                // An empty part empties an intersection, and the first part
                // of a difference is all there is.
                if op == CsgOp::Intersection || (op == CsgOp::Difference && i == 0) {
                    return Ok(None);
                }
                continue;
            };
            if hidden && op == CsgOp::Difference && i == 0 {
                self.parser.warn(
                    child.loc,
                    "no ray can pass this part's bounded_by (a bound is empty): the first \
                     part of a difference is drawn without it, where POV-Ray shows no \
                     surface of it",
                );
            }
            if (is_clear(child) || hidden) && (op != CsgOp::Difference || i > 0) {
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
        // POV-Ray subtracts by inverting, and inverting a clipped object
        // keeps its clips (`Built::Clipped`): A minus B clipped by C is A
        // where B is not and C is. So such a difference is the
        // intersection of its first child and its others inverted.
        if op == CsgOp::Difference && shown[1..].iter().any(holds_clipped) {
            let mut parts = shown.into_iter();
            let first = parts.next().expect("a first child");
            shown = std::iter::once(first).chain(parts.map(flip)).collect();
            op = CsgOp::Intersection;
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
}

/// `node` with its inside flipped, as POV-Ray inverts an object: an
/// operation by De Morgan's laws, its children inverted, wherever a clipped
/// object below it must keep its clips (`Built::Clipped`); otherwise, with
/// the same inside, by the node's own flag.
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
            inverse: false,
            children,
        } if op != Op::Clip && children.iter().any(holds_clipped) => {
            let (op, children) = match op {
                Op::Union | Op::Merge => {
                    (Op::Intersection, children.into_iter().map(flip).collect())
                }
                Op::Intersection => (Op::Merge, children.into_iter().map(flip).collect()),
                // A minus the rest, inverted: outside A, or inside any of the rest.
                _ => {
                    let mut parts = children.into_iter();
                    let first = parts.next().map(flip);
                    (Op::Merge, first.into_iter().chain(parts).collect())
                }
            };
            Built::Op {
                op,
                inverse: false,
                children,
            }
        }
        Built::Op {
            op,
            inverse,
            children,
        } => Built::Op {
            op,
            inverse: !inverse,
            children,
        },
        Built::Clipped { object, clips } => Built::Clipped {
            object: Box::new(flip(*object)),
            clips,
        },
        Built::Gated { gate, child } => Built::Gated {
            gate,
            child: Box::new(flip(*child)),
        },
    }
}

/// Whether a clipped object is among `node`'s parts, outside any clip of
/// the reader's own (whose inverse is always the whole node's).
fn holds_clipped(node: &Built) -> bool {
    match node {
        Built::Leaf { .. } => false,
        Built::Op { op, children, .. } => *op != Op::Clip && children.iter().any(holds_clipped),
        Built::Clipped { .. } => true,
        Built::Gated { child, .. } => holds_clipped(child),
    }
}

/// The geometry tree of `built`, its leaves appended to `leaves`.
pub(super) fn tree(built: Built, leaves: &mut Vec<Leaf>) -> Node {
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
        Built::Clipped { object, clips } => Node::Op {
            op: Op::Clip,
            inverse: false,
            children: std::iter::once(*object)
                .chain(clips)
                .map(|c| tree(c, leaves))
                .collect(),
        },
        Built::Gated { gate, child } => Node::Gated {
            gate,
            child: Box::new(tree(*child, leaves)),
        },
    }
}

/// For an open cylinder or cone in CSG, with its capped box `clip` (its
/// axis along z from 0 to the length, in the frame `to_world` places): a
/// box an eighth of the length longer at each end, wide enough for the
/// surface there, and the two half-spaces between the caps' planes.
/// Clipped to them, the longer solid is POV-Ray's open tube: the capped
/// solid's inside (its `Inside` test ignores `open`), with its faces
/// beyond the caps never seen.
fn open_tube(clip: Box3, r0: f64, r1: f64, to_world: DAffine3) -> (Box3, [Part; 2]) {
    let length = clip.max.z;
    let margin = length / 8.0;
    let reach = clip.max.x + (r1 - r0).abs() / length * margin;
    let longer = Box3 {
        min: DVec3::new(-reach, -reach, -margin),
        max: DVec3::new(reach, reach, length + margin),
    };
    let slab = [
        half_space(to_world, DVec3::NEG_Z, DVec3::ZERO),
        half_space(to_world, DVec3::Z, DVec3::new(0.0, 0.0, length)),
    ];
    (longer, slab)
}

/// The half-space n·p < n·p0 of an object's own space, placed in the world
/// by `to_world`: n'·q < n'·M(p0), with n' = M⁻ᵀ n.
fn half_space(to_world: DAffine3, n: DVec3, p0: DVec3) -> Part {
    let normal = to_world.inverse().matrix3.transpose() * n;
    Part::Plane {
        normal,
        offset: normal.dot(to_world.transform_point3(p0)),
    }
}
