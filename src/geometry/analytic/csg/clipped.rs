//! A clip at a tree's root, the commonest tree of POV-Ray's samples (a
//! quartic `clipped_by` a quadric and planes, or intersected with a clear
//! sphere): its seen surface is its first child's crossings where all the
//! clip objects are inside, each of which changes the tree's state. So the
//! nearest seen crossing is the first crossing of the first child, found
//! nearest first, at which the clip objects are all inside: the crossings
//! beyond it need not be found, refined, sorted or combined.
//!
//! The answer is the whole walk's (`Csg::events`): the same clip events,
//! the same window and the same leaf walk from the same start, so the
//! same roots. Where the whole walk could group a crossing with a clip
//! object's (within their widths, the margin `joint_inside` allows), or
//! the leaf's crossings do not alternate, the whole walk answers instead.
//! Alone the grouping of two crossings of the first child itself, closer
//! than its refinement width, is not looked for: the whole walk would see
//! no surface at such a graze, this walk sees its first crossing.

use glam::DVec3;

use super::{Cost, Csg, Event, FOUND, Kind, Node, Op, Part, State, joint_inside, margin};

impl Csg {
    /// Whether the root is a clip whose first child is a costly shape and
    /// whose clip objects are cheap solids, as `events` narrows it: what
    /// `nearest_clipped` answers.
    pub(super) fn clipped_root(&self) -> bool {
        let Node::Op {
            op: Op::Clip,
            children,
            ..
        } = &self.root
        else {
            return false;
        };
        let first_is_shape = matches!(
            children[0],
            Node::Leaf(i) if matches!(self.leaves[i as usize].part, Part::Solid(_) | Part::Sheet(_))
        );
        first_is_shape
            && self.cost(&children[0]) == Cost::Costly
            && children[1..]
                .iter()
                .all(|c| self.cost(c) == Cost::Cheap && self.solid(c))
    }

    /// The nearest seen crossing with t in (tmin, tmax) of a tree whose
    /// root `clipped_root` accepts, `seen_only` as `events` has it:
    /// Some(None) where there is none, None where the whole walk must
    /// decide (see the module's doc). `events` is scratch space.
    pub(super) fn nearest_clipped(
        &self,
        o: DVec3,
        d: DVec3,
        tmin: f64,
        tmax: f64,
        seen_only: bool,
        events: &mut Vec<Event>,
    ) -> Option<Option<Event>> {
        let Node::Op {
            inverse, children, ..
        } = &self.root
        else {
            return None;
        };
        let Node::Leaf(first) = children[0] else {
            return None;
        };
        let clips = children.len() - 1;
        events.clear();
        let mut state = State {
            op: Op::Clip,
            children: children.len() as isize,
            first: false,
            count: 0,
        };
        let line = (f64::NEG_INFINITY, tmax);
        for (k, child) in children.iter().enumerate().skip(1) {
            let inside = self.events(child, o, d, tmin, line, false, events);
            state.apply(k as u32, inside);
        }
        let Some(span) = joint_inside(events, clips, &state) else {
            return Some(None);
        };
        let window = (span.0, tmax.min(span.1));
        if seen_only && self.crosses_nothing(&children[0], o, d, tmin.max(window.0), window.1) {
            return Some(None);
        }
        let leaf = &self.leaves[first as usize];
        let (Part::Solid(shape) | Part::Sheet(shape)) = &leaf.part else {
            return None;
        };
        let solid = matches!(leaf.part, Part::Solid(_));
        let clipped = |t: f64| clip_state(events, state.count, clips, t);
        let from = shape.crossings_from(d, tmin).max(window.0);
        FOUND.with_borrow_mut(|found| {
            let wanted = |t: f64| t > tmin && t < tmax && clipped(t) != Some(false);
            shape.crossings_until(o, d, from, window.1, solid, found, wanted);
            for c in found.as_slice() {
                if !(c.t > tmin && c.t < tmax) {
                    continue;
                }
                match clipped(c.t) {
                    Some(false) => continue,
                    None => return None,
                    Some(true) => {}
                }
                let e = self.shape_event(first, c);
                // As `combine` reports it: the clip objects all inside, the
                // tree's state is the leaf's, so it changes with it.
                return Some(Some(match e.kind {
                    Kind::Sheet { .. } => Event {
                        kind: Kind::Sheet { inside: *inverse },
                        ..e
                    },
                    kind => Event {
                        kind: if (kind == Kind::Enter) != *inverse {
                            Kind::Enter
                        } else {
                            Kind::Leave
                        },
                        flip: e.flip != *inverse,
                        ..e
                    },
                }));
            }
            // Stopped at a root that did not stand as a crossing (the
            // leaf's crossings did not alternate there): the whole walk.
            (!found.stopped()).then_some(None)
        })
    }
}

