//! Scenes in POV-Ray 3.7's language (`sturmray render scene.pov`): a reader
//! for its static subset, written for sturmray. `lex` makes tokens, `parse`
//! runs the directives as it reads them, `value` evaluates expressions,
//! `texture` and `object` read what the statements describe, and `build`
//! turns that into a `Scene`: analytic shapes and CSG trees, classic
//! materials, POV-Ray's lights and camera. See docs/povray.md for the subset
//! and how each part maps.
//!
//! Coordinates are POV-Ray's own, left-handed as they are: the camera is
//! given by its image plane, so every pixel's ray is the one POV-Ray traces
//! and the image is not mirrored.

mod arrays;
mod boxes;
mod build;
mod camera;
mod colour;
mod csg;
mod flow;
mod functions;
mod lex;
mod macros;
mod object;
mod parse;
mod parts;
mod patterns;
mod texture;
mod value;

#[cfg(test)]
mod tests;

use std::path::Path;

use glam::DVec3;

use super::{Fog, GroundFog, LoadOptions, Scene, WorkingGamma};
use crate::error::Result;
use camera::CameraSpec;
use lex::Tok;
use object::{Kind, Obj};
use parse::Parser;
use value::{OBJECT_KEYWORDS, UNSUPPORTED, Value};

/// POV-Ray's image size when the command line gives none.
pub const DEFAULT_SIZE: (u32, u32) = (800, 600);

/// What a scene's statements gave, in the order read.
struct Statements {
    objects: Vec<Obj>,
    camera: CameraSpec,
    background: DVec3,
    fogs: Vec<Fog>,
    globals: Globals,
}

/// `global_settings` as far as the subset reads it.
struct Globals {
    /// `assumed_gamma`, if given (POV-Ray 3.7 changes its colour handling
    /// without it; see `working_gamma`).
    gamma: Option<WorkingGamma>,
    max_trace_level: u32,
    adc_bailout: f64,
    ambient_light: DVec3,
}

impl Default for Globals {
    fn default() -> Globals {
        Globals {
            gamma: None,
            max_trace_level: 5,
            adc_bailout: 1.0 / 255.0,
            ambient_light: DVec3::ONE,
        }
    }
}

/// Reads the scene at `path`.
pub(super) fn load(path: &Path, options: &LoadOptions) -> Result<Scene> {
    let size = options.size.unwrap_or(DEFAULT_SIZE);
    let mut parser = Parser::new(path, &options.pov_include, size)?;
    let statements = statements(&mut parser)?;
    build::scene(path, parser, statements, size)
}

/// Every top-level statement of the scene.
fn statements(p: &mut Parser) -> Result<Statements> {
    let mut s = Statements {
        objects: Vec::new(),
        camera: CameraSpec::default(),
        background: DVec3::ZERO,
        fogs: Vec::new(),
        globals: Globals::default(),
    };
    let mut cameras = 0;
    // POV-Ray draws a sky_sphere wherever a ray leaves the scene, and its
    // background only where there is none, whichever comes first.
    let mut sky = None;
    while let Some(tok) = p.peek()? {
        let loc = p.here();
        let Tok::Word(word) = tok else {
            return Err(p.error(format!(
                "expected an object, camera, light_source or setting, found {}",
                lex::describe(&tok)
            )));
        };
        match word.as_str() {
            "camera" => {
                p.next()?;
                cameras += 1;
                if cameras > 1 {
                    p.warn(loc, "a second camera: the last one is used, as in POV-Ray");
                }
                s.camera = p.camera_block()?;
                p.count("camera");
            }
            "background" => {
                p.next()?;
                p.expect('{')?;
                let cloc = p.here();
                let c = p.colour_rest(None)?;
                let c = p.as_colour(&c, cloc)?;
                s.background = DVec3::new(c[0], c[1], c[2]);
                p.expect('}')?;
                p.count("background");
            }
            "fog" => {
                p.next()?;
                if let Some(fog) = p.fog_block()? {
                    s.fogs.push(fog);
                }
                p.count("fog");
            }
            "sky_sphere" => {
                p.next()?;
                sky = p.sky_sphere_block()?.or(sky);
                p.count("sky_sphere");
            }
            "global_settings" => {
                p.next()?;
                globals(p, &mut s.globals)?;
            }
            w if OBJECT_KEYWORDS.contains(&w) || UNSUPPORTED.contains(&w) || p.names_object(w) => {
                if let Some(mut obj) = p.object_statement()? {
                    // POV-Ray gives an object with no texture the `#default`
                    // in force where its statement ends, so a shape declared
                    // before a `#default` and placed after it takes it.
                    if obj.texture.is_none() && !matches!(obj.kind, Kind::Light(_)) {
                        obj.set_texture(p.defaults());
                    }
                    s.objects.push(obj);
                }
            }
            _ => {
                p.next()?;
                if p.peek()? == Some(Tok::Punct('{')) {
                    p.skip_warning(loc, &word, "skipped");
                    p.skip_block()?;
                } else if matches!(p.symbol(&word), Some(Value::Macro(_))) {
                    let why = p.not_run(&word);
                    p.skip_warning(loc, &word, &format!("{why}: its call is skipped"));
                    p.skip_parens()?;
                } else {
                    return Err(p.error_at(
                        loc,
                        format!(
                            "expected an object, camera, light_source or setting, found `{word}`"
                        ),
                    ));
                }
            }
        }
    }
    if let Some(sky) = sky {
        s.background = sky;
    }
    Ok(s)
}

