//! Surfaces with no box of their own, as POV-Ray's quartics and planes
//! come: built unbounded (`Shape::unclipped`), then cut to the box where
//! their context can show them (`clip_to`, which `Csg::new` calls for the
//! leaves of a tree) or to a world box. A box so given may be far larger
//! than the surface's features (1e7 for a world box), so a tree walks such a
//! leaf's crossings from just behind the ray, not from where the line
//! enters the box (`crossings_from`; docs/analytic.md has the measured
//! error against the box's size).

use std::sync::OnceLock;

use glam::{DAffine3, DVec3};

use super::{Box3, Shape, Surface, world_bounds, world_box};
use crate::math::{Bounds, Vec3};
use crate::poly::solve::Solver;

/// How far behind a ray's start (in object units) a tree walks the
/// crossings of a leaf whose box is its context's (see
/// `Shape::crossings_from`): far enough that the start is off the surface
/// the ray leaves, so F's sign there is clear of its rounding noise.
const CONTEXT_MARGIN: f64 = 1.0 / 1024.0;

impl Shape {
    /// A shape with no clip box, as POV-Ray's quartics and planes come: a
    /// sphere, a torus or a tree is bounded on its own; a quadric or an
    /// algebraic surface is unbounded (see `is_bounded`) until a tree
    /// around it (`Csg::new`) or the caller (`clip_to`) gives it a box, and
    /// must be before it is traced.
    pub fn unclipped(
        surface: Surface,
        to_world: DAffine3,
        material: u32,
        solver: Solver,
    ) -> Result<Shape, String> {
        if !matches!(surface, Surface::Quadric(_) | Surface::Algebraic(_)) {
            return Shape::new(surface, to_world, None, material, solver);
        }
        // Built on a unit box, then widened: the corners of an infinite box
        // would map to NaN under a rotation.
        let mut shape = Shape::new(surface, to_world, Some(Box3::cube(1.0)), material, solver)?;
        shape.object_box = Box3::cube(f64::INFINITY);
        shape.world_bounds = Bounds {
            min: Vec3::splat(f32::NEG_INFINITY),
            max: Vec3::splat(f32::INFINITY),
        };
        Ok(shape)
    }

    /// Whether the shape has a finite box (see `unclipped`).
    pub fn is_bounded(&self) -> bool {
        self.object_box.min.is_finite() && self.object_box.max.is_finite()
    }

    /// Cuts the shape to the world box `world` (through the box around its
    /// corners in object space): for an unbounded surface, the box where its
    /// context can show it, or the world's for one alone in a scene. The
    /// crossings of a surface given its box so start near the ray, not where
    /// the line enters the box (see `crossings_from`).
    pub fn clip_to(&mut self, world: &Box3) -> Result<(), String> {
        self.clip_within(world, DAffine3::IDENTITY)
    }

    /// `clip_to` a box `b` given in the space that `frame` places in the
    /// world: for a box known in the frame of an object the surface belongs
    /// to (a POV-Ray object's own clip), which maps onto the surface's
    /// object box without the widening a rotation gives a world box.
    pub fn clip_within(&mut self, b: &Box3, frame: DAffine3) -> Result<(), String> {
        let cut = world_box(b, &(self.to_object * frame)).intersection(&self.object_box);
        if cut.is_empty() || !b.min.is_finite() || !b.max.is_finite() {
            return Err("the box around the surface leaves nothing of it, or is not finite".into());
        }
        self.context_box |= !self.is_bounded();
        self.object_box = cut;
        self.surface_box = OnceLock::new();
        self.world_bounds = world_bounds(&cut, &self.to_object.inverse());
        Ok(())
    }

    /// Whether the box `b`, in the space `to_world` places in the world,
    /// lies within the shape's box, clear of its faces by a billionth of
    /// its size: no face of the box, which closes a solid where the
    /// surface is cut, is then in `b`.
    pub(super) fn box_holds(&self, b: &Box3, to_world: &DAffine3) -> bool {
        let inner = world_box(b, &(self.to_object * *to_world));
        let own = &self.object_box;
        let margin = 1e-9 * (own.max - own.min).max_element();
        inner.min.cmpgt(own.min + margin).all() && inner.max.cmplt(own.max - margin).all()
    }

    /// Whether the shape's solid (F < 0 within its box) lies within the
    /// box of `other`, clear of its faces (`box_holds`).
    pub(super) fn held_by(&self, other: &Shape) -> bool {
        other.box_holds(&self.object_box, &self.to_object.inverse())
    }

    /// Where, in the world ray's t, a tree starts the walk over this shape's
    /// crossings for a ray that starts at tmin: at the line's entry into its
    /// box (−∞ here), where the line is known to be outside; but for a box
    /// given by the context (`clip_to`), which may be a world box 1e7 wide,
    /// just behind tmin, so Q is formed near the ray and not where its
    /// coefficients would dwarf the roots (see docs/analytic.md).
    pub(super) fn crossings_from(&self, d: DVec3, tmin: f64) -> f64 {
        if !self.context_box {
            return f64::NEG_INFINITY;
        }
        tmin - CONTEXT_MARGIN / self.to_object.transform_vector3(d).length()
    }
}
