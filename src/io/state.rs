//! Film state files: the exact f64 pixel sums of a render or a piece of one,
//! with what they hold (region, samples, seed, scene hash). `--resume`
//! continues from one, `--tile`/`--crop` write one beside the partial EXR, and
//! `merge` combines them, so a render assembled from pieces is bit-identical
//! to one rendered whole.
//!
//! Layout: the line `sturmray film state 1`, one line of JSON (the
//! [`StateHeader`]), then one 104-byte little-endian record per pixel of the
//! region, row by row: radiance 3×f64, weight f64, normal 3×f64, albedo
//! 3×f64, depth f32, samples u32, luminance Σy and Σy² 2×f64.

use std::io::Write;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::film::{Film, Pixel, Region};

const MAGIC: &str = "sturmray film state 1\n";
const RECORD: usize = 104;

/// What a film state holds besides its pixels.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StateHeader {
    /// The whole image's size.
    pub width: usize,
    pub height: usize,
    pub region: Region,
    /// The samples per pixel the render aims at.
    pub spp: u32,
    /// Sample indices 0..samples_done have been taken for every pixel (with
    /// adaptive sampling, a pixel that stopped early took fewer).
    pub samples_done: u32,
    pub seed: u64,
    /// `Scene::content_hash` of the scene rendered.
    pub scene_hash: String,
    /// The animation frame.
    pub frame: u32,
}

/// Writes the state atomically (a temporary file renamed over the target),
/// so an interrupt while writing never leaves a torn state behind.
pub fn write_state(path: &Path, header: &StateHeader, film: &Film) -> Result<()> {
    let json = serde_json::to_string(header).map_err(|e| Error::Internal(e.to_string()))?;
    let mut bytes = Vec::with_capacity(MAGIC.len() + json.len() + 1 + film.pixels.len() * RECORD);
    bytes.extend_from_slice(MAGIC.as_bytes());
    bytes.extend_from_slice(json.as_bytes());
    bytes.push(b'\n');
    for p in &film.pixels {
        for v in p
            .radiance
            .iter()
            .chain([&p.weight])
            .chain(&p.normal)
            .chain(&p.albedo)
        {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
        bytes.extend_from_slice(&p.depth.to_le_bytes());
        bytes.extend_from_slice(&p.samples.to_le_bytes());
        for v in p.luminance {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    let temporary = path.with_extension("state.partial");
    let mut file = std::fs::File::create(&temporary).map_err(|e| Error::io(&temporary, e))?;
    file.write_all(&bytes)
        .and_then(|()| file.sync_all())
        .map_err(|e| Error::io(&temporary, e))?;
    std::fs::rename(&temporary, path).map_err(|e| Error::io(path, e))
}

/// Reads a state written by [`write_state`].
pub fn read_state(path: &Path) -> Result<(StateHeader, Film)> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let bad = |what: &str| {
        Error::Input(format!(
            "{}: not a sturmray film state: {what}",
            path.display()
        ))
    };
    let rest = bytes
        .strip_prefix(MAGIC.as_bytes())
        .ok_or_else(|| bad("it does not start with `sturmray film state 1`"))?;
    let end = rest
        .iter()
        .position(|&b| b == b'\n')
        .ok_or_else(|| bad("no header line"))?;
    let header: StateHeader =
        serde_json::from_slice(&rest[..end]).map_err(|e| bad(&format!("header: {e}")))?;
    let r = header.region;
    if !r.fits(header.width, header.height) {
        return Err(bad("its region is empty or outside the image"));
    }
    let records = &rest[end + 1..];
    if records.len() != r.area() * RECORD {
        return Err(bad(&format!(
            "{} bytes of pixels where its region needs {}",
            records.len(),
            r.area() * RECORD
        )));
    }
    let mut film = Film::of_region(header.width, header.height, r);
    for (p, record) in film.pixels.iter_mut().zip(records.chunks_exact(RECORD)) {
        let f64_at = |i: usize| f64::from_le_bytes(record[8 * i..8 * i + 8].try_into().unwrap());
        *p = Pixel {
            radiance: [f64_at(0), f64_at(1), f64_at(2)],
            weight: f64_at(3),
            normal: [f64_at(4), f64_at(5), f64_at(6)],
            albedo: [f64_at(7), f64_at(8), f64_at(9)],
            depth: f32::from_le_bytes(record[80..84].try_into().unwrap()),
            samples: u32::from_le_bytes(record[84..88].try_into().unwrap()),
            luminance: [
                f64::from_le_bytes(record[88..96].try_into().unwrap()),
                f64::from_le_bytes(record[96..104].try_into().unwrap()),
            ],
        };
    }
    Ok((header, film))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::Sample;
    use crate::math::Vec3;

    #[test]
    fn a_state_reads_back_bit_for_bit() {
        let region = Region {
            x0: 2,
            y0: 1,
            x1: 5,
            y1: 3,
        };
        let mut film = Film::of_region(8, 4, region);
        for (i, p) in film.pixels.iter_mut().enumerate() {
            p.add(&Sample {
                radiance: Vec3::new(0.1, 0.2, 0.3) * i as f32,
                weight: 0.7,
                depth: 1.0 / 3.0,
                normal: Vec3::Y,
                albedo: Vec3::splat(0.5),
            });
        }
        let header = StateHeader {
            width: 8,
            height: 4,
            region,
            spp: 16,
            samples_done: 1,
            seed: 42,
            scene_hash: "ab".repeat(32),
            frame: 3,
        };
        let dir = std::env::temp_dir().join(format!("sturmray-state-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("s.state");
        write_state(&path, &header, &film).unwrap();
        let (back, read) = read_state(&path).unwrap();
        assert_eq!(back, header);
        assert_eq!(read.pixels, film.pixels);
        assert_eq!((read.width, read.height, read.region), (8, 4, region));

        // A truncated file names the problem.
        let bytes = std::fs::read(&path).unwrap();
        std::fs::write(&path, &bytes[..bytes.len() - 1]).unwrap();
        let err = read_state(&path).unwrap_err().to_string();
        assert!(err.contains("bytes of pixels"), "{err}");
        std::fs::write(&path, b"hello").unwrap();
        let err = read_state(&path).unwrap_err().to_string();
        assert!(err.contains("not a sturmray film state"), "{err}");
    }
}
