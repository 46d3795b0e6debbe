//! Light sources and meshes of POV-Ray's language: `light_source` (a point,
//! or an `area_light` grid), `mesh` (`triangle`, `smooth_triangle`) and
//! `mesh2` (vertex and face lists), as the object reader's parts.

use std::rc::Rc;

use glam::{DAffine3, DVec3};

use super::lex::Tok;
use super::object::{BeamKind, Kind, LightSource, Triangle};
use super::parse::{Loc, Parser};
use super::texture::Texture;
use super::value::Value;
use crate::error::Result;

impl Parser {
    /// `light_source { position, colour, … }` after its `{`, or
    /// `light_source { NAME … }` going on from a declared light.
    pub(super) fn light_source(&mut self) -> Result<LightSource> {
        let declared = match self.peek_word()? {
            Some(w) => match self.symbol(&w) {
                Some(Value::Object(o)) => match &o.kind {
                    Kind::Light(l) => Some((l.clone(), o.transform)),
                    _ => None,
                },
                _ => None,
            },
            None => None,
        };
        let (mut light, mut transform) = match declared {
            Some(base) => {
                self.next()?;
                base
            }
            None => (self.light_head()?, DAffine3::IDENTITY),
        };
        let mut area_at = None;
        while !self.eat('}')? {
            let iloc = self.here();
            let word = self.word()?;
            if let Some(t) = self.transform_item(&word)? {
                transform = t * transform;
                continue;
            }
            match word.as_str() {
                "area_light" => {
                    let a = self.vector()?;
                    self.eat(',')?;
                    let b = self.vector()?;
                    self.eat(',')?;
                    let n1 = self.float()?;
                    self.eat(',')?;
                    let n2 = self.float()?;
                    let count = |n: f64| n.clamp(1.0, 64.0).round() as u32;
                    light.area = Some((a, b, count(n1), count(n2)));
                    area_at = Some(iloc);
                }
                "adaptive" | "area_illumination" => {
                    self.float()?;
                }
                "circular" => light.circular = self.allow_float(1.0)? > 0.0,
                // They move an area light's grid at each point it lights,
                // where the grid here stays as given.
                "jitter" | "orient" => {
                    if self.allow_float(1.0)? > 0.0 {
                        let what = if word == "jitter" {
                            "the area light's grid is not jittered"
                        } else {
                            "the area light's grid is not turned towards what it lights"
                        };
                        self.skip_warning(iloc, &word, what);
                    }
                }
                // A bare keyword is on, as a number above zero (POV-Ray's).
                "media_attenuation" | "media_interaction" => {
                    let on = self.allow_float(1.0)? > 0.0;
                    if word == "media_attenuation" {
                        light.media_attenuation = on;
                    } else {
                        light.media_interaction = on;
                    }
                }
                "shadowless" => light.shadowless = true,
                "color" | "colour" => {
                    let cloc = self.here();
                    let c = self.colour_rest(None)?;
                    let c = self.as_colour(&c, cloc)?;
                    light.colour = DVec3::new(c[0], c[1], c[2]);
                }
                "fade_power" => light.fade_power = self.float()?,
                "fade_distance" => light.fade_distance = self.float()?,
                // POV-Ray 3.7's defaults with each type (its parser).
                "spotlight" => {
                    (light.beam, light.radius, light.falloff) = (BeamKind::Spot, 30.0, 45.0);
                    light.tightness = 0.0;
                }
                "cylinder" => {
                    (light.beam, light.radius, light.falloff) = (BeamKind::Cylinder, 0.75, 1.0);
                    light.tightness = 0.0;
                    light.parallel = true;
                }
                "parallel" => light.parallel = true,
                "point_at" => {
                    if light.beam == BeamKind::Point && !light.parallel {
                        return Err(self.light_order_error(iloc, "point_at"));
                    }
                    light.point_at = self.vector()?;
                }
                "radius" | "falloff" | "tightness" => {
                    if light.beam == BeamKind::Point {
                        return Err(self.light_order_error(iloc, &word));
                    }
                    *match word.as_str() {
                        "radius" => &mut light.radius,
                        "falloff" => &mut light.falloff,
                        _ => &mut light.tightness,
                    } = self.float()?;
                }
                "looks_like" | "projected_through" => {
                    self.skip_warning(iloc, &word, "the light is drawn without it");
                    if self.peek()? == Some(Tok::Punct('{')) {
                        self.skip_block()?;
                    }
                }
                other => self.unknown_item(iloc, other, "light_source")?,
            }
        }
        if let Some(loc) = area_at.filter(|_| light.beam != BeamKind::Point || light.parallel) {
            // POV-Ray attenuates an area light's beam once, from its centre;
            // here each light of the grid is attenuated from where it is.
            self.warn(
                loc,
                "an `area_light` with a beam (spotlight, cylinder, parallel) is drawn as a grid \
                 of beams, each attenuated from its own place, not from the centre as in POV-Ray",
            );
        }
        light.position = transform.transform_point3(light.position);
        light.point_at = transform.transform_point3(light.point_at);
        if let Some((a, b, n1, n2)) = light.area {
            light.area = Some((
                transform.transform_vector3(a),
                transform.transform_vector3(b),
                n1,
                n2,
            ));
        }
        Ok(light)
    }

