//! Analytic surfaces: spheres, quadrics, tori and algebraic surfaces, hit by
//! finding the roots of Q(t) = F(o + t·d) in f64, in object space.
//!
//! Every shape follows the same steps: take the world ray into object space
//! (an affine map keeps t), clip t to the ray's interval inside the shape's
//! box, move the origin to the entry point so Q's coefficients stay small
//! (POV-Ray's torus fix), solve for the nearest root there, and map the
//! gradient back to a world normal.

use std::sync::OnceLock;

use glam::{DAffine3, DMat3, DVec3};

use crate::math::{Bounds, Vec3, larger, smaller};
use crate::poly::closed::quadratic;
use crate::poly::solve::Solver;
use crate::poly::univariate::{PolyN, QUARTIC_SLOTS, SLOTS, normalize_pow2};

/// `$call` with the const `$slots` set to the storage the shape's Q needs:
/// five slots for a surface of degree 4 or less (`Surface::quartic`), the
/// solver's full storage otherwise (see `RayPoly`).
macro_rules! in_storage {
    ($shape:expr, $slots:ident => $call:expr) => {
        if $shape.surface.quartic() {
            const $slots: usize = crate::poly::univariate::QUARTIC_SLOTS;
            $call
        } else {
            const $slots: usize = crate::poly::univariate::SLOTS;
            $call
        }
    };
}

mod beam;
mod crossings;
pub mod csg;
mod extent;
mod gate;
mod surface;
mod unbounded;

pub use beam::{Pinhole, ShapeBeams, shadow_start_bound};
pub use crossings::{Crossing, Crossings};
use surface::root_uncertainty;
pub use surface::{Quadric, Surface};

/// An axis-aligned box in f64.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Box3 {
    pub min: DVec3,
    pub max: DVec3,
}

impl Box3 {
    pub fn cube(half: f64) -> Box3 {
        Box3 {
            min: DVec3::splat(-half),
            max: DVec3::splat(half),
        }
    }

    pub fn intersection(&self, other: &Box3) -> Box3 {
        Box3 {
            min: self.min.max(other.min),
            max: self.max.min(other.max),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// The ray's parameter interval inside the box (slab test), or None.
    fn clip_ray(&self, o: DVec3, d: DVec3, tmin: f64, tmax: f64) -> Option<(f64, f64)> {
        // As arrays: glam indexes a DVec3 by a match on the axis, a branch
        // for each of the loop's reads that the unrolled loop kept.
        let [o, d, min, max] = [o, d, self.min, self.max].map(|v| v.to_array());
        let (mut lo, mut hi) = (tmin, tmax);
        for axis in 0..3 {
            if d[axis] == 0.0 {
                if o[axis] < min[axis] || o[axis] > max[axis] {
                    return None;
                }
                continue;
            }
            let inv = 1.0 / d[axis];
            let (a, b) = ((min[axis] - o[axis]) * inv, (max[axis] - o[axis]) * inv);
            // `larger`, not `f64::max` (see `math::larger`): no NaN arises
            // here (d is finite and not 0, o is finite, a box's infinite
            // side gives ±∞).
            lo = larger(lo, smaller(a, b));
            hi = smaller(hi, larger(a, b));
        }
        (lo <= hi).then_some((lo, hi))
    }
}

/// A hit on an analytic shape: the ray parameter and the world-space normal
/// (unnormalised, from the gradient).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeHit {
    pub t: f64,
    pub normal: DVec3,
    /// Which part of a CSG tree was hit (its leaf, see `csg::Csg`); 0 for a
    /// plain shape.
    pub part: u32,
    /// A bound on the error in t (see `Shape::hit_error`): for a plain
    /// shape from the root's own refinement, which has the surface's Q at
    /// the root in hand, so the shading point needs no second substitution.
    pub error: f64,
}

/// An analytic surface placed in the world, or a CSG tree of them.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Shape {
    pub surface: Surface,
    /// Index into the scene's materials.
    pub material: u32,
    to_object: DAffine3,
    /// (M⁻¹)ᵀ: takes object-space gradients to world-space normals.
    normal_to_world: DMat3,
    /// Where the surface is searched, in object space: its own bounds clipped by the user's box.
    object_box: Box3,
    /// Where an algebraic surface's own roots are searched: the box around
    /// its points within `object_box` (see `extent`), found when first
    /// asked; None if it has none there. Derived, so not hashed.
    #[serde(skip)]
    surface_box: OnceLock<Option<Box3>>,
    /// Object space is the surface's own, scaled by 2^unit (see `new`).
    unit: i32,
    world_bounds: Bounds,
    solver: Solver,
    /// POV-Ray's `bounded_by` (see `set_gate`). Left out of the scene hash
    /// when absent, so shapes without one hash as they always have.
    #[serde(skip_serializing_if = "Option::is_none")]
    gate: Option<Box<Shape>>,
    /// Whether the box is not the surface's own but its context's (see
    /// `clip_to`); left out of the scene hash when false, as `gate`.
    #[serde(skip_serializing_if = "<&bool as std::ops::Not>::not")]
    context_box: bool,
    /// POV-Ray's `no_shadow`: seen, but never between a point and a light
    /// (see `set_no_shadow`); left out of the scene hash when false.
    #[serde(skip_serializing_if = "<&bool as std::ops::Not>::not")]
    no_shadow: bool,
    /// POV-Ray's `hollow`: its inside is air, which a fog fills (see
    /// `set_hollow`). The scene hash takes it with the fogs, the only thing
    /// it changes (so the hashes of scenes without fog stay as they were).
    #[serde(skip)]
    hollow: bool,
}

