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
        // TGA has no signature to guess from: its extension names it, as
        // `image::open` reads it.
        if reader.format().is_none()
            && let Ok(format) = image::ImageFormat::from_path(path)
        {
            reader.set_format(format);
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// An uncompressed 24-bit TGA, bottom row first, BGR: `pixels` rows
    /// from the bottom.
    fn tga(width: u16, height: u16, pixels: &[[u8; 3]]) -> Vec<u8> {
        let mut bytes = vec![0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0];
        bytes.extend_from_slice(&width.to_le_bytes());
        bytes.extend_from_slice(&height.to_le_bytes());
        bytes.extend_from_slice(&[24, 0]);
        for [b, g, r] in pixels {
            bytes.extend_from_slice(&[*b, *g, *r]);
        }
        bytes
    }

    #[test]
    fn a_tga_is_read_by_its_extension_and_a_bad_one_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.tga");
        // Bottom row blue then red; top row white then black (BGR order).
        let pixels = [[255, 0, 0], [0, 0, 255], [255, 255, 255], [0, 0, 0]];
        std::fs::write(&path, tga(2, 2, &pixels)).unwrap();
        let image = read(&path).unwrap();
        assert_eq!((image.width, image.height, image.linear), (2, 2, false));
        // Rows from the top: white, black; then blue, red.
        assert_eq!(image.texels[0], [1.0; 4]);
        assert_eq!(image.texels[2], [0.0, 0.0, 1.0, 1.0]);
        assert_eq!(image.texels[3], [1.0, 0.0, 0.0, 1.0]);
        // A header of no texels, and one of 65,535 a side: refused, named.
        for (name, side) in [("empty.tga", 0), ("huge.tga", u16::MAX)] {
            let path = dir.path().join(name);
            std::fs::write(&path, tga(side, side, &[])).unwrap();
            let message = read(&path).err().unwrap().to_string();
            assert!(message.contains(name), "{message}");
        }
    }
}
