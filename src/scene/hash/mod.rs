//! A stable hash of what a scene renders: partial renders and film states
//! carry it, so `merge` and `--resume` refuse to mix pieces of different
//! scenes. SHA-256 over the scene's canonical text (the `Debug` form of every
//! field that changes the image, streamed into the hasher), so equal scenes
//! give equal hashes on every machine and Rust version that prints floats the
//! same (shortest round-trip form, which Rust guarantees).

use std::fmt::Write;

use sha2::{Digest, Sha256};

use super::Scene;

/// Feeds formatted text into the hash without building the string.
struct Feed(Sha256);

impl Write for Feed {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        self.0.update(s.as_bytes());
        Ok(())
    }
}

impl Scene {
    /// The scene's hash as 64 hex digits. The sample count and the seed are not
    /// part of it: parts with more samples or another seed of the same scene
    /// combine. The light picker is left out: it is derived from the rest (and
    /// holds a hash map, whose order is not stable).
    pub fn content_hash(&self) -> String {
        let mut feed = Feed(Sha256::new());
        let mut render = self.render.clone();
        render.spp = 0;
        render.seed = 0;
        render.adaptive = None;
        // Writing into the hasher cannot fail.
        let _ = write!(
            feed,
            "{:?}{:?}{:?}{:?}{:?}{:?}{:?}",
            self.camera,
            render,
            self.background,
            self.materials,
            self.meshes,
            self.shapes,
            self.lights
        );
        feed.0
            .finalize()
            .iter()
            .fold(String::with_capacity(64), |mut hex, byte| {
                let _ = write!(hex, "{byte:02x}");
                hex
            })
    }
}

#[cfg(test)]
mod tests {
    use crate::scene::Scene;

    fn load(text: &str) -> Scene {
        let dir = std::env::temp_dir().join(format!("sturmray-hash-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("s.toml");
        std::fs::write(&path, text).unwrap();
        Scene::load(&path).unwrap()
    }

    const SCENE: &str = "[render]\nspp = 4\n[[objects]]\ntype = \"sphere\"\nradius = 1\n";

    #[test]
    fn equal_scenes_hash_equal_and_changes_show() {
        let a = load(SCENE).content_hash();
        assert_eq!(a.len(), 64);
        assert_eq!(a, load(SCENE).content_hash());
        // More samples or another seed: the same scene.
        let more = SCENE.replace("spp = 4", "spp = 64\nseed = 3");
        assert_eq!(a, load(&more).content_hash());
        // A different radius, or depth: another scene.
        assert_ne!(
            a,
            load(&SCENE.replace("radius = 1", "radius = 2")).content_hash()
        );
        assert_ne!(
            a,
            load(&SCENE.replace("spp = 4", "spp = 4\nmax_depth = 2")).content_hash()
        );
    }
}
