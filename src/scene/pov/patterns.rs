//! Colour-mapped pattern pigments: `gradient <v>`, `radial`, `onion`,
//! `spherical`, `cylindrical`, `boxed`, `planar`, `leopard`, `marble` and
//! `wood`, with `color_map` (entries `[v colour]` or the old `[a b c1 c2]`,
//! or a declared map), `frequency`, `phase`, the wave types and transforms.
//! What POV-Ray computes from its noise (`turbulence`, `warp`) is not
//! reproduced, nor a map whose entries vary in how much light they let
//! through (the renderer lets one fraction through a whole surface): such
//! a pigment is drawn as its colour map's mean colour, with a warning, as
//! every pattern was before these were read.

use glam::DAffine3;

use super::lex::Tok;
use super::parse::{Loc, Parser};
use super::texture::{Pigment, mean};
use super::value::Value;
use crate::error::Result;
use crate::shading::{PatternKind, Wave};

/// A colour map's entries, by value: red, green, blue, filter, transmit.
pub type ColourMap = Vec<(f64, [f64; 5])>;

/// A pattern pigment as read: the pattern, its wave and its colour map.
#[derive(Clone, Debug, PartialEq)]
pub struct MappedSpec {
    pub kind: PatternKind,
    pub wave: Wave,
    pub frequency: f64,
    pub phase: f64,
    pub map: ColourMap,
}

/// The pattern a keyword names, if it is one read here (`gradient` takes
/// its direction after the keyword).
fn kind_of(word: &str) -> Option<fn() -> PatternKind> {
    Some(match word {
        "radial" => || PatternKind::Radial,
        "onion" => || PatternKind::Onion,
        "spherical" => || PatternKind::Spherical,
        "cylindrical" => || PatternKind::Cylindrical,
        "boxed" => || PatternKind::Boxed,
        "planar" => || PatternKind::Planar,
        "leopard" => || PatternKind::Leopard,
        "marble" => || PatternKind::Marble,
        "wood" => || PatternKind::Wood,
        _ => return None,
    })
}

/// Whether `word` starts a pattern pigment read here.
pub fn is_mapped(word: &str) -> bool {
    word == "gradient" || kind_of(word).is_some()
}

/// POV-Ray's default wave of each pattern: marble and wood fold their
/// number back and forth, the others ramp.
fn default_wave(kind: PatternKind) -> Wave {
    match kind {
        PatternKind::Marble | PatternKind::Wood => Wave::Triangle,
        _ => Wave::Ramp,
    }
}

/// The mean of `map`'s colours: what stands for a pattern drawn as one colour.
pub fn map_mean(map: &ColourMap) -> [f64; 5] {
    mean(&map.iter().map(|e| e.1).collect::<Vec<_>>())
}

/// Whether some entry of `map` lets light through (filter or transmit).
pub fn see_through(map: &ColourMap) -> bool {
    map.iter().any(|e| e.1[3] + e.1[4] > 0.0)
}

/// POV-Ray's colour map for a pattern given none (rgb; filter and
/// transmit 0): black to white, and marble's, wood's and radial's own.
fn default_map(kind: PatternKind) -> ColourMap {
    let rgb = |r, g, b| [r, g, b, 0.0, 0.0];
    match kind {
        PatternKind::Marble => vec![
            (0.0, rgb(0.9, 0.8, 0.8)),
            (0.9, rgb(0.9, 0.08, 0.08)),
            (0.9, rgb(0.0, 0.0, 0.0)),
        ],
        PatternKind::Wood => vec![
            (0.6, rgb(0.666, 0.312, 0.2)),
            (0.6, rgb(0.4, 0.1333, 0.066)),
        ],
        PatternKind::Radial => vec![
            (0.0, rgb(0.0, 1.0, 1.0)),
            (0.333, rgb(1.0, 1.0, 0.0)),
            (0.666, rgb(1.0, 0.0, 1.0)),
            (1.0, rgb(0.0, 1.0, 1.0)),
        ],
        _ => vec![(0.0, rgb(0.0, 0.0, 0.0)), (1.0, rgb(1.0, 1.0, 1.0))],
    }
}

