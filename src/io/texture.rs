//! Texture images in: PNG, JPEG, TGA, BMP and Radiance HDR through the
//! `image` crate, OpenEXR through `exr`, decoded to linear RGBA f32.

use std::io::Read;
use std::path::Path;

use sha2::{Digest, Sha256};

use crate::error::{Error, Result};

/// The largest texture side, 32,768 texels: a corrupt header cannot ask for
/// more memory than a 32k × 32k image's.
const MAX_SIDE: u32 = 1 << 15;

/// A decoded image: rows from the top, RGBA per texel.
pub struct Decoded {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<[f32; 4]>,
    /// Whether the file holds light values (EXR, HDR): never sRGB-decoded.
    pub linear: bool,
    /// Whether the file has an alpha channel (else every alpha is 1): a
    /// cut-out map (`map_d`) reads it where there is one.
    pub alpha: bool,
    /// SHA-256 of the file, hex: what the scene hash records of it.
    pub sha256: String,
}

/// Reads the image at `path`; any failure is an error naming the file.
pub fn read(path: &Path) -> Result<Decoded> {
    let (file, len) = crate::io::input::open_regular(path)?;
    let mut bytes = Vec::with_capacity(len.min(1 << 30) as usize);
    file.take(len)
        .read_to_end(&mut bytes)
        .map_err(|e| Error::io(path, e))?;
    let sha256 = format!("{:x}", Sha256::digest(&bytes));
    let bad = |message: String| Error::Input(format!("{}: {message}", path.display()));
    let is_exr = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    let (width, height, texels, linear, alpha) = if is_exr {
        exr_rgba(&bytes).map_err(|e| bad(format!("not a readable OpenEXR image: {e}")))?
    } else {
        let mut reader = image::ImageReader::new(std::io::Cursor::new(&bytes))
            .with_guessed_format()
            .map_err(|e| bad(e.to_string()))?;
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(MAX_SIDE);
        limits.max_image_height = Some(MAX_SIDE);
        reader.limits(limits);
        let format = reader.format();
        let image = reader
            .decode()
            .map_err(|e| bad(format!("not a readable image: {e}")))?;
        let linear = matches!(format, Some(image::ImageFormat::Hdr));
        let alpha = image.color().has_alpha();
        let rgba = image.to_rgba32f();
        let (w, h) = rgba.dimensions();
        let texels = rgba.pixels().map(|p| p.0).collect();
        (w, h, texels, linear, alpha)
    };
    if width == 0 || height == 0 {
        return Err(bad("the image has no texels".into()));
    }
    Ok(Decoded {
        width,
        height,
        texels,
        linear,
        alpha,
        sha256,
    })
}

/// Width, height, texels, linear, has alpha.
type Rgba = (u32, u32, Vec<[f32; 4]>, bool, bool);

fn exr_rgba(bytes: &[u8]) -> std::result::Result<Rgba, String> {
    use exr::prelude::*;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |size, _| {
                let (w, h) = (size.width(), size.height());
                // Too large: nothing allocated, refused below.
                let fits = w <= MAX_SIDE as usize && h <= MAX_SIDE as usize;
                (w, vec![[0.0f32; 4]; if fits { w * h } else { 0 }])
            },
            |(w, texels): &mut (usize, Vec<[f32; 4]>), pos, (r, g, b, a): (f32, f32, f32, f32)| {
                if let Some(texel) = texels.get_mut(pos.y() * *w + pos.x()) {
                    *texel = [r, g, b, a];
                }
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(std::io::Cursor::new(bytes))
        .map_err(|e| e.to_string())?;
    let size = image.layer_data.size;
    let (w, h) = (size.width() as u32, size.height() as u32);
    if w > MAX_SIDE || h > MAX_SIDE || image.layer_data.channel_data.pixels.1.is_empty() {
        return Err(format!("{w}x{h} is larger than {MAX_SIDE} a side"));
    }
    let alpha = image.layer_data.channel_data.channels.3.is_some();
    Ok((w, h, image.layer_data.channel_data.pixels.1, true, alpha))
}