/// Whether the clip objects, whose `events` are sorted and `count` of which
/// are inside where the line starts, are all inside at t: None within the
/// margin `joint_inside` allows of one of their events, where the whole
/// walk may take a crossing at t with it.
fn clip_state(events: &[Event], count: isize, clips: usize, t: f64) -> Option<bool> {
    let mut count = count;
    for e in events {
        if (e.t - t).abs() <= margin(e) {
            return None;
        }
        if e.t < t {
            match e.kind {
                Kind::Enter => count += 1,
                Kind::Leave => count -= 1,
                Kind::Sheet { .. } => {}
            }
        }
    }
    Some(count == clips as isize)
}

#[cfg(test)]
mod tests {
    use glam::{DAffine3, DVec3};

    use super::super::{Csg, Leaf, Node, Op, Part};
    use crate::geometry::analytic::{Box3, Quadric, Shape, Surface};
    use crate::poly::solve::Solver;

    fn placed(surface: Surface, at: DVec3, clip: Option<Box3>) -> Shape {
        Shape::new(
            surface,
            DAffine3::from_translation(at),
            clip,
            0,
            Solver::default(),
        )
        .unwrap()
    }

    fn leaf(part: Part, inverse: bool) -> Leaf {
        Leaf {
            part,
            inverse,
            material: 0,
        }
    }

    fn torus(cut: Option<Box3>) -> Shape {
        let surface = Surface::Torus {
            major: 1.0,
            minor: 0.4,
        };
        placed(surface, DVec3::ZERO, cut)
    }

    fn ball(radius: f64, at: DVec3) -> Part {
        Part::Solid(placed(Surface::Sphere { radius }, at, None))
    }

    /// A clip over leaves 0, 1, …, inverted or not, within a world box (an
    /// inverted one is unbounded).
    fn clip(leaves: Vec<Leaf>, inverse: bool) -> Csg {
        let children = (0..leaves.len() as u32).map(Node::Leaf).collect();
        let root = Node::Op {
            op: Op::Clip,
            inverse,
            children,
        };
        Csg::within(root, leaves, Box3::cube(10.0)).unwrap()
    }

