//! A render as a command runs it: which part of the image (whole, `--tile
//! I/N` or `--crop`), resuming from a film state, stopping on an interrupt,
//! and the files it leaves: the EXR (with the region, samples, seed and scene
//! hash in its header), a PNG preview, and the film state beside them for
//! pieces and interrupted renders, which `--resume` and `merge` read.

use std::path::{Path, PathBuf};

use super::passes::{passes, target};
use super::{RenderOptions, RenderOutput, render_from};
use crate::accel::{Accel, Backend};
use crate::error::{Error, Result};
use crate::film::{Film, Region};
use crate::io::state::{StateFile, StateHeader, write_state};
use crate::io::{exr, png};
use crate::scene::{Adaptive, Scene};

/// Which part of the image a command renders.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    Whole,
    /// Band `index` of `count` horizontal bands of whole rows.
    Tile {
        index: usize,
        count: usize,
    },
    Crop(Region),
}

impl Part {
    /// The pixels of a width × height image this part holds.
    pub fn region(self, width: usize, height: usize) -> Result<Region> {
        match self {
            Part::Whole => Ok(Region::whole(width, height)),
            Part::Tile { index, count } => {
                if count == 0 || index >= count || count > height {
                    return Err(Error::Input(format!(
                        "--tile {index}/{count}: expected I/N with 0 <= I < N <= {height} (the image's rows)"
                    )));
                }
                Ok(Region {
                    x0: 0,
                    x1: width,
                    y0: index * height / count,
                    y1: (index + 1) * height / count,
                })
            }
            Part::Crop(r) => {
                if !r.fits(width, height) {
                    return Err(Error::Input(format!(
                        "--crop {},{},{},{}: expected x0 < x1 <= {width} and y0 < y1 <= {height}",
                        r.x0, r.y0, r.x1, r.y1
                    )));
                }
                Ok(r)
            }
        }
    }
}

/// The film state beside an output EXR: `out.exr` → `out.state`.
pub fn state_path(output: &Path) -> PathBuf {
    output.with_extension("state")
}

/// The PNG preview beside an output EXR: `out.exr` → `out.png`.
pub fn preview_path(output: &Path) -> PathBuf {
    output.with_extension("png")
}

/// A render as a command asks for it.
pub struct Job<'a> {
    pub scene: &'a Scene,
    pub accel: &'a Accel,
    /// The backend `accel` was built with, recorded in the film state.
    pub backend: Backend,
    pub part: Part,
    pub frame: u32,
    /// Continue from the film state beside `output`.
    pub resume: bool,
    /// The EXR to write.
    pub output: &'a Path,
}

/// A finished (or interrupted) render, not yet written.
pub struct Rendered<'a> {
    pub output: RenderOutput,
    header: StateHeader,
    /// Where its files go.
    path: &'a Path,
    /// Whether it needs a film state (pieces, resumed and interrupted renders).
    keep_state: bool,
}

/// What a render command wrote.
pub struct Written {
    pub output: RenderOutput,
    pub spp: u32,
    pub preview: PathBuf,
    /// The film state, when one was written (pieces and interrupted renders).
    pub state: Option<PathBuf>,
}

impl<'a> Job<'a> {
    /// Renders the job's part of the scene, resuming from the state beside
    /// the output when asked. `options.region` is filled in here.
    pub fn render(&self, mut options: RenderOptions) -> Result<Rendered<'a>> {
        let scene = self.scene;
        let (width, height) = (scene.camera.width as usize, scene.camera.height as usize);
        let region = self.part.region(width, height)?;
        let spp = options.spp.unwrap_or(scene.render.spp);
        let header = StateHeader {
            width,
            height,
            region,
            spp,
            target: target(spp, scene.render.adaptive.as_ref()),
            samples_done: 0,
            seed: scene.render.seed,
            scene_hash: scene.content_hash(),
            frame: self.frame,
            backend: self.backend.name().into(),
        };
        let resume = match self.resume {
            true => {
                let adaptive = scene.render.adaptive.as_ref();
                Some(resume_from(&state_path(self.output), &header, adaptive)?)
            }
            false => None,
        };
        options.region = Some(region);
        let out = render_from(scene, self.accel, &options, resume)?;
        Ok(Rendered {
            header: StateHeader {
                samples_done: out.samples_done,
                ..header
            },
            keep_state: self.part != Part::Whole || !out.complete || self.resume,
            output: out,
            path: self.output,
        })
    }
}