    /// A light's position and colour, which `light_source {` starts with,
    /// and POV-Ray's defaults for the rest.
    fn light_head(&mut self) -> Result<LightSource> {
        let position = self.vector()?;
        self.eat(',')?;
        let cloc = self.here();
        let c = self.colour_rest(None)?;
        let c = self.as_colour(&c, cloc)?;
        Ok(LightSource {
            position,
            colour: DVec3::new(c[0], c[1], c[2]),
            area: None,
            shadowless: false,
            beam: BeamKind::Point,
            radius: 0.0,
            falloff: 0.0,
            tightness: 0.0,
            parallel: false,
            // POV-Ray's default aim.
            point_at: DVec3::Z,
            fade_distance: 0.0,
            fade_power: 0.0,
            media_attenuation: false,
            media_interaction: true,
            circular: false,
        })
    }
    /// A light keyword before the type it belongs to: a parse error in
    /// POV-Ray too.
    fn light_order_error(&self, loc: Loc, keyword: &str) -> crate::error::Error {
        let needs = if keyword == "point_at" {
            "`spotlight`, `cylinder` or `parallel`"
        } else {
            "`spotlight` or `cylinder`"
        };
        self.error_at(
            loc,
            format!("`{keyword}` cannot be used with a standard light source: expected {needs} before it"),
        )
    }

    /// `mesh { triangle { a, b, c [texture] } smooth_triangle { … } … }`.
    pub(super) fn mesh(&mut self, loc: Loc) -> Result<Kind> {
        let mut triangles = Vec::new();
        while let Some(w) = self.peek_word()? {
            if !matches!(w.as_str(), "triangle" | "smooth_triangle") {
                break;
            }
            self.next()?;
            self.expect('{')?;
            let mut triangle = self.triangle(w == "smooth_triangle")?;
            while !self.eat('}')? {
                let tloc = self.here();
                match self.word()?.as_str() {
                    "texture" => triangle.texture = Some(self.texture_block()?),
                    other => self.unknown_item(tloc, other, "triangle")?,
                }
            }
            triangles.push(triangle);
        }
        if triangles.is_empty() {
            return Err(self.error_at(loc, "a mesh needs at least one triangle"));
        }
        Ok(Kind::Mesh(Rc::new(triangles)))
    }

    /// The corners of a `triangle`, or of a `smooth_triangle` with each
    /// corner's normal, up to its texture.
    pub(super) fn triangle(&mut self, smooth: bool) -> Result<Triangle> {
        let mut corners = [DVec3::ZERO; 3];
        let mut normals = [DVec3::ZERO; 3];
        for (i, (corner, normal)) in corners.iter_mut().zip(&mut normals).enumerate() {
            if i > 0 {
                self.eat(',')?;
            }
            *corner = self.vector()?;
            if smooth {
                self.eat(',')?;
                *normal = self.vector()?;
            }
        }
        Ok(Triangle {
            corners,
            normals: smooth.then_some(normals),
            texture: None,
        })
    }

