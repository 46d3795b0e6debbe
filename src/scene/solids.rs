//! The solids both scene languages (TOML and POV-Ray's) build from the same
//! numbers: a cylinder or cone between two points, a half-space, and the
//! frame that puts an axis along z.

use glam::{DAffine3, DMat3, DQuat, DVec3};

use crate::geometry::{Box3, Quadric, Surface};

/// The frame whose origin is `origin` and whose z axis is along `axis`.
pub(super) fn axis_frame(origin: DVec3, axis: DVec3) -> DAffine3 {
    DAffine3::from_rotation_translation(
        DQuat::from_rotation_arc(DVec3::Z, axis.normalize()),
        origin,
    )
}

/// A rotation by `r` (radians) about x, then y, then z: POV-Ray's `rotate`
/// and a TOML transform's `rotate` alike.
pub(super) fn rotation(r: DVec3) -> DAffine3 {
    DAffine3::from_rotation_z(r.z) * DAffine3::from_rotation_y(r.y) * DAffine3::from_rotation_x(r.x)
}

/// The plane n·p = distance as the linear F = n·p − distance, negative on
/// the half-space's inside.
pub(super) fn linear(normal: DVec3, distance: f64) -> Surface {
    Surface::Quadric(Quadric {
        a: DMat3::ZERO,
        b: normal,
        c: -distance,
    })
}

/// A cylinder (r0 = r1) or cone of radius r0 at z = 0 and r1 at z =
/// length, in its own frame (see [`axis_frame`]): its surface
/// x² + y² − (r0 + k z)², k the radius's slope, negative inside, and the box
/// that cuts it to z in [0, length].
pub(super) fn round(r0: f64, r1: f64, length: f64) -> (Surface, Box3) {
    let k = (r1 - r0) / length;
    let surface = Surface::Quadric(Quadric {
        a: DMat3::from_diagonal(DVec3::new(1.0, 1.0, -k * k)),
        b: DVec3::new(0.0, 0.0, -2.0 * r0 * k),
        c: -r0 * r0,
    });
    let r = r0.max(r1);
    let clip = Box3 {
        min: DVec3::new(-r, -r, 0.0),
        max: DVec3::new(r, r, length),
    };
    (surface, clip)
}
