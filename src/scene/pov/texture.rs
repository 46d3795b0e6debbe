//! Textures of POV-Ray's language: `pigment` (a colour, `checker`, and a
//! pattern's mean colour), `finish` (sturmray's classic finish, with
//! POV-Ray's defaults), `interior` (its ior), `#default`, and transforms.

use glam::{DAffine3, DVec3};

use super::lex::Tok;
use super::parse::{Loc, Parser};
use super::value::Value;
use crate::error::Result;
use crate::scene::solids::rotation;
use crate::shading::Finish;

/// POV-Ray's pigment, as far as the subset goes.
#[derive(Clone, Debug, PartialEq)]
pub enum Pigment {
    /// red, green, blue, filter, transmit.
    Colour([f64; 5]),
    /// Unit cubes of two colours alternating; the transform takes the
    /// pattern's space to the space of the texture's owner.
    Checker {
        colours: [[f64; 5]; 2],
        to_owner: DAffine3,
    },
    /// A colour-mapped pattern (see `patterns`); the transform as a
    /// checker's.
    Mapped {
        spec: Box<super::patterns::MappedSpec>,
        to_owner: DAffine3,
    },
}

impl Pigment {
    /// POV-Ray's default pigment: black.
    pub fn black() -> Pigment {
        Pigment::Colour([0.0; 5])
    }

    /// Applies a transform given after the pigment.
    pub fn transform(&mut self, t: DAffine3) {
        if let Pigment::Checker { to_owner, .. } | Pigment::Mapped { to_owner, .. } = self {
            *to_owner = t * *to_owner;
        }
    }

    /// One colour for the pigment where one must stand for it (a sky, an
    /// entry of a map): a pattern's mean colour.
    pub fn mean_colour(&self) -> [f64; 5] {
        match self {
            Pigment::Colour(c) => *c,
            Pigment::Checker { colours, .. } => mean(colours),
            Pigment::Mapped { spec, .. } => super::patterns::map_mean(&spec.map),
        }
    }
}

/// A texture: pigment and finish (normals are outside the subset).
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    pub pigment: Pigment,
    pub finish: Finish,
}

impl Texture {
    pub fn transform(&mut self, t: DAffine3) {
        self.pigment.transform(t);
    }
}

/// An object's `interior`: its index of refraction and how light fades
/// inside it (POV-Ray's defaults: ior 1, no fade).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interior {
    pub ior: f64,
    pub fade_distance: f64,
    pub fade_power: f64,
    pub fade_colour: [f64; 3],
}

impl Default for Interior {
    fn default() -> Interior {
        Interior {
            ior: 1.0,
            fade_distance: 0.0,
            fade_power: 0.0,
            fade_colour: [0.0; 3],
        }
    }
}

/// POV-Ray's default finish (ambient 0.1; sturmray's own classic default is
/// 0, see `Finish`).
pub fn pov_finish() -> Finish {
    Finish {
        ambient: 0.1,
        ..Finish::default()
    }
}

/// What `#default` set, which every new texture, pigment and finish starts from.
pub fn default_texture() -> Texture {
    Texture {
        pigment: Pigment::black(),
        finish: pov_finish(),
    }
}

/// A checker's colours where it gives none: POV-Ray's blue and green.
const CHECKER_COLOURS: [[f64; 5]; 2] = [[0.0, 0.0, 1.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0, 0.0]];

/// The name the reader keeps `#default`'s texture under (not a name a
/// scene can write: it starts with a space).
pub const DEFAULT: &str = " default";

impl Parser {
    /// A texture as `#default` left it (POV-Ray's own defaults before).
    pub(super) fn defaults(&self) -> Texture {
        match self.symbol(DEFAULT) {
            Some(Value::Texture(t)) => (**t).clone(),
            _ => default_texture(),
        }
    }

    /// `#default { texture {…} | pigment {…} | finish {…} }`.
    pub fn default_block(&mut self, _loc: Loc) -> Result<()> {
        self.expect('{')?;
        let mut t = self.defaults();
        while !self.eat('}')? {
            let loc = self.here();
            match self.word()?.as_str() {
                "texture" => t = self.texture_block()?,
                "pigment" => t.pigment = self.pigment_block()?,
                "finish" => t.finish = self.finish_block(None)?,
                other => {
                    self.skip_warning(loc, other, "not used as a default");
                    if self.peek()? == Some(Tok::Punct('{')) {
                        self.skip_block()?;
                    }
                }
            }
        }
        self.set(DEFAULT, Value::Texture(Box::new(t)));
        Ok(())
    }

