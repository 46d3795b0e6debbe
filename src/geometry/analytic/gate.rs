//! POV-Ray's `bounded_by` as a gate on a shape: rays that neither start
//! inside it nor cross its surface beyond their start never reach the
//! shape. Checked first in `Shape::intersect` and `Shape::occluded`; a shape
//! without a gate pays one branch for it.

use glam::{DAffine3, DVec3};

use super::{Box3, Quadric, Shape, Surface};
use crate::math::{larger, smaller};
use crate::poly::univariate::QUARTIC_SLOTS;

/// How far inside a gate a box must lie for the gate to be dropped
/// (`Shape::needs_gate`), as a fraction of the gate's size.
const HOLD_MARGIN: f64 = 1e-9;

/// A convex region in a shape's object space (see `Shape::region`).
#[derive(Clone, Copy)]
enum Region {
    /// The ball of this radius about the origin.
    Ball(f64),
    Block(Box3),
}

impl Shape {
    /// Gives the shape POV-Ray's `bounded_by` object: a ray is tested
    /// against the shape only if it starts inside the gate or crosses the
    /// gate's surface somewhere beyond its tmin, however far (past its tmax
    /// too); then every hit of the shape counts, inside the gate or not. For
    /// a gate that holds the shape this only saves time; for an unbounded
    /// surface it decides what is seen. The shape's box stays its own: the
    /// gate cuts rays, not space. Inside is the gate's own (F < 0 within its
    /// box, or a tree's state); a sheet has none and gates by crossings only.
    /// A tree is gated as a whole: the gate of a shape used as a tree's leaf
    /// is not consulted (a leaf gives its crossings along the whole line).
    /// A gate may have a gate of its own: a ray then passes only if it passes
    /// both, as POV-Ray's `bounded_by { A B }` asks of every bound.
    pub fn set_gate(&mut self, gate: Shape) {
        self.gate = Some(Box::new(gate));
    }

    /// Whether `gate` could turn away a ray with a hit on this shape: false
    /// when the shape's hits all lie in a box inside the gate, and inside
    /// each gate the gate has, with a margin. A ray a gate turns away stays
    /// outside it, and so outside that box, where the shape has no hit.
    ///
    /// - A plain surface is searched only within its search box (for an
    ///   algebraic surface, the box around its own points, see `extent`),
    ///   which the BVH bounds it by too: where the gate holds that box, the
    ///   box test already turns away what the gate would, and the gate only
    ///   cost time: 7-11% of the render-loop instructions of POV-Ray's
    ///   lemnisca, lemnisc2 and piriform samples (`valgrind
    ///   --tool=callgrind`). An unbounded surface's box reaches out of its
    ///   gate, which keeps it. A gate that holds the surface but not its
    ///   box is kept too: a sphere tight around a torus turns away rays
    ///   through the box's corners, and torus.pov took 2.6% more
    ///   instructions without it.
    /// - A tree is cut by a box (an intersection or clip child, see
    ///   `Csg::cut_by`) that the gate holds. The tree's walk finds the box's
    ///   span first on every ray anyway, at about a box gate's cost, so the
    ///   gate only cost time: 6-7% of the render-loop instructions of
    ///   POV-Ray's monkey and trough samples. A clip sphere is not: its
    ///   crossings cost several times a sphere gate's test, which saves them
    ///   on the rays it turns away (dropping the gate of folium.pov, whose
    ///   bound holds its clip sphere, cost 1.9% more instructions).
    pub fn needs_gate(&self, gate: &Shape) -> bool {
        let Surface::Csg(tree) = &self.surface else {
            // A surface with no point in its box has no hit to turn away.
            return self
                .search_box()
                .is_some_and(|b| !gate.holds(&self.to_object, b));
        };
        !tree.cut_by().any(|solid| match solid.region() {
            Some(Region::Block(b)) => gate.holds(&solid.to_object, &b),
            _ => false,
        })
    }

