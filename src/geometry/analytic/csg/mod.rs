//! Constructive solid geometry over analytic shapes, combined exactly along
//! each ray in Roth's manner (1982): every leaf gives all its crossings along
//! the ray's whole line (`Shape::crossings`), each node merges its children's
//! sorted crossings while it keeps how many children the line is inside, and
//! reports a crossing where its own inside state changes. The first reported
//! crossing after tmin is the hit.
//!
//! The state at the start is counted, not evaluated: crossings are taken
//! from where the line enters each leaf's box (behind the ray's origin if
//! need be), where the line is known to be outside. A secondary ray starts
//! on the surface it leaves, where the sign of F is rounding noise; counting
//! crossings from outside never asks it.
//!
//! Crossings of two children within their refinement width are one event
//! (a sphere minus the same sphere is empty; two spheres touching from
//! outside have no surface between them in a merge). Surfaces without an
//! inside (a disc, an open cylinder) are sheets: they show where the node's
//! state would change if the sheet were a solid there — clipped to an
//! intersection, outside a union's other children; subtracted, a sheet cuts
//! nothing. (POV-Ray's disc in CSG has an inside, the half-space behind
//! it: see `Part::Disc`.) `union` keeps every surface of its children, inner ones too, as
//! POV-Ray's does; `merge` keeps only the boundary.
//!
//! `clip` is POV-Ray's `clipped_by`: as a solid it is the intersection of
//! its children, but only its first child's surface is ever seen. Where a
//! clip object's boundary changes the state, the node reports a *hidden*
//! crossing: its parents count it like any other, so the inside of every
//! node above stays right, but no node turns it into a surface and no ray
//! stops there. A sphere clipped by a half-space is a bowl open at the cut,
//! through which its inner wall is seen. A gated part (`Node::Gated`,
//! POV-Ray's `bounded_by` on a part) reports hidden crossings on the rays
//! its gate stops.

use std::cell::RefCell;

use glam::{DAffine3, DVec3};

use super::crossings::face_width;
use super::{Box3, Crossing, Crossings, Shape, ShapeHit};
use bounds::{bound_leaves, narrow, node_bounds};

mod bounds;
mod clipped;
use crate::poly::solve::Solver;

/// How a node combines its children.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Op {
    Union,
    Intersection,
    Difference,
    Merge,
    /// POV-Ray's `clipped_by`: the first child's surface where it lies inside
    /// every other child; inside where all children are (see the module's doc).
    Clip,
}

/// What a leaf of the tree is.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub enum Part {
    /// A shape's volume: F < 0 within its box (see `Shape::crossings`).
    Solid(Shape),
    /// An open surface (a cylinder or cone without caps): no inside.
    Sheet(Shape),
    /// The half-space n·p < offset, in world space.
    Plane { normal: DVec3, offset: f64 },
    /// The ring hole ≤ √(x² + y²) ≤ radius of the plane z = 0 of its own
    /// space: a sheet, or with `half_space` POV-Ray's disc in CSG, whose
    /// inside is the half-space z < 0 behind the ring (its `Disc::Inside`).
    /// The plane then changes the state wherever the line crosses it, and
    /// is seen only on the ring: elsewhere its crossing is a hidden
    /// boundary, as a clip object's is.
    Disc {
        to_object: DAffine3,
        radius: f64,
        hole: f64,
        // Left out of the scene hash when false, so the hashes of scenes
        // without it stay as they were.
        #[serde(skip_serializing_if = "std::ops::Not::not")]
        half_space: bool,
    },
}

/// Why a tree cannot be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CsgError {
    #[error(
        "the CSG tree is unbounded (a half-space or an inverted object in a union, or first in a difference): intersect it with a bounded object"
    )]
    Unbounded,
    /// Certainly empty: what a renderer of POV-Ray's scenes draws as nothing.
    #[error("the children's boxes do not overlap: nothing is left")]
    Empty,
    /// A leaf that cannot be bounded (see `Csg::new`).
    #[error("{0}")]
    Leaf(String),
}

/// A leaf: a part, whether its inside is flipped, and its material.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Leaf {
    pub part: Part,
    pub inverse: bool,
    pub material: u32,
}

/// A node of the tree: a leaf (index into `Csg::leaves`) or an operation.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub enum Node {
    Leaf(u32),
    Op {
        op: Op,
        inverse: bool,
        children: Vec<Node>,
    },
    /// POV-Ray's `bounded_by` on a part of a tree: on a ray the gate does
    /// not let through (see `Shape::set_gate`), the part's surface is not
    /// seen, and its inside still counts: its crossings are hidden
    /// boundaries, as POV-Ray skips a part's intersections then but still
    /// asks its `Inside`.
    Gated {
        gate: Box<Shape>,
        child: Box<Node>,
    },
}