    /// The colour of `sky_sphere { … }` (after the keyword): its last
    /// pigment's, or a declared sky's it starts from; None if it has
    /// neither.
    pub fn sky_sphere_block(&mut self) -> Result<Option<DVec3>> {
        self.expect('{')?;
        let mut sky = None;
        while !self.eat('}')? {
            let loc = self.here();
            let word = self.word()?;
            if let Some(Value::Sky(colour)) = self.symbol(&word) {
                sky = Some(*colour);
                continue;
            }
            match word.as_str() {
                "pigment" => {
                    let pigment = self.pigment_block()?;
                    if !matches!(pigment, Pigment::Colour(_)) {
                        self.warn(loc, "a patterned sky is drawn as its mean colour");
                    }
                    let c = pigment.mean_colour();
                    sky = Some(DVec3::new(c[0], c[1], c[2]));
                }
                w => {
                    if self.transform_item(w)?.is_none() {
                        self.unknown_item(loc, w, "sky_sphere")?;
                    }
                }
            }
        }
        Ok(sky)
    }

    /// The contents of `texture { … }` (after the keyword).
    pub fn texture_block(&mut self) -> Result<Texture> {
        self.expect('{')?;
        let mut t = self.defaults();
        if let Some(w) = self.peek_word()?
            && let Some(Value::Texture(base)) = self.symbol(&w)
        {
            t = (**base).clone();
            self.next()?;
        }
        while !self.eat('}')? {
            let loc = self.here();
            let word = self.word()?;
            match word.as_str() {
                "pigment" => t.pigment = self.pigment_block()?,
                "finish" => t.finish = self.finish_block(Some(t.finish))?,
                "normal" => {
                    self.skip_warning(loc, "normal", "the surface is drawn without its bumps");
                    self.skip_block()?;
                }
                "checker" => t = self.texture_checker(loc)?,
                w => {
                    if let Some(m) = self.transform_item(w)? {
                        t.transform(m);
                    } else {
                        self.unknown_item(loc, w, "texture")?;
                    }
                }
            }
        }
        Ok(t)
    }

    /// A checker of two textures, after `checker` in a texture: unit cubes
    /// taking one texture or the other. Two plain colours make a pigment
    /// checker with the first texture's finish (a warning if the second's
    /// differs); a texture with a patterned pigment stands for the whole
    /// with a warning.
    fn texture_checker(&mut self, loc: Loc) -> Result<Texture> {
        let mut parts = Vec::new();
        while parts.len() < 2 && self.eat_word("texture")? {
            parts.push(self.texture_block()?);
            self.eat(',')?;
        }
        let mut t = self.defaults();
        match &parts[..] {
            [] => {
                t.pigment = Pigment::Checker {
                    colours: CHECKER_COLOURS,
                    to_owner: DAffine3::IDENTITY,
                }
            }
            [
                Texture {
                    pigment: Pigment::Colour(a),
                    finish,
                },
                Texture {
                    pigment: Pigment::Colour(b),
                    finish: second,
                },
            ] => {
                if finish != second {
                    self.warn(
                        loc,
                        "a checker of textures takes its first texture's finish for both",
                    );
                }
                t = Texture {
                    pigment: Pigment::Checker {
                        colours: [*a, *b],
                        to_owner: DAffine3::IDENTITY,
                    },
                    finish: *finish,
                };
            }
            [first, ..] => {
                self.warn(
                    loc,
                    "a checker of patterned textures is drawn with its first texture",
                );
                t = first.clone();
            }
        }
        Ok(t)
    }

