//! No hierarchy at all: a scene of a few analytic shapes and nothing else,
//! each shape asked in turn whose box the ray meets. Embree's traversal
//! and its user-geometry callback cost some 560 instructions a camera ray
//! of POV-Ray's tcubic.pov (one shape) beyond the shape's own work, over a
//! tenth of the ray; this walk costs 270 (`valgrind --tool=callgrind`). The
//! Embree backend answers a render's single rays through it where the
//! scene allows (see `Accel::build`): the same hits, since every shape
//! answers for itself, in the same f64 arithmetic, whoever asks.

use super::primitives::Slabs;
use crate::accel::panics::PanicSlot;
use crate::accel::primitive::{UserPrimitive, crossings, held, padding};
use crate::geometry::{Pinhole, Shape, ShapeBeams};
use crate::math::{Bounds, DVec3, Hit, INVALID_ID, Ray, Ray64};
use crate::scene::Scene;

/// The most shapes a scene traced without a BVH may have. With a BVH the
/// rays that miss most shapes skip them by a few boxes, not one each:
/// POV-Ray's helix.pov, nine clipped quartics, took 13% more render-loop
/// instructions without it, where grafbic.pov (five) and steiner.pov
/// (four) took 9% fewer.
const MOST_SHAPES: usize = 5;

pub struct ListScene {
    /// Each shape with its box as Embree holds it (`primitive::held`): a
    /// ray that misses the box is not asked of the shape, as in Embree,
    /// where a shape's gate (a `bounded_by` sphere) may be wider than it.
    shapes: Box<[(Bounds, Shape)]>,
    /// The shapes' geometry id (`Scene::shapes_geom_id`).
    geom_id: u32,
}

impl ListScene {
    /// The list, for a scene of one to `MOST_SHAPES` shapes, no
    /// triangles and no instances; None for any other scene.
    pub fn of(scene: &Scene) -> Option<ListScene> {
        if scene.triangle_count() > 0
            || !scene.instances.is_empty()
            || !(1..=MOST_SHAPES).contains(&scene.shapes.len())
        {
            return None;
        }
        // As Embree's scene has them (`SceneBuilder::add_user`).
        let bounds = || scene.shapes.iter().map(Shape::bounds);
        let pad = padding(bounds().filter(|b| !b.is_empty()));
        Some(ListScene {
            shapes: (scene.shapes.iter())
                .map(|s| (held(s.bounds(), pad), s.clone()))
                .collect(),
            geom_id: scene.shapes_geom_id(),
        })
    }

    /// How many shapes it holds.
    pub fn shape_count(&self) -> usize {
        self.shapes.len()
    }

    /// The nearest hit, as Embree's traversal finds it: in [tnear, tfar),
    /// each shape of `among` offered the ray shortened to the nearest hit
    /// so far, to solve for `exact`, the f64 ray that `ray` rounds (see
    /// `Ray64`). A panic is a miss, recorded in `panics`.
    pub(crate) fn nearest(
        &self,
        ray: &Ray,
        exact: &Ray64,
        among: ShapeSet,
        panics: &PanicSlot,
    ) -> Hit {
        panics.guard(Hit::MISS, || {
            let slabs = Slabs::new(ray);
            let (mut rest, mut hit) = (*ray, Hit::MISS);
            for (i, (b, shape)) in self.shapes.iter().enumerate() {
                if !among.has(i) || !slabs.meet(b, rest.tnear, rest.tfar) {
                    continue;
                }
                if let Some(h) = crossings(shape, &rest, exact, |_| true) {
                    rest.tfar = h.t;
                    hit = Hit {
                        t: h.t,
                        geom_id: self.geom_id,
                        prim_id: i as u32,
                        inst_id: INVALID_ID,
                        u: h.u,
                        v: h.v,
                        ng: h.ng,
                    };
                }
            }
            hit
        })
    }

