//! MTL material libraries: checked line by line here, then parsed by tobj.
//!
//! tobj reports no line numbers, panics on a colour with fewer than three
//! numbers (`Kd 1 1`), and accepts values no material can have (NaN,
//! negative colours, an index of refraction <= 0). Every statement tobj
//! reads is checked first, so each of those names its line.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::scene::MAX_COLOUR;
use crate::scene::textures::{Placement, statement};
use crate::shading::{Bump, Material, MaterialKind, Metallic, Texture, metalness};

/// One of a material's texture statements: which map it is, where it is
/// asked for, its placement, and the image file (relative to the library's
/// folder).
#[derive(Clone, Debug)]
pub(crate) struct TextureMap {
    pub slot: MapSlot,
    pub library: PathBuf,
    pub line: usize,
    pub placement: Placement,
    pub file: PathBuf,
    /// The constant a metalness map scales (the material's Pm); 1 for
    /// other maps.
    pub factor: f32,
}

/// Which of a material's parameters a texture statement maps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum MapSlot {
    /// `map_Kd`.
    Albedo,
    /// `map_d`: the cut-out mask.
    Alpha,
    /// `bump`, `map_Bump`: a height map, with `-bm`.
    Bump,
    /// `norm`: a tangent-space normal map.
    Normal,
    /// `map_Ks`: the specular colour's factor.
    Specular,
    /// `map_Pr`: a metal's roughness factor.
    Roughness,
    /// `map_Pm`: a metal's metalness factor.
    Metallic,
    /// `map_Ke`: the emission's factor.
    Emission,
}

impl MapSlot {
    fn of(keyword: &str) -> Option<MapSlot> {
        Some(match keyword {
            "map_Kd" => MapSlot::Albedo,
            "map_d" => MapSlot::Alpha,
            "bump" | "map_Bump" | "map_bump" => MapSlot::Bump,
            "norm" => MapSlot::Normal,
            "map_Ks" => MapSlot::Specular,
            "map_Pr" => MapSlot::Roughness,
            "map_Pm" => MapSlot::Metallic,
            "map_Ke" => MapSlot::Emission,
            _ => return None,
        })
    }

    /// Whether the map holds colours, sRGB-decoded; data maps (alpha,
    /// heights, normals, roughness, metalness) are read as stored.
    pub fn srgb(self) -> bool {
        matches!(
            self,
            MapSlot::Albedo | MapSlot::Specular | MapSlot::Emission
        )
    }

    /// Whether a material of `kind` has the parameter the map scales: Ks
    /// for plastic and mirror, roughness and metalness for metal, emission
    /// for emissive; the albedo, cut-out and normal maps for every kind.
    pub fn matters_for(self, kind: MaterialKind) -> bool {
        match self {
            MapSlot::Specular => matches!(kind, MaterialKind::Plastic | MaterialKind::Mirror),
            MapSlot::Roughness | MapSlot::Metallic => kind == MaterialKind::Metal,
            MapSlot::Emission => kind == MaterialKind::Emissive,
            MapSlot::Albedo | MapSlot::Alpha | MapSlot::Bump | MapSlot::Normal => true,
        }
    }
}

/// Puts a map's texture into the material's slot for it; `None` (a file
/// that could not be read, already warned about) leaves the slot's neutral
/// value: the plain colour, no cut-out. `bump` is a bump map's multiplier
/// (`-bm`), `factor` the constant a metalness map scales.
pub(crate) fn set_map(
    material: &mut Material,
    slot: MapSlot,
    texture: Option<Texture>,
    bump: f32,
    factor: f32,
) {
    match slot {
        MapSlot::Albedo => material.albedo_map = texture,
        MapSlot::Alpha => material.maps.alpha = texture,
        MapSlot::Bump => {
            material.maps.bump = texture.map(|heights| Bump {
                heights,
                scale: bump,
            });
        }
        MapSlot::Normal => material.maps.normal = texture,
        MapSlot::Specular => material.maps.specular = texture,
        MapSlot::Roughness => material.maps.roughness = texture,
        MapSlot::Metallic => {
            material.maps.metallic = texture.map(|texture| Metallic {
                map: texture,
                scale: factor,
            });
        }
        MapSlot::Emission => material.maps.emission = texture,
    }
}

/// Each material's texture statements, by material name.
pub(super) type MapsByName = HashMap<String, Vec<TextureMap>>;

/// The unread map statements of a library: line and keyword.
pub(super) type UnreadMaps = Vec<(usize, String)>;

/// Map statements sturmray does not read yet: each is a warning (its line
/// and keyword), so a material never renders differently without a word.
const UNREAD_MAPS: &[&str] = &[
    "map_Ka", "map_Ns", "map_ns", "map_NS", "map_Ps", "disp", "decal", "refl",
];

