//! The boxes of a CSG tree: each node's (a union's is its children's
//! together, an intersection's or a clip's their overlap, a difference's
//! its first child's; a half-space or an inverted child is unbounded), and
//! the box each leaf with none of its own gets from its context.

use glam::DVec3;

use super::{Leaf, Node, Op, Part};
use crate::geometry::analytic::{Box3, world_box};

/// How much a context's box is padded for a leaf with none (see `Csg::new`),
/// relative to its extent: its closing faces then lie clear of every
/// sibling's surface, and the box grows too little to cost precision.
const CONTEXT_PAD: f64 = 1.0 / 1024.0;

/// Gives every leaf with no box of its own the box of its context (see
/// `Csg::new`): `context` is where `node`'s state can show, None for
/// everywhere.
pub(super) fn bound_leaves(
    node: &Node,
    leaves: &mut [Leaf],
    context: Option<Box3>,
) -> Result<(), String> {
    match node {
        Node::Leaf(i) => match &mut leaves[*i as usize].part {
            Part::Solid(s) | Part::Sheet(s) if !s.is_bounded() => {
                let Some(b) = context else {
                    return Err("an unbounded surface (a quadric or algebraic surface with no clip box) needs a bounded object to cut it: intersect it with one, or clip it by one".into());
                };
                let pad = CONTEXT_PAD * (b.max - b.min).max_element();
                s.clip_to(&Box3 {
                    min: b.min - pad,
                    max: b.max + pad,
                })
            }
            _ => Ok(()),
        },
        Node::Op { op, children, .. } => {
            // The node's own box before any inversion: an inverted node is
            // unbounded, but its children matter only where the node's
            // uninverted state can change.
            let own = op_bounds(*op, children, leaves);
            for (k, child) in children.iter().enumerate() {
                let inner = match op {
                    Op::Union | Op::Merge => context,
                    Op::Intersection | Op::Clip => narrow(context, own),
                    Op::Difference if k == 0 => context,
                    // After the first child got its box, so a subtracted
                    // surface is cut to it too.
                    Op::Difference => narrow(context, node_bounds(&children[0], leaves)),
                };
                bound_leaves(child, leaves, inner)?;
            }
            Ok(())
        }
        Node::Gated { child, .. } => bound_leaves(child, leaves, context),
    }
}

/// The overlap of two boxes where both are bounded, else the one that is.
pub(super) fn narrow(a: Option<Box3>, b: Option<Box3>) -> Option<Box3> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.intersection(&b)),
        (a, b) => a.or(b),
    }
}

/// A node's world box, None when unbounded.
pub(super) fn node_bounds(node: &Node, leaves: &[Leaf]) -> Option<Box3> {
    match node {
        Node::Leaf(i) => {
            let leaf = &leaves[*i as usize];
            if leaf.inverse {
                return None;
            }
            match &leaf.part {
                Part::Solid(s) | Part::Sheet(s) => {
                    let b = s.box_bounds();
                    s.is_bounded().then(|| Box3 {
                        min: b.min.as_dvec3(),
                        max: b.max.as_dvec3(),
                    })
                }
                Part::Plane { .. } => None,
                // Even with a half-space inside (POV-Ray's disc), the box is
                // the ring's, as POV-Ray bounds a disc: an intersection with
                // one shows only within its children's boxes' overlap.
                Part::Disc {
                    to_object, radius, ..
                } => Some(world_box(
                    &Box3 {
                        min: DVec3::new(-radius, -radius, 0.0),
                        max: DVec3::new(*radius, *radius, 0.0),
                    },
                    &to_object.inverse(),
                )),
            }
        }
        Node::Op {
            op,
            inverse,
            children,
        } => {
            if *inverse {
                return None;
            }
            op_bounds(*op, children, leaves)
        }
        // POV-Ray bounds a part with a `bounded_by` by its bound's box where
        // that is the smaller, as it culls rays by it: what the part's
        // inside shows of its siblings (a box's faces inside a half-space)
        // shows only there.
        Node::Gated { gate, child } => {
            // Every gate of a chain must be passed: the boxes intersect.
            let mut bound = Box3::cube(f64::INFINITY);
            let mut next = Some(gate.as_ref());
            while let Some(g) = next {
                let b = g.bounds();
                bound = bound.intersection(&Box3 {
                    min: b.min.as_dvec3(),
                    max: b.max.as_dvec3(),
                });
                next = g.gate.as_deref();
            }
            let volume = |b: &Box3| (b.max - b.min).max(DVec3::ZERO).element_product();
            match node_bounds(child, leaves) {
                Some(own) if volume(&own) <= volume(&bound) => Some(own),
                _ => Some(bound),
            }
        }
    }
}

/// A child's box as an intersection or difference bounds by it. POV-Ray's
/// CSG intersection takes a plane's own box (`Compute_Plane_Min_Max`), not
/// the one its `bounded_by` gave it, though a union takes that one.
fn overlapped_bounds(child: &Node, leaves: &[Leaf]) -> Option<Box3> {
    match child {
        Node::Gated { child: inner, .. } if matches!(**inner, Node::Leaf(i) if matches!(leaves[i as usize].part, Part::Plane { .. })) => {
            node_bounds(inner, leaves)
        }
        _ => node_bounds(child, leaves),
    }
}

/// The box of an operation over `children`, as if it were not inverted.
fn op_bounds(op: Op, children: &[Node], leaves: &[Leaf]) -> Option<Box3> {
    let mut boxes = children.iter().map(|c| match op {
        Op::Union | Op::Merge => node_bounds(c, leaves),
        _ => overlapped_bounds(c, leaves),
    });
    match op {
        Op::Union | Op::Merge => boxes.try_fold(None, |acc: Option<Box3>, b| {
            let b = b?;
            Some(Some(acc.map_or(b, |a| Box3 {
                min: a.min.min(b.min),
                max: a.max.max(b.max),
            })))
        })?,
        Op::Intersection | Op::Clip => boxes.flatten().reduce(|a, b| a.intersection(&b)),
        Op::Difference => boxes.next().flatten(),
    }
}
