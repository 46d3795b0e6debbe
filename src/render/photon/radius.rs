//! The default gather radius, derived from the stored photons themselves (a
//! k-nearest-neighbour density estimate's own scale, as Jensen's photon maps
//! choose it per gather), never from the scene's bounds: a floor 2000 units
//! wide does not make a caustic 1 unit wide any coarser.
//!
//! The rule: around each of a fixed, evenly spaced subset of the stored
//! photons (in emission order, so the same for any thread count), the distance
//! to its `NEIGHBOURS`-th nearest photon; the radius is the geometric mean of
//! the middle half of those distances. The subset is drawn from the photons,
//! so it samples the caustics in proportion to their photon density: the disk
//! holds about `NEIGHBOURS` photons around the typical stored photon and more
//! where a caustic is brighter.
//! A floor keeps the radius above the resolution of the photons' f32
//! coordinates, so it is never 0 and π r² never underflows.

use std::fmt;

use rayon::prelude::*;

use super::Photon;
use super::nearest::Nearest;
use crate::math::Vec3;

/// The photons a gather disk holds around the typical stored photon, and more
/// where the caustic is brighter: the estimate's relative noise there is about
/// 1/√16 = 25%. Chosen by measurement (docs/integrators.md): against a
/// reference of 40 million photons, 16 gave about the least squared error
/// (more blur a caustic's focus, fewer blotch its dim parts), and each
/// doubling costs every gather in a bright spot twice the photons.
const NEIGHBOURS: usize = 16;

/// How many stored photons the radius is measured around, at most: 4096 came
/// within 2% of the radius over every photon on `scenes/path.toml` (108,141
/// stored) and 3% on `scenes/whitted.toml`, and on the former the rule (the
/// tree and its queries) took about 20 ms, a thirtieth of the photon pass,
/// where every photon took 300 ms.
const SAMPLES: usize = 4096;

/// The smallest distance counted, relative to the largest coordinate of the
/// photon it is measured around: 2⁻²² is two to four f32 ulps there, below
/// which distances are rounding noise (photons all at one point have none).
const RESOLUTION: f32 = 1.0 / (1u32 << 22) as f32;

/// The smallest radius at all, for photons all at the origin: its square is
/// still a normal f32, so π r² is neither 0 nor subnormal.
const SMALLEST: f32 = 1.0842022e-19; // √(f32::MIN_POSITIVE)

/// The gather radius and where it came from, for the report.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Radius {
    pub value: f32,
    pub from: RadiusFrom,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RadiusFrom {
    /// `render.photons.radius`, as the scene gives it.
    Scene,
    /// The typical distance to the `NEIGHBOURS`-th nearest photon.
    Photons,
    /// No photon was stored: the map is empty and any radius gathers nothing.
    Nothing,
}

impl Radius {
    /// The scene's radius when it gives one, otherwise the rule above.
    pub(super) fn choose(explicit: Option<f32>, photons: &[Photon]) -> Radius {
        if let Some(value) = explicit {
            return Radius {
                value,
                from: RadiusFrom::Scene,
            };
        }
        // A photon lies where a ray hit, so it is finite; were one not, it is
        // left out rather than make the radius infinite or NaN.
        let points: Vec<Vec3> = photons
            .iter()
            .map(|ph| ph.p)
            .filter(|p| p.is_finite())
            .collect();
        if points.is_empty() {
            return Radius {
                value: 1.0,
                from: RadiusFrom::Nothing,
            };
        }
        Radius {
            value: from_points(points),
            from: RadiusFrom::Photons,
        }
    }
}

impl fmt::Display for RadiusFrom {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RadiusFrom::Scene => write!(f, "render.photons.radius"),
            RadiusFrom::Photons => write!(
                f,
                "from the photons: {NEIGHBOURS} within it around a typical one of \
                 {SAMPLES} sampled"
            ),
            RadiusFrom::Nothing => write!(f, "no photons stored: unused"),
        }
    }
}

