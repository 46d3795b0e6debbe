//! Triangle meshes in world space.

use crate::math::{Bounds, Mat3, Mat4, Vec2, Vec3, unit};

/// One OBJ object: its own vertices, triangles in file order (after fan
/// triangulation) and one material index per triangle. Degenerate triangles
/// are kept, so a triangle's index is its index in the file.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Mesh {
    pub name: String,
    pub positions: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle, an index into the scene's materials.
    pub materials: Vec<u32>,
    /// Per vertex, the shading normal (OBJ's `vn`), or none at all. A zero
    /// normal marks a corner without one: its triangles are shaded flat.
    /// Left out of the scene hash when empty, so meshes without hash as before.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub normals: Vec<Vec3>,
    /// Per vertex, the texture coordinates (OBJ's `vt`), or none at all.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub uvs: Vec<Vec2>,
    /// Per vertex, a linear RGB colour (a PLY's `red`, `green`, `blue`), or
    /// none at all: where present it is the surface's albedo.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub colours: Vec<Vec3>,
}

impl Mesh {
    pub fn bounds(&self) -> Bounds {
        let mut b = Bounds::EMPTY;
        for &p in &self.positions {
            b.grow(p);
        }
        b
    }

    pub fn transform(&mut self, m: &Mat4) {
        for p in &mut self.positions {
            *p = m.transform_point3(*p);
        }
        // Normals move by the inverse transpose; their length does not matter.
        let normal = Mat3::from_mat4(*m).inverse().transpose();
        for n in &mut self.normals {
            *n = normal * *n;
        }
    }

    /// The interpolated shading normal at barycentrics (b1, b2) of a
    /// triangle (unit, not oriented), or `None` where the mesh or one of the
    /// triangle's corners has no normal, or they cancel: such a triangle is flat.
    pub fn shading_normal(&self, prim: u32, b1: f32, b2: f32) -> Option<Vec3> {
        if self.normals.is_empty() {
            return None;
        }
        let [n0, n1, n2] = self.triangles[prim as usize].map(|i| self.normals[i as usize]);
        if n0 == Vec3::ZERO || n1 == Vec3::ZERO || n2 == Vec3::ZERO {
            return None;
        }
        let n = unit((1.0 - b1 - b2) * n0 + b1 * n1 + b2 * n2);
        (n != Vec3::ZERO).then_some(n)
    }

    /// The interpolated texture coordinates at barycentrics (b1, b2) of a
    /// triangle, if the mesh has them.
    pub fn uv(&self, prim: u32, b1: f32, b2: f32) -> Option<Vec2> {
        self.interpolate(&self.uvs, prim, b1, b2)
    }

    /// The interpolated vertex colour at barycentrics (b1, b2) of a
    /// triangle, if the mesh has colours.
    pub fn colour(&self, prim: u32, b1: f32, b2: f32) -> Option<Vec3> {
        self.interpolate(&self.colours, prim, b1, b2)
    }

    /// A per-vertex attribute at barycentrics (b1, b2), if the mesh has it.
    fn interpolate<T>(&self, values: &[T], prim: u32, b1: f32, b2: f32) -> Option<T>
    where
        T: Copy + std::ops::Add<Output = T> + std::ops::Mul<f32, Output = T>,
    {
        if values.is_empty() {
            return None;
        }
        let [t0, t1, t2] = self.triangles[prim as usize].map(|i| values[i as usize]);
        Some(t0 * (1.0 - b1 - b2) + t1 * b1 + t2 * b2)
    }

    /// The derivatives dp/du and dp/dv of a triangle's positions in its
    /// texture coordinates (pbrt's), or `None` without uv or where the
    /// triangle's uv are degenerate.
    pub fn uv_derivatives(&self, prim: u32) -> Option<(Vec3, Vec3)> {
        if self.uvs.is_empty() {
            return None;
        }
        let corners = self.triangles[prim as usize];
        let [p0, p1, p2] = corners.map(|i| self.positions[i as usize]);
        let [t0, t1, t2] = corners.map(|i| self.uvs[i as usize]);
        let (duv02, duv12) = (t0 - t2, t1 - t2);
        let (dp02, dp12) = (p0 - p2, p1 - p2);
        let det = duv02.x * duv12.y - duv02.y * duv12.x;
        if det.abs() < 1e-12 || !det.is_finite() {
            return None;
        }
        let inv = 1.0 / det;
        let dpdu = (duv12.y * dp02 - duv02.y * dp12) * inv;
        let dpdv = (duv02.x * dp12 - duv12.x * dp02) * inv;
        (dpdu.is_finite() && dpdv.is_finite()).then_some((dpdu, dpdv))
    }

    /// The unit geometric normal of a triangle, (p1 − p0) × (p2 − p0) normalised,
    /// or zero for a degenerate one. Normalised by `unit`: edges 1e10 long
    /// give a normal whose squared length overflows f32.
    pub fn normal(&self, prim: u32) -> Vec3 {
        let [a, b, c] = self.triangles[prim as usize].map(|i| self.positions[i as usize]);
        unit((b - a).cross(c - a))
    }
}
