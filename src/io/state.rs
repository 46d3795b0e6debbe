//! Film state files: the exact f64 pixel sums of a render or a piece of one,
//! with what they hold (region, samples, seed, scene hash, backend).
//! `--resume` continues from one, `--tile`/`--crop` write one beside the
//! partial EXR, and `merge` combines them, so a render assembled from pieces
//! is bit-identical to one rendered whole.
//!
//! Layout: the line `sturmray film state 2`, one line of JSON (the
//! [`StateHeader`]), then one 104-byte little-endian record per pixel of the
//! region, row by row: radiance 3×f64, weight f64, normal 3×f64, albedo
//! 3×f64, depth f32, samples u32, luminance Σy and Σy² 2×f64; last, the
//! SHA-256 of everything before it (32 bytes).
//!
//! A state is trusted with sums that go straight into images, so reading one
//! checks everything: the size against the header before anything is
//! allocated, every field's range, every pixel's sums and sample count, and
//! the checksum. SHA-256 is already used for the scene hash; it catches any
//! damage (a flipped bit, a torn copy, an edit), and at a few hundred MB/s
//! it costs less than the disk. Any fault is bad input naming the file (and
//! the pixel), never a wrong image.

use std::fs::File;
use std::io::{BufRead, BufReader, Read, Take, Write};
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::error::{Error, Result};
use crate::film::{Film, Pixel, Region};

/// The first line, with the format number that changes with the layout.
const MAGIC: &str = "sturmray film state 2\n";
/// What every format's first line starts with.
const FAMILY: &str = "sturmray film state ";
const RECORD: usize = 104;
const DIGEST: usize = 32;
/// Far more than any header sturmray writes (about 300 bytes); bounds what
/// is read before the header is understood.
const MAX_LINE: u64 = 4096;

/// What a film state holds besides its pixels.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StateHeader {
    /// The whole image's size.
    pub width: usize,
    pub height: usize,
    pub region: Region,
    /// The samples per pixel the render aims at.
    pub spp: u32,
    /// The samples per pixel a finished render has taken: `spp`, or with
    /// adaptive sampling its `max_spp` (pixels that converge take fewer).
    pub target: u32,
    /// Sample indices 0..samples_done have been taken (or, with adaptive
    /// sampling, decided on) for every pixel.
    pub samples_done: u32,
    pub seed: u64,
    /// `Scene::content_hash` of the scene rendered.
    pub scene_hash: String,
    /// The animation frame.
    pub frame: u32,
    /// The backend that traced it (`Backend::name`): backends agree only to
    /// rounding, so a render continued on another would not be the image
    /// either one renders.
    pub backend: String,
}

impl StateHeader {
    /// Whether the render this state holds is finished.
    pub fn complete(&self) -> bool {
        self.samples_done == self.target
    }

    /// What is wrong with the header's fields, if anything.
    fn fault(&self) -> Option<String> {
        let hex = self.scene_hash.len() == 64
            && self
                .scene_hash
                .bytes()
                .all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b));
        if !self.region.fits(self.width, self.height) {
            Some("its region is empty or outside the image".into())
        } else if self.spp == 0 || self.target < self.spp {
            Some(format!(
                "spp {} and target {}: expected 1 <= spp <= target",
                self.spp, self.target
            ))
        } else if self.samples_done > self.target {
            // 0 is a render stopped before its first pass (in the photon
            // pass): its pixels must then be empty, which each is checked for.
            Some(format!(
                "samples_done {}: expected at most the target, {}",
                self.samples_done, self.target
            ))
        } else if !hex {
            Some("scene_hash: expected 64 hexadecimal digits".into())
        } else {
            None
        }
    }

    /// What is wrong with a pixel of this state, if anything: its sums must
    /// be finite, and it must hold the samples the header says were taken.
    fn pixel_fault(&self, p: &Pixel) -> Option<String> {
        let sums = p
            .radiance
            .iter()
            .chain([&p.weight])
            .chain(&p.normal)
            .chain(&p.albedo)
            .chain(&p.luminance);
        let adaptive = self.target > self.spp;
        // An adaptive pixel takes every base sample, then may stop early.
        let fewest = if adaptive {
            self.spp.min(self.samples_done)
        } else {
            self.samples_done
        };
        // Each sample adds an f32 value times an f32 weight (or a square of
        // one): larger sums cannot come from samples, and bounding them
        // keeps `merge`'s additions finite.
        let most = f64::from(p.samples) * f64::from(f32::MAX).powi(2);
        if sums.clone().any(|v| !v.is_finite()) {
            Some("a sum is NaN or infinite".into())
        } else if sums.clone().any(|v| v.abs() > most) {
            Some("a sum is larger than its samples can add up to".into())
        } else if p.luminance[1] < 0.0 {
            Some("its sum of squares is negative".into())
        } else if p.depth.is_nan() || p.depth < 0.0 {
            Some(format!("depth {}: expected a number >= 0", p.depth))
        } else if p.samples < fewest || p.samples > self.samples_done {
            Some(format!(
                "{} samples where the state has taken {} per pixel",
                p.samples, self.samples_done
            ))
        } else if p.samples == 0 && *p != Pixel::default() {
            // Sums (bounded above by the samples) and a depth without
            // samples would be counted twice once resumed.
            Some("values without samples".into())
        } else {
            None
        }
    }
}

