//! 8-bit sRGB PNG previews of the beauty image.

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use png::{BitDepth, ColorType, Encoder, EncodingError, ScaledFloat, SrgbRenderingIntent};

use crate::error::{Error, Result};

/// Writes `beauty` (linear RGB, row-major, row 0 at the top) as an 8-bit
/// sRGB PNG. Values are clamped to [0, 1] and NaN becomes 0: a preview shows
/// the image, it does not tone-map it.
pub fn write_png_preview(
    path: &Path,
    width: usize,
    height: usize,
    beauty: &[[f32; 3]],
) -> Result<()> {
    let bad = |msg: String| Error::Input(format!("PNG {}: {msg}", path.display()));
    let (w, h) = match (u32::try_from(width), u32::try_from(height)) {
        (Ok(w), Ok(h)) if w > 0 && h > 0 => (w, h),
        _ => return Err(bad(format!("image size {width}x{height} cannot be stored"))),
    };
    let n = width
        .checked_mul(height)
        .ok_or_else(|| bad(format!("image size {width}x{height} is too large")))?;
    if beauty.len() != n {
        return Err(bad(format!(
            "the image has {} pixels, expected {n} ({width} x {height})",
            beauty.len()
        )));
    }
    let data: Vec<u8> = beauty
        .iter()
        .flatten()
        .map(|&c| linear_to_srgb8(c))
        .collect();

    let png_err = |e: EncodingError| match e {
        EncodingError::IoError(e) => Error::io(path, e),
        other => Error::Internal(format!("PNG {}: {other}", path.display())),
    };
    super::output::write_atomic(path, |file| encode(file, w, h, &data).map_err(png_err))
}

/// Encodes 8-bit sRGB pixels as a PNG into `file`.
fn encode(
    file: &mut BufWriter<File>,
    w: u32,
    h: u32,
    data: &[u8],
) -> std::result::Result<(), EncodingError> {
    let mut encoder = Encoder::new(file, w, h);
    encoder.set_color(ColorType::Rgb);
    encoder.set_depth(BitDepth::Eight);
    encoder.set_source_srgb(SrgbRenderingIntent::Perceptual);
    // The PNG spec recommends gAMA and cHRM beside sRGB for readers that
    // do not know sRGB; the encoder writes them only when they carry
    // exactly the sRGB values, which these are (PNG spec 11.3.3.5).
    encoder.set_source_gamma(ScaledFloat::from_scaled(45455));
    encoder.set_source_chromaticities(png::SourceChromaticities {
        white: (
            ScaledFloat::from_scaled(31270),
            ScaledFloat::from_scaled(32900),
        ),
        red: (
            ScaledFloat::from_scaled(64000),
            ScaledFloat::from_scaled(33000),
        ),
        green: (
            ScaledFloat::from_scaled(30000),
            ScaledFloat::from_scaled(60000),
        ),
        blue: (
            ScaledFloat::from_scaled(15000),
            ScaledFloat::from_scaled(6000),
        ),
    });
    let mut writer = encoder.write_header()?;
    writer.write_image_data(data)?;
    // finish() writes IEND and flushes; dropping the writer would hide its errors.
    writer.finish()
}

/// The sRGB transfer function (IEC 61966-2-1), quantised to 8 bits with
/// rounding to nearest.
fn linear_to_srgb8(c: f32) -> u8 {
    // NaN fails both comparisons in clamp's sense, so map it first.
    let c = if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) };
    let s = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    // s is in [0, 1], so the product is in [0.5, 255.5] and the cast exact.
    (s * 255.0 + 0.5) as u8
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn temp(name: &str) -> PathBuf {
        std::env::temp_dir().join(format!("sturmray-png-{}-{name}.png", std::process::id()))
    }

    #[test]
    fn transfer_curve_known_values() {
        assert_eq!(linear_to_srgb8(0.0), 0);
        assert_eq!(linear_to_srgb8(1.0), 255);
        assert_eq!(linear_to_srgb8(0.5), 188);
        // 0.18 (middle grey) is 118 in every sRGB table.
        assert_eq!(linear_to_srgb8(0.18), 118);
        // The linear segment: 0.002 * 12.92 * 255 = 6.59.
        assert_eq!(linear_to_srgb8(0.002), 7);
        assert_eq!(linear_to_srgb8(f32::NAN), 0);
        assert_eq!(linear_to_srgb8(-3.0), 0);
        assert_eq!(linear_to_srgb8(f32::NEG_INFINITY), 0);
        assert_eq!(linear_to_srgb8(7.0), 255);
        assert_eq!(linear_to_srgb8(f32::INFINITY), 255);
        // Monotone over the whole range.
        let mut last = 0;
        for i in 0..=10_000 {
            let v = linear_to_srgb8(i as f32 / 10_000.0);
            assert!(v >= last);
            last = v;
        }
    }

    #[test]
    fn decoded_file_has_srgb_chunk_and_encoded_values() {
        let (w, h) = (3, 2);
        // Row 0 at the top: the first row of the file.
        let beauty = [
            [0.0, 0.5, 1.0],
            [f32::NAN, 2.0, -1.0],
            [0.5, 0.5, 0.5],
            [1.0, 1.0, 1.0],
            [0.0, 0.0, 0.0],
            [0.18, 0.5, 0.0],
        ];
        let path = temp("decode");
        write_png_preview(&path, w, h, &beauty).unwrap();
        let file = File::open(&path).unwrap();
        let mut reader = png::Decoder::new(std::io::BufReader::new(file))
            .read_info()
            .unwrap();
        let info = reader.info();
        assert_eq!((info.width, info.height), (3, 2));
        assert_eq!(info.color_type, ColorType::Rgb);
        assert_eq!(info.bit_depth, BitDepth::Eight);
        assert_eq!(info.srgb, Some(SrgbRenderingIntent::Perceptual));
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let frame = reader.next_frame(&mut buf).unwrap();
        std::fs::remove_file(&path).unwrap();
        assert_eq!(
            &buf[..frame.buffer_size()],
            &[
                0, 188, 255, 0, 255, 0, 188, 188, 188, //
                255, 255, 255, 0, 0, 0, 118, 188, 0,
            ]
        );
    }

    #[test]
    fn rejects_wrong_sizes() {
        let path = temp("bad");
        for (w, h, n) in [(2, 2, 3), (0, 4, 0), (usize::MAX, 1, 0)] {
            let beauty = vec![[0.0; 3]; n];
            match write_png_preview(&path, w, h, &beauty) {
                Err(Error::Input(msg)) => assert!(msg.contains("sturmray-png-"), "{msg}"),
                other => panic!("{w}x{h}: expected Error::Input, got {other:?}"),
            }
        }
        assert!(!path.exists());
    }
}
