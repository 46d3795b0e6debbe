//! Triangle meshes in world space.

use crate::math::{Bounds, Mat4, Vec3, unit};

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
    }

    /// The unit geometric normal of a triangle, (p1 − p0) × (p2 − p0) normalised,
    /// or zero for a degenerate one. Normalised by `unit`: edges 1e10 long
    /// give a normal whose squared length overflows f32.
    pub fn normal(&self, prim: u32) -> Vec3 {
        let [a, b, c] = self.triangles[prim as usize].map(|i| self.positions[i as usize]);
        unit((b - a).cross(c - a))
    }
}
