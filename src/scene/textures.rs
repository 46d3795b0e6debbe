//! The texture images of one scene: each file read once however many
//! materials use it, and a file that cannot be read is a warning (the
//! material keeps the map's neutral value: its plain colour, no cut-out),
//! never an error.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::math::Vec2;
use crate::shading::{Image, Texture, TextureSource, srgb_to_linear};

/// The images read so far, by file and colour space; `None` for a file
/// that failed (warned about once).
#[derive(Default)]
pub(crate) struct Textures {
    images: HashMap<(PathBuf, bool), Option<Arc<Image>>>,
}

/// A texture statement's placement, MTL's options: `-s u v`, `-o u v`,
/// `-clamp on`, and a bump map's multiplier `-bm`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Placement {
    pub scale: Vec2,
    pub offset: Vec2,
    pub clamp: bool,
    pub bump: f32,
}

impl Default for Placement {
    fn default() -> Self {
        Placement {
            scale: Vec2::ONE,
            offset: Vec2::ZERO,
            clamp: false,
            bump: 1.0,
        }
    }
}

impl Textures {
    /// The texture of the image at `path` with `placement`: sRGB-decoded if
    /// `srgb` (a colour map), linear otherwise, and always linear for a
    /// file of light values (EXR, HDR). `None`, with a warning in
    /// `warnings` naming `asked_by`, if the file cannot be read.
    pub fn texture(
        &mut self,
        path: &Path,
        srgb: bool,
        placement: &Placement,
        asked_by: &str,
        warnings: &mut Vec<String>,
    ) -> Option<Texture> {
        // A file that failed in the other colour space fails here too:
        // warned about once.
        if let Some(None) = self.images.get(&(path.to_owned(), !srgb)) {
            return None;
        }
        let key = (path.to_owned(), srgb);
        let image = self
            .images
            .entry(key)
            .or_insert_with(|| match crate::io::texture::read(path) {
                Ok(decoded) => Some(Arc::new(image(path, decoded, srgb))),
                Err(e) => {
                    warnings.push(format!(
                        "{asked_by}: texture {}: {e}; the map is left out (the material's \
                         plain colour, no cut-out)",
                        path.display()
                    ));
                    None
                }
            })
            .clone()?;
        Some(Texture {
            image,
            scale: placement.scale,
            offset: placement.offset,
            clamp: placement.clamp,
        })
    }
}

fn image(path: &Path, decoded: crate::io::texture::Decoded, srgb: bool) -> Image {
    let srgb = srgb && !decoded.linear;
    let mut texels = decoded.texels;
    if srgb {
        for t in &mut texels {
            for c in &mut t[..3] {
                *c = srgb_to_linear(*c);
            }
        }
    }
    Image {
        width: decoded.width,
        height: decoded.height,
        texels,
        alpha: decoded.alpha,
        source: TextureSource {
            path: path.to_owned(),
            sha256: decoded.sha256,
            srgb,
        },
    }
}

/// Splits an MTL texture statement's arguments into its placement and the
/// file name (the rest, which may hold spaces). Options sturmray does not
/// use are skipped with their arguments; a malformed number is the message.
pub(crate) fn statement(args: &str) -> Result<(Placement, String), String> {
    let words: Vec<&str> = args.split_whitespace().collect();
    let mut placement = Placement::default();
    let mut i = 0;
    // Up to `max` numbers after an option (MTL's -s and -o take u [v [w]]).
    let numbers = |i: &mut usize, max: usize| -> Vec<f32> {
        let mut found = Vec::new();
        while found.len() < max
            && let Some(v) = words.get(*i).and_then(|w| w.parse::<f32>().ok())
        {
            found.push(v);
            *i += 1;
        }
        found
    };
    while let Some(word) = words.get(i).filter(|w| w.starts_with('-')) {
        i += 1;
        match *word {
            "-s" | "-o" => {
                let v = numbers(&mut i, 3);
                if v.is_empty() || v.iter().any(|x| !x.is_finite()) {
                    return Err(format!("`{word}` expects 1 to 3 finite numbers"));
                }
                let uv = Vec2::new(
                    v[0],
                    v.get(1)
                        .copied()
                        .unwrap_or(if *word == "-s" { 1.0 } else { 0.0 }),
                );
                if *word == "-s" {
                    placement.scale = uv;
                } else {
                    placement.offset = uv;
                }
            }
            "-clamp" => {
                placement.clamp = match words.get(i) {
                    Some(&"on") => true,
                    Some(&"off") => false,
                    _ => return Err("`-clamp` expects on or off".into()),
                };
                i += 1;
            }
            "-blendu" | "-blendv" | "-cc" | "-imfchan" | "-type" => i += 1,
            "-bm" => match numbers(&mut i, 1).first() {
                Some(&v) if v.is_finite() => placement.bump = v,
                _ => return Err("`-bm` expects a finite number".into()),
            },
            "-boost" | "-texres" => drop(numbers(&mut i, 1)),
            "-mm" => drop(numbers(&mut i, 2)),
            "-t" => drop(numbers(&mut i, 3)),
            _ => return Err(format!("unknown texture option `{word}`")),
        }
    }
    let file = words[i.min(words.len())..].join(" ");
    if file.is_empty() {
        return Err("expected a file name".into());
    }
    Ok((placement, file))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statements_give_placement_and_file() {
        assert_eq!(
            statement("wood.png").unwrap(),
            (Placement::default(), "wood.png".into())
        );
        let (p, file) = statement("-s 2 3 1 -o 0.5 -clamp on -bm 0.3 my wood.png").unwrap();
        assert_eq!(file, "my wood.png");
        assert_eq!(
            p,
            Placement {
                scale: Vec2::new(2.0, 3.0),
                offset: Vec2::new(0.5, 0.0),
                clamp: true,
                bump: 0.3
            }
        );
        assert!(statement("-s x.png").unwrap_err().contains("`-s` expects"));
        assert!(statement("-clamp maybe x.png").is_err());
        assert!(statement("-bm x.png").unwrap_err().contains("`-bm`"));
        assert!(statement("-zz x.png").unwrap_err().contains("`-zz`"));
        assert!(statement("-s 1 1").unwrap_err().contains("file name"));
    }
}