/// The rule over at least one finite point; run on the current rayon pool,
/// each sample on its own, so the answer does not depend on the thread count.
fn from_points(points: Vec<Vec3>) -> f32 {
    let k = NEIGHBOURS.min(points.len());
    let samples = SAMPLES.min(points.len());
    let queries: Vec<Vec3> = (0..samples)
        .map(|i| points[i * points.len() / samples])
        .collect();
    let tree = Nearest::new(points);
    let mut distances: Vec<f32> = queries
        .into_par_iter()
        // Never below the resolution of the sample's own coordinates.
        .map(|q| {
            tree.kth::<NEIGHBOURS>(q, k)
                .max(RESOLUTION * q.abs().max_element())
        })
        .collect();
    distances.sort_by(f32::total_cmp);
    // The middle half, averaged in log. A caustic's photons often fall in two
    // groups, a tight focus and a wide spread, with few distances between
    // them: a median there jumps from one group to the other as a few photons
    // come or go, while this mean moves with their shares. The farthest
    // quarter, the sparse photons a wide floor adds, does not count at all.
    let n = distances.len();
    let middle = &distances[n / 4..n - n / 4];
    let mean_log = middle
        .iter()
        .map(|&d| f64::from(d.max(SMALLEST)).ln())
        .sum::<f64>()
        / middle.len() as f64;
    (mean_log.exp() as f32).max(SMALLEST)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// A caustic as a glass ball makes one on a floor of half-width `floor`:
    /// 9 of every 10 photons in a bright spot of radius 0.2 around (1, 0, 2),
    /// the 10th anywhere on the floor.
    fn caustic(floor: f32) -> Vec<Photon> {
        let mut rng = Rng::for_sample(7, 8, 9);
        (0..20_000)
            .map(|i| {
                let [a, b] = rng.next_2d();
                let p = if i % 10 == 9 {
                    Vec3::new(2.0 * a - 1.0, 0.0, 2.0 * b - 1.0) * floor
                } else {
                    // Denser towards the middle, as a focused spot is.
                    let (r, phi) = (0.2 * a, 2.0 * std::f32::consts::PI * b);
                    Vec3::new(1.0 + r * phi.cos(), 0.0, 2.0 + r * phi.sin())
                };
                Photon::at(p)
            })
            .collect()
    }

    fn default_radius(photons: &[Photon]) -> f32 {
        let r = Radius::choose(None, photons);
        assert_eq!(r.from, RadiusFrom::Photons);
        r.value
    }

    #[test]
    fn the_disk_holds_neighbours_photons_around_the_typical_photon() {
        let photons = caustic(50.0);
        let r = default_radius(&photons);
        let mut counts: Vec<usize> = (0..photons.len())
            .step_by(97)
            .map(|i| {
                let q = photons[i].p;
                photons.iter().filter(|ph| ph.p.distance(q) <= r).count()
            })
            .collect();
        counts.sort_unstable();
        // The median of another subset of the photons: within a fifth of the
        // aim (the spot's density varies across it, and 4096 samples set r).
        let median = counts[counts.len() / 2];
        assert!(
            (NEIGHBOURS * 4 / 5..=NEIGHBOURS * 6 / 5).contains(&median),
            "{median} photons within {r}"
        );
        // The spot is far smaller than the floor, and so is the radius.
        assert!(r < 0.05, "{r}");
    }

    #[test]
    fn scaling_the_photons_scales_the_radius() {
        let photons = caustic(1000.0);
        let r = default_radius(&photons);
        for s in [1e-4, 0.125, 3.0, 1e5] {
            let scaled: Vec<Photon> = photons.iter().map(|ph| Photon::at(ph.p * s)).collect();
            let got = default_radius(&scaled);
            // A power of two scales every distance exactly. Another factor
            // rounds each coordinate once, by 6e-8 of a coordinate some 200
            // times the radius: about 2e-5 of a distance between photons.
            assert!(
                (got / (s * r) - 1.0).abs() < 1e-4,
                "{s}: {got} vs {}",
                s * r
            );
        }
    }

    #[test]
    fn the_floor_size_does_not_change_the_radius() {
        // The sparse tenth sits on floors from 400 to 400,000 units wide, too
        // sparse to come near the spot, among the farthest quarter: the middle
        // half is the spot's, the same photons' distances bit for bit.
        let r = default_radius(&caustic(200.0));
        assert!(r < 0.05, "{r}");
        for floor in [2000.0, 20_000.0, 200_000.0] {
            assert_eq!(default_radius(&caustic(floor)), r, "floor {floor}");
        }
    }

    #[test]
    fn an_explicit_radius_wins() {
        let r = Radius::choose(Some(0.25), &caustic(2000.0));
        assert_eq!((r.value, r.from), (0.25, RadiusFrom::Scene));
    }

    #[test]
    fn degenerate_photons_still_give_a_usable_radius() {
        let usable = |r: Radius| {
            let area = std::f32::consts::PI * r.value * r.value;
            assert!(area.is_normal(), "{r:?}: π r² = {area}");
        };
        let none = Radius::choose(None, &[]);
        assert_eq!(none.from, RadiusFrom::Nothing);
        usable(none);
        // One photon, fewer photons than NEIGHBOURS, all at one point, all at
        // the origin: no distance is positive, or too few are.
        let p = Vec3::new(3.0, -1e5, 0.5);
        for photons in [
            vec![Photon::at(p)],
            vec![Photon::at(p); 5],
            vec![Photon::at(p); 1000],
            vec![Photon::at(Vec3::ZERO); 1000],
            vec![Photon::at(Vec3::splat(1e-30)); 3],
        ] {
            let r = Radius::choose(None, &photons);
            assert_eq!(r.from, RadiusFrom::Photons);
            usable(r);
        }
        // At one point far out, the floor is the coordinates' resolution (up
        // to the rounding of a logarithm and its exponential).
        let far = default_radius(&vec![Photon::at(p); 1000]);
        assert!((far / (1e5 * RESOLUTION) - 1.0).abs() < 1e-6, "{far}");
        // Fewer photons than NEIGHBOURS: each one's farthest, 2, √5 and √5,
        // all in the middle half of three; their geometric mean is ∛10.
        let few = [Vec3::ZERO, Vec3::X, Vec3::new(0.0, 0.0, 2.0)].map(Photon::at);
        let got = default_radius(&few);
        assert!((got / 10f32.cbrt() - 1.0).abs() < 1e-6, "{got}");
    }

    #[test]
    fn a_stray_non_finite_photon_is_left_out() {
        let mut photons = caustic(2.0);
        let r = default_radius(&photons);
        photons[0] = Photon::at(Vec3::splat(f32::NAN));
        photons[10] = Photon::at(Vec3::splat(f32::INFINITY));
        let got = default_radius(&photons);
        // Two of 20,000 photons fewer among the samples and the neighbours:
        // a few percent at most.
        assert!(
            got.is_finite() && (got / r - 1.0).abs() < 0.05,
            "{got} vs {r}"
        );
    }

    #[test]
    fn the_radius_is_the_same_for_any_thread_count() {
        let photons = caustic(2000.0);
        let on = |threads| {
            crate::render::thread_pool(Some(threads))
                .unwrap()
                .install(|| default_radius(&photons))
        };
        assert_eq!(on(1).to_bits(), on(2).to_bits());
    }
}
