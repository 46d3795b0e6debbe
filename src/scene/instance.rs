//! Instances: a prototype's geometry (meshes and analytic shapes, declared
//! once under `[prototypes.NAME]`) placed any number of times, each placement
//! with its own transform and optionally its own material. Every backend
//! traces a hit on an instance in the prototype's own space and reports it
//! in world space, with the instance's index (`Hit::inst_id`).

use glam::{Affine3A, Mat3};

use crate::geometry::{Mesh, Shape};
use crate::math::{Bounds, Ray, Vec3, gamma};

/// Geometry declared once and placed by instances. Its geometry ids are
/// numbered as a scene's are: mesh i is geometry i, the shapes one more
/// geometry after them (`shapes_geom_id`).
#[derive(Clone, Debug, serde::Serialize)]
pub struct Prototype {
    pub name: String,
    pub meshes: Vec<Mesh>,
    pub shapes: Vec<Shape>,
    /// Found once: every instance's box starts from it.
    #[serde(skip)]
    bounds: Bounds,
}

impl Prototype {
    pub fn new(name: String, meshes: Vec<Mesh>, shapes: Vec<Shape>) -> Prototype {
        let bounds = (meshes.iter().map(Mesh::bounds))
            .chain(shapes.iter().map(Shape::bounds))
            .fold(Bounds::EMPTY, Bounds::union);
        Prototype {
            name,
            meshes,
            shapes,
            bounds,
        }
    }

    /// The geometry id of the prototype's analytic shapes.
    pub fn shapes_geom_id(&self) -> u32 {
        self.meshes.len() as u32
    }

    /// The box of the prototype's geometry in its own space.
    pub fn bounds(&self) -> Bounds {
        self.bounds
    }

    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(|m| m.triangles.len()).sum()
    }
}

/// One placement of a prototype.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Instance {
    /// Index into `Scene::prototypes`.
    pub prototype: u32,
    /// Prototype space to world space.
    pub to_world: Affine3A,
    /// World space to prototype space: rays enter the prototype by it.
    #[serde(skip)]
    from_world: Affine3A,
    /// Normals from prototype space to world space (the inverse transpose).
    #[serde(skip)]
    normal_to_world: Mat3,
    /// Whether the transform mirrors (a negative determinant), which turns
    /// each triangle's winding.
    #[serde(skip)]
    mirrors: bool,
    /// Replaces every material of the prototype's geometry when given.
    pub material: Option<u32>,
    /// The materials this instance's analytic shapes show in place of the
    /// prototype's (or `material`), as (theirs, this instance's): a copy
    /// with the checker moved with the instance (see `scene::file`), so it
    /// stays in the shape's own space. Only materials with a checker.
    pub shape_materials: Vec<(u32, u32)>,
}

impl Instance {
    /// An instance of `prototype` placed by `to_world`, which must be
    /// invertible (the loader checks the scale).
    pub fn new(prototype: u32, to_world: Affine3A, material: Option<u32>) -> Instance {
        let from_world = to_world.inverse();
        Instance {
            prototype,
            to_world,
            from_world,
            normal_to_world: Mat3::from(from_world.matrix3).transpose(),
            mirrors: to_world.matrix3.determinant() < 0.0,
            material,
            shape_materials: Vec::new(),
        }
    }

    /// The material an analytic shape of material `m` (its own, or the
    /// instance's `material`) shows through this instance.
    pub fn shape_material(&self, m: u32) -> u32 {
        (self.shape_materials.iter())
            .find(|&&(from, _)| from == m)
            .map_or(m, |&(_, to)| to)
    }

    /// The ray in prototype space. Its parameter is unchanged (the direction
    /// is transformed, not normalised), so a hit's t holds in both spaces.
    pub fn ray_to_prototype(&self, ray: &Ray) -> Ray {
        Ray {
            origin: self.from_world.transform_point3(ray.origin),
            dir: self.from_world.transform_vector3(ray.dir),
            ..*ray
        }
    }

    /// A point in prototype space, with a bound on its error per axis, in
    /// world space: the error carried through the matrix, plus the rounding
    /// of the transform itself (pbrt's bound for a transformed point).
    pub fn point_to_world(&self, p: Vec3, error: Vec3) -> (Vec3, Vec3) {
        let m = Mat3::from(self.to_world.matrix3);
        let abs = Mat3::from_cols(m.x_axis.abs(), m.y_axis.abs(), m.z_axis.abs());
        let t = Vec3::from(self.to_world.translation);
        let world = m * p + t;
        let error = (1.0 + gamma(3)) * (abs * error) + gamma(3) * (abs * p.abs() + t.abs());
        (world, error)
    }

    /// A normal (of any length) from prototype space to world space.
    pub fn normal_to_world(&self, n: Vec3) -> Vec3 {
        self.normal_to_world * n
    }

    /// A hit's geometric normal from prototype space to world space. A
    /// triangle's is the cross product of its edges, which a mirroring
    /// transform turns round with the winding (as in a mesh placed by that
    /// transform, so an instance hits as the flattened copy does); an analytic
    /// shape's is its outward gradient, and stays outward.
    pub fn ng_to_world(&self, ng: Vec3, triangle: bool) -> Vec3 {
        let n = self.normal_to_world(ng);
        if triangle && self.mirrors { -n } else { n }
    }

    /// The world box around a box in prototype space (its eight corners moved).
    pub fn bounds_to_world(&self, b: Bounds) -> Bounds {
        if b.is_empty() {
            return b;
        }
        let mut world = Bounds::EMPTY;
        for i in 0..8 {
            let pick = |bit: usize, lo: f32, hi: f32| if i & bit == 0 { lo } else { hi };
            let corner = Vec3::new(
                pick(1, b.min.x, b.max.x),
                pick(2, b.min.y, b.max.y),
                pick(4, b.min.z, b.max.z),
            );
            world.grow(self.to_world.transform_point3(corner));
        }
        world
    }
}
