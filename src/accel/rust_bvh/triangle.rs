//! Embree's robust ray–triangle test (the Plücker form it uses under
//! `RTC_SCENE_FLAG_ROBUST`), so the pure-Rust backends report the same t, u, v
//! and geometric normal as Embree within rounding, and are watertight the same
//! way: the edge tests of two triangles sharing an edge use the same numbers.

use crate::math::{Ray, Vec3};

/// Embree's `min_rcp_input`: below this |U + V + W| the barycentrics are set to 0
/// rather than divided by.
const MIN_RCP_INPUT: f32 = 1e-18;

/// What a triangle reports for a hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct TriangleHit {
    pub t: f32,
    /// Barycentrics as Embree defines them: p = (1 − u − v)·p0 + u·p1 + v·p2.
    pub u: f32,
    pub v: f32,
    /// Unnormalised geometric normal, (p1 − p0) × (p2 − p0) as Embree computes it.
    pub ng: Vec3,
}

/// The hit of `ray` on the triangle `corners` with tnear ≤ t ≤ tfar (Embree's
/// bounds, both inclusive), or `None`. A degenerate triangle has a zero normal,
/// so a zero denominator, and is never hit.
#[inline]
pub(super) fn intersect(corners: &[Vec3; 3], ray: &Ray) -> Option<TriangleHit> {
    // Corners relative to the ray origin: the Plücker coordinates simplify and the
    // edge tests become numerically stable.
    let [v0, v1, v2] = corners.map(|c| c - ray.origin);
    let d = ray.dir;
    let e0 = v2 - v0;
    let e1 = v0 - v1;
    let e2 = v1 - v2;
    // Signed volumes of the ray with each edge; U weighs p1, V weighs p2.
    let u = e0.cross(v2 + v0).dot(d);
    let v = e1.cross(v0 + v1).dot(d);
    let w = e2.cross(v1 + v2).dot(d);
    let uvw = u + v + w;
    let eps = f32::EPSILON * uvw.abs();
    let inside = u.min(v).min(w) >= -eps || u.max(v).max(w) <= eps;
    if !inside {
        return None;
    }
    let ng = stable_normal(e0, e1, e2);
    // Embree doubles both den and the numerator; the factor cancels in t.
    let den = ng.dot(d);
    if den == 0.0 {
        return None;
    }
    let t = v0.dot(ng) / den;
    if !(ray.tnear <= t && t <= ray.tfar) {
        return None;
    }
    let rcp = if uvw.abs() < MIN_RCP_INPUT {
        0.0
    } else {
        1.0 / uvw
    };
    Some(TriangleHit {
        t,
        u: u * rcp,
        v: v * rcp,
        ng,
    })
}

/// Embree's `stable_triangle_normal`: a × b and b × c are equal for edges that
/// sum to zero; per component take the one whose products cancel less.
fn stable_normal(a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let (ab_x, ab_y, ab_z) = (a.z * b.y, a.x * b.z, a.y * b.x);
    let (bc_x, bc_y, bc_z) = (b.z * c.y, b.x * c.z, b.y * c.x);
    let cross_ab = Vec3::new(a.y * b.z - ab_x, a.z * b.x - ab_y, a.x * b.y - ab_z);
    let cross_bc = Vec3::new(b.y * c.z - bc_x, b.z * c.x - bc_y, b.x * c.y - bc_z);
    let pick = |ab: f32, bc: f32, x: f32, y: f32| if ab.abs() < bc.abs() { x } else { y };
    Vec3::new(
        pick(ab_x, bc_x, cross_ab.x, cross_bc.x),
        pick(ab_y, bc_y, cross_ab.y, cross_bc.y),
        pick(ab_z, bc_z, cross_ab.z, cross_bc.z),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRIANGLE: [Vec3; 3] = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ];

    fn down_at(x: f32, y: f32) -> Ray {
        Ray::new(Vec3::new(x, y, 2.0), Vec3::new(0.0, 0.0, -1.0))
    }

    #[test]
    fn barycentrics_weigh_the_second_and_third_corner() {
        let hit = intersect(&TRIANGLE, &down_at(0.25, 0.5)).unwrap();
        assert_eq!(hit.t, 2.0);
        assert!(
            (hit.u - 0.25).abs() < 1e-6 && (hit.v - 0.5).abs() < 1e-6,
            "{hit:?}"
        );
        // (p1 − p0) × (p2 − p0) = +z, unnormalised: twice the area.
        assert_eq!(hit.ng, Vec3::Z);
    }

    #[test]
    fn misses_outside_and_respects_the_interval() {
        assert!(intersect(&TRIANGLE, &down_at(0.75, 0.5)).is_none());
        let mut ray = down_at(0.2, 0.2);
        ray.tfar = 1.5;
        assert!(intersect(&TRIANGLE, &ray).is_none());
        ray.tfar = 2.0;
        assert!(intersect(&TRIANGLE, &ray).is_some(), "tfar is inclusive");
        ray.tnear = 2.5;
        ray.tfar = f32::INFINITY;
        assert!(intersect(&TRIANGLE, &ray).is_none());
    }

    #[test]
    fn degenerate_triangles_are_never_hit() {
        let repeated = [Vec3::ZERO, Vec3::ZERO, Vec3::X];
        let collinear = [Vec3::ZERO, Vec3::X, 2.0 * Vec3::X];
        for corners in [repeated, collinear] {
            for ray in [down_at(0.0, 0.0), down_at(0.5, 0.0), down_at(1.0, 0.0)] {
                assert!(intersect(&corners, &ray).is_none(), "{corners:?}");
            }
            let along = Ray::new(Vec3::new(-1.0, 0.0, 0.0), Vec3::X);
            assert!(intersect(&corners, &along).is_none(), "{corners:?}");
        }
    }

    #[test]
    fn a_shared_edge_is_watertight() {
        // Two triangles sharing the diagonal of the unit square: a ray through a point
        // on the diagonal hits at least one of them.
        let other = [TRIANGLE[1], Vec3::new(1.0, 1.0, 0.0), TRIANGLE[2]];
        for i in 0..=100 {
            let s = i as f32 / 100.0;
            let ray = down_at(s, 1.0 - s);
            assert!(
                intersect(&TRIANGLE, &ray).is_some() || intersect(&other, &ray).is_some(),
                "a crack at s = {s}"
            );
        }
    }
}