/// A whole CSG tree: one entry of the scene's shapes.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Csg {
    root: Node,
    leaves: Vec<Leaf>,
    bounds: Box3,
    /// Whether the root is a clip that `nearest_clipped` answers. Derived,
    /// so not hashed.
    #[serde(skip)]
    clipped: bool,
    /// Whether a boundary can change the state of the tree's surfaces
    /// beyond the tree's box (a POV-Ray disc's plane, a gated part's
    /// siblings), so that only lines through the box may meet the tree.
    /// Derived, so not hashed.
    #[serde(skip)]
    reaches_out: bool,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Enter,
    Leave,
    /// A surface with no change of state; `inside`: whether the node that
    /// reports it is inside there.
    Sheet {
        inside: bool,
    },
}

/// A crossing as a node reports it to its parent.
#[derive(Clone, Copy, Debug)]
struct Event {
    t: f64,
    width: f64,
    kind: Kind,
    leaf: u32,
    face: Option<u8>,
    /// Whether the leaf's outward normal points into the reporting node.
    flip: bool,
    /// Which child of the node being combined reported it.
    child: u32,
    /// A boundary with no surface (a clip object's): the state changes
    /// there, but nothing is seen.
    hidden: bool,
}

thread_local! {
    /// The events of the ray being traced, reused: no allocation per ray
    /// once it has grown to the largest tree's needs.
    static EVENTS: RefCell<Vec<Event>> = const { RefCell::new(Vec::new()) };
    /// One leaf's crossings, reused for every leaf (see `Crossings`).
    static FOUND: RefCell<Crossings> = RefCell::new(Crossings::default());
}

impl Csg {
    /// The tree's leaves, by index.
    pub fn leaves(&self) -> &[Leaf] {
        &self.leaves
    }

    /// Whether no point of a region lies inside the tree or on its seen
    /// surface, where `outside(i)` proves that of leaf i, a solid or
    /// half-space leaf whose F > 0 throughout the region: an intersection
    /// or a clip is outside where one child is, a union or merge where all
    /// are, a difference where its first child is; the inverse of a part,
    /// or a sheet or disc, is never proven outside. The state is
    /// then the same at every point of the region, so no line through it
    /// crosses the tree's surface there (see `beam`). Each leaf is asked
    /// at most once.
    pub(crate) fn outside(&self, outside: &mut impl FnMut(usize) -> bool) -> bool {
        self.node_outside(&self.root, outside)
    }

    fn node_outside(&self, node: &Node, outside: &mut impl FnMut(usize) -> bool) -> bool {
        match node {
            Node::Leaf(i) => {
                let leaf = &self.leaves[*i as usize];
                !leaf.inverse
                    && matches!(leaf.part, Part::Solid(_) | Part::Plane { .. })
                    && outside(*i as usize)
            }
            Node::Op { inverse: true, .. } => false,
            Node::Op { op, children, .. } => match op {
                Op::Intersection | Op::Clip => {
                    children.iter().any(|c| self.node_outside(c, outside))
                }
                Op::Union | Op::Merge => children.iter().all(|c| self.node_outside(c, outside)),
                Op::Difference => self.node_outside(&children[0], outside),
            },
            Node::Gated { child, .. } => self.node_outside(child, outside),
        }
    }

    /// Whether a segment in the tree's box crosses none of its seen
    /// surfaces, given that the solid leaf `leaf` is crossed nowhere on it
    /// and keeps one side: inside (F < 0) or out. Out, it is as `outside`
    /// proves. Either way its own surface is not met: nor are the faces of
    /// its box where they lie beyond the tree's box, or beyond a solid
    /// that clips it; so neither is a clip whose first child that leaf
    /// is, nor an operation of it alone. (Where a boundary reaches out of
    /// the box, `reaches_out`, false.)
    pub(crate) fn unseen(&self, leaf: usize, inside: bool) -> bool {
        !self.reaches_out
            && (self.node_outside(&self.root, &mut |i| i == leaf && !inside)
                || self.node_unseen(&self.root, leaf, inside, &[]))
    }

    /// Whether no seen surface of the tree lies on the faces of leaf
    /// `leaf`'s box, so that every hit on that leaf is a point of its
    /// surface (F = 0): where the leaf is alone or a clip's first child and
    /// its faces lie beyond the tree's box or the clipping solid's.
    pub(crate) fn faces_hidden(&self, leaf: usize) -> bool {
        !self.reaches_out && self.node_unseen(&self.root, leaf, true, &[])
    }