/// Writes the state atomically, with its checksum.
pub fn write_state(path: &Path, header: &StateHeader, film: &Film) -> Result<()> {
    let json = serde_json::to_string(header).map_err(|e| Error::Internal(e.to_string()))?;
    super::output::write_atomic(path, |w| {
        write_body(w, &json, film).map_err(|e| Error::io(path, e))
    })
}

fn write_body(w: &mut impl Write, json: &str, film: &Film) -> std::io::Result<()> {
    let mut sha = Sha256::new();
    let mut put = |bytes: &[u8]| {
        sha.update(bytes);
        w.write_all(bytes)
    };
    put(MAGIC.as_bytes())?;
    put(json.as_bytes())?;
    put(b"\n")?;
    for p in film.pixels.iter() {
        put(&encode(p))?;
    }
    let digest = sha.finalize();
    w.write_all(&digest)
}

fn encode(p: &Pixel) -> [u8; RECORD] {
    let mut record = [0u8; RECORD];
    let f64s = p
        .radiance
        .iter()
        .chain([&p.weight])
        .chain(&p.normal)
        .chain(&p.albedo);
    for (slot, v) in record.chunks_exact_mut(8).zip(f64s) {
        slot.copy_from_slice(&v.to_le_bytes());
    }
    record[80..84].copy_from_slice(&p.depth.to_le_bytes());
    record[84..88].copy_from_slice(&p.samples.to_le_bytes());
    record[88..96].copy_from_slice(&p.luminance[0].to_le_bytes());
    record[96..104].copy_from_slice(&p.luminance[1].to_le_bytes());
    record
}

fn decode(record: &[u8; RECORD]) -> Pixel {
    let f64_at = |at: usize| {
        let mut b = [0u8; 8];
        b.copy_from_slice(&record[at..at + 8]);
        f64::from_le_bytes(b)
    };
    let four = |at: usize| [record[at], record[at + 1], record[at + 2], record[at + 3]];
    Pixel {
        radiance: [f64_at(0), f64_at(8), f64_at(16)],
        weight: f64_at(24),
        normal: [f64_at(32), f64_at(40), f64_at(48)],
        albedo: [f64_at(56), f64_at(64), f64_at(72)],
        depth: f32::from_le_bytes(four(80)),
        samples: u32::from_le_bytes(four(84)),
        luminance: [f64_at(88), f64_at(96)],
    }
}

/// A film state whose header has been read and checked, its size too;
/// [`StateFile::read_film`] reads and checks the pixels. Split so that a
/// caller can refuse a state by its header before reading its pixels.
pub struct StateFile {
    path: PathBuf,
    pub header: StateHeader,
    reader: BufReader<Take<File>>,
    sha: Sha256,
}