/// Q(s) = F(start + s·d) of one ray in object space (|d| = 1, s the distance
/// from `start`): the search looks for its roots in s ∈ (0, hi), where the
/// ray's own t is (t0 + s) / length. `start` is either the ray's own origin
/// (tmin, excluded) or its entry into the shape's box, where no surface
/// point lies. Q is held in `S` slots: a surface of degree 4 or less
/// (`Surface::quartic`) is searched with Q in five, so no 36-slot copy of it
/// is made on the way (those copies, and the conversions back to five
/// slots in the solver, were 4% of the instructions of POV-Ray's
/// bicube.pov, `valgrind --tool=callgrind`).
#[derive(Clone, Copy, Debug)]
pub struct RayPoly<const S: usize = SLOTS> {
    pub q: PolyN<S>,
    pub hi: f64,
    start: DVec3,
    d: DVec3,
    t0: f64,
    /// Where the interval ends, as the clip gave it (the box's exit or
    /// tmax, in distance): t0 + hi may round below tmax where tmax ends it.
    t1: f64,
    length: f64,
    /// Q's coefficient count before trimming: what F's rounding noise at
    /// `start` is scaled by (see `Shape::side_of_start`).
    formed: usize,
}

impl<const S: usize> RayPoly<S> {
    /// Whether the shape's box, not tmin, starts the interval: the line
    /// enters the box after tmin, through a face.
    fn enters_after(&self, tmin: f64) -> bool {
        self.t0 > tmin * self.length
    }

    /// Whether the box, not tmax, ends the interval: the line leaves it
    /// through a face before tmax.
    fn leaves_before(&self, tmax: f64) -> bool {
        self.t1 < tmax * self.length
    }
}

/// A ray in a shape's object space (see `RayPoly`, whose fields these are).
struct RayFrame {
    start: DVec3,
    d: DVec3,
    t0: f64,
    t1: f64,
    hi: f64,
    length: f64,
}

/// The roots found for one ray, in the ray's own parameter.
struct Found {
    t: f64,
    object_point: DVec3,
    /// The bound on the error in t (see `ShapeHit::error`).
    error: f64,
}

impl Shape {
    /// `to_world` places the surface; `clip` (object space) bounds it. Unbounded
    /// surfaces (quadrics other than spheres and ellipsoids, algebraic ones) need a
    /// clip box: the caller supplies one.
    pub fn new(
        surface: Surface,
        to_world: DAffine3,
        clip: Option<Box3>,
        material: u32,
        solver: Solver,
    ) -> Result<Shape, String> {
        if to_world.matrix3.determinant().abs() < 1e-300 || !to_world.is_finite() {
            return Err("the transform is singular or not finite".into());
        }
        let natural = match &surface {
            Surface::Sphere { radius } => Some(Box3::cube(*radius)),
            Surface::Torus { major, minor } => Some(Box3 {
                min: DVec3::new(-(major + minor), -(major + minor), -minor),
                max: DVec3::new(major + minor, major + minor, *minor),
            }),
            Surface::Quadric(_) | Surface::Algebraic(_) => None,
            Surface::Csg(tree) => Some(tree.bounds()),
        };
        // Pad natural bounds a little, so no surface point lies exactly on the box
        // where the search interval starts.
        let natural = natural.map(|b| {
            let pad = 1e-9 * (b.max - b.min).max_element();
            Box3 {
                min: b.min - pad,
                max: b.max + pad,
            }
        });
        let object_box = match (natural, clip) {
            (Some(n), Some(c)) => n.intersection(&c),
            (Some(b), None) | (None, Some(b)) => b,
            (None, None) => return Err("an unbounded surface needs a clip box".into()),
        };
        if object_box.is_empty() {
            return Err("the clip box leaves nothing of the surface".into());
        }
        let world_bounds = world_bounds(&object_box, &to_world);
        // Spheres and tori are solved at unit size: object space is rescaled
        // by the power of two 2^unit that brings their box's extent near 1, so
        // a torus of radius 1e8 is searched with the same numbers (and
        // tolerances) as one of radius 1; the factor moves into the
        // transform, exactly.
        let extent = (object_box.max - object_box.min).max_element();
        let unit = match surface {
            // A box of no extent (a clip box that is one point) stays as it is.
            Surface::Sphere { .. } | Surface::Torus { .. } if extent > 0.0 => {
                -extent.log2().round() as i32
            }
            Surface::Sphere { .. } | Surface::Torus { .. } => 0,
            // A clip box says where to look, not how large the surface's
            // features are: these keep their own units.
            Surface::Quadric(_) | Surface::Algebraic(_) | Surface::Csg(_) => 0,
        };
        let to_object = DAffine3::from_scale(DVec3::splat(2f64.powi(unit))) * to_world.inverse();
        Ok(Shape {
            world_bounds,
            normal_to_world: to_object.matrix3.transpose(),
            surface: surface.at_scale_pow2(unit),
            material,
            to_object,
            object_box: Box3 {
                min: object_box.min * 2f64.powi(unit),
                max: object_box.max * 2f64.powi(unit),
            },
            surface_box: OnceLock::new(),
            unit,
            solver,
            gate: None,
            context_box: false,
            no_shadow: false,
            hollow: false,
        })
    }

    /// The material of the hit's `part` (see [`ShapeHit::part`]): a CSG
    /// leaf's own.
    pub fn material_of(&self, part: u32) -> u32 {
        match &self.surface {
            Surface::Csg(tree) => tree.material(part),
            _ => self.material,
        }
    }

    /// Every material the shape's surfaces use.
    pub fn materials(&self) -> Vec<u32> {
        match &self.surface {
            Surface::Csg(tree) => tree.materials().collect(),
            _ => vec![self.material],
        }
    }