    /// `unseen` for `node`, shown only where each of `clips` is inside.
    fn node_unseen(&self, node: &Node, leaf: usize, inside: bool, clips: &[Node]) -> bool {
        match node {
            Node::Leaf(i) => {
                let clipped = |s: &Shape| {
                    clips.iter().any(|c| match c {
                        Node::Leaf(c) => match &self.leaves[*c as usize] {
                            Leaf {
                                part: Part::Solid(cut),
                                inverse: false,
                                ..
                            } => cut.held_by(s),
                            _ => false,
                        },
                        _ => false,
                    })
                };
                *i as usize == leaf
                    && match &self.leaves[leaf].part {
                        Part::Sheet(_) => true,
                        Part::Solid(s) => {
                            !inside || s.box_holds(&self.bounds, &DAffine3::IDENTITY) || clipped(s)
                        }
                        Part::Plane { .. } | Part::Disc { .. } => false,
                    }
            }
            // A clip shows its first child's surface, where every other
            // child is inside (an inversion moves no surface).
            Node::Op {
                op: Op::Clip,
                children,
                ..
            } => {
                self.node_unseen(&children[0], leaf, inside, &children[1..])
                    || (children[1..].iter())
                        .any(|c| self.node_outside(c, &mut |i| i == leaf && !inside))
            }
            Node::Op { children, .. } => {
                (children.iter()).all(|c| self.node_unseen(c, leaf, inside, &[]))
            }
            Node::Gated { child, .. } => self.node_unseen(child, leaf, inside, clips),
        }
    }

    /// A tree over `leaves`. Its box: a union's is the union of its
    /// children's, an intersection's (and a clip's) the overlap of theirs, a
    /// difference's its first child's; a half-space or an inverted child is
    /// unbounded, and a tree that is unbounded as a whole is refused.
    ///
    /// A leaf with no box (`Shape::unclipped`) gets the box where its
    /// context can show it: in an intersection or a clip, the overlap of its
    /// bounded siblings' boxes; subtracted, its difference's first child's;
    /// slightly padded, so the faces that close it never meet a sibling's
    /// surface. With none to give, it is refused.
    pub fn new(root: Node, leaves: Vec<Leaf>) -> Result<Csg, CsgError> {
        Csg::build(root, leaves, None)
    }

    /// A tree cut by the world box `world`: what may be unbounded as a whole
    /// (POV-Ray's lone planes, or a union holding an unbounded quartic) is
    /// bounded by it, and leaves with no box get it where nothing nearer
    /// bounds them (see `new`). POV-Ray traces to 1e7 units at most.
    pub fn within(root: Node, leaves: Vec<Leaf>, world: Box3) -> Result<Csg, CsgError> {
        Csg::build(root, leaves, Some(world))
    }

    fn build(root: Node, mut leaves: Vec<Leaf>, world: Option<Box3>) -> Result<Csg, CsgError> {
        bound_leaves(&root, &mut leaves, world).map_err(CsgError::Leaf)?;
        let bounds = narrow(node_bounds(&root, &leaves), world).ok_or(CsgError::Unbounded)?;
        if bounds.is_empty() {
            return Err(CsgError::Empty);
        }
        let reaches_out = reaches_out(&root)
            || leaves.iter().any(|l| {
                matches!(
                    l.part,
                    Part::Disc {
                        half_space: true,
                        ..
                    }
                )
            });
        let mut csg = Csg {
            root,
            leaves,
            bounds,
            clipped: false,
            reaches_out,
        };
        csg.clipped = csg.clipped_root();
        Ok(csg)
    }

    pub fn bounds(&self) -> Box3 {
        self.bounds
    }