    /// Each shape's G along a pinhole camera's rays (`ShapeBeams`), for the
    /// shapes that have one; None if none has.
    pub(crate) fn beams(&self, pinhole: &Pinhole) -> Option<ListBeams<'_>> {
        let shapes: Box<[_]> = (self.shapes.iter())
            .map(|(b, shape)| shape.beams(pinhole, 0.0, b))
            .collect();
        let screens: Box<[_]> = (self.shapes.iter())
            .map(|(b, _)| pinhole.screen(b.min.as_dvec3(), b.max.as_dvec3()))
            .collect();
        (shapes.iter().any(Option::is_some) || screens.iter().any(Option::is_some))
            .then_some(ListBeams { shapes, screens })
    }

    /// Whether any shape blocks the ray; a panic counts as no hit.
    pub(crate) fn occluded(&self, ray: &Ray, among: ShapeSet, panics: &PanicSlot) -> bool {
        panics.guard(false, || {
            let slabs = Slabs::new(ray);
            (self.shapes.iter().enumerate()).any(|(i, (b, shape))| {
                among.has(i)
                    && slabs.meet(b, ray.tnear, ray.tfar)
                    && UserPrimitive::occluded(shape, ray)
            })
        })
    }

    /// Each shape's F along the rays of a point light at `light`
    /// (`Pinhole::toward` the shape's box), where some shape's can be
    /// formed: for proving that shadow rays from a shape's own lit points
    /// meet it nowhere (`LightBeams::lights`).
    pub(crate) fn light_beams(&self, light: DVec3) -> Option<LightBeams<'_>> {
        let shapes: Box<[_]> = (self.shapes.iter())
            .map(|(b, shape)| {
                // Expanded about the box's centre, where the hits are.
                let centre = 0.5 * (b.min + b.max).as_dvec3();
                let depth = (centre - light).length();
                Pinhole::toward(light, centre)
                    .and_then(|pinhole| shape.beams(&pinhole, depth, b))
                    .filter(ShapeBeams::proves_lights)
            })
            .collect();
        shapes
            .iter()
            .any(Option::is_some)
            .then_some(LightBeams(shapes))
    }
}

/// Which shapes of a list a ray is offered to, by their place in it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShapeSet(u8);

impl ShapeSet {
    pub const ALL: ShapeSet = ShapeSet(u8::MAX);

    pub const NONE: ShapeSet = ShapeSet(0);

    /// The set of a list's first `n` shapes: a list of `n` shapes' every
    /// shape, which a set holding none of them then differs from only by
    /// being `NONE`.
    pub fn first(n: usize) -> ShapeSet {
        ShapeSet(
            u8::MAX
                .checked_shr(u8::BITS.saturating_sub(n as u32))
                .unwrap_or(0),
        )
    }

    /// The set of shape `i` alone (none for an `i` past the list's).
    pub fn only(i: usize) -> ShapeSet {
        ShapeSet(1u8.checked_shl(i as u32).unwrap_or(0))
    }

    /// The set without shape `i`.
    pub fn without(self, i: usize) -> ShapeSet {
        self.minus(ShapeSet::only(i))
    }

    /// The set without the shapes of `other`.
    pub fn minus(self, other: ShapeSet) -> ShapeSet {
        ShapeSet(self.0 & !other.0)
    }

    /// The shapes of either set.
    pub fn with(self, other: ShapeSet) -> ShapeSet {
        ShapeSet(self.0 | other.0)
    }

    fn has(self, i: usize) -> bool {
        self.0 & (1 << i) != 0
    }
}

// Every shape of a list has its bit.
const _: () = assert!(MOST_SHAPES <= u8::BITS as usize);

/// The list's shapes along a pinhole camera's rays (see `ShapeBeams`).
pub struct ListBeams<'a> {
    shapes: Box<[Option<ShapeBeams<'a>>]>,
    /// Where on the image each shape's box is seen (`Pinhole::screen`):
    /// no ray through a pixel outside it is asked of the shape, as its
    /// box is missed.
    screens: Box<[Option<[f64; 4]>]>,
}

/// The list's shapes along one point light's rays (`ListScene::light_beams`).
pub struct LightBeams<'a>(Box<[Option<ShapeBeams<'a>>]>);

impl LightBeams<'_> {
    /// Whether no shadow ray towards the light from any of `points`, each
    /// a lit point of shape `i` (of its CSG leaf `leaf`, 0 for a plain
    /// surface) with a bound on how far from it its shadow ray starts,
    /// meets shape `i` (`ShapeBeams::lights`).
    pub fn lights(&self, i: usize, leaf: usize, points: &[(DVec3, f64)], short: f64) -> bool {
        (self.0.get(i)).is_some_and(|b| b.as_ref().is_some_and(|b| b.lights(leaf, points, short)))
    }
}