    /// Whether `inner`, a box in the object space of a shape whose map to it
    /// from world space is `to_inner`, lies inside this gate (a sphere or a
    /// box) and each gate it has, with a margin of `HOLD_MARGIN` of the
    /// gate's size (far beyond the rounding of the maps and of any ray's
    /// test). Any other gate holds nothing here.
    fn holds(&self, to_inner: &DAffine3, inner: &Box3) -> bool {
        if let Some(next) = &self.gate
            && !next.holds(to_inner, inner)
        {
            return false;
        }
        let outer = match &self.surface {
            Surface::Csg(tree) => match tree.lone_solid() {
                Some(solid) => solid,
                None => return false,
            },
            _ => self,
        };
        let Some(outer_region) = outer.region() else {
            return false;
        };
        // A gate's box that cuts its sphere makes the gate smaller than the ball.
        if let Region::Ball(r) = outer_region
            && !outer.box_holds_sphere(r)
        {
            return false;
        }
        // Inner's object space mapped into outer's; both regions are
        // convex, so the box is inside if its corners are.
        let map = outer.to_object * to_inner.inverse();
        (0..8).all(|k| {
            let corner = DVec3::select(
                glam::BVec3::new(k & 1 != 0, k & 2 != 0, k & 4 != 0),
                inner.max,
                inner.min,
            );
            let p = map.transform_point3(corner);
            match outer_region {
                Region::Ball(r) => p.length() <= r * (1.0 - HOLD_MARGIN),
                Region::Block(b) => {
                    let margin = HOLD_MARGIN * (b.max - b.min).max_element();
                    p.cmpge(b.min + margin).all() && p.cmple(b.max - margin).all()
                }
            }
        })
    }

    /// The convex region, in object space, that holds this shape as a
    /// solid: a sphere's ball (its box can only cut it smaller) or a box's
    /// block (F = c < 0 within it); None for other shapes.
    fn region(&self) -> Option<Region> {
        match &self.surface {
            Surface::Sphere { radius } => Some(Region::Ball(*radius)),
            Surface::Quadric(q) if q.constant().is_some_and(|c| c < 0.0) => {
                Some(Region::Block(self.object_box))
            }
            _ => None,
        }
    }

    /// Whether this shape, as another's gate, lets the ray from o + tmin·d on
    /// through (see `set_gate`).
    pub(super) fn lets_through(&self, o: DVec3, d: DVec3, tmin: f64) -> bool {
        if let Some(next) = &self.gate
            && !next.lets_through(o, d, tmin)
        {
            return false;
        }
        // A box or capped cylinder gate is a tree of one closed solid of a
        // quadric: its inside (F < 0 within its box) in closed form. The
        // tree's walk of its events took 1,070 instructions a ray on
        // trough.pov's box gate (`valgrind --tool=callgrind`).
        let gate = match &self.surface {
            Surface::Csg(tree) => match tree.lone_solid().filter(|s| s.quadratic()) {
                Some(solid) => solid,
                None => return tree.inside_or_crossed(o, d, tmin),
            },
            _ => self,
        };
        if gate.quadratic() {
            return gate.comes_near(o, d, tmin);
        }
        let p = self.to_object.transform_point3(o + tmin * d);
        let in_box = p.cmpge(self.object_box.min).all() && p.cmple(self.object_box.max).all();
        // On the surface (F within its noise) counts as inside: a gate that
        // opens once too often costs time, never a hit.
        (in_box && self.side(p, DVec3::X) != Some(false))
            || self.search(o, d, tmin, f64::INFINITY, true).is_some()
    }

    /// `lets_through` for a sphere or quadric gate, without refining a root:
    /// whether Q(s) = c0 + c1 s + c2 s² comes within its rounding noise of
    /// zero, or below it, anywhere on the ray inside the gate's box beyond
    /// tmin. That holds whenever the ray starts inside or crosses the
    /// surface, and also for the few rays that enter the inside through a
    /// face of the box or pass within rounding of a tangent, for which the
    /// gate only opens needlessly. The full test's polish was most of the
    /// gate's cost: a fifth of the instructions of POV-Ray's torus.pov,
    /// whose quartic has a bounding sphere (`valgrind --tool=callgrind`).
    fn comes_near(&self, o: DVec3, d: DVec3, tmin: f64) -> bool {
        match &self.surface {
            Surface::Sphere { radius } if self.box_holds_sphere(*radius) => {
                self.sphere_comes_near(*radius, o, d, tmin)
            }
            Surface::Quadric(quadric) => self.quadric_comes_near(quadric, o, d, tmin),
            _ => self.framed_comes_near(o, d, tmin),
        }
    }

