//! Image textures: linear RGBA texels looked up by texture coordinates,
//! filtered bilinearly, wrapping (or clamped, MTL's `-clamp on`).

use std::path::PathBuf;
use std::sync::Arc;

use crate::math::{Vec2, Vec3};

/// A texture image in linear values, rows from the top as files store them.
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<[f32; 4]>,
    /// Whether the file has an alpha channel (`Decoded::alpha`).
    pub alpha: bool,
    /// Where it was read from and the file's SHA-256: the scene hash's
    /// record of it (its texels would be too many to hash each time).
    pub source: TextureSource,
}

#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct TextureSource {
    pub path: PathBuf,
    pub sha256: String,
    /// Whether the file's values were sRGB-decoded (a colour map).
    pub srgb: bool,
}

impl std::fmt::Debug for Image {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "Image({}x{}, {:?})",
            self.width, self.height, self.source
        )
    }
}

impl Image {
    /// The mean of the texels' colours: a wrapping map's mean over any
    /// whole number of periods.
    pub fn mean(&self) -> Vec3 {
        let sum = self.texels.iter().fold([0.0f64; 3], |mut sum, t| {
            for c in 0..3 {
                sum[c] += f64::from(t[c]);
            }
            sum
        });
        let count = self.texels.len().max(1) as f64;
        Vec3::new(
            (sum[0] / count) as f32,
            (sum[1] / count) as f32,
            (sum[2] / count) as f32,
        )
    }

    /// The texel at integer coordinates, wrapped or clamped into the image.
    fn texel(&self, x: i64, y: i64, clamp: bool) -> [f32; 4] {
        let (w, h) = (i64::from(self.width), i64::from(self.height));
        let (x, y) = if clamp {
            (x.clamp(0, w - 1), y.clamp(0, h - 1))
        } else {
            (x.rem_euclid(w), y.rem_euclid(h))
        };
        self.texels[(y * w + x) as usize]
    }
}

/// An image with MTL's placement options: uv is scaled by `scale`, then
/// moved by `offset` (`-s`, `-o`), and wraps unless `clamp`.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Texture {
    #[serde(serialize_with = "source_of")]
    pub image: Arc<Image>,
    pub scale: Vec2,
    pub offset: Vec2,
    pub clamp: bool,
}

fn source_of<S: serde::Serializer>(image: &Arc<Image>, s: S) -> Result<S::Ok, S::Error> {
    serde::Serialize::serialize(&image.source, s)
}

impl PartialEq for Texture {
    fn eq(&self, other: &Texture) -> bool {
        Arc::ptr_eq(&self.image, &other.image)
            && (self.scale, self.offset, self.clamp) == (other.scale, other.offset, other.clamp)
    }
}

impl Texture {
    pub fn new(image: Arc<Image>) -> Texture {
        Texture {
            image,
            scale: Vec2::ONE,
            offset: Vec2::ZERO,
            clamp: false,
        }
    }

    /// RGBA at `uv`, bilinear between the four nearest texel centres. v
    /// runs up the image (OBJ's convention), rows down it.
    pub fn rgba(&self, uv: Vec2) -> [f32; 4] {
        let image = &*self.image;
        let mut uv = uv * self.scale + self.offset;
        if self.clamp {
            uv = uv.clamp(Vec2::ZERO, Vec2::ONE);
        }
        if !uv.is_finite() {
            uv = Vec2::ZERO;
        }
        let x = f64::from(uv.x) * f64::from(image.width) - 0.5;
        let y = (1.0 - f64::from(uv.y)) * f64::from(image.height) - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = ((x - x0) as f32, (y - y0) as f32);
        // Beyond 2^53 the texel is arbitrary but in the image.
        let (x0, y0) = (x0 as i64, y0 as i64);
        let mut sum = [0.0f32; 4];
        for (dx, dy, w) in [
            (0, 0, (1.0 - fx) * (1.0 - fy)),
            (1, 0, fx * (1.0 - fy)),
            (0, 1, (1.0 - fx) * fy),
            (1, 1, fx * fy),
        ] {
            let t = image.texel(x0.wrapping_add(dx), y0.wrapping_add(dy), self.clamp);
            for c in 0..4 {
                sum[c] += w * t[c];
            }
        }
        sum
    }