    /// The contents of `pigment { … }`.
    pub fn pigment_block(&mut self) -> Result<Pigment> {
        self.expect('{')?;
        let mut p = self.defaults().pigment;
        while !self.eat('}')? {
            let loc = self.here();
            let Some(word) = self.peek_word()? else {
                // A colour given as a vector expression, `pigment { <1, 0, 0> }`.
                let v = self.expression(false)?;
                p = Pigment::Colour(self.surface_colour(&v, loc)?);
                continue;
            };
            if let Some(Value::Pigment(base)) = self.symbol(&word) {
                p = base.clone();
                self.next()?;
                continue;
            }
            if let Some(m) = self.transform_item(&word)? {
                p.transform(m);
                continue;
            }
            match word.as_str() {
                "checker" => {
                    self.next()?;
                    let mut colours = CHECKER_COLOURS;
                    for c in &mut colours {
                        // A colour, a number or a vector; none (the block's
                        // end, a transform) keeps POV-Ray's default.
                        let given = match self.peek_word()? {
                            Some(w) => self.starts_colour(&w),
                            None => self.starts_number()? || self.peek()? == Some(Tok::Punct('<')),
                        };
                        if given {
                            let loc = self.here();
                            let v = self.colour_rest(None)?;
                            *c = self.as_colour(&v, loc)?;
                            self.eat(',')?;
                        }
                    }
                    p = Pigment::Checker {
                        colours,
                        to_owner: DAffine3::IDENTITY,
                    };
                }
                "quick_color" | "quick_colour" => {
                    self.next()?;
                    self.colour_rest(None)?;
                }
                w if self.starts_colour(w) => {
                    let v = self.colour_rest(None)?;
                    p = Pigment::Colour(self.surface_colour(&v, loc)?);
                }
                w if super::patterns::is_mapped(w) => {
                    self.next()?;
                    p = self.mapped_pigment(loc, &word)?;
                }
                // A map after a declared pattern pigment replaces its map
                // (woods.inc's `pigment { P_WoodGrain1A color_map { M_Wood1A } }`);
                // after a pigment drawn as one colour, its mean is that colour.
                "color_map" | "colour_map" => {
                    self.next()?;
                    let map = self.colour_map_block()?;
                    match &mut p {
                        Pigment::Mapped { spec, .. }
                            if !map.is_empty() && !super::patterns::see_through(&map) =>
                        {
                            spec.map = map
                        }
                        _ => p = Pigment::Colour(super::patterns::map_mean(&map)),
                    }
                }
                _ => {
                    self.next()?;
                    p = Pigment::Colour(self.pattern(loc, &word)?);
                }
            }
        }
        Ok(p)
    }

    /// A pigment's colour, with a warning where its filter and transmit
    /// lie outside what a surface can let through: POV-Ray weighs the
    /// surface by 1 - filter - transmit even below zero (a contrast trick,
    /// as in its `advanced/bwstripe.pov`), where the classic material
    /// keeps their sum in [0, 1] (see `Builder::material`).
    fn surface_colour(&mut self, v: &Value, loc: Loc) -> Result<[f64; 5]> {
        let c = self.as_colour(v, loc)?;
        let clear = c[3] + c[4];
        if c[3] < 0.0 || c[4] < 0.0 || clear > 1.0 {
            self.warn(
                loc,
                format!(
                    "filter {} and transmit {} are drawn as a surface that lets through {}",
                    c[3],
                    c[4],
                    clear.clamp(0.0, 1.0)
                ),
            );
        }
        Ok(c)
    }

    /// Whether the word `w` begins a colour.
    pub(super) fn starts_colour(&self, w: &str) -> bool {
        matches!(
            w,
            "color"
                | "colour"
                | "rgb"
                | "rgbf"
                | "rgbt"
                | "rgbft"
                | "srgb"
                | "srgbf"
                | "srgbt"
                | "srgbft"
                | "red"
                | "green"
                | "blue"
        ) || matches!(self.symbol(w), Some(Value::Vector(_) | Value::Float(_)))
    }

    /// A pattern pigment outside the subset (`granite`, `bozo`, …) up to the
    /// end of its pigment block: drawn as the mean of the colours of its
    /// colour map, with a warning.
    fn pattern(&mut self, loc: Loc, keyword: &str) -> Result<[f64; 5]> {
        let colours = self.map_colours()?;
        self.skip_warning(
            loc,
            keyword,
            if colours.is_empty() {
                "the pattern is drawn black (no colour map read)"
            } else {
                "the pattern is drawn as the mean colour of its colour map"
            },
        );
        Ok(mean(&colours))
    }