    /// A one-line summary for `sturmray info`, in the units the scene gave.
    pub fn describe(&self) -> String {
        self.surface.at_scale_pow2(-self.unit).describe()
    }

    /// The centre and radius of the world-space sphere this shape is, if it is
    /// a whole sphere under a similarity transform (rotation, uniform scale,
    /// translation) and no clip box cuts it: what a sphere light needs.
    pub fn world_sphere(&self) -> Option<(DVec3, f64)> {
        let Surface::Sphere { radius } = self.surface else {
            return None;
        };
        // A gated sphere is not seen from every side a light would sample.
        if self.gate.is_some() {
            return None;
        }
        let whole = Box3::cube(radius);
        if self.object_box.intersection(&whole) != whole {
            return None;
        }
        let to_world = self.to_object.inverse();
        let m = to_world.matrix3;
        let scale = m.x_axis.length();
        let similar = [m.y_axis.length(), m.z_axis.length()]
            .iter()
            .all(|s| (s - scale).abs() <= 1e-9 * scale)
            && [
                m.x_axis.dot(m.y_axis),
                m.y_axis.dot(m.z_axis),
                m.z_axis.dot(m.x_axis),
            ]
            .iter()
            .all(|d| d.abs() <= 1e-9 * scale * scale);
        similar.then_some((to_world.translation, radius * scale))
    }

    /// World-space bounds of what rays can hit, rounded outwards to f32:
    /// for an algebraic surface, of the box around its points.
    pub fn bounds(&self) -> Bounds {
        match (&self.surface, self.search_box()) {
            (Surface::Algebraic(_), Some(b)) => world_bounds(b, &self.to_object.inverse()),
            _ => self.world_bounds,
        }
    }

    /// World-space bounds of the shape's box, rounded outwards to f32:
    /// where, as a CSG leaf, it may be inside.
    pub fn box_bounds(&self) -> Bounds {
        self.world_bounds
    }

    /// Where the surface's own roots are searched, in object space: the
    /// box around an algebraic surface's points (see `extent`), or the
    /// shape's box; None if the surface has no point in its box.
    fn search_box(&self) -> Option<&Box3> {
        match &self.surface {
            Surface::Algebraic(f) => self
                .surface_box
                .get_or_init(|| extent::surface_box(f, &self.object_box))
                .as_ref(),
            _ => Some(&self.object_box),
        }
    }

    /// The nearest hit with t in (tmin, tmax) of the world ray o + t·d.
    pub fn intersect(&self, o: DVec3, d: DVec3, tmin: f64, tmax: f64) -> Option<ShapeHit> {
        if let Some(gate) = &self.gate
            && !gate.lets_through(o, d, tmin)
        {
            return None;
        }
        if let Surface::Csg(tree) = &self.surface {
            return tree.intersect(o, d, tmin, tmax);
        }
        let found = self.search(o, d, tmin, tmax, false)?;
        Some(ShapeHit {
            t: found.t,
            normal: self.normal_at(found.object_point),
            part: 0,
            error: found.error,
        })
    }

    /// The world normal (unnormalised) at a point of the surface in object space.
    fn normal_at(&self, object_point: DVec3) -> DVec3 {
        // Scaled by a power of two (exact, direction unchanged): a gradient
        // of 1e200 (degree 16 at 1e13 from the origin) would overflow |n|²,
        // and normalising would give a zero normal, shaded black.
        let mut gradient = self.surface.gradient(object_point).to_array();
        // Only when needed: the scaling costs more than the comparison, and
        // ordinary gradients square without harm.
        let largest = gradient.iter().fold(0.0f64, |m, g| m.max(g.abs()));
        if !(1e-100..=1e100).contains(&largest) {
            normalize_pow2(&mut gradient);
        }
        self.normal_to_world * DVec3::from(gradient)
    }

    /// A bound on the error in t of a hit of the world ray o + t·d at `t`,
    /// computed afresh: the root's uncertainty (see `Surface::uncertainty`)
    /// plus the solver's tolerance. A search gives the same bound from the
    /// root it refined (`ShapeHit::error`); a CSG tree asks its leaf here.
    pub fn hit_error(&self, o: DVec3, d: DVec3, t: f64) -> f64 {
        let (o, d) = (
            self.to_object.transform_point3(o),
            self.to_object.transform_vector3(d),
        );
        let length = d.length();
        let d = d / length;
        let distance = t * length;
        let uncertainty = self.surface.uncertainty(o + distance * d, d);
        error_in_t(uncertainty, self.refine_width(distance), length)
    }

    /// Whether the world ray o + t·d crosses the surface for some t in (tmin, tmax).
    pub fn occluded(&self, o: DVec3, d: DVec3, tmin: f64, tmax: f64) -> bool {
        if self.no_shadow {
            return false;
        }
        if let Some(gate) = &self.gate
            && !gate.lets_through(o, d, tmin)
        {
            return false;
        }
        if let Surface::Csg(tree) = &self.surface {
            return tree.occluded(o, d, tmin, tmax);
        }
        self.search(o, d, tmin, tmax, true).is_some()
    }

    /// POV-Ray's `no_shadow`: the shape is seen but casts no shadow (no
    /// occlusion query finds it: shadow rays and light sampling pass it).
    pub fn set_no_shadow(&mut self) {
        self.no_shadow = true;
    }

    /// Whether occlusion queries find the shape (see `set_no_shadow`).
    pub fn casts_shadow(&self) -> bool {
        !self.no_shadow
    }