    /// `comes_near` on the ray's Q in its frame (from the entry into the
    /// gate's box, unit direction): the box may cut the surface.
    fn framed_comes_near(&self, o: DVec3, d: DVec3, tmin: f64) -> bool {
        // In the quartic storage: a gate needs no solver's Q.
        let Some(ray) = self.ray_polynomial_in::<QUARTIC_SLOTS>(o, d, tmin, f64::INFINITY) else {
            return false;
        };
        let c = ray.q.coeffs();
        let coeff = |k: usize| c.get(k).copied().unwrap_or(0.0);
        let (c0, c1, c2) = (coeff(0), coeff(1), coeff(2));
        let q = |s: f64| c0 + s * (c1 + s * c2);
        let hi = ray.hi;
        let noise = 16.0 * f64::EPSILON * (c0.abs() + hi * (c1.abs() + hi * c2.abs()));
        let mut least = q(0.0).min(q(hi));
        if c2 > 0.0 {
            let vertex = -c1 / (2.0 * c2);
            if vertex > 0.0 && vertex < hi {
                least = least.min(q(vertex));
            }
        }
        // A NaN (a ray at infinity) opens the gate: the shape decides.
        least.is_nan() || least <= noise
    }

    /// `comes_near` for a quadric, in object space and in the ray's own t
    /// (an affine map keeps t), as `sphere_comes_near` does for a sphere but
    /// within the gate's box: Q(t) = c0 + c1 t + c2 t² at its least over the
    /// ray's interval in the box beyond tmin (the ends, and the vertex when
    /// it lies between), against the rounding of its terms there. Each of
    /// c0, c1, c2 and Q's evaluation is within a few roundings of the
    /// quadric's terms made positive along the way, which at the farthest t
    /// reached is `magnitude(|o| + |t| |d|)`: only rays within rounding of a
    /// tangent can be decided otherwise than by the framed path, and the
    /// noise opens the gate for them. The framed path's unit direction (a
    /// square root and three divisions), entry point and trimmed Q were most
    /// of its 640 instructions a call on POV-Ray's helix.pov, whose
    /// `clipped_by` cylinder gates its quartic (`valgrind --tool=callgrind`).
    fn quadric_comes_near(&self, quadric: &Quadric, o: DVec3, d: DVec3, tmin: f64) -> bool {
        let (o, d) = (
            self.to_object.transform_point3(o),
            self.to_object.transform_vector3(d),
        );
        let Some((t0, t1)) = self.object_box.clip_ray(o, d, tmin, f64::INFINITY) else {
            return false;
        };
        // A box gate (F = c < 0 within its box): Q is c all along, below
        // any noise, so the steps below open it wherever the line meets the
        // box. They were a third of the box gates of POV-Ray's monkey,
        // trough and quarpara samples (`valgrind --tool=callgrind`).
        if quadric.constant().is_some_and(|c| c < 0.0) {
            return true;
        }
        let [c0, c1, c2] = quadric.along_line(o, d);
        let q = |t: f64| c0 + t * (c1 + t * c2);
        let mut least = q(t0).min(q(t1));
        if c2 > 0.0 {
            let vertex = -c1 / (2.0 * c2);
            if vertex > t0 && vertex < t1 {
                least = least.min(q(vertex));
            }
        }
        let reach = t0.abs().max(t1.abs());
        let noise = 16.0 * f64::EPSILON * quadric.magnitude(o.abs() + reach * d.abs());
        // A NaN (a ray at infinity, an unbounded box) opens the gate: the
        // shape decides.
        least.is_nan() || least <= noise
    }

