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

/// A material's `map_Kd`: where it is asked for, its placement, and the
/// image file (relative to the library's folder).
#[derive(Clone, Debug)]
pub(crate) struct AlbedoMap {
    pub library: PathBuf,
    pub line: usize,
    pub placement: Placement,
    pub file: PathBuf,
}

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
        "newmtl" | "map_Ka" | "map_Kd" | "map_Ks" | "map_Bump" | "map_bump" | "map_Ns"
        | "map_ns" | "map_NS" | "bump" | "map_d" => Expect::Text,
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
/// with each material's `map_Kd` by name.
pub(super) fn load(path: &Path) -> Result<(Vec<tobj::Material>, HashMap<String, AlbedoMap>)> {
    let text = crate::io::input::read_text(path)?;
    let error = |line: usize, message: String| Error::Mesh {
        path: path.to_owned(),
        line,
        message,
    };
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut maps = HashMap::new();
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
        match keyword {
            "newmtl" => current = Some(args.join(" ")),
            "map_Kd" => {
                let (placement, file) = statement(&args.join(" "))
                    .map_err(|m| error(number + 1, format!("`map_Kd`: {m}")))?;
                if let Some(name) = &current {
                    let map = AlbedoMap {
                        library: path.to_owned(),
                        line: number + 1,
                        placement,
                        file: dir.join(file),
                    };
                    maps.insert(name.clone(), map);
                }
            }
            _ => {}
        }
    }
    let (materials, _) = tobj::load_mtl_buf(&mut text.as_bytes())
        .map_err(|e| error(0, format!("malformed material library: {e}")))?;
    Ok((materials, maps))
}