    /// The material of every leaf whose surface can be seen: a clip
    /// object's never is, so what its material calls for (refraction, say)
    /// is not planned for it.
    pub fn materials(&self) -> impl Iterator<Item = u32> + '_ {
        let mut seen = vec![false; self.leaves.len()];
        mark_seen(&self.root, &mut seen);
        self.leaves
            .iter()
            .zip(seen)
            .filter_map(|(leaf, seen)| seen.then_some(leaf.material))
    }

    pub fn material(&self, part: u32) -> u32 {
        self.leaves[part as usize].material
    }

    pub fn describe(&self) -> String {
        describe(&self.root, &self.leaves)
    }

    pub fn set_solver(&mut self, solver: Solver) {
        for leaf in &mut self.leaves {
            if let Part::Solid(s) | Part::Sheet(s) = &mut leaf.part {
                s.set_solver(solver);
            }
        }
        set_gate_solver(&mut self.root, solver);
    }

    /// The nearest crossing of the tree's surface with t in (tmin, tmax), and
    /// which leaf it is on (the hit's `part`). Shadow rays ask the same: an
    /// intersection or difference must know each child's state along the
    /// ray; only a clip lets them stop early (see `events`).
    pub fn intersect(&self, o: DVec3, d: DVec3, tmin: f64, tmax: f64) -> Option<ShapeHit> {
        self.nearest(o, d, tmin, tmax, false, |e| {
            let normal = self.leaf_normal(e, o, d);
            ShapeHit {
                t: e.t,
                normal: if e.flip { -normal } else { normal },
                part: e.leaf,
                // On a face of the leaf's box the point is the slab's, good
                // to its rounding; the surface's own bound means nothing
                // there (a box's F is a constant: its bound was the box's
                // size, and rays spawned from a face started that far off).
                error: match e.face {
                    Some(_) => face_width(e.t),
                    None => self.hit_error(e.leaf, o, d, e.t),
                },
            }
        })
    }

    /// Whether `intersect` finds a hit, without the hit's normal and error.
    pub fn occluded(&self, o: DVec3, d: DVec3, tmin: f64, tmax: f64) -> bool {
        self.nearest(o, d, tmin, tmax, true, |_| ()).is_some()
    }

    /// `seen` of the nearest seen event with t in (tmin, tmax); `seen_only`
    /// as `events` has it.
    fn nearest<R>(
        &self,
        o: DVec3,
        d: DVec3,
        tmin: f64,
        tmax: f64,
        seen_only: bool,
        seen: impl FnOnce(&Event) -> R,
    ) -> Option<R> {
        // Only a line through the tree's box meets the tree, as a renderer
        // bounding by boxes (POV-Ray) has it. Every crossing lies in the
        // box anyway, but where a boundary reaches out of it (see
        // `reaches_out`); elsewhere the test cost up to 7.5% of the
        // render-loop instructions of POV-Ray's CSG samples (helix.pov).
        if self.reaches_out {
            self.bounds.clip_ray(o, d, tmin, tmax)?;
        }
        EVENTS.with_borrow_mut(|events| {
            let clipped = self
                .clipped
                .then(|| self.nearest_clipped(o, d, tmin, tmax, seen_only, events))
                .flatten();
            clipped
                .unwrap_or_else(|| self.nearest_walked(o, d, tmin, tmax, seen_only, events))
                .as_ref()
                .map(seen)
        })
    }

    /// The nearest seen event with t in (tmin, tmax), from the whole walk
    /// over the tree's events (into `events`, scratch space).
    fn nearest_walked(
        &self,
        o: DVec3,
        d: DVec3,
        tmin: f64,
        tmax: f64,
        seen_only: bool,
        events: &mut Vec<Event>,
    ) -> Option<Event> {
        events.clear();
        let line = (f64::NEG_INFINITY, tmax);
        self.events(&self.root, o, d, tmin, line, seen_only, events);
        events
            .iter()
            .find(|e| !e.hidden && e.t > tmin && e.t < tmax)
            .copied()
    }

    /// The shape of a tree that is one solid leaf, not inverted (a box, a
    /// capped cylinder, a sphere as POV-Ray's reader builds them): its
    /// inside is the shape's F < 0 within the shape's box.
    pub(in crate::geometry::analytic) fn lone_solid(&self) -> Option<&Shape> {
        let Node::Leaf(i) = self.root else {
            return None;
        };
        match &self.leaves[i as usize] {
            Leaf {
                part: Part::Solid(s),
                inverse: false,
                ..
            } => Some(s),
            _ => None,
        }
    }

    /// The solids every seen point of the tree lies in: the children that
    /// are plain solid leaves of a root intersection or clip, not inverted.
    pub(in crate::geometry::analytic) fn cut_by(&self) -> impl Iterator<Item = &Shape> {
        let children = match &self.root {
            Node::Op {
                op: Op::Intersection | Op::Clip,
                inverse: false,
                children,
            } => children.as_slice(),
            _ => &[],
        };
        children.iter().filter_map(|child| match child {
            Node::Leaf(i) => match &self.leaves[*i as usize] {
                Leaf {
                    part: Part::Solid(s),
                    inverse: false,
                    ..
                } => Some(s),
                _ => None,
            },
            _ => None,
        })
    }

    /// Whether the line o + t·d is inside the tree at t = tmin or crosses its
    /// seen surface beyond it: what a gate asks (see `Shape::set_gate`).
    pub fn inside_or_crossed(&self, o: DVec3, d: DVec3, tmin: f64) -> bool {
        EVENTS.with_borrow_mut(|events| {
            events.clear();
            let line = (f64::NEG_INFINITY, f64::INFINITY);
            let start = self.events(&self.root, o, d, tmin, line, false, events);
            let inside = events
                .iter()
                .take_while(|e| e.t <= tmin)
                .fold(start, |inside, e| match e.kind {
                    Kind::Enter => true,
                    Kind::Leave => false,
                    Kind::Sheet { .. } => inside,
                });
            inside || events.iter().any(|e| !e.hidden && e.t > tmin)
        })
    }

    /// A bound on the error in t of a hit on leaf `part` at t.
    fn hit_error(&self, part: u32, o: DVec3, d: DVec3, t: f64) -> f64 {
        match &self.leaves[part as usize].part {
            Part::Solid(s) | Part::Sheet(s) => s.hit_error(o, d, t),
            Part::Plane { .. } | Part::Disc { .. } => face_width(t),
        }
    }

    fn leaf_normal(&self, e: &Event, o: DVec3, d: DVec3) -> DVec3 {
        match &self.leaves[e.leaf as usize].part {
            Part::Solid(s) | Part::Sheet(s) => s.crossing_normal(
                o,
                d,
                &Crossing {
                    t: e.t,
                    width: e.width,
                    entering: e.kind == Kind::Enter,
                    face: e.face,
                },
            ),
            Part::Plane { normal, .. } => *normal,
            Part::Disc { to_object, .. } => to_object.matrix3.transpose() * DVec3::Z,
        }
    }

    /// Appends the crossings of `node`'s surface along the line o + t·d with
    /// t in `window` (at most tmax above), increasing, to `out`; returns
    /// whether the line is inside at the window's start. Those at t > tmin,
    /// where the ray starts, are right; a leaf may start its crossings a
    /// little before tmin (see `Shape::crossings_from`), so some before it
    /// may be missing. A window that starts later than the line is one the
    /// caller knows its node to be outside before (see `joint_inside`).
    ///
    /// With `seen_only`, the caller wants only the seen crossings in (tmin,
    /// tmax) (of the root): a clip whose first child, a costly shape,
    /// certainly crosses nothing in that part of the window where the clip
    /// objects are all inside (`Shape::crosses_nothing`, which refines no
    /// root) reports none, since a clip shows only its first child's
    /// crossings. Most shadow rays from a clipped quartic leave it and meet
    /// nothing more, yet the full walk found and polished every root of the
    /// quartic in the window, the one the ray starts on too (the tree's
    /// crossings are counted from outside). Only shadow rays ask: on camera
    /// rays, most of which hit the trees they reach, the test cost more than
    /// it saved in five of POV-Ray's eight clip samples (`valgrind
    /// --tool=callgrind`, docs/povray.md).
    #[allow(clippy::too_many_arguments)]
    fn events(
        &self,
        node: &Node,
        o: DVec3,
        d: DVec3,
        tmin: f64,
        window: (f64, f64),
        seen_only: bool,
        out: &mut Vec<Event>,
    ) -> bool {
        match node {
            Node::Leaf(i) => self.leaf_events(*i, o, d, tmin, window, out),
            Node::Gated { gate, child } => {
                let from = out.len();
                let inside = self.events(child, o, d, tmin, window, false, out);
                if !gate.lets_through(o, d, tmin) {
                    for e in &mut out[from..] {
                        e.hidden = true;
                    }
                }
                inside
            }
            Node::Op {
                op,
                inverse,
                children,
            } => {
                let base = out.len();
                let mut state = State {
                    op: *op,
                    children: children.len() as isize,
                    first: false,
                    count: 0,
                };
                // An intersection (or a clip) is inside only where all its
                // children are: the costly children (quartics and above) are
                // searched only where the cheap ones are all inside, which
                // they give first. helix.pov's quartics clipped by a quadric
                // and two planes spent most of their instructions outside
                // the clip (`valgrind --tool=callgrind`). A sheet among the
                // cheap ones shows where the others are inside: no narrowing.
                let narrows = matches!(op, Op::Intersection | Op::Clip)
                    && children.iter().any(|c| self.cost(c) == Cost::Costly)
                    && children
                        .iter()
                        .all(|c| self.cost(c) == Cost::Costly || self.solid(c));
                let mut window = window;
                for pass in [Cost::Cheap, Cost::Costly] {
                    if narrows && pass == Cost::Costly {
                        let cheap = children.iter().filter(|c| self.cost(c) == Cost::Cheap);
                        let Some(inside) = joint_inside(&mut out[base..], cheap.count(), &state)
                        else {
                            // Never all inside: neither is the node, and the
                            // costly children's crossings change nothing.
                            out.truncate(base);
                            return *inverse;
                        };
                        window = (window.0.max(inside.0), window.1.min(inside.1));
                        if seen_only
                            && *op == Op::Clip
                            && self.cost(&children[0]) == Cost::Costly
                            && self.crosses_nothing(
                                &children[0],
                                o,
                                d,
                                tmin.max(window.0),
                                window.1,
                            )
                        {
                            out.truncate(base);
                            return *inverse;
                        }
                    }
                    for (k, child) in children.iter().enumerate() {
                        if (self.cost(child) == Cost::Costly) != (pass == Cost::Costly) {
                            continue;
                        }
                        let from = out.len();
                        let inside = self.events(child, o, d, tmin, window, false, out);
                        let clipping = *op == Op::Clip && k > 0;
                        for e in &mut out[from..] {
                            e.child = k as u32;
                            e.hidden |= clipping;
                        }
                        state.apply(k as u32, inside);
                    }
                }
                // Stable, so a child's own crossings at one t keep their order
                // (its scratch is on the stack for the event counts of a ray).
                out[base..].sort_by(|a, b| a.t.total_cmp(&b.t).then(a.child.cmp(&b.child)));
                let start = state.inside() != *inverse;
                combine(&mut state, *inverse, out, base);
                start
            }
        }
    }

    /// Whether `node` is a shape that certainly crosses nothing with t in
    /// (tmin, tmax) (see `Shape::crosses_nothing`).
    fn crosses_nothing(&self, node: &Node, o: DVec3, d: DVec3, tmin: f64, tmax: f64) -> bool {
        let Node::Leaf(i) = node else {
            return false;
        };
        match &self.leaves[*i as usize].part {
            Part::Solid(s) => s.crosses_nothing(o, d, tmin, tmax, true),
            Part::Sheet(s) => s.crosses_nothing(o, d, tmin, tmax, false),
            Part::Plane { .. } | Part::Disc { .. } => false,
        }
    }

    /// How much finding a node's crossings costs: closed forms and
    /// quadratics are cheap, anything of higher degree is costly.
    fn cost(&self, node: &Node) -> Cost {
        match node {
            Node::Leaf(i) => match &self.leaves[*i as usize].part {
                Part::Solid(s) | Part::Sheet(s) if !s.quadratic() => Cost::Costly,
                _ => Cost::Cheap,
            },
            Node::Op { children, .. } => {
                if children.iter().any(|c| self.cost(c) == Cost::Costly) {
                    Cost::Costly
                } else {
                    Cost::Cheap
                }
            }
            Node::Gated { child, .. } => self.cost(child),
        }
    }

    /// Whether every leaf under `node` has an inside (no sheets).
    fn solid(&self, node: &Node) -> bool {
        match node {
            Node::Leaf(i) => matches!(
                self.leaves[*i as usize].part,
                Part::Solid(_)
                    | Part::Plane { .. }
                    | Part::Disc {
                        half_space: true,
                        ..
                    }
            ),
            Node::Op { children, .. } => children.iter().all(|c| self.solid(c)),
            Node::Gated { child, .. } => self.solid(child),
        }
    }

    /// The event of crossing `c` of leaf `i`, of the given kind.
    fn leaf_event(&self, i: u32, c: &Crossing, kind: Kind) -> Event {
        Event {
            t: c.t,
            width: c.width,
            kind,
            leaf: i,
            face: c.face,
            flip: self.leaves[i as usize].inverse,
            child: 0,
            hidden: false,
        }
    }

    /// The event of crossing `c` of leaf `i`, a shape (solid or sheet).
    fn shape_event(&self, i: u32, c: &Crossing) -> Event {
        let leaf = &self.leaves[i as usize];
        let kind = match (&leaf.part, c.entering != leaf.inverse) {
            (Part::Solid(_), true) => Kind::Enter,
            (Part::Solid(_), false) => Kind::Leave,
            _ => Kind::Sheet { inside: false },
        };
        self.leaf_event(i, c, kind)
    }

    fn leaf_events(
        &self,
        i: u32,
        o: DVec3,
        d: DVec3,
        tmin: f64,
        window: (f64, f64),
        out: &mut Vec<Event>,
    ) -> bool {
        let tmax = window.1;
        let leaf = &self.leaves[i as usize];
        let inverse = leaf.inverse;
        let crossing = |t| Crossing {
            t,
            width: face_width(t),
            entering: false,
            face: None,
        };
        match &leaf.part {
            Part::Solid(s) | Part::Sheet(s) => {
                let solid = matches!(leaf.part, Part::Solid(_));
                let from = s.crossings_from(d, tmin).max(window.0);
                FOUND.with_borrow_mut(|found| {
                    let starts = s.crossings(o, d, from, tmax, solid, found);
                    for c in found.as_slice() {
                        out.push(self.shape_event(i, c));
                    }
                    solid && (starts != inverse)
                })
            }
            Part::Plane { normal, offset } => {
                let (nd, no) = (normal.dot(d), normal.dot(o));
                let t = (offset - no) / nd;
                if nd != 0.0 && t < tmax {
                    let kind = if (nd < 0.0) != inverse {
                        Kind::Enter
                    } else {
                        Kind::Leave
                    };
                    out.push(self.leaf_event(i, &crossing(t), kind));
                }
                // Far back along the line, n·p is below the offset when the
                // line runs towards +n.
                (nd > 0.0 || (nd == 0.0 && no < *offset)) != inverse
            }
            Part::Disc {
                to_object,
                radius,
                hole,
                half_space,
            } => {
                let (o, d) = (
                    to_object.transform_point3(o),
                    to_object.transform_vector3(d),
                );
                let t = -o.z / d.z;
                let p = o + t * d;
                let r2 = p.x * p.x + p.y * p.y;
                let on_ring = r2 <= radius * radius && r2 >= hole * hole;
                if !half_space {
                    if d.z != 0.0 && t < tmax && on_ring {
                        out.push(self.leaf_event(i, &crossing(t), Kind::Sheet { inside: false }));
                    }
                    return false;
                }
                // As a plane's, with the ring's normal +z facing out.
                if d.z != 0.0 && t < tmax {
                    let kind = if (d.z < 0.0) != inverse {
                        Kind::Enter
                    } else {
                        Kind::Leave
                    };
                    out.push(Event {
                        hidden: !on_ring,
                        ..self.leaf_event(i, &crossing(t), kind)
                    });
                }
                (d.z > 0.0 || (d.z == 0.0 && o.z < 0.0)) != inverse
            }
        }
    }
}