    /// POV-Ray's `hollow`: the shape's inside is air, as its outside is,
    /// for a fog.
    pub fn set_hollow(&mut self) {
        self.hollow = true;
    }

    /// Whether the shape's inside is air (see `set_hollow`).
    pub fn hollow(&self) -> bool {
        self.hollow
    }

    /// Swaps the root finder, for studies that compare them on one scene.
    pub fn set_solver(&mut self, solver: Solver) {
        if let Surface::Csg(tree) = &mut self.surface {
            tree.set_solver(solver);
        }
        if let Some(gate) = &mut self.gate {
            gate.set_solver(solver);
        }
        self.solver = solver;
    }

    /// The polynomial the search for hits of the world ray o + t·d with t in
    /// (tmin, tmax) solves, or None if the ray misses the shape's box.
    pub fn ray_polynomial(&self, o: DVec3, d: DVec3, tmin: f64, tmax: f64) -> Option<RayPoly> {
        self.ray_polynomial_in(o, d, tmin, tmax)
    }

    /// `ray_polynomial` with Q in `S` slots, which must hold the surface's
    /// degree + 1 coefficients (five do for `Surface::quartic`). The
    /// arithmetic is the same in any storage, so Q is the same bits.
    fn ray_polynomial_in<const S: usize>(
        &self,
        o: DVec3,
        d: DVec3,
        tmin: f64,
        tmax: f64,
    ) -> Option<RayPoly<S>> {
        self.ray_polynomial_within(&self.object_box, o, d, tmin, tmax)
    }

    /// `ray_polynomial_in` from where the ray enters `within`, a box
    /// that holds the surface's points in the shape's box.
    fn ray_polynomial_within<const S: usize>(
        &self,
        within: &Box3,
        o: DVec3,
        d: DVec3,
        tmin: f64,
        tmax: f64,
    ) -> Option<RayPoly<S>> {
        let frame = self.ray_frame(within, o, d, tmin, tmax)?;
        let q = self.surface.along_in::<S>(frame.start, frame.d);
        let formed = q.coeffs().len();
        Some(RayPoly {
            q: q.trimmed(1e-14, frame.hi),
            hi: frame.hi,
            start: frame.start,
            d: frame.d,
            t0: frame.t0,
            t1: frame.t1,
            length: frame.length,
            formed,
        })
    }

    /// The world line o + t·d in object space, with the length of its
    /// direction there; None for a direction of zero or infinite length.
    fn object_line(&self, o: DVec3, d: DVec3) -> Option<(DVec3, DVec3, f64)> {
        let (o, d) = (
            self.to_object.transform_point3(o),
            self.to_object.transform_vector3(d),
        );
        let length = d.length();
        (length > 0.0 && length.is_finite()).then_some((o, d, length))
    }

    /// The world ray o + t·d in object space, from where it enters the
    /// box `within` (object space), or None if it misses the box.
    fn ray_frame(
        &self,
        within: &Box3,
        o: DVec3,
        d: DVec3,
        tmin: f64,
        tmax: f64,
    ) -> Option<RayFrame> {
        // Search in object-space distance, not in t: a shape scaled by 1e-6 would
        // otherwise give Q(t) coefficients spanning 1e24 to 1, and tolerances would
        // mean nothing in the object's own units. t = distance / |d|.
        let (o, d, length) = self.object_line(o, d)?;
        let d = d / length;
        let (t0, t1) = within.clip_ray(o, d, tmin * length, tmax * length)?;
        // Move the origin to where the ray enters the box: Q's coefficients then
        // describe the surface near the ray's start, not far away from it.
        Some(RayFrame {
            start: o + t0 * d,
            d,
            t0,
            t1,
            hi: t1 - t0,
            length,
        })
    }

    fn search(&self, o: DVec3, d: DVec3, tmin: f64, tmax: f64, shadow: bool) -> Option<Found> {
        if let Surface::Quadric(q) = &self.surface
            && q.misses_line(
                self.to_object.transform_point3(o),
                self.to_object.transform_vector3(d),
            )
        {
            return None;
        }
        in_storage!(self, S => self.search_in::<S>(o, d, tmin, tmax, shadow))
    }

    /// `search` with the ray's Q in `S` slots (see `ray_polynomial_in`).
    fn search_in<const S: usize>(
        &self,
        o: DVec3,
        d: DVec3,
        tmin: f64,
        tmax: f64,
        shadow: bool,
    ) -> Option<Found> {
        let ray = self.ray_polynomial_within::<S>(self.search_box()?, o, d, tmin, tmax)?;
        // Shadow rays: a Sturm count of zero settles most of them without refining.
        if shadow && !self.quadratic() && !self.solver.any(&ray.q, 0.0, ray.hi) {
            return None;
        }
        let mut found = None;
        self.each_crossing(&ray, |s, _, uncertainty| {
            found = Some(Found {
                t: (ray.t0 + s) / ray.length,
                object_point: ray.start + s * ray.d,
                error: error_in_t(uncertainty, self.refine_width(ray.t0 + s), ray.length),
            });
            false
        });
        found
    }

    fn quadratic(&self) -> bool {
        matches!(self.surface, Surface::Sphere { .. } | Surface::Quadric(_))
    }