    /// The colours of a colour map (or of a whole pattern pigment): every
    /// colour in its `[ … ]` entries and every declared colour named, up to
    /// the `}` that closes the block (left in the stream).
    pub fn map_colours(&mut self) -> Result<Vec<[f64; 5]>> {
        let mut colours: Vec<[f64; 5]> = Vec::new();
        let mut depth = 0usize;
        loop {
            match self.peek()? {
                Some(Tok::Punct('}')) if depth == 0 => return Ok(colours),
                Some(Tok::Punct('{')) => {
                    depth += 1;
                    self.next()?;
                }
                Some(Tok::Punct('}')) => {
                    depth -= 1;
                    self.next()?;
                }
                Some(Tok::Punct('[')) => {
                    self.next()?;
                    while !self.eat(']')? {
                        let loc = self.here();
                        let w = self.peek_word()?;
                        let declared = w.as_deref().and_then(|w| self.symbol(w)).cloned();
                        if let Some(Value::Pigment(p)) = &declared {
                            // A declared pigment as an entry (a pigment_map's):
                            // its colour, a checker's mean.
                            colours.push(p.mean_colour());
                            self.next()?;
                        } else if let Some(name) = w.as_deref()
                            && self.starts_colour(name)
                            && !matches!(declared, Some(Value::Float(_)))
                        {
                            let v = self.colour_rest(None)?;
                            colours.push(self.as_colour(&v, loc)?);
                        } else if w.is_some()
                            && !self.starts_number()?
                            && !matches!(declared, Some(Value::Vector(_)))
                        {
                            // A pattern pigment as an entry (`[0.5 gradient z
                            // color_map { … }]`): outside the subset.
                            let w = w.unwrap_or_default();
                            self.skip_warning(loc, &w, "a pattern in a map entry is left out");
                            self.skip_entry()?;
                            break;
                        } else {
                            self.expression(false)?;
                        }
                        self.eat(',')?;
                    }
                }
                Some(Tok::Word(w)) => {
                    self.next()?;
                    // A declared colour (a colour map declared earlier is
                    // kept as its mean colour).
                    match self.symbol(&w) {
                        Some(Value::Vector(c)) if c.len() == 5 => {
                            let mut colour = [0.0; 5];
                            colour.copy_from_slice(c);
                            colours.push(colour);
                        }
                        Some(Value::ColourMap(map)) => colours.extend(map.iter().map(|e| e.1)),
                        _ => {}
                    }
                }
                Some(_) => {
                    self.next()?;
                }
                None => return Err(self.error("this block is never closed (`}`)")),
            }
        }
    }

    /// The contents of `finish { … }`, starting from `base` (or the default).
    pub fn finish_block(&mut self, base: Option<Finish>) -> Result<Finish> {
        self.expect('{')?;
        let mut f = base.unwrap_or_else(|| self.defaults().finish);
        if let Some(w) = self.peek_word()?
            && let Some(Value::Finish(named)) = self.symbol(&w)
        {
            f = *named;
            self.next()?;
        }
        while !self.eat('}')? {
            let loc = self.here();
            let word = self.word()?;
            let fraction = |p: &mut Parser, name: &str| -> Result<f32> {
                let v = p.finish_amount(name, loc)?;
                // POV-Ray takes any amount; the classic material's lie in
                // [0, 1] (see `Builder::material`).
                if !(0.0..=1.0).contains(&v) {
                    p.warn(
                        loc,
                        format!(
                            "`{name} {v}` is outside [0, 1]: drawn as {}",
                            v.clamp(0.0, 1.0)
                        ),
                    );
                }
                Ok(v as f32)
            };
            match word.as_str() {
                "ambient" => f.ambient = fraction(self, "ambient")?,
                "diffuse" => {
                    if self.eat_word("albedo")? {
                        self.warn(loc, "`diffuse albedo` is read as plain diffuse");
                    }
                    f.diffuse = fraction(self, "diffuse")?;
                }
                "phong" => f.phong = fraction(self, "phong")?,
                "phong_size" => f.phong_size = self.float()? as f32,
                "specular" => f.specular = fraction(self, "specular")?,
                "roughness" => f.roughness = self.float()? as f32,
                "metallic" => {
                    f.metallic = self.allow_float(1.0)? as f32;
                }
                "reflection" => self.reflection(&mut f, loc)?,
                "brilliance" => f.brilliance = self.float()? as f32,
                "conserve_energy" | "crand" => {
                    if word == "crand" {
                        self.float()?;
                    }
                    self.skip_warning(loc, &word, "ignored");
                }
                "emission" => {
                    let v = self.expression(false)?;
                    let c = self.as_colour(&v, loc)?;
                    f.ambient += ((c[0] + c[1] + c[2]) / 3.0) as f32;
                    self.warn(loc, "`emission` is added to ambient, as a grey");
                }
                other => self.unknown_item(loc, other, "finish")?,
            }
        }
        Ok(f)
    }

