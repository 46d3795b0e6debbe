//! Vectors (glam), rays and hit records shared by every backend.

pub use glam::{Mat3, Mat4, Vec3};

/// A ray in world space with its parametric interval [tnear, tfar].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
    pub tnear: f32,
    pub tfar: f32,
}

impl Ray {
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Ray {
            origin,
            dir,
            tnear: 0.0,
            tfar: f32::INFINITY,
        }
    }

    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }
}

/// Marks "no geometry" / "no primitive" in hit records, as Embree does.
pub const INVALID_ID: u32 = u32::MAX;

/// The nearest hit of a ray: distance, which geometry and primitive, the
/// barycentric (u, v) and the unnormalised geometric normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub geom_id: u32,
    pub prim_id: u32,
    pub u: f32,
    pub v: f32,
    pub ng: Vec3,
}

impl Hit {
    /// The record of a ray that hit nothing: t = inf, both ids invalid.
    pub const MISS: Hit = Hit {
        t: f32::INFINITY,
        geom_id: INVALID_ID,
        prim_id: INVALID_ID,
        u: 0.0,
        v: 0.0,
        ng: Vec3::ZERO,
    };

    pub fn is_hit(&self) -> bool {
        self.geom_id != INVALID_ID
    }
}

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    pub min: Vec3,
    pub max: Vec3,
}

impl Bounds {
    pub const EMPTY: Bounds = Bounds {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    pub fn grow(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    pub fn union(self, other: Bounds) -> Bounds {
        Bounds {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    pub fn diagonal(&self) -> Vec3 {
        self.max - self.min
    }
}