/// Whether a node's crossings are costly to find (see `Csg::cost`).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Cost {
    Cheap,
    Costly,
}

/// The span of the line where `cheap` children, whose events are
/// `events` and whose states at the line's start `state` holds, are all
/// inside at once: from the first time to the last, widened by the
/// crossings' widths and a margin, so the costly children's roots near its
/// ends are found and combined as before. None if they never are. Sorts
/// `events` (the caller sorts them again with the others).
fn joint_inside(events: &mut [Event], cheap: usize, state: &State) -> Option<(f64, f64)> {
    events.sort_by(|a, b| a.t.total_cmp(&b.t));
    let all = cheap as isize;
    let mut count = state.count;
    let mut span: Option<(f64, f64)> = (count == all).then_some((f64::NEG_INFINITY, f64::INFINITY));
    for e in events.iter() {
        let was = count == all;
        match e.kind {
            Kind::Enter => count += 1,
            Kind::Leave => count -= 1,
            Kind::Sheet { .. } => continue,
        }
        let margin = margin(e);
        if count == all && !was {
            span = Some((span.map_or(e.t - margin, |s| s.0), f64::INFINITY));
        } else if was && count != all {
            span = span.map(|s| (s.0, e.t + margin));
        }
    }
    span
}

/// How far either side of a cheap child's event `joint_inside` widens its
/// span: past the event's width, where a costly child's crossing may be
/// grouped with it.
fn margin(e: &Event) -> f64 {
    4.0 * e.width + 1e-9 * e.t.abs().max(1.0)
}