impl StateFile {
    pub fn open(path: &Path) -> Result<StateFile> {
        let (file, len) = super::input::open_regular(path)?;
        let bad = |what: String| {
            Error::Input(format!(
                "{}: not a sturmray film state: {what}",
                path.display()
            ))
        };
        let mut reader = BufReader::new(file.take(len));
        let mut sha = Sha256::new();
        let magic = line(&mut reader, path)?;
        if magic != MAGIC.as_bytes() {
            let found = String::from_utf8_lossy(&magic);
            return Err(bad(match found.strip_prefix(FAMILY) {
                Some(format) => format!(
                    "format {}, from another version of sturmray; this one reads format {} \
                     (render the part again)",
                    format.trim_end(),
                    MAGIC[FAMILY.len()..].trim_end()
                ),
                None => format!("it does not start with `{}`", MAGIC.trim_end()),
            }));
        }
        sha.update(&magic);
        let text = line(&mut reader, path)?;
        sha.update(&text);
        let header: StateHeader =
            serde_json::from_slice(&text).map_err(|e| bad(format!("header: {e}")))?;
        if let Some(fault) = header.fault() {
            return Err(Error::Input(format!(
                "{}: damaged film state: {fault}",
                path.display()
            )));
        }
        let pixels = header.region.area() as u64 * RECORD as u64;
        let need = (magic.len() + text.len() + DIGEST) as u64 + pixels;
        if len != need {
            return Err(bad(format!(
                "{len} bytes where its header and region need {need}"
            )));
        }
        Ok(StateFile {
            path: path.to_owned(),
            header,
            reader,
            sha,
        })
    }

    /// The pixels, each checked against the header as it is read (so a
    /// damaged file costs no more memory than its good part), then the
    /// checksum of the whole file.
    pub fn read_film(mut self) -> Result<Film> {
        let h = &self.header;
        let r = h.region;
        let io = |e| Error::io(&self.path, e);
        let mut pixels = Vec::with_capacity(r.area().min(1 << 16));
        let mut record = [0u8; RECORD];
        for i in 0..r.area() {
            self.reader.read_exact(&mut record).map_err(io)?;
            self.sha.update(record);
            let pixel = decode(&record);
            if let Some(fault) = h.pixel_fault(&pixel) {
                return Err(Error::Input(format!(
                    "{}: damaged film state: pixel ({}, {}): {fault}",
                    self.path.display(),
                    r.x0 + i % r.width(),
                    r.y0 + i / r.width()
                )));
            }
            pixels.push(pixel);
        }
        let mut digest = [0u8; DIGEST];
        self.reader.read_exact(&mut digest).map_err(io)?;
        if digest[..] != self.sha.finalize()[..] {
            return Err(Error::Input(format!(
                "{}: damaged film state: its checksum does not match its contents",
                self.path.display()
            )));
        }
        Ok(Film {
            width: h.width,
            height: h.height,
            region: r,
            pixels: pixels.into(),
        })
    }
}

/// A line of at most [`MAX_LINE`] bytes, with its newline.
fn line(reader: &mut BufReader<Take<File>>, path: &Path) -> Result<Vec<u8>> {
    let mut line = Vec::new();
    reader
        .by_ref()
        .take(MAX_LINE)
        .read_until(b'\n', &mut line)
        .map_err(|e| Error::io(path, e))?;
    if line.last() != Some(&b'\n') {
        return Err(Error::Input(format!(
            "{}: not a sturmray film state: no header line",
            path.display()
        )));
    }
    Ok(line)
}

