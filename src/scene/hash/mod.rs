//! A stable hash of what a scene renders: partial renders and film states
//! carry it, so `merge` and `--resume` refuse to mix pieces of different
//! scenes. SHA-256 over a canonical serialisation of the parsed scene: every
//! field that changes the image, as serde_json writes it (fields in
//! declaration order, floats in shortest round-trip form), streamed into the
//! hasher. Unlike `Debug` text, whose format Rust does not promise, that
//! serialisation only changes when the scene's types do.

use std::fmt::Write as _;
use std::io;

use sha2::{Digest, Sha256};

use super::Scene;

/// Feeds serialised bytes into the hash without building the text.
struct Feed(Sha256);

impl io::Write for Feed {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        self.0.update(bytes);
        Ok(bytes.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

impl Scene {
    /// The scene's hash as 64 hex digits. The sample count and the seed are not
    /// part of it: parts with more samples or another seed of the same scene
    /// combine. The light picker is left out: it is derived from the rest (and
    /// holds a hash map, whose order is not stable).
    pub fn content_hash(&self) -> String {
        let mut render = self.render.clone();
        render.spp = 0;
        render.seed = 0;
        render.adaptive = None;
        let parts = (
            &self.camera,
            &render,
            &self.background,
            &self.materials,
            &self.meshes,
            &self.shapes,
            &self.lights,
        );
        let mut feed = Feed(Sha256::new());
        // The parts are plain data (no maps, whose keys could fail to be
        // strings) and the hasher takes every byte, so this cannot fail.
        serde_json::to_writer(&mut feed, &parts).expect("a scene serialises");
        // Only scenes with instances hash them, so the hashes of all others
        // (and their golden values) stay as they were.
        if !self.instances.is_empty() {
            serde_json::to_writer(&mut feed, &(&self.prototypes, &self.instances))
                .expect("a scene serialises");
        }
        // Likewise the environment: its map by contents (SHA-256), scale,
        // rotation, or its constant radiance.
        if let Some(environment) = &self.environment {
            serde_json::to_writer(&mut feed, &("environment", &environment.source))
                .expect("a scene serialises");
        }
        // And the fogs, for scenes that have them, with the shapes whose
        // inside they fill (`hollow`), which changes nothing without one.
        if !self.fogs.is_empty() {
            let hollow: Vec<usize> = (0..self.shapes.len())
                .filter(|&i| self.shapes[i].hollow())
                .collect();
            serde_json::to_writer(&mut feed, &("fogs", &self.fogs, hollow))
                .expect("a scene serialises");
        }
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
mod tests;
