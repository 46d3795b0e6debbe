//! Where the parts of a POV-Ray scene can show: boxes that may be infinite
//! along some axes (a half-space bounds one side of one axis), moved by
//! interval arithmetic, so that intersections of unbounded parts can still
//! be finite.

use glam::{DAffine3, DVec3};

use super::object::{CsgOp, Kind, Obj};
use crate::geometry::Box3;

/// The world box of an object placed by `parent`: where its inside can be,
/// infinite along the axes it does not bound (a half-space bounds one side
/// of one axis, a quadric cylinder the axes across it), so that the
/// intersections of unbounded parts can still be finite.
pub(super) fn world_box(obj: &Obj, parent: DAffine3) -> Box3 {
    transform_box(&own_box(obj), parent * obj.transform)
}

/// The object's box in its own space (before its transform), padded as
/// `world_box` pads: where a surface of its own is cut to this, a rotation
/// above it widens nothing, as it widens a world box mapped back through it.
pub(super) fn framed_box(obj: &Obj) -> Box3 {
    transform_box(&own_box(obj), DAffine3::IDENTITY)
}

/// `world_box` in the object's own space, unpadded.
fn own_box(obj: &Obj) -> Box3 {
    let everywhere = Box3 {
        min: DVec3::NEG_INFINITY,
        max: DVec3::INFINITY,
    };
    if obj.inverse {
        return everywhere;
    }
    let local = match &obj.kind {
        Kind::Sphere { center, radius } => Box3 {
            min: *center - *radius,
            max: *center + *radius,
        },
        Kind::Box { a, b } => Box3 {
            min: a.min(*b),
            max: a.max(*b),
        },
        Kind::Torus { major, minor } => Box3 {
            min: DVec3::new(-(major + minor), -minor, -(major + minor)),
            max: DVec3::new(major + minor, *minor, major + minor),
        },
        Kind::Round {
            base, cap, r0, r1, ..
        } => {
            let r = r0.max(*r1);
            Box3 {
                min: base.min(*cap) - r,
                max: base.max(*cap) + r,
            }
        }
        Kind::Disc { center, radius, .. } => Box3 {
            min: *center - *radius,
            max: *center + *radius,
        },
        Kind::Mesh(triangles) => {
            let mut b = Box3 {
                min: DVec3::INFINITY,
                max: DVec3::NEG_INFINITY,
            };
            for triangle in triangles.iter() {
                for p in &triangle.corners {
                    b.min = b.min.min(*p);
                    b.max = b.max.max(*p);
                }
            }
            b
        }
        Kind::Plane { normal, distance } => half_space(*normal, *distance).unwrap_or(everywhere),
        Kind::Quadric { a, b, c } => quadric_box(a, *b, *c).unwrap_or(everywhere),
        Kind::Poly(_) | Kind::Light(_) => everywhere,
        Kind::Csg { op, children } => {
            let mut boxes = children
                .iter()
                .filter(|c| !matches!(c.kind, Kind::Light(_)))
                .map(|c| world_box(c, DAffine3::IDENTITY));
            match op {
                CsgOp::Union | CsgOp::Merge => boxes
                    .reduce(|a, c| Box3 {
                        min: a.min.min(c.min),
                        max: a.max.max(c.max),
                    })
                    .unwrap_or(everywhere),
                CsgOp::Intersection => boxes.fold(everywhere, |a, c| a.intersection(&c)),
                CsgOp::Difference => boxes.next().unwrap_or(everywhere),
            }
        }
    };
    obj.clipped_by
        .iter()
        .map(|c| world_box(c, DAffine3::IDENTITY))
        .fold(local, |b, c| b.intersection(&c))
}

/// The half-space n·p < d bounds one side of an axis when n is along it.
fn half_space(normal: DVec3, distance: f64) -> Option<Box3> {
    let n = normal.normalize();
    let axis = (0..3).find(|&i| n[i].abs() == 1.0)?;
    let mut b = Box3 {
        min: DVec3::NEG_INFINITY,
        max: DVec3::INFINITY,
    };
    if n[axis] > 0.0 {
        b.max[axis] = distance;
    } else {
        b.min[axis] = -distance;
    }
    Some(b)
}

/// The inside of Σ aᵢ xᵢ² + b·x + c < 0 with a diagonal, aᵢ ≥ 0 (an
/// ellipsoid, or a cylinder along the axes with aᵢ = 0 and bᵢ = 0): on each
/// axis with aᵢ > 0, |xᵢ + bᵢ/2aᵢ| ≤ √(R/aᵢ), R = Σ bⱼ²/4aⱼ − c.
fn quadric_box(a: &glam::DMat3, b: DVec3, c: f64) -> Option<Box3> {
    let d = DVec3::new(a.x_axis.x, a.y_axis.y, a.z_axis.z);
    let off = [
        a.x_axis.y, a.x_axis.z, a.y_axis.z, a.y_axis.x, a.z_axis.x, a.z_axis.y,
    ];
    if off.iter().any(|v| *v != 0.0) || d.min_element() < 0.0 || d.max_element() <= 0.0 {
        return None;
    }
    if (0..3).any(|i| d[i] == 0.0 && b[i] != 0.0) {
        return None;
    }
    let r = (0..3)
        .filter(|&i| d[i] > 0.0)
        .map(|i| b[i] * b[i] / (4.0 * d[i]))
        .sum::<f64>()
        - c;
    let mut out = Box3 {
        min: DVec3::NEG_INFINITY,
        max: DVec3::INFINITY,
    };
    for i in (0..3).filter(|&i| d[i] > 0.0) {
        let (centre, half) = (-b[i] / (2.0 * d[i]), (r.max(0.0) / d[i]).sqrt());
        out.min[i] = centre - half;
        out.max[i] = centre + half;
    }
    Some(out)
}

/// The box of `b` moved by `m`, by interval arithmetic so that infinite
/// sides stay infinite only along the axes they reach, padded so that no
/// surface lies on a face.
fn transform_box(b: &Box3, m: DAffine3) -> Box3 {
    let mut out = Box3 {
        min: m.translation,
        max: m.translation,
    };
    for k in 0..3 {
        for j in 0..3 {
            let f = m.matrix3.col(j)[k];
            if f == 0.0 {
                continue;
            }
            let (p, q) = (f * b.min[j], f * b.max[j]);
            out.min[k] += p.min(q);
            out.max[k] += p.max(q);
        }
    }
    // Each finite face moves out by a millionth of its distance from the
    // origin and of the box's size: a surface on a face (a half-space's plane)
    // lies strictly inside.
    let finite = |v: f64| if v.is_finite() { v.abs() } else { 0.0 };
    let size = (0..3)
        .map(|k| finite(out.max[k] - out.min[k]))
        .fold(0.0, f64::max);
    for k in 0..3 {
        out.min[k] -= 1e-6 * (1.0 + finite(out.min[k]) + size);
        out.max[k] += 1e-6 * (1.0 + finite(out.max[k]) + size);
    }
    out
}