    /// Calls `visit(s, entering, uncertainty)` for each root of the ray's Q
    /// where the ray crosses the surface, nearest first, while it returns
    /// true; `uncertainty` is the root's (see `Surface::uncertainty`). Only roots
    /// where the ray crosses are accepted (see `polish`): touching and
    /// phantom roots are stepped past, at most `MAX_TOUCHES` of them.
    fn each_crossing<const S: usize>(
        &self,
        ray: &RayPoly<S>,
        mut visit: impl FnMut(f64, bool, f64) -> bool,
    ) {
        // By reference: a copy of the ray's Q (full-size storage) per walk
        // showed in the profile.
        let RayPoly {
            q, hi, start, d, ..
        } = ray;
        let (hi, start, d) = (*hi, *start, *d);
        // A quadric's roots come in closed form, the same bits each time
        // they are solved for: solved once, not once per root (three
        // solves per line of a clipping sphere in POV-Ray's tcubic.pov).
        let quadratic = self.quadratic();
        let mut closed = [0.0; 4];
        let solved = if quadratic {
            quadratic_roots(q.coeffs(), &mut closed)
        } else {
            0
        };
        let closed = &closed[..solved];
        let mut from = 0.0;
        let mut touches = 0;
        while touches < MAX_TOUCHES {
            let Some(s) = (if quadratic {
                closed.iter().copied().find(|&s| s > from && s < hi)
            } else {
                self.solver.nearest(q, from, hi)
            }) else {
                return;
            };
            match self.polish(q, start, d, s, from) {
                Ok((s, entering, uncertainty)) => {
                    if !visit(s, entering, uncertainty) {
                        return;
                    }
                    // Past the bisection's last interval, which holds the sign
                    // change: the samples of the next polish start on its far side.
                    from = s + self.refine_width(s);
                }
                Err(next) => {
                    from = next;
                    touches += 1;
                }
            }
        }
    }

    /// The width to which `polish` refines a root at distance s.
    fn refine_width(&self, s: f64) -> f64 {
        self.solver.tolerance * s.abs().max(1.0)
    }

    /// Re-solves around a root s of Q (formed at `start`) with Q formed at the
    /// root itself, whose rounding is far smaller: far from `start`, Q's value
    /// carries errors of ε Σ|c_k||s|^k, which near a triple-like root leave s
    /// off by 1e-4, and f64 Sturm counts there may see roots that are not.
    ///
    /// Only a sign change of the local Q is accepted: the ray crosses the
    /// surface there. A tangent touch, or a pair of roots that rounding made out
    /// of a complex pair (near the heart surface's rim, where F's gradient
    /// vanishes), has none. Returns the refined root, whether the ray
    /// enters there (F goes from + to −) and the root's uncertainty (see
    /// `Surface::uncertainty`), or where to search on.
    fn polish<const N: usize>(
        &self,
        q: &PolyN<N>,
        start: DVec3,
        d: DVec3,
        s: f64,
        from: f64,
    ) -> Result<(f64, bool, f64), f64> {
        if self.surface.quartic() {
            if let Some(proven) = self.proven_on_q(q, start, d, s, from) {
                return Ok(proven);
            }
            self.polish_in::<QUARTIC_SLOTS, N>(q, start, d, s, from)
        } else {
            self.polish_in::<SLOTS, N>(q, start, d, s, from)
        }
    }

    /// `polish`'s answer without forming Q at the root, where the ray's own
    /// Q (degree 4 or less) settles it: its noise near s (F's terms made
    /// positive along the ray from `start`, so the rounding of Q's
    /// coefficients counts too) leaves the root within the refinement
    /// width, Q' keeps its sign over the window (`polish`'s, 4 refinement
    /// widths each side), and Q's values at the window's ends stand above
    /// the noise with opposite signs: one crossing, within the window. Else
    /// None, and `polish` looks closer. Most hits of a quartic are settled
    /// here: forming Q at the root and scanning it was a tenth of the
    /// instructions of POV-Ray's torus.pov (`valgrind --tool=callgrind`).
    fn proven_on_q<const N: usize>(
        &self,
        q: &PolyN<N>,
        start: DVec3,
        d: DVec3,
        s: f64,
        from: f64,
    ) -> Option<(f64, bool, f64)> {
        // With Q's length known at compile time the work unrolls, with no
        // copies through memcpy and no calls for powers: a clipping
        // sphere's polish cost about 400 instructions (`valgrind
        // --tool=callgrind`, POV-Ray's tcubic.pov). The same operations in
        // the same order: the same bits.
        match q.coeffs().len() {
            2 => self.proven_with::<2, N>(q, start, d, s, from),
            3 => self.proven_with::<3, N>(q, start, d, s, from),
            4 => self.proven_with::<4, N>(q, start, d, s, from),
            5 => self.proven_with::<5, N>(q, start, d, s, from),
            _ => None,
        }
    }

    /// `proven_on_q` for a Q of `M` coefficients.
    fn proven_with<const M: usize, const N: usize>(
        &self,
        q: &PolyN<N>,
        start: DVec3,
        d: DVec3,
        s: f64,
        from: f64,
    ) -> Option<(f64, bool, f64)> {
        let coarse = q.coeffs();
        let n = coarse.len();
        let floor = self.refine_width(s);
        let window = 4.0 * floor;
        // Q's noise near s grows with the terms along the whole way from
        // `start`: where that way is long against the root's own distance
        // from the origin, it drowns the root (camera rays far from a
        // quartic), and only Q formed at the root will do.
        let reach = start.abs() + (s.abs() + window) * d.abs();
        let far = reach.element_sum() > 6.0 * (start + s * d).abs().element_sum();
        if far || n != M || s - window <= from {
            return None;
        }
        // Q's Taylor coefficients at s, by repeated synthetic division.
        let mut c = [0.0; M];
        c.copy_from_slice(coarse);
        for i in 0..M {
            for k in (i..M - 1).rev() {
                c[k] += s * c[k + 1];
            }
        }
        let c = &c[..];
        let noise = f64::EPSILON * (4 * n) as f64 * self.surface.magnitude(reach);
        let uncertainty = root_uncertainty(c, noise);
        if !(uncertainty <= floor && monotone_over(c, window)) {
            return None;
        }
        let at = |h: f64| c.iter().rev().fold(0.0, |acc, ck| acc * h + ck);
        let (before, after) = (at(-window), at(window));
        let crossed =
            before.abs() > noise && after.abs() > noise && (before < 0.0) != (after < 0.0);
        crossed.then_some((s, before > 0.0, uncertainty))
    }