impl Rendered<'_> {
    /// Writes the EXR, its preview and, when needed, the film state.
    pub fn write(self) -> Result<Written> {
        let preview = write_image(self.path, &self.output.film, &self.header)?;
        let state = self.keep_state.then(|| state_path(self.path));
        if let Some(path) = &state {
            write_state(path, &self.header, &self.output.film)?;
        }
        Ok(Written {
            output: self.output,
            spp: self.header.spp,
            preview,
            state,
        })
    }
}

/// The film and samples of the state at `path`, which must be from the
/// render `header` describes (but for its samples); checked by its header
/// before its pixels are read.
fn resume_from(
    path: &Path,
    header: &StateHeader,
    adaptive: Option<&Adaptive>,
) -> Result<(Film, u32)> {
    let file = StateFile::open(path)?;
    let saved = &file.header;
    let expected = StateHeader {
        samples_done: saved.samples_done,
        ..header.clone()
    };
    if *saved != expected {
        return Err(Error::Input(format!(
            "--resume: {} is from another render (it holds {}; this render is {})",
            path.display(),
            describe(saved),
            describe(&expected)
        )));
    }
    // A render stops only where a pass ends (or, in the photon pass, before
    // the first): resuming from anywhere else would skip samples.
    let done = saved.samples_done;
    if done != 0
        && !passes(header.spp, adaptive, 0)
            .iter()
            .any(|r| r.end == done)
    {
        return Err(Error::Input(format!(
            "{}: damaged film state: samples_done {done} is not where a pass of this render ends",
            path.display()
        )));
    }
    Ok((file.read_film()?, done))
}

fn describe(h: &StateHeader) -> String {
    let r = h.region;
    format!(
        "{}x{} region [{}, {}) x [{}, {}), {} spp ({} at most), seed {}, frame {}, backend {}, scene {}",
        h.width,
        h.height,
        r.x0,
        r.x1,
        r.y0,
        r.y1,
        h.spp,
        h.target,
        h.seed,
        h.frame,
        h.backend,
        // Checked hexadecimal when read, so any length slices on a character.
        &h.scene_hash[..h.scene_hash.len().min(12)]
    )
}

/// Writes the EXR (data window = the region, display window = the whole image)
/// and its PNG preview; returns the preview's path.
pub fn write_image(output: &Path, film: &Film, header: &StateHeader) -> Result<PathBuf> {
    let layers = film.layers();
    let r = film.region;
    let image = exr::ImageLayers {
        width: r.width(),
        height: r.height(),
        origin: (r.x0, r.y0),
        display: (film.width, film.height),
        beauty: &layers.beauty,
        depth: &layers.depth,
        normal: &layers.normal,
        albedo: &layers.albedo,
    };
    let attributes = [
        ("sturmray.spp", header.spp.to_string()),
        ("sturmray.samples_done", header.samples_done.to_string()),
        ("sturmray.seed", header.seed.to_string()),
        ("sturmray.scene_hash", header.scene_hash.clone()),
        ("sturmray.frame", header.frame.to_string()),
        (
            "sturmray.region",
            format!("{},{},{},{}", r.x0, r.y0, r.x1, r.y1),
        ),
    ];
    exr::write_exr(output, &image, &attributes)?;
    let preview = preview_path(output);
    png::write_png_preview(&preview, r.width(), r.height(), &layers.beauty)?;
    Ok(preview)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_are_bands_that_cover_the_image() {
        let bands: Vec<Region> = (0..3)
            .map(|index| Part::Tile { index, count: 3 }.region(10, 7).unwrap())
            .collect();
        assert_eq!(bands[0].y0, 0);
        assert_eq!(bands[2].y1, 7);
        for pair in bands.windows(2) {
            assert_eq!(pair[0].y1, pair[1].y0);
        }
        assert!(
            bands
                .iter()
                .all(|b| b.x0 == 0 && b.x1 == 10 && b.area() > 0)
        );
        for bad in [
            Part::Tile { index: 3, count: 3 },
            Part::Tile { index: 0, count: 0 },
            Part::Tile { index: 0, count: 8 },
            Part::Crop(Region {
                x0: 2,
                y0: 0,
                x1: 2,
                y1: 1,
            }),
            Part::Crop(Region {
                x0: 0,
                y0: 0,
                x1: 11,
                y1: 1,
            }),
        ] {
            assert!(bad.region(10, 7).is_err(), "{bad:?}");
        }
    }
}