impl Parser {
    /// The rest of a pigment after the pattern keyword `word` (at `loc`),
    /// up to the pigment's `}` (left in the stream).
    pub(super) fn mapped_pigment(&mut self, loc: Loc, word: &str) -> Result<Pigment> {
        let kind = match kind_of(word) {
            Some(kind) => kind(),
            // POV-Ray normalises the direction as it reads it.
            None => PatternKind::Gradient(self.vector()?.normalize_or_zero()),
        };
        let mut spec = MappedSpec {
            kind,
            wave: default_wave(kind),
            frequency: 1.0,
            phase: 0.0,
            map: Vec::new(),
        };
        let mut to_owner = DAffine3::IDENTITY;
        // What this reader cannot draw as POV-Ray does, if anything, as the
        // warning names it.
        let mut unread: Option<String> = None;
        while unread.is_none() {
            let Some(w) = self.peek_word()? else {
                if self.peek()? != Some(Tok::Punct('}')) {
                    unread = Some("an item of this pigment".into());
                }
                break;
            };
            if let Some(t) = self.transform_item(&w)? {
                to_owner = t * to_owner;
                continue;
            }
            self.next()?;
            match w.as_str() {
                "color_map" | "colour_map" => spec.map = self.colour_map_block()?,
                "frequency" => spec.frequency = self.float()?,
                "phase" => spec.phase = self.float()?,
                "ramp_wave" => spec.wave = Wave::Ramp,
                "triangle_wave" => spec.wave = Wave::Triangle,
                "sine_wave" => spec.wave = Wave::Sine,
                "scallop_wave" => spec.wave = Wave::Scallop,
                "cubic_wave" => spec.wave = Wave::Cubic,
                "poly_wave" => {
                    let exponent = self.allow_float(1.0)?;
                    spec.wave = Wave::Poly(exponent);
                }
                // Without turbulence these change nothing.
                "octaves" | "omega" | "lambda" => {
                    self.float()?;
                }
                "turbulence" => {
                    if self.vector()? != glam::DVec3::ZERO {
                        unread = Some(format!("`{w}`"));
                    }
                }
                _ => unread = Some(format!("`{w}`")),
            }
        }
        // The renderer lets one fraction through a whole surface: a map
        // with clear entries is drawn as its mean, as before patterns were
        // read, not as a pattern whose clear parts would show opaque.
        if unread.is_none() && see_through(&spec.map) {
            unread = Some("filter or transmit in the colour map".into());
        }
        if unread.is_none() {
            if spec.map.is_empty() {
                spec.map = default_map(kind);
            }
            return Ok(Pigment::Mapped {
                spec: Box::new(spec),
                to_owner,
            });
        }
        // The rest of the block as before: the mean of every colour in it.
        let mut colours: Vec<[f64; 5]> = spec.map.iter().map(|e| e.1).collect();
        colours.extend(self.map_colours()?);
        let item = unread.unwrap_or_default();
        self.skip_warning(
            loc,
            word,
            &format!("{item} is not reproduced: the pattern is drawn as the mean colour of its colour map"),
        );
        Ok(Pigment::Colour(mean(&colours)))
    }

    /// A colour map's block after its keyword: `{ [v colour] … }`, the old
    /// form `[a b colour1 colour2]`, or a declared map's name. An entry
    /// whose colour is not one (a pattern) is left out with a warning.
    pub(super) fn colour_map_block(&mut self) -> Result<ColourMap> {
        self.expect('{')?;
        if let Some(w) = self.peek_word()?
            && let Some(Value::ColourMap(map)) = self.symbol(&w)
        {
            let map = map.clone();
            self.next()?;
            self.expect('}')?;
            return Ok(map);
        }
        let mut map = ColourMap::new();
        while !self.eat('}')? {
            self.expect('[')?;
            let first = self.float()?;
            // Commas between the parts are optional (`[0.0, 0.3 color …]`).
            self.eat(',')?;
            let second = if self.starts_number()? {
                Some(self.float()?)
            } else {
                None
            };
            self.eat(',')?;
            let loc = self.here();
            let Some(colour) = self.map_entry_colour()? else {
                let w = self.peek_word()?.unwrap_or_default();
                self.skip_warning(
                    loc,
                    &w,
                    "an entry that is not a colour is left out of the colour map",
                );
                self.skip_entry()?;
                continue;
            };
            map.push((first, colour));
            if let Some(second) = second {
                self.eat(',')?;
                let loc = self.here();
                match self.map_entry_colour()? {
                    Some(c) => map.push((second, c)),
                    None => return Err(self.error_at(loc, "expected the entry's second colour")),
                }
            }
            self.expect(']')?;
        }
        // In the order written, as POV-Ray looks them up.
        Ok(map)
    }

    /// A colour map entry's colour, or None if what follows is not one.
    fn map_entry_colour(&mut self) -> Result<Option<[f64; 5]>> {
        let loc = self.here();
        match self.peek()? {
            Some(Tok::Word(w)) if self.starts_colour(&w) => {
                let v = self.colour_rest(None)?;
                Ok(Some(self.as_colour(&v, loc)?))
            }
            Some(Tok::Punct('<')) => {
                let v = self.expression(false)?;
                Ok(Some(self.as_colour(&v, loc)?))
            }
            _ => Ok(None),
        }
    }
}