    /// A finish amount: a number, or a colour read as its mean (with a warning).
    fn finish_amount(&mut self, name: &str, loc: Loc) -> Result<f64> {
        let v = self.expression(false)?;
        Ok(match v {
            Value::Float(f) => f,
            Value::Vector(c) => {
                self.warn(
                    loc,
                    format!("a coloured `{name}` is read as the mean of its colour"),
                );
                c.iter().take(3).sum::<f64>() / 3.0
            }
            _ => return Err(self.error_at(loc, format!("expected a number after `{name}`"))),
        })
    }

    /// `reflection f`, `reflection { [min] max [fresnel] [metallic] }`.
    fn reflection(&mut self, f: &mut Finish, loc: Loc) -> Result<()> {
        if !self.eat('{')? {
            let r = self.finish_amount("reflection", loc)? as f32;
            f.reflection = r;
            f.reflection_max = r;
            return Ok(());
        }
        let first = self.finish_amount("reflection", loc)? as f32;
        self.eat(',')?;
        let (min, max) = if self.starts_number()? {
            (first, self.finish_amount("reflection", loc)? as f32)
        } else {
            (first, first)
        };
        f.reflection = min;
        f.reflection_max = max;
        while !self.eat('}')? {
            let loc = self.here();
            match self.word()?.as_str() {
                "fresnel" => {
                    f.fresnel = self.allow_float(1.0)? != 0.0;
                }
                "metallic" => {
                    f.metallic = self.allow_float(1.0)? as f32;
                }
                "falloff" | "exponent" => {
                    self.float()?;
                    self.skip_warning(loc, "reflection falloff", "ignored");
                }
                other => self.unknown_item(loc, other, "reflection")?,
            }
        }
        Ok(())
    }

    /// The number after a keyword, or `bare` where none follows (POV-Ray's
    /// `Allow_Float`): `hollow`, `hollow off`, `metallic 0.5`, `circular`.
    pub fn allow_float(&mut self, bare: f64) -> Result<f64> {
        if self.starts_number()? {
            self.float()
        } else {
            Ok(bare)
        }
    }

    /// Whether the next token starts a number.
    pub fn starts_number(&mut self) -> Result<bool> {
        Ok(match self.peek()? {
            Some(Tok::Number(_)) | Some(Tok::Punct('-' | '(' | '+')) => true,
            Some(Tok::Word(w)) => {
                matches!(self.symbol(&w), Some(Value::Float(_)))
                    || matches!(
                        w.as_str(),
                        "pi" | "sqrt"
                            | "sin"
                            | "cos"
                            | "abs"
                            | "pow"
                            | "on"
                            | "off"
                            | "true"
                            | "false"
                            | "yes"
                            | "no"
                    )
            }
            _ => false,
        })
    }

    /// The contents of `interior { … }`.
    pub fn interior_block(&mut self) -> Result<Interior> {
        self.expect('{')?;
        let mut interior = Interior::default();
        if let Some(w) = self.peek_word()?
            && let Some(Value::Interior(named)) = self.symbol(&w)
        {
            interior = *named;
            self.next()?;
        }
        while !self.eat('}')? {
            let loc = self.here();
            let word = self.word()?;
            match word.as_str() {
                "ior" => interior.ior = self.float()?,
                "fade_distance" => interior.fade_distance = self.float()?,
                "fade_power" => interior.fade_power = self.float()?,
                "fade_color" | "fade_colour" => {
                    let c = self.expression(false)?;
                    let c = self.as_colour(&c, loc)?;
                    interior.fade_colour = [c[0], c[1], c[2]];
                }
                other => self.unknown_item(loc, other, "interior")?,
            }
        }
        Ok(interior)
    }