    /// `mesh2 { vertex_vectors { n, … } face_indices { n, … } … }`.
    pub(super) fn mesh2(&mut self, loc: Loc) -> Result<Kind> {
        let mut vertices: Vec<DVec3> = Vec::new();
        let mut normals: Vec<DVec3> = Vec::new();
        let mut faces: Vec<([usize; 3], Option<usize>)> = Vec::new();
        // Per face, its corners' indices into `normals`; with none given,
        // the face's own indices are (POV-Ray's rule).
        let mut normal_faces: Vec<[usize; 3]> = Vec::new();
        let mut textures: Vec<Texture> = Vec::new();
        while let Some(w) = self.peek_word()? {
            match w.as_str() {
                "vertex_vectors" | "normal_vectors" | "uv_vectors" => {
                    self.next()?;
                    self.expect('{')?;
                    let n = self.float()? as usize;
                    let mut list = Vec::with_capacity(n.min(1 << 20));
                    for _ in 0..n {
                        self.eat(',')?;
                        let v = self.expression(false)?;
                        if let Value::Vector(c) = v {
                            list.push(DVec3::new(c[0], c[1], c.get(2).copied().unwrap_or(0.0)));
                        }
                    }
                    self.eat(',')?;
                    self.expect('}')?;
                    match w.as_str() {
                        "vertex_vectors" => vertices = list,
                        "normal_vectors" => normals = list,
                        _ => {}
                    }
                }
                "texture_list" => {
                    self.next()?;
                    self.expect('{')?;
                    let n = self.float()? as usize;
                    for _ in 0..n {
                        self.eat(',')?;
                        if self.eat_word("texture")? {
                            textures.push(self.texture_block()?);
                        }
                    }
                    self.expect('}')?;
                }
                "face_indices" | "normal_indices" | "uv_indices" => {
                    self.next()?;
                    self.expect('{')?;
                    let n = self.float()? as usize;
                    for _ in 0..n {
                        self.eat(',')?;
                        let floc = self.here();
                        let v = self.vector()?;
                        let mut texture = None;
                        while self.eat(',')? {
                            if self.starts_number()? {
                                let t = self.float()?;
                                texture.get_or_insert(t as usize);
                            } else {
                                break;
                            }
                        }
                        let idx = [v.x, v.y, v.z];
                        if w != "uv_indices" && idx.iter().any(|&i| i < 0.0 || i.fract() != 0.0) {
                            return Err(self.error_at(floc, format!("{w} are whole numbers >= 0")));
                        }
                        let idx = idx.map(|i| i as usize);
                        match w.as_str() {
                            "face_indices" => faces.push((idx, texture)),
                            "normal_indices" => normal_faces.push(idx),
                            _ => {}
                        }
                    }
                    self.eat(',')?;
                    self.expect('}')?;
                }
                _ => break,
            }
        }
        let mut triangles = Vec::with_capacity(faces.len());
        for (k, (idx, texture)) in faces.into_iter().enumerate() {
            let Some(p) = idx
                .iter()
                .map(|&i| vertices.get(i).copied())
                .collect::<Option<Vec<_>>>()
            else {
                return Err(self.error_at(
                    loc,
                    format!(
                        "a face refers to a vertex beyond the {} in vertex_vectors",
                        vertices.len()
                    ),
                ));
            };
            // Smooth where normals are given (a face past the end of
            // normal_indices is flat).
            let corner_normals = if normals.is_empty() {
                None
            } else if normal_faces.is_empty() {
                Some(idx)
            } else {
                normal_faces.get(k).copied()
            };
            let smooth = match corner_normals {
                None => None,
                Some(n) => {
                    let found: Option<Vec<DVec3>> =
                        n.iter().map(|&i| normals.get(i).copied()).collect();
                    let Some(found) = found else {
                        return Err(self.error_at(
                            loc,
                            format!(
                                "a face refers to a normal beyond the {} in normal_vectors",
                                normals.len()
                            ),
                        ));
                    };
                    Some([found[0], found[1], found[2]])
                }
            };
            triangles.push(Triangle {
                corners: [p[0], p[1], p[2]],
                normals: smooth,
                texture: texture.and_then(|t| textures.get(t).cloned()),
            });
        }
        if triangles.is_empty() {
            return Err(self.error_at(loc, "a mesh2 needs at least one face"));
        }
        Ok(Kind::Mesh(Rc::new(triangles)))
    }
}