/// The inside state of an operation's children at one point of the line:
/// how many are inside (the first child apart, for a difference).
struct State {
    op: Op,
    children: isize,
    first: bool,
    /// Signed: a leaf whose crossings do not alternate (one that gave up on
    /// a ray) cannot make it wrap.
    count: isize,
}

impl State {
    fn apply(&mut self, child: u32, inside: bool) {
        if self.op == Op::Difference && child == 0 {
            self.first = inside;
        } else {
            self.count += if inside { 1 } else { 0 };
        }
    }

    fn step(&mut self, e: &Event) {
        match (e.kind, self.op == Op::Difference && e.child == 0) {
            (Kind::Sheet { .. }, _) => {}
            (kind, true) => self.first = kind == Kind::Enter,
            (Kind::Enter, false) => self.count += 1,
            (Kind::Leave, false) => self.count -= 1,
        }
    }

    fn inside(&self) -> bool {
        match self.op {
            Op::Union | Op::Merge => self.count > 0,
            Op::Intersection | Op::Clip => self.count == self.children,
            Op::Difference => self.first && self.count <= 0,
        }
    }

    /// Whether the sheet `e` lies on this node's surface: the node's state
    /// would differ with its child inside and outside there.
    fn shows(&self, e: &Event) -> bool {
        let Kind::Sheet { inside } = e.kind else {
            return false;
        };
        if e.hidden {
            return false;
        }
        let others = self.count - isize::from(inside);
        match self.op {
            Op::Union | Op::Merge => others <= 0,
            Op::Intersection => others == self.children - 1,
            Op::Clip => e.child == 0 && others == self.children - 1,
            Op::Difference => e.child == 0 && self.count <= 0,
        }
    }
}

