//! Ray counts by kind, per render.

use serde::Serialize;

/// Rays traced, by kind. Kinds the renderer does not spawn yet stay zero,
/// which the tests and `--stats` report as such.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct RayStats {
    pub camera: u64,
    pub shadow: u64,
    pub reflection: u64,
    pub refraction: u64,
    pub diffuse: u64,
    pub photon: u64,
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
    }
}
