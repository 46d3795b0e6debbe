//! The box around a surface's own points within the shape's box, where its
//! rays are searched (`Shape::search_box`). POV-Ray's quartics come
//! unbounded, cut by the world box 1e7 wide or by a `bounded_by` sphere
//! several times their size, and every ray into that box formed its Q and
//! screened its whole interval there: most of a torus scene's camera rays
//! miss the torus. Within the box around the surface's points, those rays
//! are dismissed by the box's slab test, and the acceleration structure
//! never calls the shape for most of them.
//!
//! The box is found by subdividing the shape's box and dropping the cells
//! where F certainly has no zero (`Dense::excludes_zero`, a certified
//! enclosure of F). Any set of cells that kept every cell not excluded
//! holds all the surface's points, so the search can stop at any point
//! and its box still holds them: the work bounds only how tight it is.

use std::collections::BinaryHeap;

use glam::DVec3;

use super::Box3;
use crate::poly::trivariate::{Dense, Trivariate};

/// The enclosure tests allowed per shape, in units of a degree-4 test:
/// one costs about (degree + 1)⁴ operations. A quartic's box takes a few
/// milliseconds.
const WORK: usize = 40_000;

/// Breadth first, the levels stop growing at this many cells: by then
/// the cells are near the surface's own size, and each level more would
/// quadruple them.
const LEVEL_CELLS: usize = 256;

/// Then each of the six faces is pushed in, best first, by cutting at
/// most this many cells (see `Cells::farthest`).
const FACE_CELLS: usize = 256;

/// The box around every point of F = 0 within `within`, padded, or None
/// if F certainly has no zero there. An unbounded `within`, or an F whose
/// tests cost too much for the work allowed, gives `within` back.
pub(super) fn surface_box(f: &Trivariate, within: &Box3) -> Option<Box3> {
    let degree_work = ((f.degree() + 1) as f64 / 5.0).powi(4).max(1.0);
    let tests = (WORK as f64 / degree_work) as usize;
    let faces = 6 * 2 * FACE_CELLS;
    if tests < 2 * faces || !(within.min.is_finite() && within.max.is_finite()) {
        return Some(*within);
    }
    let mut left = tests;
    let start = match far_bound(f, &mut left) {
        Some(r) => within.intersection(&Box3 {
            min: -DVec3::from(r),
            max: DVec3::from(r),
        }),
        None => *within,
    };
    let mut cells = Cells {
        dense: f.dense(),
        left,
    };
    if start.is_empty() || cells.excluded(&start) {
        return None;
    }
    // Breadth first: every level's cells together hold the surface. First
    // cut at F's own coordinate planes, where F's features usually are: a
    // cell across one has Bernstein coefficients of both signs from every
    // even power, and can never be excluded.
    let mut level = vec![start];
    for axis in 0..3 {
        if start.min[axis] < 0.0 && start.max[axis] > 0.0 {
            level = level
                .iter()
                .flat_map(|cell| {
                    let (mut below, mut above) = (*cell, *cell);
                    below.max[axis] = 0.0;
                    above.min[axis] = 0.0;
                    [below, above]
                })
                .collect();
        }
    }
    level.retain(|c| !cells.excluded(c));
    while level.len() <= LEVEL_CELLS && cells.left > faces {
        let mut next = Vec::with_capacity(8 * level.len());
        for cell in &level {
            next.extend(children(cell).filter(|c| !cells.excluded(c)));
        }
        if next.is_empty() {
            return None;
        }
        level = next;
    }
    // Then each face the surface does not reach, from the cells of the
    // last level: where a cell still touches the start's face, the surface
    // may run on to it (a cylinder along its axis), and splitting cells
    // there would be work for nothing.
    let mut found = start;
    for axis in 0..3 {
        for up in [false, true] {
            let touches = |c: &Box3| {
                if up {
                    c.max[axis] >= start.max[axis]
                } else {
                    c.min[axis] <= start.min[axis]
                }
            };
            if level.iter().any(touches) {
                continue;
            }
            let face = cells.farthest(&level, axis, up)?;
            if up {
                found.max[axis] = face;
            } else {
                found.min[axis] = face;
            }
        }
    }
    let pad = 1e-9 * (found.max - found.min).max_element();
    let padded = Box3 {
        min: found.min - pad,
        max: found.max + pad,
    };
    Some(padded.intersection(within))
}