/// Roth's walk over the sorted children's events in `out[base..]`, which it
/// replaces with the node's own.
fn combine(state: &mut State, inverse: bool, out: &mut Vec<Event>, base: usize) {
    let (mut read, mut write) = (base, base);
    while read < out.len() {
        let head = out[read];
        let mut end = read + 1;
        while end < out.len() && out[end].t - head.t <= head.width.max(out[end].width) {
            end += 1;
        }
        let before = state.inside();
        for e in &out[read..end] {
            state.step(e);
        }
        let after = state.inside();
        let group = &out[read..end];
        let found = if before != after {
            // A surface where one changes the state with a hidden boundary
            // (a clip object's face meeting the clipped surface) is seen.
            let changes = || group.iter().filter(|e| !is_sheet(e));
            let shown = changes().find(|e| !e.hidden);
            shown.or_else(|| changes().next()).map(|e| Event {
                kind: if after != inverse {
                    Kind::Enter
                } else {
                    Kind::Leave
                },
                // The leaf's outward normal is the node's where the leaf's
                // state and the node's change the same way.
                flip: (e.flip != ((e.kind == Kind::Enter) != after)) != inverse,
                ..*e
            })
        } else {
            let sheet = Kind::Sheet {
                inside: after != inverse,
            };
            match state.op {
                // Inner surfaces of a union stay, as in POV-Ray; hidden
                // boundaries inside it change nothing and are dropped.
                Op::Union => group
                    .iter()
                    .find(|e| !e.hidden)
                    .map(|e| Event { kind: sheet, ..*e }),
                _ => group
                    .iter()
                    .find(|e| state.shows(e))
                    .map(|e| Event { kind: sheet, ..*e }),
            }
        };
        if let Some(e) = found {
            out[write] = e;
            write += 1;
        }
        read = end;
    }
    out.truncate(write);
}