/// Reads and checks a whole state written by [`write_state`].
pub fn read_state(path: &Path) -> Result<(StateHeader, Film)> {
    let file = StateFile::open(path)?;
    let header = file.header.clone();
    Ok((header, file.read_film()?))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::Sample;
    use crate::math::Vec3;

    const REGION: Region = Region {
        x0: 2,
        y0: 1,
        x1: 5,
        y1: 3,
    };

    fn header() -> StateHeader {
        StateHeader {
            width: 8,
            height: 4,
            region: REGION,
            spp: 16,
            target: 16,
            samples_done: 1,
            seed: 42,
            scene_hash: "ab".repeat(32),
            frame: 3,
            backend: "embree".into(),
        }
    }

    fn film() -> Film {
        let mut film = Film::of_region(8, 4, REGION);
        for (i, p) in film.pixels.iter_mut().enumerate() {
            p.add(&Sample {
                radiance: Vec3::new(0.1, 0.2, 0.3) * i as f32,
                weight: 0.7,
                depth: 1.0 / 3.0,
                normal: Vec3::Y,
                albedo: Vec3::splat(0.5),
            });
        }
        film
    }

    /// A path in a folder of its own that is removed when the test ends.
    fn temp(name: &str) -> (tempfile::TempDir, PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(name);
        (dir, path)
    }

    fn error(path: &Path) -> String {
        match read_state(path) {
            Err(e @ Error::Input(_)) => e.to_string(),
            other => panic!("expected bad input, got {:?}", other.map(|(h, _)| h)),
        }
    }

    #[test]
    fn a_state_reads_back_bit_for_bit() {
        let (header, film) = (header(), film());
        let (_dir, path) = temp("s.state");
        write_state(&path, &header, &film).unwrap();
        let (back, read) = read_state(&path).unwrap();
        assert_eq!(back, header);
        assert_eq!(read.pixels, film.pixels);
        assert_eq!((read.width, read.height, read.region), (8, 4, REGION));

        // A truncated file names the problem.
        let bytes = std::fs::read(&path).unwrap();
        std::fs::write(&path, &bytes[..bytes.len() - 1]).unwrap();
        assert!(error(&path).contains("bytes where its header"));
        std::fs::write(&path, b"hello").unwrap();
        assert!(error(&path).contains("not a sturmray film state"));
        std::fs::write(&path, b"sturmray film state 1\n{}\n").unwrap();
        let err = error(&path);
        assert!(
            err.contains("format 1") && err.contains("format 2"),
            "{err}"
        );
    }

    #[test]
    fn every_flipped_bit_is_refused() {
        let (_dir, path) = temp("flip.state");
        write_state(&path, &header(), &film()).unwrap();
        let good = std::fs::read(&path).unwrap();
        // A bit in the header, in each pixel field of a record, in the digest.
        let header_end = good.iter().position(|&b| b == b'}').unwrap();
        let data = good.len() - DIGEST - REGION.area() * RECORD;
        let mut offsets = vec![MAGIC.len() + 10, header_end - 3, good.len() - 1];
        offsets.extend((0..RECORD).step_by(4).map(|k| data + RECORD + k));
        for at in offsets {
            for bit in [0, 6] {
                let mut bytes = good.clone();
                bytes[at] ^= 1 << bit;
                std::fs::write(&path, &bytes).unwrap();
                let err = error(&path);
                assert!(err.contains("flip.state"), "byte {at}: {err}");
            }
        }
    }

    #[test]
    fn ranges_and_pixels_are_checked_even_under_a_valid_checksum() {
        let (_dir, path) = temp("range.state");
        let cases: Vec<(StateHeader, Film, &str)> = vec![
            (
                StateHeader {
                    samples_done: 17,
                    ..header()
                },
                film(),
                "samples_done 17",
            ),
            (
                StateHeader {
                    samples_done: 0,
                    ..header()
                },
                film(),
                "pixel (2, 1): 1 samples where the state has taken 0",
            ),
            (
                StateHeader {
                    samples_done: 0,
                    ..header()
                },
                {
                    let mut f = Film::of_region(8, 4, REGION);
                    // Sums are bounded by the samples; this is the rest.
                    f.pixel_mut(3, 2).depth = 1.0;
                    f
                },
                "pixel (3, 2): values without samples",
            ),
            (StateHeader { spp: 0, ..header() }, film(), "spp 0"),
            (
                StateHeader {
                    scene_hash: "é".repeat(32),
                    ..header()
                },
                film(),
                "scene_hash",
            ),
            (
                StateHeader {
                    samples_done: 2,
                    ..header()
                },
                film(),
                "pixel (2, 1): 1 samples",
            ),
            (
                header(),
                {
                    let mut f = film();
                    f.pixel_mut(4, 2).radiance[1] = f64::NAN;
                    f
                },
                "pixel (4, 2): a sum is NaN",
            ),
            (
                header(),
                {
                    let mut f = film();
                    f.pixel_mut(3, 1).samples = 0;
                    f
                },
                "pixel (3, 1)",
            ),
        ];
        for (h, f, needle) in cases {
            write_state(&path, &h, &f).unwrap();
            let err = error(&path);
            assert!(
                err.contains(needle) && err.contains("range.state"),
                "{needle}: {err}"
            );
        }
        // Stopped before the first pass: no samples, no sums.
        let empty = StateHeader {
            samples_done: 0,
            ..header()
        };
        write_state(&path, &empty, &Film::of_region(8, 4, REGION)).unwrap();
        read_state(&path).unwrap();
        // Adaptive: pixels hold spp to samples_done samples.
        let adaptive = StateHeader {
            spp: 1,
            target: 4,
            samples_done: 2,
            ..header()
        };
        let mut f = film();
        f.pixel_mut(2, 1).samples = 2;
        write_state(&path, &adaptive, &f).unwrap();
        read_state(&path).unwrap();
    }
}