/// Axis weights tried for `far_bound`, in turn: the plain degree first,
/// then one axis against the other two, as in the piriform's
/// x⁴ − x³ + y² + z², whose leading form x⁴ vanishes across the plane
/// x = 0 but whose terms of weighted degree 4 under (1, 2, 2) do not.
const WEIGHTS: [[u32; 3]; 7] = [
    [1, 1, 1],
    [1, 2, 2],
    [2, 1, 2],
    [2, 2, 1],
    [1, 1, 2],
    [1, 2, 1],
    [2, 1, 1],
];

/// Half-sides beyond which F has no zero, from the first of `WEIGHTS`
/// that shows them; None when none does (the surface may go to infinity)
/// or the tests left run out.
fn far_bound(f: &Trivariate, left: &mut usize) -> Option<[f64; 3]> {
    WEIGHTS.iter().find_map(|&w| {
        let r = weighted_bound(f, w, left)?;
        Some(w.map(|w| r.powi(w as i32)))
    })
}

/// A radius R, in the weighted norm ρ(p) = max_i |p_i|^(1/w_i), beyond
/// which F has no zero, when F's terms of highest weighted degree D
/// (Σ w_i e_i) form an F_D that keeps one sign on the faces of the unit
/// cube; None when it does not, or the tests left cannot show it.
///
/// |F_D| ≥ m > 0 on the faces is found by subdividing them (best first,
/// from the cell whose enclosure reaches lowest). F_D(ρ^w ∘ u) = ρ^D F_D(u),
/// and every point with ρ(p) = ρ is ρ^w ∘ u for some u on the faces, so
/// |F_D(p)| ≥ m ρ^D there, while the terms of weighted degree k < D add
/// up to at most A_k ρ^k, A_k the sum of their |coefficients|. For ρ ≥ 1
/// beyond the one positive root of m ρ^D − Σ A_k ρ^k (one sign change:
/// Descartes), F cannot vanish.
fn weighted_bound(f: &Trivariate, w: [u32; 3], left: &mut usize) -> Option<f64> {
    let weighted = |e: [u8; 3]| {
        (0..3)
            .map(|i| w[i] as usize * usize::from(e[i]))
            .sum::<usize>()
    };
    let degree = f.terms().iter().map(|&(e, _)| weighted(e)).max()?;
    if degree == 0 {
        return None;
    }
    let mut lower = vec![0.0; degree];
    let top = Trivariate::from_terms(f.terms().iter().filter_map(|&(e, c)| {
        let k = weighted(e);
        if k < degree {
            lower[k] += c.abs();
            None
        } else {
            Some((e, c))
        }
    }));
    let sign = top.eval([1.0, 0.0, 0.0]).signum();
    let mut dense = top.dense();
    let mut heap = BinaryHeap::new();
    // Keyed by the negated lower bound of sign·F_D: the lowest pops first.
    // A centre where sign·F_D is not positive ends the search.
    let mut push = |heap: &mut BinaryHeap<Keyed>, cell: Box3, left: &mut usize| {
        *left = left.saturating_sub(1);
        let centre = 0.5 * (cell.min + cell.max);
        let half = 0.5 * (cell.max - cell.min);
        let (value, spread) = dense.enclose(centre.to_array(), half.to_array());
        heap.push(Keyed {
            reach: spread - sign * value,
            cell,
        });
        sign * value > 0.0
    };
    for axis in 0..3 {
        for side in [-1.0, 1.0] {
            let mut face = Box3::cube(1.0);
            face.min[axis] = side;
            face.max[axis] = side;
            if !push(&mut heap, face, left) {
                return None;
            }
        }
    }
    let m = loop {
        let Keyed { reach, cell } = heap.pop()?;
        if reach < 0.0 {
            break -reach;
        }
        if *left == 0 {
            return None;
        }
        for child in children(&cell) {
            if !push(&mut heap, child, left) {
                return None;
            }
        }
    };
    let excess = |rho: f64| {
        let below: f64 = lower.iter().rev().fold(0.0, |acc, a| acc * rho + a);
        m * rho.powi(degree as i32) - below
    };
    let (mut lo, mut hi) = (0.0, 1f64.max(lower.iter().sum::<f64>() / m));
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if excess(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    // Above the computed root by far more than its rounding.
    Some(hi.max(1.0) * (1.0 + 1e-6))
}

/// F, for testing cells, and how many tests are left.
struct Cells {
    dense: Dense,
    left: usize,
}

impl Cells {
    /// Whether F certainly has no zero in `cell`.
    fn excluded(&mut self, cell: &Box3) -> bool {
        self.left = self.left.saturating_sub(1);
        let width = cell.max - cell.min;
        let centre = cell.min + 0.5 * width;
        // The centred form first: a third of the Bernstein form's cost, and
        // enough for most small cells beside the surface.
        self.dense
            .excludes_zero(centre.to_array(), (0.5 * width).to_array())
            || self
                .dense
                .bernstein_excludes(cell.min.to_array(), width.to_array())
    }

    /// How far the surface may reach along `axis` (towards + if `up`)
    /// among `cells`, which hold it: the farthest-reaching cell is cut in
    /// two across `axis` and the halves that may hold the surface kept,
    /// `FACE_CELLS` times; the farthest reach left is the answer. Cut
    /// across the axis only, the cells along the face (a ring of them on
    /// a torus's top) do not multiply, and each round over them halves
    /// how far the face may lie beyond the surface. None if every cell is
    /// excluded on the way.
    fn farthest(&mut self, cells: &[Box3], axis: usize, up: bool) -> Option<f64> {
        let keyed = |cell: Box3| Keyed {
            reach: if up { cell.max[axis] } else { -cell.min[axis] },
            cell,
        };
        let mut heap: BinaryHeap<Keyed> = cells.iter().copied().map(keyed).collect();
        for _ in 0..FACE_CELLS {
            let Keyed { cell, .. } = heap.pop()?;
            let mid = 0.5 * (cell.min[axis] + cell.max[axis]);
            let (mut below, mut above) = (cell, cell);
            below.max[axis] = mid;
            above.min[axis] = mid;
            for half in [below, above] {
                if !self.excluded(&half) {
                    heap.push(keyed(half));
                }
            }
        }
        let reach = heap.peek()?.reach;
        Some(if up { reach } else { -reach })
    }
}

/// The halves of a box along each of its axes of nonzero width: eight,
/// or four for a flat cell, and so on.
fn children(cell: &Box3) -> impl Iterator<Item = Box3> + use<> {
    let (cell, mid) = (*cell, 0.5 * (cell.min + cell.max));
    let flat = (cell.min.cmpeq(cell.max)).bitmask();
    (0..8usize)
        .filter(move |i| i & flat as usize == 0)
        .map(move |i| {
            let mut child = cell;
            for axis in 0..3 {
                if i >> axis & 1 == 0 {
                    child.max[axis] = mid[axis];
                } else {
                    child.min[axis] = mid[axis];
                }
            }
            child
        })
}

/// A cell keyed by how far it reaches towards the face being found.
struct Keyed {
    reach: f64,
    cell: Box3,
}

impl PartialEq for Keyed {
    fn eq(&self, other: &Keyed) -> bool {
        self.reach.total_cmp(&other.reach).is_eq()
    }
}

impl Eq for Keyed {}

impl PartialOrd for Keyed {
    fn partial_cmp(&self, other: &Keyed) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Keyed {
    fn cmp(&self, other: &Keyed) -> std::cmp::Ordering {
        self.reach.total_cmp(&other.reach)
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;
    use proptest::prelude::*;

    use super::surface_box;
    use crate::geometry::analytic::Box3;
    use crate::poly::expr::parse;
    use crate::poly::trivariate::Trivariate;

    fn f(expr: &str) -> Trivariate {
        parse(expr, &[]).unwrap()
    }

    fn holds(b: &Box3, p: DVec3) -> bool {
        p.cmpge(b.min).all() && p.cmple(b.max).all()
    }

    /// A point of the surface on each of `steps` pieces of the line o + t·d
    /// in `within` where F changes sign.
    fn crossings(f: &Trivariate, within: &Box3, o: DVec3, d: DVec3, steps: usize) -> Vec<DVec3> {
        let lo = (within.min - o) / d;
        let hi = (within.max - o) / d;
        let (t0, t1) = (lo.min(hi).max_element(), lo.max(hi).min_element());
        let mut found = Vec::new();
        if t0 >= t1 {
            return found;
        }
        let at = |k: usize| o + (t0 + (t1 - t0) * k as f64 / steps as f64) * d;
        let sign = |p: DVec3| f.eval(p.to_array()) < 0.0;
        for k in 0..steps {
            let (mut a, mut b) = (at(k), at(k + 1));
            if sign(a) != sign(b) {
                // Bisected down to a point of the surface, up to rounding.
                for _ in 0..64 {
                    let mid = 0.5 * (a + b);
                    if sign(mid) == sign(a) {
                        a = mid;
                    } else {
                        b = mid;
                    }
                }
                found.push(a);
            }
        }
        found
    }

    #[test]
    fn a_torus_in_the_world_box_gets_a_box_near_its_own() {
        // R = 2, r = 0.5 about the z axis: |x|, |y| ≤ 2.5, |z| ≤ 0.5.
        let torus = f("(x^2 + y^2 + z^2 + 4 - 0.25)^2 - 16*(x^2 + y^2)");
        let world = Box3::cube(1e7);
        let b = surface_box(&torus, &world).unwrap();
        for axis in 0..2 {
            assert!(b.max[axis] >= 2.5 && b.max[axis] < 2.5 * 1.05, "{b:?}");
            assert!(b.min[axis] <= -2.5 && b.min[axis] > -2.5 * 1.05, "{b:?}");
        }
        assert!(b.max.z >= 0.5 && b.max.z < 0.6 && b.min.z <= -0.5, "{b:?}");
    }

    #[test]
    fn a_surface_bounded_only_under_weights_is_boxed_too() {
        // The piriform: x ∈ [0, 1], y² + z² ≤ 27/256. Its leading form x⁴
        // vanishes on the plane x = 0; under weights (1, 2, 2) it does not.
        let piriform = f("x^4 - x^3 + y^2 + z^2");
        let b = surface_box(&piriform, &Box3::cube(1e6)).unwrap();
        assert!(
            b.min.x <= 0.0 && b.min.x > -0.2 && b.max.x >= 1.0 && b.max.x < 1.2,
            "{b:?}"
        );
        let r = (27.0f64 / 256.0).sqrt();
        assert!(b.max.y >= r && b.max.y < 2.0 * r && b.min.z <= -r, "{b:?}");
    }

    #[test]
    fn a_surface_with_no_point_in_the_box_has_no_box() {
        assert_eq!(
            surface_box(&f("x^2 + y^2 + z^2 + 1"), &Box3::cube(10.0)),
            None
        );
        let sphere = f("x^2 + y^2 + z^2 - 1");
        let beside = Box3 {
            min: DVec3::splat(2.0),
            max: DVec3::splat(3.0),
        };
        assert_eq!(surface_box(&sphere, &beside), None);
    }

    #[test]
    fn an_unbounded_surface_keeps_its_box_where_it_runs_on() {
        // A cylinder along z: the whole box in z, far tighter in x and y.
        // Not as tight as a torus's box: the cells along all 2000 units of
        // its axis share the work a torus spends on a few, so x and y
        // settle within some 8 radii, not 1.1 (a bound on work, not on
        // soundness, which `every_crossing_lies_in_the_box` checks).
        let within = Box3::cube(1000.0);
        let b = surface_box(&f("x^2 + y^2 - 1"), &within).unwrap();
        assert_eq!((b.min.z, b.max.z), (-1000.0, 1000.0));
        assert!(b.max.x >= 1.0 && b.max.x < 10.0 && b.min.y <= -1.0, "{b:?}");
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]

        /// Soundness on random quartics: every sign change of F along
        /// random lines through the box lies in the surface's box.
        #[test]
        fn every_crossing_lies_in_the_box(
            coeffs in proptest::collection::vec(-4.0f64..4.0, 35),
            lines in proptest::collection::vec(
                (proptest::array::uniform3(-3.0f64..3.0), proptest::array::uniform3(-1.0f64..1.0)),
                24,
            ),
        ) {
            let mut terms = Vec::new();
            let mut k = 0;
            for a in 0..=4u8 {
                for b in 0..=4 - a {
                    for c in 0..=4 - a - b {
                        terms.push(([a, b, c], coeffs[k]));
                        k += 1;
                    }
                }
            }
            let f = Trivariate::from_terms(terms);
            let within = Box3 { min: DVec3::splat(-3.0), max: DVec3::new(3.0, 2.0, 3.5) };
            let b = surface_box(&f, &within);
            for (o, d) in lines {
                let d = DVec3::from(d);
                for p in crossings(&f, &within, DVec3::from(o), d, 400) {
                    let b = b.expect("a crossing, but no box");
                    prop_assert!(holds(&b, p), "{p:?} outside {b:?}");
                }
            }
        }
    }
}