    /// Whether the sphere's box holds all of it (no clip box cuts it), so
    /// that the box decides nothing a ray's closest approach does not.
    fn box_holds_sphere(&self, radius: f64) -> bool {
        self.object_box.min.cmple(DVec3::splat(-radius)).all()
            && self.object_box.max.cmpge(DVec3::splat(radius)).all()
    }

    /// `comes_near` for a whole sphere: Q(t) = |o + t·d|² − r² in object
    /// space and in the ray's own t (an affine map keeps t), at its least
    /// over [tmin, ∞), against the rounding noise of its terms there. That
    /// needs neither the box's slabs nor a unit direction: POV-Ray's samples
    /// bound their quartics by spheres, and the general path's ray frame
    /// (a square root and six divisions) and trimmed Q were most of the
    /// gate's 575 instructions a ray in torus.pov (`valgrind
    /// --tool=callgrind`). Only rays within rounding of the tangent can be
    /// decided otherwise than there, and the noise opens the gate for them.
    fn sphere_comes_near(&self, radius: f64, o: DVec3, d: DVec3, tmin: f64) -> bool {
        let (o, d) = (
            self.to_object.transform_point3(o),
            self.to_object.transform_vector3(d),
        );
        let Some([c0, c1, c2]) = self.surface.along_line(o, d) else {
            return true;
        };
        // The closest approach at or beyond tmin: Q falls until the vertex.
        let vertex = if c2 > 0.0 {
            larger(-c1 / (2.0 * c2), tmin)
        } else {
            tmin
        };
        let q = |t: f64| c0 + t * (c1 + t * c2);
        let reach = larger(tmin.abs(), vertex.abs());
        let noise = 16.0
            * f64::EPSILON
            * (o.length_squared() + radius * radius + reach * (c1.abs() + reach * c2));
        // A NaN (a ray at infinity) opens the gate: the shape decides.
        let least = smaller(q(tmin), q(vertex));
        least.is_nan() || least <= noise
    }
}

#[cfg(test)]
mod tests {
    use glam::{DAffine3, DMat3, DQuat, DVec3};

    use super::super::{Box3, Quadric, Shape, Surface};
    use crate::poly::solve::Solver;

    /// Ray `i` of a test's spread, in the world of `to_world`: from an
    /// object-space point `distance` from the origin (between its two
    /// values) towards one within `aim` of it on each axis, with a length
    /// of direction from 0.5 to 1.5, and tmin 0.4 on every third ray.
    fn test_ray(
        to_world: &DAffine3,
        i: u32,
        aim: f64,
        distance: (f64, f64),
    ) -> (DVec3, DVec3, f64) {
        let k = f64::from(i);
        let target = DVec3::new((k * 0.37).sin(), (k * 0.61).cos(), (k * 0.83).sin()) * aim;
        let from = DVec3::new((k * 0.11).cos(), (k * 0.29).sin(), (k * 0.47).cos()).normalize()
            * (distance.0 + (distance.1 - distance.0) * (0.5 + 0.5 * (k * 0.93).sin()));
        let (o, target) = (
            to_world.transform_point3(from),
            to_world.transform_point3(target),
        );
        let d = (target - o) * (0.5 + (k * 0.17).cos().abs());
        (o, d, if i.is_multiple_of(3) { 0.4 } else { 0.0 })
    }

    /// F's least over the line's interval in the box beyond tmin (at its
    /// ends, or at Q's vertex between them), with the interval; None where
    /// the line misses the box.
    fn least_in_box(
        object: &Quadric,
        object_box: &Box3,
        po: DVec3,
        pd: DVec3,
        tmin: f64,
    ) -> Option<(f64, f64, f64)> {
        let (t0, t1) = object_box.clip_ray(po, pd, tmin, f64::INFINITY)?;
        let q = |t: f64| object.eval(po + t * pd);
        let ad = object.a * pd;
        let curve = pd.dot(ad);
        let vertex = if curve > 0.0 {
            (-(2.0 * po.dot(ad) + object.b.dot(pd)) / (2.0 * curve)).clamp(t0, t1)
        } else {
            t0
        };
        Some((q(t0).min(q(t1)).min(q(vertex)), t0, t1))
    }