    /// The trees the short walk answers: a quartic clipped by a ball and a
    /// half-space (helix.pov's form), by an x² + y² < 1.2² cylinder cut
    /// to a box, by an inverted ball, cut by its own box, as a sheet, and
    /// with the leaf or the root inverted.
    fn trees() -> Vec<Csg> {
        let cylinder = Quadric {
            a: glam::DMat3::from_diagonal(DVec3::new(1.0, 1.0, 0.0)),
            b: DVec3::ZERO,
            c: -1.44,
        };
        let cylinder = placed(
            Surface::Quadric(cylinder),
            DVec3::new(0.4, 0.0, 0.0),
            Some(Box3::cube(3.0)),
        );
        let half = |normal: DVec3, offset| Part::Plane { normal, offset };
        let cut = Box3 {
            min: DVec3::splat(-2.0),
            max: DVec3::new(2.0, 2.0, 0.2),
        };
        let near = DVec3::new(0.5, 0.0, 0.0);
        vec![
            clip(
                vec![
                    leaf(Part::Solid(torus(None)), false),
                    leaf(ball(1.2, near), false),
                    leaf(half(DVec3::Z, 0.2), false),
                ],
                false,
            ),
            clip(
                vec![
                    leaf(Part::Solid(torus(None)), false),
                    leaf(Part::Solid(cylinder), false),
                    leaf(half(DVec3::Z, 0.1), false),
                    leaf(half(-DVec3::Z, 0.3), false),
                ],
                false,
            ),
            clip(
                vec![
                    leaf(Part::Solid(torus(None)), false),
                    leaf(ball(0.8, DVec3::new(1.0, 0.0, 0.0)), true),
                ],
                false,
            ),
            clip(
                vec![
                    leaf(Part::Solid(torus(Some(cut))), false),
                    leaf(ball(1.2, near), false),
                ],
                false,
            ),
            clip(
                vec![
                    leaf(Part::Sheet(torus(None)), false),
                    leaf(half(DVec3::X, 0.3), false),
                ],
                false,
            ),
            clip(
                vec![
                    leaf(Part::Solid(torus(None)), true),
                    leaf(ball(1.2, near), false),
                ],
                true,
            ),
        ]
    }

    /// Every tree's short walk, wherever it answers, gives the whole walk's
    /// nearest seen event, for camera rays and shadow rays (`seen_only`),
    /// from far away, from near and on the surface (as secondary rays
    /// start), with and without a tmax; and it answers at least 95% of
    /// them (the rest, near the clip objects' surfaces, fall back: 2% of
    /// the first tree's when this was written).
    #[test]
    fn the_short_walk_of_a_clip_finds_what_the_whole_walk_does() {
        for (k, tree) in trees().iter().enumerate() {
            assert!(tree.clipped, "tree {k} is not one the short walk answers");
            let (mut answered, mut hits, mut rays) = (0, 0, 0);
            let mut events = Vec::new();
            for i in 0..3000 {
                let x = f64::from(i);
                let target = DVec3::new((x * 0.37).sin(), (x * 0.61).cos(), 0.5 * (x * 0.83).sin());
                let from = DVec3::new((x * 0.11).cos(), (x * 0.29).sin(), (x * 0.47).cos())
                    * (0.3 + 4.0 * (0.5 + 0.5 * (x * 0.93).sin()));
                let d = (target - from) * (0.5 + (x * 0.17).cos().abs());
                let tmax = if i % 4 == 0 { 0.7 } else { f64::INFINITY };
                // Secondary rays: from the first hit on, as a shadow or a
                // reflected ray leaves the surface.
                let first = tree.nearest_walked(from, d, 0.0, f64::INFINITY, false, &mut events);
                let mut starts = vec![(from, d, 0.0)];
                if let Some(e) = first {
                    starts.push((from + e.t * d, d, 1e-9));
                    starts.push((from + e.t * d, -d, 1e-9));
                }
                for (o, d, tmin) in starts {
                    for seen_only in [false, true] {
                        rays += 1;
                        let whole = tree.nearest_walked(o, d, tmin, tmax, seen_only, &mut events);
                        let Some(short) =
                            tree.nearest_clipped(o, d, tmin, tmax, seen_only, &mut events)
                        else {
                            continue;
                        };
                        answered += 1;
                        hits += usize::from(whole.is_some());
                        let key = |e: Option<super::Event>| {
                            e.map(|e| (e.t, e.leaf, e.face, e.flip, e.kind))
                        };
                        assert_eq!(
                            key(short),
                            key(whole),
                            "tree {k}, ray {i} from {o} along {d}, tmin {tmin}, tmax {tmax}, seen only {seen_only}"
                        );
                    }
                }
            }
            assert!(
                answered * 100 >= rays * 95 && hits * 10 >= answered,
                "tree {k}: {answered} of {rays} rays answered, {hits} hits"
            );
        }
    }
}