    /// `polish` with the local Q in `S` slots (see `Surface::along_in`).
    fn polish_in<const S: usize, const N: usize>(
        &self,
        q: &PolyN<N>,
        start: DVec3,
        d: DVec3,
        s: f64,
        from: f64,
    ) -> Result<(f64, bool, f64), f64> {
        let floor = self.refine_width(s);
        let p = start + s * d;
        let local = self.surface.along_in::<S>(p, d);
        let local_noise =
            f64::EPSILON * (4 * local.coeffs().len()) as f64 * self.surface.magnitude(p);
        // How far the coarse root may be from the true one: Q's evaluation error at
        // s (or the local one, if larger), turned into distance by the local Taylor
        // coefficients. Four times that reaches past the noise on both sides.
        let coarse = q.coeffs();
        let noise =
            (f64::EPSILON * (4 * coarse.len()) as f64 * abs_eval(coarse, s)).max(local_noise);
        let reach = root_uncertainty(local.coeffs(), noise);
        let window = 4.0 * reach.max(floor);
        // The root's own uncertainty, from F's noise at the root alone: what
        // `Surface::uncertainty` gives there.
        let uncertainty = if noise == local_noise {
            reach
        } else {
            root_uncertainty(local.coeffs(), local_noise)
        };
        let span = Span {
            lo: (-window).max(from - s),
            hi: window,
            noise: local_noise,
            floor,
        };
        match span.newton_settled(&local).or_else(|| span.scanned(&local)) {
            Some((h, entering)) => Ok((s + h, entering, uncertainty)),
            None => Err(s + window),
        }
    }
}

/// A hit's error bound in the ray's t from its root's uncertainty and its
/// refinement width, both in object-space distance, and the length of the
/// ray's direction there: twice the uncertainty (capped at one unit of
/// object space) for the root's noise on either side.
fn error_in_t(uncertainty: f64, refine: f64, length: f64) -> f64 {
    (2.0 * uncertainty.min(1.0) + refine) / length
}

/// Whether the polynomial of Taylor coefficients c (at 0) is monotone over
/// [−window, window]: Q' moves by at most Σ k |c_k| window^(k−1) there, so
/// it keeps the sign of c_1 if that is less than |c_1|.
fn monotone_over(c: &[f64], window: f64) -> bool {
    let drift: f64 = (2..c.len())
        .map(|k| k as f64 * c[k].abs() * window.powi(k as i32 - 1))
        .sum();
    c.len() >= 2 && c[1].abs() > drift
}

/// Where `polish_in` looks for the crossing of q, the ray's Q formed at a
/// coarse root: [lo, hi] around it, values within `noise` of zero having no
/// sign to trust, the crossing wanted to within `floor`.
#[derive(Clone, Copy)]
struct Span {
    lo: f64,
    hi: f64,
    noise: f64,
    floor: f64,
}

impl Span {
    /// The crossing without the scan and bisection, where one Newton step
    /// from 0 settles it: q is monotone over [−hi, hi] (the window around
    /// the coarse root), so it crosses zero there at most once, and its
    /// values half a refinement width either side of the step stand above
    /// the noise with opposite signs, so it crosses between them, within
    /// [lo, hi]. The scan and bisection would find that crossing too, to
    /// the same width. Returns the step and whether q falls there (the ray
    /// enters). Most hits of camera rays far from a quartic end here: the
    /// scan and bisection were a third of their polish (`valgrind
    /// --tool=callgrind` on POV-Ray's torus.pov).
    fn newton_settled<const S: usize>(&self, q: &PolyN<S>) -> Option<(f64, bool)> {
        let c = q.coeffs();
        if !monotone_over(c, self.hi) {
            return None;
        }
        let h = -c[0] / c[1];
        let (a, b) = (h - 0.5 * self.floor, h + 0.5 * self.floor);
        if !(a >= self.lo && b <= self.hi) {
            return None;
        }
        let (fa, fb) = (q.eval(a), q.eval(b));
        let crossed = fa.abs() > self.noise && fb.abs() > self.noise && (fa < 0.0) != (fb < 0.0);
        crossed.then_some((h, fa > 0.0))
    }

    /// The first crossing of q in [lo, hi], found by sampling and refined by
    /// bisection to `floor`, with whether q falls there; None if it has none.
    fn scanned<const S: usize>(&self, q: &PolyN<S>) -> Option<(f64, bool)> {
        const SAMPLES: u32 = 32;
        let step = (self.hi - self.lo) / f64::from(SAMPLES);
        let mut last: Option<(f64, f64)> = None;
        for i in 0..=SAMPLES {
            let b = self.lo + step * f64::from(i);
            let fb = q.eval(b);
            // A change counts only between samples that both rise above
            // the noise.
            if fb.abs() <= self.noise {
                continue;
            }
            if let Some((a, fa)) = last
                && (fa < 0.0) != (fb < 0.0)
            {
                return Some((bisect(q, a, fa, b, self.floor), fa > 0.0));
            }
            last = Some((b, fb));
        }
        None
    }
}