    /// The whole-sphere gate decides as the framed one, box and all, on
    /// every ray that is not within 1e-9 of the tangent: under a rotation,
    /// a non-uniform scale and a translation (an ellipsoid in the world),
    /// from outside, inside and beyond the sphere, with tmin past the
    /// origin on some. Near the tangent the two may differ, but only by
    /// opening: neither loses a ray that passes inside.
    #[test]
    fn a_whole_sphere_gate_decides_as_the_framed_one() {
        let to_world = DAffine3::from_scale_rotation_translation(
            DVec3::new(2.0, 0.5, 1.25),
            DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -0.7, 1.1),
            DVec3::new(3.0, -1.0, 7.0),
        );
        let radius = 1.5;
        let gate = Shape::new(
            Surface::Sphere { radius },
            to_world,
            None,
            0,
            Solver::default(),
        )
        .unwrap();
        let Surface::Sphere {
            radius: unit_radius,
        } = gate.surface
        else {
            unreachable!()
        };
        assert!(gate.box_holds_sphere(unit_radius));
        let to_object = to_world.inverse();
        let (mut crossing, mut missing, mut tangent) = (0, 0, 0);
        for i in 0..20_000 {
            // Aim within the sphere's box, from 0.3 to 6 radii out.
            let (o, d, tmin) = test_ray(&to_world, i, 1.3 * radius, (0.3 * radius, 6.0 * radius));
            // The truth in object space, where the gate is the sphere.
            let (po, pd) = (
                to_object.transform_point3(o),
                to_object.transform_vector3(d),
            );
            let t = (-po.dot(pd) / pd.length_squared()).max(tmin);
            let closest = (po + t * pd).length_squared() / (radius * radius) - 1.0;
            let fast = gate.comes_near(o, d, tmin);
            let framed = gate.framed_comes_near(o, d, tmin);
            if closest.abs() < 1e-9 {
                tangent += 1;
                continue;
            }
            let inside = closest < 0.0;
            assert_eq!(fast, inside, "ray {i}: closest {closest:e}");
            assert_eq!(framed, inside, "ray {i}: closest {closest:e}");
            if inside {
                crossing += 1;
            } else {
                missing += 1;
            }
        }
        assert!(
            crossing > 5_000 && missing > 5_000,
            "{crossing} crossing, {missing} missing, {tangent} tangent"
        );
    }

    /// The quadric gate decides as the framed one, on every ray that does
    /// not pass within 1e-9 (of the terms' scale) of touching the surface
    /// inside the box: for a cylinder cut by its box (helix.pov's gate) and
    /// a one-sheeted hyperboloid, under a rotation, a non-uniform scale and
    /// a translation, from outside and inside, with tmin past the origin on
    /// some. Every ray counts both ways.
    #[test]
    fn a_quadric_gate_decides_as_the_framed_one() {
        let to_world = DAffine3::from_scale_rotation_translation(
            DVec3::new(1.5, 0.75, 2.0),
            DQuat::from_euler(glam::EulerRot::XYZ, -0.4, 0.9, 0.2),
            DVec3::new(-2.0, 4.0, 3.0),
        );
        let clip = Box3 {
            min: DVec3::new(-2.0, -2.0, -1.5),
            max: DVec3::new(2.0, 2.0, 1.0),
        };
        let quadrics = [
            // x² + y² − 1: a cylinder along z, cut by the box's z faces.
            Quadric {
                a: DMat3::from_diagonal(DVec3::new(1.0, 1.0, 0.0)),
                b: DVec3::ZERO,
                c: -1.0,
            },
            // x² + y² − z² − 0.5, shifted: a hyperboloid of one sheet.
            Quadric {
                a: DMat3::from_diagonal(DVec3::new(1.0, 1.0, -1.0)),
                b: DVec3::new(0.2, 0.0, 0.1),
                c: -0.5,
            },
        ];
        for quadric in quadrics {
            let gate = Shape::new(
                Surface::Quadric(quadric),
                to_world,
                Some(clip),
                0,
                Solver::default(),
            )
            .unwrap();
            let Surface::Quadric(object) = &gate.surface else {
                unreachable!()
            };
            let to_object = gate.to_object;
            let (mut open, mut closed, mut tangent) = (0, 0, 0);
            for i in 0..20_000 {
                let (o, d, tmin) = test_ray(&to_world, i, 2.2, (0.5, 6.5));
                // Q's least over the ray's interval in the box, in object
                // space, against the scale of its terms there.
                let (po, pd) = (
                    to_object.transform_point3(o),
                    to_object.transform_vector3(d),
                );
                if let Some((least, t0, t1)) = least_in_box(object, &gate.object_box, po, pd, tmin)
                {
                    let scale = object.magnitude(po.abs() + t1.abs().max(t0.abs()) * pd.abs());
                    if (least / scale).abs() < 1e-9 {
                        tangent += 1;
                        continue;
                    }
                }
                let fast = gate.comes_near(o, d, tmin);
                let framed = gate.framed_comes_near(o, d, tmin);
                assert_eq!(fast, framed, "ray {i}");
                if fast {
                    open += 1;
                } else {
                    closed += 1;
                }
            }
            assert!(
                open > 3_000 && closed > 3_000,
                "{open} open, {closed} closed, {tangent} near a tangent"
            );
        }
    }

    /// A gate that is a tree of one closed quadric solid (a box, a capped
    /// cylinder) decides as the tree's walk of its events does, on every
    /// ray that does not pass within 1e-9 of touching the solid: under a
    /// rotation, a non-uniform scale and a translation, from outside and
    /// inside, with tmin past the origin on some.
    #[test]
    fn a_box_or_capped_cylinder_gate_decides_as_its_tree() {
        use super::super::csg::{Csg, Leaf, Node, Part};
        let to_world = DAffine3::from_scale_rotation_translation(
            DVec3::new(1.5, 0.75, 2.0),
            DQuat::from_euler(glam::EulerRot::XYZ, 0.7, -0.3, 0.5),
            DVec3::new(1.0, -2.0, 4.0),
        );
        let solids = [
            // A box: F = −1 everywhere, cut by its box.
            (
                Quadric {
                    a: DMat3::ZERO,
                    b: DVec3::ZERO,
                    c: -1.0,
                },
                Box3 {
                    min: DVec3::new(-1.0, -0.5, -1.5),
                    max: DVec3::new(1.0, 1.5, 0.5),
                },
            ),
            // A capped cylinder: x² + y² < 1 between z = −1 and z = 1.
            (
                Quadric {
                    a: DMat3::from_diagonal(DVec3::new(1.0, 1.0, 0.0)),
                    b: DVec3::ZERO,
                    c: -1.0,
                },
                Box3 {
                    min: DVec3::new(-1.0, -1.0, -1.0),
                    max: DVec3::ONE,
                },
            ),
        ];
        for (quadric, clip) in solids {
            let solid = Shape::new(
                Surface::Quadric(quadric),
                to_world,
                Some(clip),
                0,
                Solver::default(),
            )
            .unwrap();
            let (to_object, object_box) = (solid.to_object, solid.object_box);
            let Surface::Quadric(object) = solid.surface.clone() else {
                unreachable!()
            };
            let leaf = Leaf {
                part: Part::Solid(solid),
                inverse: false,
                material: 0,
            };
            let tree = Csg::new(Node::Leaf(0), vec![leaf]).unwrap();
            let gate = Shape::new(
                Surface::Csg(Box::new(tree.clone())),
                DAffine3::IDENTITY,
                None,
                0,
                Solver::default(),
            )
            .unwrap();
            let (mut open, mut closed, mut touching) = (0, 0, 0);
            for i in 0..20_000 {
                let (o, d, tmin) = test_ray(&to_world, i, 1.6, (0.3, 5.0));
                let (po, pd) = (
                    to_object.transform_point3(o),
                    to_object.transform_vector3(d),
                );
                // F's least over the ray's interval in the box, and how
                // near the ray comes to the box's faces from outside it.
                if let Some((least, t0, t1)) = least_in_box(&object, &object_box, po, pd, tmin)
                    && (least.abs() < 1e-9 || (t1 - t0) * pd.length() < 1e-9)
                {
                    touching += 1;
                    continue;
                }
                let fast = gate.lets_through(o, d, tmin);
                assert_eq!(fast, tree.inside_or_crossed(o, d, tmin), "ray {i}");
                if fast {
                    open += 1;
                } else {
                    closed += 1;
                }
            }
            assert!(
                open > 3_000 && closed > 3_000,
                "{open} open, {closed} closed, {touching} touching"
            );
        }
    }

    /// A sphere whose box is cut by a clip box keeps the framed path: the
    /// box decides there.
    #[test]
    fn a_clipped_sphere_gate_keeps_its_box() {
        let clip = Box3 {
            min: DVec3::new(-1.0, -1.0, 0.0),
            max: DVec3::ONE,
        };
        let gate = Shape::new(
            Surface::Sphere { radius: 1.0 },
            DAffine3::IDENTITY,
            Some(clip),
            0,
            Solver::default(),
        )
        .unwrap();
        let Surface::Sphere { radius } = gate.surface else {
            unreachable!()
        };
        assert!(!gate.box_holds_sphere(radius));
        // Through the cut-away lower half only: closed.
        let (o, d) = (DVec3::new(-5.0, 0.0, -0.5), DVec3::X);
        assert!(!gate.comes_near(o, d, 0.0));
        assert!(gate.comes_near(o + DVec3::Z, d, 0.0));
    }

    /// A tree cut by a box needs no gate that holds the box, and the gate
    /// left off changes no hit: a torus clipped by a box (monkey.pov's and
    /// trough.pov's form), rotated and scaled, under a sphere gate and a
    /// box gate that hold the box, each tested against the gated tree on
    /// rays from all sides. A gate the box reaches out of, or one whose own
    /// gate it reaches out of, stays.
    #[test]
    fn a_gate_that_holds_a_trees_clip_box_is_not_needed() {
        use super::super::csg::{Csg, Leaf, Node, Op, Part};
        let to_world = DAffine3::from_scale_rotation_translation(
            DVec3::splat(1.5),
            DQuat::from_euler(glam::EulerRot::XYZ, 0.4, -0.8, 0.3),
            DVec3::new(2.0, -1.0, 3.0),
        );
        let placed = |surface: Surface, clip: Option<Box3>| {
            Shape::new(surface, to_world, clip, 0, Solver::default()).unwrap()
        };
        let block = || Quadric {
            a: DMat3::ZERO,
            b: DVec3::ZERO,
            c: -1.0,
        };
        let cut = Box3 {
            min: DVec3::new(-1.0, -1.0, -0.2),
            max: DVec3::new(1.4, 1.0, 0.3),
        };
        let leaf = |part| Leaf {
            part,
            inverse: false,
            material: 0,
        };
        let torus = Surface::Torus {
            major: 1.0,
            minor: 0.4,
        };
        let root = Node::Op {
            op: Op::Clip,
            inverse: false,
            children: vec![Node::Leaf(0), Node::Leaf(1)],
        };
        let leaves = vec![
            leaf(Part::Solid(placed(torus, None))),
            leaf(Part::Solid(placed(Surface::Quadric(block()), Some(cut)))),
        ];
        let tree = Csg::within(root, leaves, Box3::cube(100.0)).unwrap();
        let shape = Shape::new(
            Surface::Csg(Box::new(tree)),
            DAffine3::IDENTITY,
            None,
            0,
            Solver::default(),
        )
        .unwrap();
        // The cut's farthest corner is 1.75 from the centre.
        let ball = |radius| placed(Surface::Sphere { radius }, None);
        let slab = |half: f64| placed(Surface::Quadric(block()), Some(Box3::cube(half)));
        let mut chained = ball(2.0);
        chained.set_gate(slab(1.2));
        assert!(shape.needs_gate(&ball(1.7)));
        assert!(shape.needs_gate(&slab(1.3)));
        assert!(shape.needs_gate(&chained));
        for gate in [ball(1.9), slab(1.5)] {
            assert!(!shape.needs_gate(&gate));
            gate_changes_nothing(&shape, gate, &to_world, 2.5, (0.5, 4.0));
        }
    }

    /// Asserts that `shape` under `gate` has the hits and shadows it has
    /// without it on 20,000 rays (`test_ray`'s, aimed within `aim` of the
    /// centre from `distance`), of which over 1,000 hit and over 3,000
    /// the gate turns away.
    fn gate_changes_nothing(
        shape: &Shape,
        gate: Shape,
        to_world: &DAffine3,
        aim: f64,
        distance: (f64, f64),
    ) {
        let mut gated = shape.clone();
        gated.set_gate(gate);
        let (mut hits, mut gated_out) = (0, 0);
        for i in 0..20_000 {
            let (o, d, tmin) = test_ray(to_world, i, aim, distance);
            let key = |h: Option<super::super::ShapeHit>| h.map(|h| (h.t.to_bits(), h.part));
            let plain = shape.intersect(o, d, tmin, f64::INFINITY);
            assert_eq!(
                key(plain),
                key(gated.intersect(o, d, tmin, f64::INFINITY)),
                "ray {i}"
            );
            assert_eq!(
                shape.occluded(o, d, tmin, 1.0),
                gated.occluded(o, d, tmin, 1.0),
                "ray {i}"
            );
            hits += usize::from(plain.is_some());
            gated_out += usize::from(!gated.gate.as_ref().unwrap().lets_through(o, d, tmin));
        }
        assert!(
            hits > 1_000 && gated_out > 3_000,
            "{hits} hits, {gated_out} turned away"
        );
    }

    /// A surface whose hits all lie in a box its gate holds needs no gate:
    /// a quartic torus (R = 1, r = 0.4), rotated and scaled, under a sphere
    /// and a box that hold the box around its points, each tested against
    /// the gated torus on rays from all sides. A sphere that holds the
    /// torus but not that box keeps its gate, as does one over an unbounded
    /// surface (a quartic cylinder cut only by its shape's box).
    #[test]
    fn a_gate_that_holds_a_surfaces_points_is_not_needed() {
        use crate::poly::trivariate::Trivariate;
        let to_world = DAffine3::from_scale_rotation_translation(
            DVec3::splat(1.5),
            DQuat::from_euler(glam::EulerRot::XYZ, 0.4, -0.8, 0.3),
            DVec3::new(2.0, -1.0, 3.0),
        );
        let placed = |surface: Surface, clip: Option<Box3>| {
            Shape::new(surface, to_world, clip, 0, Solver::default()).unwrap()
        };
        let torus = crate::poly::trivariate::tests::torus(1.0, 0.4);
        let shape = placed(Surface::Algebraic(Box::new(torus)), Some(Box3::cube(10.0)));
        let cylinder =
            Trivariate::from_terms([([4, 0, 0], 1.0), ([0, 4, 0], 1.0), ([0, 0, 0], -1.0)]);
        let cylinder = placed(
            Surface::Algebraic(Box::new(cylinder)),
            Some(Box3::cube(10.0)),
        );
        let ball = |radius| placed(Surface::Sphere { radius }, None);
        let block = |half: f64| {
            let solid = Quadric {
                a: DMat3::ZERO,
                b: DVec3::ZERO,
                c: -1.0,
            };
            placed(Surface::Quadric(solid), Some(Box3::cube(half)))
        };
        // The torus reaches 1.4 from its centre, its box's corners 2.02.
        assert!(shape.needs_gate(&ball(1.8)));
        assert!(cylinder.needs_gate(&ball(5.0)));
        for gate in [ball(2.3), block(1.6)] {
            assert!(!shape.needs_gate(&gate));
            gate_changes_nothing(&shape, gate, &to_world, 3.0, (0.5, 5.0));
        }
    }
}