impl ListBeams<'_> {
    /// The shapes of `among` that some ray through pixel coordinates
    /// (x, y) in [x0, x1] × [y0, y1] may hit: all but those proven missed.
    pub fn may_hit(&self, xs: (f64, f64), ys: (f64, f64), among: ShapeSet) -> ShapeSet {
        let among = self.in_sight(xs, ys, among);
        let missed = (self.shapes.iter().enumerate())
            .filter(|&(i, beams)| among.has(i) && beams.as_ref().is_some_and(|b| b.misses(xs, ys)))
            .fold(0, |set, (i, _)| set | (1 << i));
        ShapeSet(among.0 & !missed)
    }

    /// The shapes of `among` whose box some ray through pixel coordinates
    /// (x, y) in [x0, x1] × [y0, y1] may meet (`Pinhole::screen`): a few
    /// comparisons a shape, cheap enough for every pixel. Only the list's
    /// shapes: a set none of them is in is `ShapeSet::NONE`.
    pub fn in_sight(
        &self,
        (x0, x1): (f64, f64),
        (y0, y1): (f64, f64),
        among: ShapeSet,
    ) -> ShapeSet {
        let unseen = (self.screens.iter().enumerate())
            .filter(|(_, screen)| {
                screen.is_some_and(|[sx0, sx1, sy0, sy1]| {
                    x1 < sx0 || sx1 < x0 || y1 < sy0 || sy1 < y0
                })
            })
            .fold(0, |set, (i, _)| set | (1 << i));
        ShapeSet(among.0 & self.listed().0 & !unseen)
    }

    /// The set of every shape of the list.
    pub fn listed(&self) -> ShapeSet {
        ShapeSet::first(self.screens.len())
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::{ShapeSet, Slabs};

    use crate::accel::{Accel, Backend};
    use crate::math::{Hit, Ray, Ray64, Vec3};
    use crate::scene::{LoadOptions, Scene};

    /// A POV-Ray scene of `objects` under a camera at z = −10.
    fn pov(objects: &str) -> Scene {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("list.pov");
        let text = format!(
            "camera {{ location <0.3, 1.2, -10> look_at <0, 0, 0> angle 40 }}\n\
             light_source {{ <20, 30, -40> color rgb 1 }}\n{objects}"
        );
        std::fs::write(&path, text).unwrap();
        let options = LoadOptions {
            size: Some((48, 36)),
            ..LoadOptions::default()
        };
        Scene::load_with(&path, &options).unwrap()
    }

    /// Scenes the list answers: a torus whose `bounded_by` sphere is wider
    /// than the box Embree holds for it, over an unbounded plane; a clipped
    /// cubic (tcubic.pov's); and five solids, some overlapping, some of
    /// them CSG, two shipped scenes. No two surfaces coincide, where the
    /// first shape in the list wins a tie that Embree's order decides.
    fn scenes() -> Vec<(String, Scene)> {
        let torus = "quartic { < 1,0,0,0,2,0,0,2,0,-104, 0,0,0,0,0,0,0,0,0,0, \
                     1,0,0,2,0,56,0,0,0,0, 1,0,-104,0,784 > \
                     bounded_by { sphere { 0, 12 } } scale 0.25 }\n\
                     plane { y, -3 }";
        let cubic = "intersection { quartic { < 0,0,0,-0.5,0,0,0,0,0,-0.5, \
                     0,0,0,0,0,0,0,0,0,0, 0,0,0,0,0,1,0,0,0,0, 0,0,1,0,0 > } \
                     sphere { 0, 2 } bounded_by { sphere { 0, 2.2 } } rotate <0, -15, 0> }";
        let five = "sphere { <-1, 0, 0>, 1.5 }\n sphere { <1, 0.2, 0.5>, 1.2 }\n\
                    difference { box { -1, 1 } sphere { <0.5, 0.5, -0.5>, 0.9 } translate <0, 1.5, 0> }\n\
                    torus { 2, 0.3 rotate 90*x translate <0, 0, 2> }\n\
                    cylinder { <-3, -2, 1>, <3, -2, 1>, 0.5 }";
        let shipped = |relative: &str| {
            let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(relative);
            (relative.to_string(), Scene::load(&path).unwrap())
        };
        vec![
            ("torus over a plane".into(), pov(torus)),
            ("clipped cubic".into(), pov(cubic)),
            ("five solids".into(), pov(five)),
            shipped("scenes/gallery/csg.toml"),
            shipped("scenes/accuracy/thin_tori.toml"),
        ]
    }

    /// Whether the list's hit is Embree's, to the bit (0), or ties with it
    /// (1): a hit at the same t on another shape, where two surfaces meet
    /// (an object standing on a floor), which each answers by its own order.
    fn same(list: Hit, embree: Hit, name: &str, ray: &Ray) -> usize {
        if list == embree {
            return 0;
        }
        let tie = list.is_hit()
            && list.t.to_bits() == embree.t.to_bits()
            && list.prim_id != embree.prim_id;
        assert!(tie, "{name}: {ray:?}: list {list:?}, Embree {embree:?}");
        1
    }

    /// Every ray the list answers, it answers as Embree does, to the bit
    /// (but for a tie, see `same`):
    /// camera rays (with their f64 rays and without), and from each camera
    /// hit a reflected ray, a ray on into the surface and a shadow ray
    /// towards a light point, each also cut short of its hit.
    #[test]
    fn the_list_answers_as_embree_does() {
        for (name, scene) in scenes() {
            let Accel::Embree(embree, Some(list)) =
                Accel::build(&scene, Backend::Embree, Some(1)).unwrap()
            else {
                panic!("{name}: not traced through the list");
            };
            let panics = embree.panics();
            let (mut hits, mut blocked, mut rays, mut ties) = (0, 0, 0, 0);
            let frame = scene.camera.frame();
            let (w, h) = (scene.camera.width as f32, scene.camera.height as f32);
            for i in 0..48 * 36 {
                let (x, y) = ((i % 48) as f32 + 0.5, (i / 48) as f32 + 0.5);
                let exact = frame.ray64(x * w / 48.0, y * h / 36.0);
                let camera = exact.rounded();
                let first = list.nearest(&camera, &exact, ShapeSet::ALL, panics);
                ties += same(first, embree.intersect_exact(&exact), &name, &camera);
                ties += same(
                    list.nearest(&camera, &Ray64::of(&camera), ShapeSet::ALL, panics),
                    embree.intersect(&camera),
                    &name,
                    &camera,
                );
                if !first.is_hit() {
                    continue;
                }
                hits += 1;
                let p = camera.at(first.t);
                let n = first.ng.normalize();
                let reflected = camera.dir - 2.0 * camera.dir.dot(n) * n;
                let light = Vec3::new(20.0, 30.0, -40.0) - p;
                for (dir, tfar) in [
                    (reflected, f32::INFINITY),
                    (camera.dir, f32::INFINITY),
                    (light, 1.0),
                    (reflected, 0.5),
                ] {
                    let ray = Ray {
                        origin: p,
                        dir,
                        tnear: 1e-4,
                        tfar,
                    };
                    rays += 1;
                    ties += same(
                        list.nearest(&ray, &Ray64::of(&ray), ShapeSet::ALL, panics),
                        embree.intersect(&ray),
                        &name,
                        &ray,
                    );
                    let occluded = list.occluded(&ray, ShapeSet::ALL, panics);
                    assert_eq!(occluded, embree.occluded(&ray), "{name}: shadow {ray:?}");
                    blocked += usize::from(occluded);
                }
            }
            embree.check().unwrap();
            // Enough of each kind that a difference would show; ties are
            // rare, and only csg.toml's objects stand on its floor.
            assert!(
                hits >= 30 && blocked >= 20 && rays - blocked >= 20,
                "{name}: {hits} hits, {blocked} of {rays} blocked"
            );
            assert!(ties * 200 <= rays, "{name}: {ties} ties in {rays} rays");
        }
    }

    /// Only a scene of a few shapes alone is traced through the list.
    #[test]
    fn a_scene_with_triangles_instances_or_many_shapes_keeps_its_bvh() {
        let list = |relative: &str| {
            let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(relative);
            let scene = Scene::load(&path).unwrap();
            matches!(
                Accel::build(&scene, Backend::Embree, Some(1)).unwrap(),
                Accel::Embree(_, Some(_))
            )
        };
        assert!(list("scenes/gallery/tori.toml"), "five tori");
        assert!(!list("scenes/whitted.toml"), "three shapes and a mesh");
        assert!(
            !list("scenes/glass_torus.toml"),
            "four shapes and two triangles"
        );
        let instanced = "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 30\nwidth = 8\nheight = 8\n\
                         [[prototypes.ball.objects]]\ntype = \"sphere\"\nradius = 0.5\n\
                         [[objects]]\ntype = \"instance\"\nprototype = \"ball\"\n";
        let instanced =
            Scene::from_toml(Path::new("instanced.toml"), instanced, Vec::new()).unwrap();
        assert_eq!((instanced.shapes.len(), instanced.instances.len()), (0, 1));
        assert!(matches!(
            Accel::build(&instanced, Backend::Embree, Some(1)).unwrap(),
            Accel::Embree(_, None)
        ));
        let many = (0..6)
            .map(|i| format!("sphere {{ <{i}, 0, 0>, 0.4 }}\n"))
            .collect::<String>();
        let many = pov(&many);
        assert!(matches!(
            Accel::build(&many, Backend::Embree, Some(1)).unwrap(),
            Accel::Embree(_, None)
        ));
    }

    /// Rays through a rectangle of pixels offered only the shapes it may
    /// hit (`ListBeams::may_hit`) find the hit every shape finds, to the
    /// bit: on rectangles of 1, 3 and 8 pixels a side over the image of
    /// each scene the list answers and of two quartics in `bounded_by`
    /// spheres, one of them quarcyl.pov's unbounded spindle, whose box
    /// reaches far beyond its sphere. Some shapes must be proven missed
    /// where some ray of the rectangle meets their box, or it shows nothing.
    #[test]
    fn rays_offered_the_shapes_they_may_hit_find_every_hit() {
        let spindle = "quartic { < 0,0,0,0,1,0,0,0,0,0.01, 0,0,0,0,0,0,0,0,0,0, \
                       0,0,0,1,0,0,0,0,0,0, 0,0,0.01,0,-0.01 > \
                       bounded_by { sphere { 0, 2 } } scale 1.5 rotate <-30, 20, 50> }";
        let torus = "quartic { < 1,0,0,0,2,0,0,2,0,-104, 0,0,0,0,0,0,0,0,0,0, \
                     1,0,0,2,0,56,0,0,0,0, 1,0,-104,0,784 > \
                     bounded_by { sphere { 0, 12 } } scale 0.25 rotate <60, 10, 0> }";
        let mut all = scenes();
        all.push(("spindle".into(), pov(spindle)));
        all.push(("gated torus".into(), pov(torus)));
        let mut proven_anywhere = 0;
        for (name, scene) in all {
            let Accel::Embree(embree, Some(list)) =
                Accel::build(&scene, Backend::Embree, Some(1)).unwrap()
            else {
                panic!("{name}: not traced through the list");
            };
            let frame = scene.camera.frame();
            let Some(beams) = list.beams(&frame.pinhole().unwrap()) else {
                continue;
            };
            let (w, h) = (scene.camera.width as usize, scene.camera.height as usize);
            for side in [1, 3, 8] {
                for (x0, y0) in (0..h)
                    .step_by(side)
                    .flat_map(|y| (0..w).step_by(side).map(move |x| (x, y)))
                {
                    let (x1, y1) = ((x0 + side).min(w), (y0 + side).min(h));
                    let span = |a: usize, b: usize| (a as f64 + 0.5, b as f64 - 0.5);
                    let among = beams.may_hit(span(x0, x1), span(y0, y1), ShapeSet::ALL);
                    for (x, y) in (y0..y1).flat_map(|y| (x0..x1).map(move |x| (x, y))) {
                        let exact = frame.ray64(x as f32 + 0.5, y as f32 + 0.5);
                        let ray = exact.rounded();
                        let want = list.nearest(&ray, &exact, ShapeSet::ALL, embree.panics());
                        let got = list.nearest(&ray, &exact, among, embree.panics());
                        assert_eq!(got, want, "{name}: pixel ({x}, {y}), rectangle side {side}");
                        let slabs = Slabs::new(&ray);
                        proven_anywhere += (list.shapes.iter().enumerate())
                            .filter(|(i, (b, _))| {
                                !among.has(*i) && slabs.meet(b, ray.tnear, ray.tfar)
                            })
                            .count();
                    }
                }
            }
        }
        assert!(
            proven_anywhere > 1000,
            "{proven_anywhere} rays skipped a shape whose box they meet"
        );
    }

    /// A list's every shape, and no other bit: a set with none of them left
    /// is `NONE`.
    #[test]
    fn a_list_s_first_shapes_are_its_every_shape() {
        assert_eq!(ShapeSet::first(0), ShapeSet::NONE);
        for n in 1..=8 {
            let each = (0..n).fold(ShapeSet::NONE, |set, i| set.with(ShapeSet::only(i)));
            assert_eq!(ShapeSet::first(n), each, "{n}");
            assert_eq!((0..n).fold(each, |set, i| set.without(i)), ShapeSet::NONE);
        }
        assert_eq!(ShapeSet::first(9), ShapeSet::ALL);
    }
}