/// What the numbers of a statement must be.
enum Expect {
    /// Three finite numbers from 0 to [`MAX_COLOUR`] (a colour).
    Colour,
    /// One finite number >= 0.
    NonNegative,
    /// One finite number > 0.
    Positive,
    /// One number from 0 to 1.
    Fraction,
    /// An illumination model, 0 to 10 (tobj reads it as a u8).
    Model,
    /// Anything after the keyword: a name or a texture file.
    Text,
}

fn expectation(keyword: &str) -> Option<Expect> {
    Some(match keyword {
        "Ka" | "Kd" | "Ks" | "Ke" => Expect::Colour,
        "Ns" => Expect::NonNegative,
        "Ni" => Expect::Positive,
        "d" | "Pr" | "Pm" => Expect::Fraction,
        "illum" => Expect::Model,
        "newmtl" | "map_Ka" | "map_Kd" | "map_Ks" | "map_Ke" | "map_Pr" | "map_Pm" | "map_Bump"
        | "map_bump" | "map_Ns" | "map_ns" | "map_NS" | "bump" | "map_d" | "norm" => Expect::Text,
        _ => return None,
    })
}

/// Why one statement's arguments are refused, if they are.
fn problem(keyword: &str, args: &[&str], expect: &Expect) -> Option<String> {
    let numbers = |n: usize| -> Result<Vec<f32>, String> {
        let found: Vec<f32> = args.iter().map_while(|w| w.parse().ok()).collect();
        if found.len() < n {
            return Err(format!(
                "`{keyword}` expects {n} number{}, found `{}`",
                if n == 1 { "" } else { "s" },
                args.join(" ")
            ));
        }
        Ok(found[..n].to_vec())
    };
    let check = |n: usize, ok: fn(f32) -> bool, what: &str| match numbers(n) {
        Err(message) => Some(message),
        Ok(v) if v.iter().all(|&x| x.is_finite() && ok(x)) => None,
        Ok(v) => Some(format!("`{keyword}` expects {what}, found {v:?}")),
    };
    match expect {
        Expect::Colour => check(
            3,
            |x| (0.0..=MAX_COLOUR).contains(&x),
            &format!("finite numbers >= 0 and at most {MAX_COLOUR:e}"),
        ),
        Expect::NonNegative => check(1, |x| x >= 0.0, "a finite number >= 0"),
        Expect::Positive => check(1, |x| x > 0.0, "a finite number > 0"),
        Expect::Fraction => check(1, |x| (0.0..=1.0).contains(&x), "a number from 0 to 1"),
        Expect::Model => match args.first().map(|w| w.parse::<u8>()) {
            Some(Ok(0..=10)) => None,
            _ => Some(format!(
                "`illum` expects a model number from 0 to 10, found `{}`",
                args.join(" ")
            )),
        },
        Expect::Text => args
            .is_empty()
            .then(|| format!("`{keyword}` expects a name after it")),
    }
}

/// Reads the materials of an MTL file, refusing bad statements by line,
/// with each material's texture statements by name (a later statement for
/// the same map replaces an earlier one).
pub(super) fn load(path: &Path) -> Result<(Vec<tobj::Material>, MapsByName, UnreadMaps)> {
    let text = crate::io::input::read_text(path)?;
    let error = |line: usize, message: String| Error::Mesh {
        path: path.to_owned(),
        line,
        message,
    };
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut maps = HashMap::new();
    let mut unread = Vec::new();
    let mut current = None;
    for (number, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        let args: Vec<&str> = words.take_while(|w| !w.starts_with('#')).collect();
        if let Some(expect) = expectation(keyword)
            && let Some(message) = problem(keyword, &args, &expect)
        {
            return Err(error(number + 1, message));
        }
        if keyword == "newmtl" {
            current = Some(args.join(" "));
        } else if UNREAD_MAPS.contains(&keyword) {
            unread.push((number + 1, keyword.to_owned()));
        } else if let Some(slot) = MapSlot::of(keyword) {
            let (placement, file) = statement(&args.join(" "))
                .map_err(|m| error(number + 1, format!("`{keyword}`: {m}")))?;
            if let Some(name) = &current {
                let map = TextureMap {
                    slot,
                    library: path.to_owned(),
                    line: number + 1,
                    placement,
                    file: dir.join(file),
                    factor: 1.0,
                };
                let list: &mut Vec<TextureMap> = maps.entry(name.clone()).or_default();
                list.retain(|m| m.slot != slot);
                list.push(map);
            }
        }
    }
    let (materials, _) = tobj::load_mtl_buf(&mut text.as_bytes())
        .map_err(|e| error(0, format!("malformed material library: {e}")))?;
    for m in &materials {
        let list = maps.get_mut(&m.name).into_iter().flatten();
        for map in list.filter(|map| map.slot == MapSlot::Metallic) {
            map.factor = metalness(m);
        }
    }
    Ok((materials, maps, unread))
}