/// Marks the leaves under `node` whose surface can be seen: all but those
/// under a clip's clip objects.
fn mark_seen(node: &Node, seen: &mut [bool]) {
    match node {
        Node::Leaf(i) => seen[*i as usize] = true,
        Node::Op { op, children, .. } => {
            let shown = if *op == Op::Clip {
                &children[..1]
            } else {
                children
            };
            for child in shown {
                mark_seen(child, seen);
            }
        }
        Node::Gated { child, .. } => mark_seen(child, seen),
    }
}

/// Whether a gated part is under `node` (see `Csg::reaches_out`).
fn reaches_out(node: &Node) -> bool {
    match node {
        Node::Leaf(_) => false,
        Node::Op { children, .. } => children.iter().any(reaches_out),
        Node::Gated { .. } => true,
    }
}

fn set_gate_solver(node: &mut Node, solver: Solver) {
    match node {
        Node::Leaf(_) => {}
        Node::Op { children, .. } => {
            for child in children {
                set_gate_solver(child, solver);
            }
        }
        Node::Gated { gate, child } => {
            gate.set_solver(solver);
            set_gate_solver(child, solver);
        }
    }
}

fn is_sheet(e: &Event) -> bool {
    matches!(e.kind, Kind::Sheet { .. })
}

fn describe(node: &Node, leaves: &[Leaf]) -> String {
    match node {
        Node::Leaf(i) => {
            let leaf = &leaves[*i as usize];
            let what = match &leaf.part {
                Part::Solid(s) => s.describe(),
                Part::Sheet(s) => format!("open {}", s.describe()),
                Part::Plane { .. } => "plane".into(),
                Part::Disc {
                    half_space: false, ..
                } => "disc".into(),
                Part::Disc {
                    half_space: true, ..
                } => "disc (inside: the half-space behind it)".into(),
            };
            if leaf.inverse {
                format!("inverse {what}")
            } else {
                what
            }
        }
        Node::Op {
            op,
            inverse,
            children,
        } => {
            let inner: Vec<String> = children.iter().map(|c| describe(c, leaves)).collect();
            let name = format!("{op:?}").to_lowercase();
            let inv = if *inverse { "inverse " } else { "" };
            format!("{inv}{name}({})", inner.join(", "))
        }
        Node::Gated { child, .. } => format!("bounded {}", describe(child, leaves)),
    }
}