    /// The colour at `uv`.
    pub fn rgb(&self, uv: Vec2) -> Vec3 {
        let [r, g, b, _] = self.rgba(uv);
        Vec3::new(r, g, b)
    }

    /// A scalar map's value at `uv` (a bump map's height): the luminance of
    /// its linear colour, MTL's default channel (`-imfchan l`) for scalar maps.
    pub fn scalar(&self, uv: Vec2) -> f32 {
        self.rgb(uv).dot(crate::math::LUMINANCE)
    }

    /// A cut-out map's opacity at `uv`: its alpha channel where the file has
    /// one (as Blender's importer links the image's alpha to the material's),
    /// else the luminance (a grey mask, as pbrt reads a float texture).
    pub fn opacity(&self, uv: Vec2) -> f32 {
        let [r, g, b, a] = self.rgba(uv);
        if self.image.alpha {
            a
        } else {
            Vec3::new(r, g, b).dot(crate::math::LUMINANCE)
        }
    }
}

/// sRGB's transfer function inverted: an 8-bit colour's stored value to light.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 2 × 2 texels: red, green on the top row; blue, white below.
    fn quad() -> Texture {
        Texture::new(Arc::new(Image {
            width: 2,
            height: 2,
            texels: vec![
                [1.0, 0.0, 0.0, 1.0],
                [0.0, 1.0, 0.0, 1.0],
                [0.0, 0.0, 1.0, 1.0],
                [1.0, 1.0, 1.0, 0.0],
            ],
            alpha: true,
            source: TextureSource {
                path: "q.png".into(),
                sha256: String::new(),
                srgb: false,
            },
        }))
    }

    #[test]
    fn texel_centres_give_their_texel_and_v_runs_up() {
        let t = quad();
        assert_eq!(t.rgb(Vec2::new(0.25, 0.75)), Vec3::X);
        assert_eq!(t.rgb(Vec2::new(0.75, 0.75)), Vec3::Y);
        assert_eq!(t.rgb(Vec2::new(0.25, 0.25)), Vec3::Z);
        assert_eq!(t.rgba(Vec2::new(0.75, 0.25))[3], 0.0);
    }

    #[test]
    fn bilinear_between_centres_and_wrapping_across_the_edge() {
        let t = quad();
        // Halfway between red and green.
        assert_eq!(t.rgb(Vec2::new(0.5, 0.75)), Vec3::new(0.5, 0.5, 0.0));
        // u = 0 lies halfway between the last column (green) and the first (red).
        assert_eq!(t.rgb(Vec2::new(0.0, 0.75)), Vec3::new(0.5, 0.5, 0.0));
        // A whole period further is the same place.
        assert_eq!(t.rgb(Vec2::new(3.25, -1.25)), Vec3::X);
        // Clamped, u = 0 is the first column alone.
        let clamped = Texture {
            clamp: true,
            ..quad()
        };
        assert_eq!(clamped.rgb(Vec2::new(-2.0, 0.75)), Vec3::X);
        // -s and -o: uv × 0.5 + (0.5, 0) puts (0.5, 1.5) at (0.75, 0.75): green.
        let placed = Texture {
            scale: Vec2::splat(0.5),
            offset: Vec2::new(0.5, 0.0),
            ..quad()
        };
        assert_eq!(placed.rgb(Vec2::new(0.5, 1.5)), Vec3::Y);
        assert_eq!(t.rgb(Vec2::splat(f32::NAN)), t.rgb(Vec2::ZERO));
    }

    #[test]
    fn opacity_is_the_alpha_channel_or_else_the_luminance() {
        let t = quad();
        // White with alpha 0: the alpha decides.
        assert_eq!(t.opacity(Vec2::new(0.75, 0.25)), 0.0);
        assert_eq!(t.opacity(Vec2::new(0.25, 0.75)), 1.0);
        let image = Image {
            alpha: false,
            texels: t.image.texels.clone(),
            source: t.image.source.clone(),
            ..*t.image
        };
        let grey = Texture::new(Arc::new(image));
        // Without an alpha channel: white is opaque, pure red its luminance.
        assert!((grey.opacity(Vec2::new(0.75, 0.25)) - 1.0).abs() < 1e-6);
        assert_eq!(grey.opacity(Vec2::new(0.25, 0.75)), 0.2126);
    }

    #[test]
    fn srgb_decoding_is_the_standard_curve() {
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_to_linear(0.5) - 0.214).abs() < 1e-3);
    }
}