impl Parser {
    /// `fog { … }` after its keyword: None for one POV-Ray draws nothing
    /// of (a distance of 0).
    fn fog_block(&mut self) -> Result<Option<Fog>> {
        self.expect('{')?;
        let mut colour = [0.0; 5];
        let (mut distance, mut kind, mut offset, mut alt) = (0.0, 1.0, 0.0, 0.0);
        let mut up = DVec3::Y;
        while !self.eat('}')? {
            let loc = self.here();
            // A declared colour, as in `fog { distance 200 Wheat*.5 }`.
            if let Some(w) = self.peek_word()?
                && matches!(self.symbol(&w), Some(Value::Vector(_)))
            {
                let c = self.expression(false)?;
                colour = self.as_colour(&c, loc)?;
                continue;
            }
            if self.starts_number()? {
                self.warn(
                    loc,
                    "a fog's distance should follow `distance` (POV-Ray's warning too)",
                );
                distance = self.float()?;
                continue;
            }
            let word = self.word()?;
            if let Some(t) = self.transform_item(&word)? {
                if word == "translate" {
                    self.warn(
                        loc,
                        "a fog's up vector can't be translated (POV-Ray's warning too)",
                    );
                } else {
                    up = t.transform_vector3(up);
                }
                continue;
            }
            match word.as_str() {
                "color" | "colour" => {
                    let c = self.colour_rest(None)?;
                    colour = self.as_colour(&c, loc)?;
                }
                w if value::COLOUR_WORDS.contains(&w) => {
                    let c = self.colour_rest(Some((word.clone(), loc)))?;
                    colour = self.as_colour(&c, loc)?;
                }
                "distance" => distance = self.float()?,
                "fog_type" => kind = self.float()?,
                "fog_offset" => offset = self.float()?,
                "fog_alt" => alt = self.float()?,
                "up" => up = self.vector()?,
                "turbulence" | "octaves" | "omega" | "lambda" | "turb_depth" => {
                    self.expression(false)?;
                    self.skip_warning(loc, &word, "the fog is drawn without its turbulence");
                }
                other => self.unknown_item(loc, other, "fog")?,
            }
        }
        // POV-Ray leaves out a fog of no distance; its ground fog divides
        // by the altitude, which must then not be 0.
        if distance.abs() <= 1e-10 {
            return Ok(None);
        }
        let ground = (kind.round() as i64 == 2).then(|| GroundFog {
            offset,
            alt: if alt == 0.0 { 1e-10 } else { alt },
            up: up.normalize_or(DVec3::Y),
        });
        let rgb = DVec3::new(colour[0], colour[1], colour[2]).as_vec3();
        Ok(Some(Fog {
            distance: distance.abs(),
            colour: rgb,
            filter: colour[3] as f32,
            transmit: colour[4] as f32,
            ground,
        }))
    }
}

/// `global_settings { … }` after its keyword.
fn globals(p: &mut Parser, g: &mut Globals) -> Result<()> {
    p.expect('{')?;
    while !p.eat('}')? {
        let loc = p.here();
        let word = p.word()?;
        match word.as_str() {
            "assumed_gamma" => {
                let gamma = if p.eat_word("srgb")? {
                    WorkingGamma::Srgb
                } else {
                    let gamma = p.float()?;
                    // POV-Ray refuses a gamma of 0 or below; a typo is not
                    // worth a failed render: linear, with a warning.
                    let valid = gamma > 0.0 && gamma <= 10.0;
                    if !valid {
                        p.warn(
                            loc,
                            format!("assumed_gamma {gamma} is not a gamma: read as 1 (linear)"),
                        );
                    }
                    if valid && gamma != 1.0 {
                        WorkingGamma::Power(gamma as f32)
                    } else {
                        WorkingGamma::Linear
                    }
                };
                // POV-Ray keeps the first, as sturmray does.
                if g.gamma.is_some() {
                    p.warn(loc, "a second assumed_gamma is ignored, as in POV-Ray");
                } else {
                    g.gamma = Some(gamma);
                }
            }
            "max_trace_level" => {
                let v = p.float()?;
                g.max_trace_level = v.clamp(1.0, 256.0) as u32;
            }
            "adc_bailout" => g.adc_bailout = p.float()?.clamp(0.0, 1.0),
            "ambient_light" => {
                let c = p.colour_rest(None)?;
                let c = p.as_colour(&c, loc)?;
                g.ambient_light = DVec3::new(c[0], c[1], c[2]);
            }
            other => p.unknown_item(loc, other, "global_settings")?,
        }
    }
    Ok(())
}
