//! What a render counts as it goes: rays by kind and by depth, and, for
//! `sturmray explain`, the whole ray tree of one sample.

use serde::Serialize;

use crate::math::{Hit, Vec3};
use crate::poly::solve::unseparated_count;
use crate::scene::Scene;

/// How many depths the per-depth counts keep apart; deeper rays share the last.
pub const DEPTHS: usize = 16;

/// Rays traced, by kind, and all rays by the depth of the tree they start at
/// (0: camera rays and the shadow rays of their hits).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct RayStats {
    pub camera: u64,
    pub shadow: u64,
    pub reflection: u64,
    pub refraction: u64,
    pub diffuse: u64,
    pub photon: u64,
    pub by_depth: [u64; DEPTHS],
    /// Root queries (one ray against one analytic surface) whose f64 Sturm
    /// isolation could not separate two or more roots and reported them as
    /// one (see [`crate::poly::solve::unseparated_count`]). Not rays, so not
    /// in [`RayStats::total`]; zero unless roots lie closer together than
    /// the solver's tolerance, as on high-degree surfaces with clustered
    /// roots.
    pub unseparated: u64,
}

impl RayStats {
    pub fn total(&self) -> u64 {
        self.camera + self.shadow + self.reflection + self.refraction + self.diffuse + self.photon
    }
}

impl std::ops::AddAssign for RayStats {
    fn add_assign(&mut self, o: RayStats) {
        self.camera += o.camera;
        self.shadow += o.shadow;
        self.reflection += o.reflection;
        self.refraction += o.refraction;
        self.diffuse += o.diffuse;
        self.photon += o.photon;
        self.unseparated += o.unseparated;
        for (a, b) in self.by_depth.iter_mut().zip(o.by_depth) {
            *a += b;
        }
    }
}

/// The kinds of ray in the tree.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum RayKind {
    Camera,
    Shadow,
    Reflection,
    Refraction,
    /// A diffuse or glossy bounce of a path (global illumination).
    Diffuse,
    /// A photon's flight from a light or a specular bounce (the caustic pass).
    Photon,
}

/// One node of a sample's ray tree, for `explain`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Node {
    pub depth: u32,
    pub kind: RayKind,
    /// What the ray hit: "mesh NAME triangle P", "shape I (KIND)", "background",
    /// or for shadow rays "light I: blocked" / "light I: visible".
    pub hit: String,
    pub t: f32,
    pub material: Option<String>,
    /// The branch's weight: what its radiance is multiplied by on its way to the pixel.
    pub weight: [f32; 3],
    /// The radiance the ray brings back (for shadow rays: the light's contribution).
    pub radiance: [f32; 3],
}

impl Node {
    /// The node of a ray that ended at `hit` (a miss: the background, or the
    /// environment light).
    pub fn of_hit(scene: &Scene, hit: &Hit, kind: RayKind, depth: u32, weight: Vec3) -> Node {
        let (what, material) = if hit.is_hit() {
            let (meshes, shapes, _) = scene.hit_geometry(hit);
            let what = match meshes.get(hit.geom_id as usize) {
                Some(mesh) => format!("mesh {:?} triangle {}", mesh.name, hit.prim_id),
                None => {
                    let shape = &shapes[hit.prim_id as usize];
                    format!("shape {} ({})", hit.prim_id, shape.describe())
                }
            };
            let what = match scene.instances.get(hit.inst_id as usize) {
                Some(_) => format!("instance {}: {what}", hit.inst_id),
                None => what,
            };
            (what, Some(scene.material_of(hit)))
        } else {
            let what = if scene.environment.is_some() {
                "environment"
            } else {
                "background"
            };
            (what.to_string(), None)
        };
        Node {
            depth,
            kind,
            hit: what,
            t: hit.t,
            material: material.map(|m| scene.materials[m as usize].name.clone()),
            weight: weight.to_array(),
            radiance: [0.0; 3],
        }
    }
}

/// Counts, and the tree when one is being recorded. Made and finished
/// ([`Tally::totals`]) on one thread: the solver's unseparated queries are
/// a per-thread count, read at both ends.
pub struct Tally {
    pub stats: RayStats,
    pub tree: Option<Vec<Node>>,
    /// The thread's unseparated count when the tally was made.
    pub(super) unseparated_before: u64,
}

impl Default for Tally {
    fn default() -> Self {
        Tally {
            stats: RayStats::default(),
            tree: None,
            unseparated_before: unseparated_count(),
        }
    }
}

impl Tally {
    /// The counts, with the solver's unseparated queries since the tally
    /// was made.
    pub fn totals(&self) -> RayStats {
        RayStats {
            unseparated: unseparated_count() - self.unseparated_before,
            ..self.stats
        }
    }

    pub fn count(&mut self, kind: RayKind, depth: u32) {
        let s = &mut self.stats;
        match kind {
            RayKind::Camera => s.camera += 1,
            RayKind::Shadow => s.shadow += 1,
            RayKind::Reflection => s.reflection += 1,
            RayKind::Refraction => s.refraction += 1,
            RayKind::Diffuse => s.diffuse += 1,
            RayKind::Photon => s.photon += 1,
        }
        s.by_depth[(depth as usize).min(DEPTHS - 1)] += 1;
    }

    /// Records a node when a tree is being kept; returns its index for `finish`.
    pub fn open(&mut self, node: impl FnOnce() -> Node) -> Option<usize> {
        let tree = self.tree.as_mut()?;
        tree.push(node());
        Some(tree.len() - 1)
    }

    /// Where the next node will go: the start of a path for [`Tally::close_path`].
    pub fn mark(&self) -> usize {
        self.tree.as_ref().map_or(0, Vec::len)
    }

    /// Adds to a path node what its vertex contributes to the pixel (weighted
    /// by the path's throughput so far).
    pub fn add(&mut self, index: Option<usize>, contribution: Vec3) {
        if let (Some(tree), Some(i)) = (self.tree.as_mut(), index) {
            let r = &mut tree[i].radiance;
            *r = (Vec3::from(*r) + contribution).to_array();
        }
    }

    /// Turns the contributions [`Tally::add`] recorded on the path's nodes
    /// (from `start` on) into the radiance each ray brings back: what its own
    /// vertex and every later one contribute, divided by its own weight.
    pub fn close_path(&mut self, start: usize) {
        let Some(tree) = self.tree.as_mut() else {
            return;
        };
        let mut later = Vec3::ZERO;
        for node in tree[start..].iter_mut().rev() {
            later += Vec3::from(node.radiance);
            let weight = Vec3::from(node.weight);
            let brought = Vec3::select(weight.cmpgt(Vec3::ZERO), later / weight, Vec3::ZERO);
            node.radiance = brought.to_array();
        }
    }

    /// Fills in the radiance of a node opened before its children were traced.
    pub fn finish(&mut self, index: Option<usize>, radiance: Vec3) {
        if let (Some(tree), Some(i)) = (self.tree.as_mut(), index) {
            tree[i].radiance = radiance.to_array();
        }
    }
}