    /// `transform { … }` (after the keyword) or `transform NAME`.
    pub fn transform_block(&mut self) -> Result<DAffine3> {
        if let Some(w) = self.peek_word()? {
            return match self.symbol(&w) {
                Some(Value::Transform(t)) => {
                    let t = *t;
                    self.next()?;
                    Ok(t)
                }
                _ => Err(self.error(format!("`{w}` is not a declared transform"))),
            };
        }
        self.expect('{')?;
        let mut m = DAffine3::IDENTITY;
        while !self.eat('}')? {
            let loc = self.here();
            let word = self.word()?;
            if word == "inverse" {
                m = m.inverse();
            } else if let Some(t) = self.transform_item(&word)? {
                m = t * m;
            } else if let Some(Value::Transform(t)) = self.symbol(&word) {
                m = *t * m;
            } else {
                return Err(self.error_at(loc, format!("`{word}` is not a transform")));
            }
        }
        Ok(m)
    }

    /// If `word` is a transform keyword (already peeked or taken), takes it
    /// and its value and returns the transform.
    pub fn transform_item(&mut self, word: &str) -> Result<Option<DAffine3>> {
        if !matches!(
            word,
            "translate" | "rotate" | "scale" | "matrix" | "transform"
        ) {
            return Ok(None);
        }
        if self.peek_word()?.as_deref() == Some(word) {
            self.next()?;
        }
        let loc = self.here();
        Ok(Some(match word {
            "translate" => DAffine3::from_translation(self.vector()?),
            "rotate" => rotation(self.vector()? * (std::f64::consts::PI / 180.0)),
            "scale" => {
                let mut s = self.vector()?;
                for i in 0..3 {
                    if s[i] == 0.0 {
                        self.warn(loc, "a scale of 0 is changed to 1, as POV-Ray does");
                        s[i] = 1.0;
                    }
                }
                DAffine3::from_scale(s)
            }
            "matrix" => {
                if !self.eat('<')? {
                    return Err(self.error_at(loc, "`matrix` takes 12 numbers in < >"));
                }
                let m = self.numbers_to_bracket()?;
                if m.len() != 12 {
                    return Err(self.error_at(loc, "`matrix` takes 12 numbers"));
                }
                DAffine3::from_cols(
                    DVec3::new(m[0], m[1], m[2]),
                    DVec3::new(m[3], m[4], m[5]),
                    DVec3::new(m[6], m[7], m[8]),
                    DVec3::new(m[9], m[10], m[11]),
                )
            }
            _ => self.transform_block()?,
        }))
    }

    /// An item of a block that the subset does not know: skipped with a
    /// warning, with its block or value.
    pub fn unknown_item(&mut self, loc: Loc, word: &str, block: &str) -> Result<()> {
        self.skip_warning(loc, word, &format!("skipped in this {block}"));
        if self.peek()? == Some(Tok::Punct('{')) {
            self.skip_block()?;
        } else if self.peek()? == Some(Tok::Punct('(')) {
            // A macro's call, or a value in parentheses: skipped balanced,
            // since a call's arguments need not make one expression.
            self.skip_parens()?;
        } else if self.peek()? == Some(Tok::Punct('[')) {
            // An array's element (arrays are outside the subset).
            self.skip_brackets()?;
        } else if self.starts_number()? || self.peek()? == Some(Tok::Punct('<')) {
            self.expression(false)?;
        }
        Ok(())
    }
}

/// The mean of `colours` (black for none).
pub fn mean(colours: &[[f64; 5]]) -> [f64; 5] {
    let n = colours.len().max(1) as f64;
    let mut mean = [0.0; 5];
    for c in colours {
        for i in 0..5 {
            mean[i] += c[i] / n;
        }
    }
    mean
}
