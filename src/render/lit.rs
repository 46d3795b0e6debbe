//! Shadow rays spared a tile at a time. A point light's rays are
//! light + s·D(u, v), D affine in (u, v), as a pinhole camera's are
//! (`Pinhole::toward`), so a shape's F along them is one polynomial, formed
//! once a render. A tile's camera hits on a shape, seen from the light, lie
//! in a window of (u, v) and a stretch of s. Where F keeps one sign along
//! the light's rays through the window up to that stretch, and is monotone
//! along them across it (`ShapeBeams::lights`), each hit is the first
//! point of the shape its light ray meets: its shadow ray, which starts
//! just off the surface on the light's side, meets the shape nowhere. The
//! search it would have made finds no root, so the image is the same.
//!
//! A CSG tree is proven a leaf at a time: the leaf's crossing-free sign
//! along the shadow rays then leaves none of the tree's surfaces to meet
//! (`Csg::unseen`), or the tree is not skipped.
//!
//! In POV-Ray's single-quartic samples every shadow ray starts on the
//! quartic it tests, at some 1,650 instructions a ray on lemnisca.pov
//! (`valgrind --tool=callgrind`): 40% of its render loop.

use super::batch::TileCameras;
use super::whitted::SHADOW_SHORT;
use crate::accel::{Accel, LightBeams, ShapeSet};
use crate::film::Region;
use crate::geometry::shadow_start_bound;
use crate::math::{DVec3, Hit, Ray64};
use crate::scene::Scene;

/// The fewest points a proof is tried for.
const FEWEST: usize = 16;

/// The point lights whose shadow rays a tile's proofs may spare, each with
/// its index among the scene's lights and its shapes' F along its rays.
pub(super) struct LightProofs<'a> {
    lights: Vec<(usize, DVec3, LightBeams<'a>)>,
    geom_id: u32,
    /// Every shape of the list: a shadow ray proven clear of the only
    /// one is offered `ShapeSet::NONE`.
    listed: ShapeSet,
}

/// The lights towards which the shape a pixel's camera ray hit is proven
/// to cast no shadow on the hit, and the shapes its shadow rays towards
/// them are then offered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Lit {
    /// Bit i: the scene's light i (lights from 64 on are never proven).
    lights: u64,
    among: ShapeSet,
}

impl Lit {
    pub const NONE: Lit = Lit {
        lights: 0,
        among: ShapeSet::ALL,
    };

    /// The shapes a shadow ray from the camera hit towards the scene's
    /// light `light` must be offered.
    pub fn among(&self, light: usize) -> ShapeSet {
        let proven = 1u64
            .checked_shl(light as u32)
            .is_some_and(|bit| self.lights & bit != 0);
        if proven { self.among } else { ShapeSet::ALL }
    }
}

impl<'a> LightProofs<'a> {
    /// The scene's point and spot lights (the first 64) whose rays some
    /// shape can be proven along (`Accel::light_beams`); None if there is
    /// none.
    pub(super) fn new(scene: &Scene, accel: &'a Accel) -> Option<LightProofs<'a>> {
        let lights: Vec<_> = (scene.lights.iter().enumerate().take(u64::BITS as usize))
            .filter_map(|(i, light)| {
                let at = light.point()?.as_dvec3();
                Some((i, at, accel.light_beams(at)?))
            })
            .collect();
        (!lights.is_empty()).then(|| LightProofs {
            lights,
            geom_id: scene.shapes_geom_id(),
            listed: ShapeSet::first(scene.shapes.len()),
        })
    }

    /// Each pixel's `Lit`, row by row, for the hits of `cameras` as last
    /// traced over `grid`: proven over the whole tile, and where that
    /// fails, over each quarter of it.
    pub(super) fn prove(&self, cameras: &TileCameras, grid: Region, lit: &mut Vec<Lit>) {
        let hits: Vec<Option<Point>> = cameras
            .hits()
            .map(|(ray, hit)| self.point(ray, hit))
            .collect();
        lit.clear();
        lit.extend(hits.iter().map(|h| match h {
            Some(point) => Lit {
                lights: 0,
                among: self.listed.without(point.on.0),
            },
            None => Lit::NONE,
        }));
        let (w, h) = (grid.width(), grid.height());
        let whole = [(0, w, 0, h)];
        let quarters = [
            (0, w / 2, 0, h / 2),
            (w / 2, w, 0, h / 2),
            (0, w / 2, h / 2, h),
            (w / 2, w, h / 2, h),
        ];
        // At most a point a pixel: sized once, not grown a push at a time
        // (see `TileCameras::new`).
        let mut points = Vec::with_capacity(hits.len());
        let mut members = Vec::with_capacity(hits.len());
        // The (shape, leaf) pairs hit, each proven on its own.
        let mut surfaces: Vec<(usize, usize)> = hits.iter().flatten().map(|h| h.on).collect();
        surfaces.sort_unstable();
        surfaces.dedup();
        for (light, at, beams) in &self.lights {
            let bit = 1u64 << light;
            for &(shape, leaf) in &surfaces {
                for rects in [&whole[..], &quarters[..]] {
                    let mut all = true;
                    for &(x0, x1, y0, y1) in rects {
                        points.clear();
                        members.clear();
                        for y in y0..y1 {
                            for x in x0..x1 {
                                let i = y * w + x;
                                let Some(Point { on, p, pad, n }) = hits[i] else {
                                    continue;
                                };
                                let seen = cameras.ray(i).dir;
                                // The light on the side the camera sees:
                                // elsewhere the pixel has no shadow ray
                                // (and its point would fail the proof).
                                if on == (shape, leaf) && n.dot(*at - p) * n.dot(-seen) > 0.0 {
                                    points.push((p, pad));
                                    members.push(i);
                                }
                            }
                        }
                        // A proof costs about what 20 shadow rays do.
                        if members.len() < FEWEST {
                            all = false;
                            continue;
                        }
                        if beams.lights(shape, leaf, &points, f64::from(SHADOW_SHORT)) {
                            for &i in &members {
                                lit[i].lights |= bit;
                            }
                        } else {
                            all = false;
                        }
                    }
                    if all {
                        break;
                    }
                }
            }
        }
    }

    /// A camera hit on one of the list's shapes (the root's error being
    /// in the hit's v, its CSG leaf in u: `accel::analytic`).
    fn point(&self, ray: &Ray64, hit: &Hit) -> Option<Point> {
        if !hit.is_hit() || hit.geom_id != self.geom_id {
            return None;
        }
        let t = f64::from(hit.t);
        let p = ray.origin + t * ray.dir;
        let pad = shadow_start_bound(ray.origin, ray.dir, t, f64::from(hit.v));
        (p.is_finite() && pad.is_finite()).then(|| Point {
            on: (hit.prim_id as usize, hit.u as usize),
            p,
            pad,
            n: hit.ng.as_dvec3(),
        })
    }
}

/// A camera hit on one of the list's shapes.
#[derive(Clone, Copy)]
struct Point {
    /// The shape, and its CSG leaf (0 for a plain surface).
    on: (usize, usize),
    /// The point (world).
    p: DVec3,
    /// A bound on how far from it the hit's shadow rays start
    /// (`shadow_start_bound`).
    pad: f64,
    /// The surface's normal.
    n: DVec3,
}