/// Halves [a, b], across which q changes sign, down to `width`.
fn bisect<const S: usize>(q: &PolyN<S>, mut a: f64, fa: f64, mut b: f64, width: f64) -> f64 {
    for _ in 0..80 {
        if b - a <= width {
            break;
        }
        let m = 0.5 * (a + b);
        if (q.eval(m) < 0.0) == (fa < 0.0) {
            a = m;
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}

/// Σ |c_k| |x|^k: the scale of the rounding error in evaluating the polynomial at x.
fn abs_eval(c: &[f64], x: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, ck| acc * x.abs() + ck.abs())
}

/// How many touching roots one search steps past before giving up on the ray.
const MAX_TOUCHES: usize = 8;

/// The roots of c0 + c1 s + c2 s², increasing, by the stable formula.
fn quadratic_roots(c: &[f64], roots: &mut [f64; 4]) -> usize {
    let coeff = |k: usize| c.get(k).copied().unwrap_or(0.0);
    quadratic(coeff(0), coeff(1), coeff(2), roots)
}

/// The world bounds of an object box: its 8 corners mapped, rounded outwards to f32.
fn world_bounds(b: &Box3, to_world: &DAffine3) -> Bounds {
    let Box3 { min: lo, max: hi } = world_box(b, to_world);
    // f64 → f32 rounds to nearest; one more step outwards keeps the box conservative.
    let down = |x: f64| (x as f32).next_down();
    let up = |x: f64| (x as f32).next_up();
    Bounds {
        min: Vec3::new(down(lo.x), down(lo.y), down(lo.z)),
        max: Vec3::new(up(hi.x), up(hi.y), up(hi.z)),
    }
}

/// The box around an object box's 8 corners mapped by `to_world`.
fn world_box(b: &Box3, to_world: &DAffine3) -> Box3 {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for i in 0..8 {
        let corner = DVec3::new(
            if i & 1 == 0 { b.min.x } else { b.max.x },
            if i & 2 == 0 { b.min.y } else { b.max.y },
            if i & 4 == 0 { b.min.z } else { b.max.z },
        );
        let p = to_world.transform_point3(corner);
        lo = lo.min(p);
        hi = hi.max(p);
    }
    Box3 { min: lo, max: hi }
}

#[cfg(test)]
mod tests {
    use super::{Box3, Shape, Span, Surface};
    use crate::poly::solve::Solver;
    use crate::poly::trivariate::tests::torus;
    use crate::poly::univariate::{PolyN, QUARTIC_SLOTS};
    use glam::{DAffine3, DVec3};

    /// The torus R = 2, r = 0.5 as an algebraic surface.
    fn algebraic_torus() -> Shape {
        let f = torus(2.0, 0.5);
        let clip = Box3 {
            min: DVec3::new(-2.6, -2.6, -0.6),
            max: DVec3::new(2.6, 2.6, 0.6),
        };
        let surface = Surface::Algebraic(Box::new(f));
        Shape::new(
            surface,
            DAffine3::IDENTITY,
            Some(clip),
            0,
            Solver::default(),
        )
        .unwrap()
    }

    /// Where the ray's own Q settles a root (`proven_on_q`), the full
    /// polish, which forms Q at the root, agrees: the same side, and roots
    /// within both error bounds. Rays from near the torus (where the short
    /// way keeps Q's noise small) in many directions, grazing ones among
    /// them; most must be settled on the ray's Q, or the test shows nothing.
    #[test]
    fn a_root_proven_on_the_rays_q_is_the_polished_one() {
        let torus = algebraic_torus();
        let (mut proven, mut rays) = (0, 0);
        for i in 0..4000 {
            let k = f64::from(i);
            let o = DVec3::new(
                2.9 * (k * 0.71).sin(),
                2.9 * (k * 0.53).cos(),
                0.7 * (k * 0.29).sin(),
            );
            let aim = DVec3::new(
                2.0 * (k * 0.13).cos(),
                2.0 * (k * 0.13).sin(),
                0.5 * (k * 0.37).sin(),
            );
            let d = (aim - o).normalize();
            let Some(ray) = torus.ray_polynomial(o, d, 0.0, f64::INFINITY) else {
                continue;
            };
            let Some(s) = torus.solver.nearest(&ray.q, 0.0, ray.hi) else {
                continue;
            };
            rays += 1;
            let Some((s_q, entering_q, u_q)) = torus.proven_on_q(&ray.q, ray.start, ray.d, s, 0.0)
            else {
                continue;
            };
            proven += 1;
            let full = torus.polish_in::<QUARTIC_SLOTS, _>(&ray.q, ray.start, ray.d, s, 0.0);
            let (s_p, entering_p, u_p) = full.expect("a proven crossing is one for polish too");
            let width = torus.refine_width(s);
            assert_eq!(entering_q, entering_p, "ray {i}");
            assert!(
                (s_q - s_p).abs() <= 2.0 * (u_q + u_p) + 4.0 * width,
                "ray {i}: {s_q} against {s_p} (uncertainties {u_q:e}, {u_p:e})"
            );
        }
        assert!(rays > 1000 && proven * 10 > rays * 8, "{proven} of {rays}");
    }

    /// Where one Newton step settles a polish (`newton_settled`), the scan
    /// and bisection it saves find the same crossing: the same side, within
    /// a refinement width. Quartics with a root near 0 (where the coarse
    /// root put it) and others far off, either sign, some with the near
    /// root before `lo` (already passed), some doubled (a touch, which
    /// neither may take) and some with a second root inside the window
    /// (no longer monotone there: Newton must decline). Most simple ones
    /// must be settled, or the test shows nothing.
    #[test]
    fn a_root_settled_by_newton_is_the_scanned_one() {
        let (floor, window) = (1e-12, 4e-11);
        let (mut settled, mut simple) = (0, 0);
        for i in 0..3000 {
            let k = f64::from(i);
            let near = 3e-11 * (k * 0.77).sin();
            let second = match i % 4 {
                0 => near,                           // a touch
                1 => near + 2e-11 * (k * 0.3).cos(), // two roots in the window
                _ => 1.0 + (k * 0.41).sin().abs(),   // far away
            };
            let far = -2.0 - (k * 0.23).cos().abs();
            let sign = if i % 3 == 0 { -1.0 } else { 1.0 };
            // sign (h − near)(h − second)((h − far)² + 1), expanded.
            let mut c = [0.0; QUARTIC_SLOTS];
            c[..3].copy_from_slice(&[sign * (far * far + 1.0), -2.0 * sign * far, sign]);
            for root in [near, second] {
                for j in (0..QUARTIC_SLOTS).rev() {
                    let below = if j > 0 { c[j - 1] } else { 0.0 };
                    c[j] = below - root * c[j];
                }
            }
            let q = PolyN::<QUARTIC_SLOTS>::new(&c);
            let noise = f64::EPSILON * 16.0 * c.iter().map(|x| x.abs()).sum::<f64>();
            let lo = if i % 5 == 0 {
                near + 2.0 * floor
            } else {
                -window
            };
            let span = Span {
                lo,
                hi: window,
                noise,
                floor,
            };
            let (fast, slow) = (span.newton_settled(&q), span.scanned(&q));
            if i % 4 >= 2 && lo < near {
                simple += 1;
            }
            let Some((h, entering)) = fast else {
                continue;
            };
            settled += 1;
            assert!(i % 4 >= 2, "case {i}: Newton took a touch or a pair");
            let (h_slow, entering_slow) = slow.expect("a settled crossing is a scanned one");
            assert_eq!(entering, entering_slow, "case {i}");
            assert!(
                (h - h_slow).abs() <= floor,
                "case {i}: {h} against {h_slow}"
            );
            assert!(
                (h - near).abs() <= 0.5 * floor,
                "case {i}: {h} against {near}"
            );
        }
        assert!(settled * 10 > simple * 9, "{settled} of {simple}");
    }

    /// A quadric's quick miss (`Quadric::misses_line`) is never wrong: no
    /// ray it rejects has a root of the searched Q, on any of a cylinder,
    /// a cone, both hyperboloids and an ellipsoid, placed by a rotation, a
    /// non-uniform scale and a translation, with rays from near and far,
    /// grazing ones among them. And it rejects most misses, or it saves
    /// nothing.
    #[test]
    fn a_quadric_s_quick_miss_has_no_root() {
        use super::surface::Quadric;
        use crate::poly::closed::quadratic;
        use glam::{DMat3, DQuat};
        let quadrics = [
            (DVec3::new(1.0, 1.0, 0.0), -0.01),  // a thin cylinder along z
            (DVec3::new(1.0, 1.0, -1.0), 0.0),   // a cone
            (DVec3::new(1.0, 1.0, -1.0), -1.0),  // a hyperboloid of one sheet
            (DVec3::new(-1.0, -1.0, 1.0), -1.0), // of two sheets
            (DVec3::new(1.0, 4.0, 9.0), -1.0),   // an ellipsoid
        ];
        let place = DAffine3::from_scale_rotation_translation(
            DVec3::new(2.0, 0.5, 1.5),
            DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -0.7, 1.1),
            DVec3::new(0.5, -2.0, 3.0),
        );
        let (mut rejected, mut misses) = (0, 0);
        for (diagonal, c) in quadrics {
            let q = Quadric {
                a: DMat3::from_diagonal(diagonal),
                b: DVec3::ZERO,
                c,
            };
            let shape = Shape::new(
                Surface::Quadric(q.clone()),
                place,
                Some(Box3::cube(1e7)),
                0,
                Solver::default(),
            )
            .unwrap();
            for i in 0..4000 {
                let k = f64::from(i);
                let far = if i % 2 == 0 { 8.0 } else { 1e4 };
                let o = far * DVec3::new((k * 0.7).sin(), (k * 0.3).cos(), (k * 0.11).sin());
                // Aimed near the surface's centre, some within 1e-9 of
                // grazing the thin cylinder's wall.
                let aim = place.transform_point3(DVec3::new(
                    0.1 * (k * 0.37).cos() + if i % 7 == 0 { 0.1 } else { 0.0 },
                    0.2 * (k * 0.53).sin(),
                    (k * 0.19).cos(),
                ));
                let d = (aim - o).normalize() * (1.0 + 1e-9 * (k * 0.9).sin());
                let (oo, od) = (
                    shape.to_object.transform_point3(o),
                    shape.to_object.transform_vector3(d),
                );
                let quick = q.misses_line(oo, od);
                let Some(ray) = shape.ray_polynomial(o, d, 0.0, f64::INFINITY) else {
                    continue;
                };
                let c = ray.q.coeffs();
                let coeff = |j: usize| c.get(j).copied().unwrap_or(0.0);
                let mut roots = [0.0; 4];
                let n = quadratic(coeff(0), coeff(1), coeff(2), &mut roots);
                if n == 0 {
                    misses += 1;
                    rejected += usize::from(quick);
                }
                assert!(
                    !(quick && n > 0),
                    "quadric {diagonal}, ray {i}: rejected, yet Q has roots {:?}",
                    &roots[..n]
                );
            }
        }
        assert!(
            rejected * 10 > misses * 9,
            "{rejected} of {misses} misses rejected"
        );
    }
}
