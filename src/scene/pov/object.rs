//! Objects of POV-Ray's language as read: each shape's own parameters, its
//! transform, texture, interior and modifiers (`inverse`, `no_shadow`,
//! `bounded_by`, `clipped_by`), CSG operations over children, and light
//! sources (which may sit inside CSG).
//!
//! Everything an object carries is kept in the object's own space: a
//! texture, a clip or a bound given after some transforms is moved back by
//! them, so that the object's final transform places it as POV-Ray does
//! (later transforms move all of it, earlier ones only the shape).

use std::rc::Rc;

use glam::{DAffine3, DMat3, DVec3};

use super::lex::Tok;
use super::parse::{Loc, Parser};
use super::texture::{Interior, Pigment, Texture};
use super::value::{OBJECT_KEYWORDS, UNSUPPORTED, Value};
use crate::error::Result;
use crate::poly::trivariate::Trivariate;

/// How a CSG node combines its children.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CsgOp {
    Union,
    Intersection,
    Difference,
    Merge,
}

/// A light source: POV-Ray's point light (the same brightness at every
/// distance), or an array of them (`area_light`), optionally a beam.
#[derive(Clone, Debug, PartialEq)]
pub struct LightSource {
    pub position: DVec3,
    pub colour: DVec3,
    /// Two edge vectors and how many lights along each.
    pub area: Option<(DVec3, DVec3, u32, u32)>,
    pub shadowless: bool,
    pub beam: BeamKind,
    /// `radius`, `falloff` (degrees for a spotlight, distances for a
    /// cylinder) and `tightness`, POV-Ray's defaults until given.
    pub radius: f64,
    pub falloff: f64,
    pub tightness: f64,
    pub parallel: bool,
    pub point_at: DVec3,
    /// `fade_distance` and `fade_power`, POV-Ray's 0 (no fade) until given.
    pub fade_distance: f64,
    pub fade_power: f64,
    /// Whether the fogs dim the light on its way (both must be on, as in
    /// POV-Ray; `media_interaction` is on by default).
    pub media_attenuation: bool,
    pub media_interaction: bool,
    /// `circular`: the area light's grid bent into a disc.
    pub circular: bool,
}

/// Which of POV-Ray's light types a `light_source` is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BeamKind {
    Point,
    Spot,
    Cylinder,
}

/// A triangle of a mesh: its corners, its corners' normals (a
/// `smooth_triangle`'s), and its own texture if it gave one.
#[derive(Clone, Debug)]
pub struct Triangle {
    pub corners: [DVec3; 3],
    pub normals: Option<[DVec3; 3]>,
    pub texture: Option<Texture>,
}

#[derive(Clone, Debug)]
pub enum Kind {
    Sphere {
        center: DVec3,
        radius: f64,
    },
    Box {
        a: DVec3,
        b: DVec3,
    },
    /// A cylinder (r0 = r1) or a cone.
    Round {
        base: DVec3,
        cap: DVec3,
        r0: f64,
        r1: f64,
        open: bool,
    },
    Plane {
        normal: DVec3,
        distance: f64,
    },
    /// POV-Ray's torus: in the xz plane, about the y axis.
    Torus {
        major: f64,
        minor: f64,
    },
    Disc {
        center: DVec3,
        normal: DVec3,
        radius: f64,
        hole: f64,
    },
    Quadric {
        a: DMat3,
        b: DVec3,
        c: f64,
    },
    /// `cubic`, `quartic`, `poly`.
    Poly(Trivariate),
    /// Triangles (a mesh's, or one alone), shared by the copies of a
    /// declared mesh, as POV-Ray shares them.
    Mesh(Rc<Vec<Triangle>>),
    Csg {
        op: CsgOp,
        children: Vec<Obj>,
    },
    Light(LightSource),
}

/// How deep objects may nest (CSG in CSG, bounds and clips), as read. The
/// parser's own limit counts braces; this one also counts the nesting that
/// declared objects placed in new ones make, as a loop that wraps an object
/// in itself on every pass makes: sundial.pov with its counter broken
/// nested so until the stack overflowed.
const MAX_OBJECT_DEPTH: usize = 256;

/// The objects copied from declared objects over one scene (each object in
/// a copy counts; a mesh's triangles are shared, not copied): past it, a
/// loop that copies a growing object on every pass (`#declare U = union {
/// U U }`) stops with an error instead of filling the memory. An object
/// takes 576 bytes as read, so 2^21 are some 1.2 GB of copies, far beyond
/// what POV-Ray's own samples copy.
const MAX_OBJECT_PARTS: usize = 1 << 21;

/// The words that modify an object (see `Parser::modifiers_until`).
const OBJECT_MODIFIERS: &[&str] = &[
    "translate",
    "rotate",
    "scale",
    "matrix",
    "transform",
    "texture",
    "pigment",
    "finish",
    "interior",
    "material",
    "inverse",
    "open",
    "no_shadow",
    "sturm",
    "hollow",
    "double_illuminate",
    "no_reflection",
    "no_image",
    "no_radiosity",
    "global_lights",
    "bounded_by",
    "clipped_by",
    "photons",
    "radiosity",
    "normal",
    "inside_vector",
];

/// An object as read.
#[derive(Clone, Debug)]
pub struct Obj {
    pub kind: Kind,
    /// Object space to its parent's (the world's at the top).
    pub transform: DAffine3,
    pub texture: Option<Texture>,
    pub interior: Option<Interior>,
    pub inverse: bool,
    pub no_shadow: bool,
    /// `hollow`: its inside is air, which a fog fills.
    pub hollow: bool,
    pub bounded_by: Vec<Obj>,
    pub clipped_by: Vec<Obj>,
    /// One list was read as a copy of the other (`bounded_by { clipped_by }`
    /// or the reverse): the bound then holds the clipped object, and a gate
    /// would only repeat the clip's own test.
    pub bound_is_clip: bool,
    pub loc: Loc,
}

impl Obj {
    pub(super) fn new(kind: Kind, loc: Loc) -> Obj {
        Obj {
            kind,
            transform: DAffine3::IDENTITY,
            texture: None,
            interior: None,
            inverse: false,
            no_shadow: false,
            hollow: false,
            bounded_by: Vec::new(),
            clipped_by: Vec::new(),
            bound_is_clip: false,
            loc,
        }
    }

    /// Gives each part of a CSG object that has no interior of its own the
    /// object's, down the tree, as POV-Ray's post-processing of a finished
    /// object does (an `interior` on `object { Glass_Thing }` is every
    /// part's). Bounds and clips are never drawn, so they keep none.
    pub(super) fn promote_interior(&mut self) {
        if let Kind::Csg { children, .. } = &mut self.kind {
            for child in children {
                child.interior = child.interior.or(self.interior);
                child.promote_interior();
            }
        }
    }

    /// Moves the object (and all it carries) by `t`.
    fn apply(&mut self, t: DAffine3) {
        self.transform = t * self.transform;
    }

    /// How deep the object nests (1 alone) and how many parts it has: each
    /// object in it, and in its bounds and clips. A mesh is one part: its
    /// copies share its triangles.
    fn extent(&self) -> (usize, usize) {
        let children = match &self.kind {
            Kind::Csg { children, .. } => children.as_slice(),
            _ => &[],
        };
        children
            .iter()
            .chain(&self.bounded_by)
            .chain(&self.clipped_by)
            .map(Obj::extent)
            .fold((1, 1), |(depth, parts), (d, p)| {
                (depth.max(d + 1), parts + p)
            })
    }

    /// `m`, given in the object's parent space now, in its own space.
    fn local(&self) -> DAffine3 {
        self.transform.inverse()
    }

    /// Sets the texture, given in the parent's space now.
    pub(super) fn set_texture(&mut self, mut t: Texture) {
        t.transform(self.local());
        self.texture = Some(t);
    }
}

impl Parser {
    /// An object statement (`sphere { … }`, `object { … }`, …); None for a
    /// shape outside the subset, skipped with a warning.
    pub fn object_statement(&mut self) -> Result<Option<Obj>> {
        self.nested(Parser::object_inner)
    }

    fn object_inner(&mut self) -> Result<Option<Obj>> {
        let loc = self.here();
        let keyword = self.word()?;
        if !OBJECT_KEYWORDS.contains(&keyword.as_str()) && !UNSUPPORTED.contains(&keyword.as_str())
        {
            // A declared object's name alone is that object, as in POV-Ray
            // (`union { Thing }`); any other word is an error at its place.
            return match self.symbol(&keyword) {
                Some(Value::Object(o)) => {
                    // Modifiers may follow, as after `object { Name`.
                    let o = o.clone();
                    let mut obj = self.copy_object(&o, loc)?;
                    self.modifiers_until(&mut obj, false)?;
                    self.within_depth(obj, loc).map(Some)
                }
                Some(Value::Unsupported(k)) => {
                    let k = k.clone();
                    self.skip_warning(loc, &k, "the object is left out");
                    Ok(None)
                }
                _ => Err(self.error_at(loc, format!("expected an object, found `{keyword}`"))),
            };
        }
        if UNSUPPORTED.contains(&keyword.as_str()) {
            self.skip_warning(loc, &keyword, "the object is left out");
            self.skip_block()?;
            return Ok(None);
        }
        self.expect('{')?;
        let mut obj = match keyword.as_str() {
            "object" => {
                let inner_loc = self.here();
                match self.peek()? {
                    Some(Tok::Word(w))
                        if OBJECT_KEYWORDS.contains(&w.as_str())
                            || UNSUPPORTED.contains(&w.as_str()) =>
                    {
                        match self.object_statement()? {
                            Some(o) => o,
                            None => {
                                self.skip_rest()?;
                                return Ok(None);
                            }
                        }
                    }
                    Some(Tok::Word(w)) => {
                        self.next()?;
                        match self.symbol(&w) {
                            Some(Value::Object(o)) => {
                                let o = o.clone();
                                self.copy_object(&o, inner_loc)?
                            }
                            Some(Value::Unsupported(k)) => {
                                let k = k.clone();
                                self.skip_warning(inner_loc, &k, "the object is left out");
                                self.skip_rest()?;
                                return Ok(None);
                            }
                            Some(Value::Macro(_)) => {
                                let why = self.not_run(&w);
                                self.skip_warning(
                                    inner_loc,
                                    &w,
                                    &format!("{why}: the object is left out"),
                                );
                                self.skip_parens()?;
                                self.skip_rest()?;
                                return Ok(None);
                            }
                            _ => {
                                return Err(self.error_at(
                                    inner_loc,
                                    format!("`{w}` is not a declared object"),
                                ));
                            }
                        }
                    }
                    _ => return Err(self.error("expected an object or a declared object's name")),
                }
            }
            "light_source" => {
                let light = self.light_source()?;
                self.count("light_source");
                return Ok(Some(Obj::new(Kind::Light(light), loc)));
            }
            _ => {
                let kind = self.shape(&keyword, loc)?;
                self.count(&keyword);
                Obj::new(kind, loc)
            }
        };
        self.modifiers(&mut obj)?;
        self.within_depth(obj, loc).map(Some)
    }

    /// The object read at `loc`, if it nests at most [`MAX_OBJECT_DEPTH`]
    /// levels deep.
    fn within_depth(&self, obj: Obj, loc: Loc) -> Result<Obj> {
        if obj.extent().0 > MAX_OBJECT_DEPTH {
            return Err(self.error_at(
                loc,
                format!(
                    "objects nest deeper than {MAX_OBJECT_DEPTH} levels here: does a loop \
                     wrap an object in itself on every pass?"
                ),
            ));
        }
        Ok(obj)
    }

    /// A copy of the declared object `o`, counted against
    /// [`MAX_OBJECT_PARTS`].
    fn copy_object(&mut self, o: &Obj, loc: Loc) -> Result<Obj> {
        self.object_parts += o.extent().1;
        if self.object_parts > MAX_OBJECT_PARTS {
            return Err(self.error_at(
                loc,
                format!(
                    "declared objects have been copied {MAX_OBJECT_PARTS} objects in all: does \
                     a loop copy a growing object on every pass?"
                ),
            ));
        }
        Ok(o.clone())
    }

    /// Whether `w` is the name of a declared object (or of one outside the
    /// subset), which stands for that object where one may stand.
    pub(super) fn names_object(&self, w: &str) -> bool {
        matches!(
            self.symbol(w),
            Some(Value::Object(_) | Value::Unsupported(_))
        )
    }

    /// Skips the rest of an object block after its start.
    fn skip_rest(&mut self) -> Result<()> {
        let mut depth = 1usize;
        while depth > 0 {
            match self.next()? {
                Tok::Punct('{') => depth += 1,
                Tok::Punct('}') => depth -= 1,
                _ => {}
            }
        }
        Ok(())
    }

    /// The parameters of a shape `keyword`, after its `{`.
    fn shape(&mut self, keyword: &str, loc: Loc) -> Result<Kind> {
        Ok(match keyword {
            "sphere" => {
                let center = self.vector()?;
                self.eat(',')?;
                let radius = self.positive("the radius")?;
                Kind::Sphere { center, radius }
            }
            "box" => {
                let a = self.vector()?;
                self.eat(',')?;
                let b = self.vector()?;
                Kind::Box { a, b }
            }
            "cylinder" | "cone" => {
                let base = self.vector()?;
                self.eat(',')?;
                let r0 = if keyword == "cone" {
                    let r = self.float()?;
                    self.eat(',')?;
                    r
                } else {
                    0.0
                };
                let cap = self.vector()?;
                self.eat(',')?;
                let r1 = self.float()?;
                let r0 = if keyword == "cone" { r0 } else { r1 };
                if !(r0 >= 0.0 && r1 >= 0.0 && r0.max(r1) > 0.0) {
                    return Err(self.error_at(loc, "the radii must be >= 0, one of them > 0"));
                }
                if (cap - base).length() == 0.0 {
                    return Err(
                        self.error_at(loc, "the cap is at the base: the axis has no length")
                    );
                }
                Kind::Round {
                    base,
                    cap,
                    r0,
                    r1,
                    open: false,
                }
            }
            "plane" => {
                let normal = self.vector()?;
                self.eat(',')?;
                let distance = self.float()?;
                if normal.length() == 0.0 {
                    return Err(self.error_at(loc, "the plane's normal is zero"));
                }
                Kind::Plane { normal, distance }
            }
            "torus" => {
                let major = self.positive("the major radius")?;
                self.eat(',')?;
                let minor = self.positive("the minor radius")?;
                Kind::Torus { major, minor }
            }
            "disc" => {
                let center = self.vector()?;
                self.eat(',')?;
                let normal = self.vector()?;
                self.eat(',')?;
                let radius = self.positive("the radius")?;
                let hole = if self.eat(',')? { self.float()? } else { 0.0 };
                if normal.length() == 0.0 {
                    return Err(self.error_at(loc, "the disc's normal is zero"));
                }
                if !(0.0..radius).contains(&hole) {
                    return Err(self.error_at(loc, "the hole must be >= 0 and below the radius"));
                }
                Kind::Disc {
                    center,
                    normal,
                    radius,
                    hole,
                }
            }
            "quadric" => {
                let sq = self.vector()?;
                self.eat(',')?;
                let mixed = self.vector()?;
                self.eat(',')?;
                let lin = self.vector()?;
                self.eat(',')?;
                let c = self.float()?;
                // A x² + B y² + C z² + D xy + E xz + F yz + G x + H y + I z + J.
                let a = DMat3::from_cols(
                    DVec3::new(sq.x, mixed.x / 2.0, mixed.y / 2.0),
                    DVec3::new(mixed.x / 2.0, sq.y, mixed.z / 2.0),
                    DVec3::new(mixed.y / 2.0, mixed.z / 2.0, sq.z),
                );
                Kind::Quadric { a, b: lin, c }
            }
            "cubic" | "quartic" | "poly" => {
                let degree = match keyword {
                    "cubic" => 3,
                    "quartic" => 4,
                    _ => {
                        let n = self.float()?;
                        self.eat(',')?;
                        if !(n.fract() == 0.0 && (2.0..=35.0).contains(&n)) {
                            return Err(
                                self.error_at(loc, "a poly's order is a whole number from 2 to 35")
                            );
                        }
                        n as u32
                    }
                };
                let coeff_loc = self.here();
                let v = self.poly_coefficients()?;
                let n = ((degree + 1) * (degree + 2) * (degree + 3) / 6) as usize;
                if v.len() != n {
                    return Err(self.error_at(
                        coeff_loc,
                        format!(
                            "a {keyword} of order {degree} takes {n} coefficients, found {}",
                            v.len()
                        ),
                    ));
                }
                Kind::Poly(poly_terms(degree, &v))
            }
            "union" | "intersection" | "difference" | "merge" | "light_group" => {
                let op = match keyword {
                    "union" | "light_group" => CsgOp::Union,
                    "intersection" => CsgOp::Intersection,
                    "difference" => CsgOp::Difference,
                    _ => CsgOp::Merge,
                };
                let mut children = Vec::new();
                while let Some(w) = self.peek_word()? {
                    if !(OBJECT_KEYWORDS.contains(&w.as_str())
                        || UNSUPPORTED.contains(&w.as_str())
                            && !matches!(
                                w.as_str(),
                                "normal" | "material" | "photons" | "radiosity"
                            )
                        || self.names_object(&w))
                    {
                        break;
                    }
                    if let Some(child) = self.object_statement()? {
                        children.push(child);
                    }
                }
                // A light group's own lights light only its objects, which
                // the renderer cannot restrict: they are left out, and its
                // objects are lit by the scene's lights, as a union's are.
                if keyword == "light_group" {
                    let objects = children.len();
                    children.retain(|c| !matches!(c.kind, Kind::Light(_)));
                    if children.len() < objects {
                        self.skip_warning(
                            loc,
                            keyword,
                            "read as a union of its objects; its own lights, which would light \
                             only them, are left out",
                        );
                    }
                }
                Kind::Csg { op, children }
            }
            "mesh" => self.mesh(loc)?,
            "mesh2" => self.mesh2(loc)?,
            // A triangle alone is a mesh of one: textured and placed as
            // any object, by the modifiers after its corners.
            "triangle" | "smooth_triangle" => {
                Kind::Mesh(Rc::new(vec![self.triangle(keyword == "smooth_triangle")?]))
            }
            _ => unreachable!("object keywords are matched before"),
        })
    }

    /// The numbers of a `poly`: one vector of any length.
    fn poly_coefficients(&mut self) -> Result<Vec<f64>> {
        self.expect('<')?;
        self.numbers_to_bracket()
    }

    fn positive(&mut self, what: &str) -> Result<f64> {
        let loc = self.here();
        let v = self.float()?;
        if v > 0.0 && v.is_finite() {
            Ok(v)
        } else {
            Err(self.error_at(loc, format!("{what} must be a number > 0, found {v}")))
        }
    }

    /// An object's modifiers, up to and including its `}`.
    fn modifiers(&mut self, obj: &mut Obj) -> Result<()> {
        self.modifiers_until(obj, true)
    }

    /// The modifiers of an object up to its `}` (`closed`), or, after a
    /// declared object's name alone, as many as follow it.
    fn modifiers_until(&mut self, obj: &mut Obj, closed: bool) -> Result<()> {
        loop {
            if closed && self.eat('}')? {
                return Ok(());
            }
            let loc = self.here();
            let word = match self.peek()? {
                Some(Tok::Word(w)) if !closed && !OBJECT_MODIFIERS.contains(&w.as_str()) => {
                    return Ok(());
                }
                Some(Tok::Word(w)) => w,
                _ if !closed => return Ok(()),
                Some(other) => {
                    return Err(self.error(format!(
                        "expected a modifier of this object or `}}`, found {}",
                        super::lex::describe(&other)
                    )));
                }
                None => return Err(self.error("this object is never closed (`}`)")),
            };
            if let Some(t) = self.transform_item(&word)? {
                obj.apply(t);
                continue;
            }
            if super::value::OBJECT_KEYWORDS.contains(&word.as_str()) {
                return Err(self.error(format!(
                    "expected a modifier of this object or `}}`, found the object `{word}` \
                     (is a `}}` missing before it?)"
                )));
            }
            self.next()?;
            match word.as_str() {
                "texture" => {
                    let t = self.texture_block()?;
                    if obj.texture.is_some() {
                        self.warn(loc, "a layered texture: only its first layer is drawn");
                    } else {
                        obj.set_texture(t);
                    }
                }
                "pigment" => {
                    let mut p = self.pigment_block()?;
                    p.transform(obj.local());
                    obj.texture.get_or_insert_with(|| self.defaults()).pigment = p;
                }
                "finish" => {
                    let base = obj.texture.as_ref().map(|t| t.finish);
                    let f = self.finish_block(base)?;
                    obj.texture.get_or_insert_with(|| self.defaults()).finish = f;
                }
                "interior" => obj.interior = Some(self.interior_block()?),
                "material" => {
                    self.expect('{')?;
                    while !self.eat('}')? {
                        let loc = self.here();
                        match self.word()?.as_str() {
                            "texture" => {
                                let t = self.texture_block()?;
                                obj.set_texture(t);
                            }
                            "interior" => obj.interior = Some(self.interior_block()?),
                            other => self.unknown_item(loc, other, "material")?,
                        }
                    }
                }
                "inverse" => obj.inverse = !obj.inverse,
                "open" => match &mut obj.kind {
                    Kind::Round { open, .. } => *open = true,
                    _ => self.warn(loc, "`open` applies to cylinders and cones; ignored"),
                },
                "no_shadow" => obj.no_shadow = true,
                "hollow" => {
                    // `hollow off` (or 0) undoes it, as in POV-Ray.
                    obj.hollow = self.allow_float(1.0)? != 0.0;
                }
                "sturm" | "double_illuminate" | "no_reflection" | "no_image" | "no_radiosity"
                | "global_lights" => {
                    // `sturm`: sturmray's solver always isolates roots with
                    // Sturm sequences. `global_lights`: a light group is lit
                    // by the scene's lights in any case (its own are left out).
                    if self.starts_number()? {
                        self.float()?;
                    }
                    if matches!(word.as_str(), "no_reflection" | "no_image") {
                        self.skip_warning(loc, &word, "ignored: the object is seen everywhere");
                    }
                }
                "bounded_by" | "clipped_by" => self.bound_or_clip(obj, &word, loc)?,
                "photons" | "radiosity" | "normal" => {
                    self.skip_warning(loc, &word, "skipped");
                    self.skip_block()?;
                }
                "inside_vector" => {
                    self.vector()?;
                }
                other => self.unknown_item(loc, other, "object")?,
            }
        }
    }
}

impl Parser {
    /// A `bounded_by` or `clipped_by` block (after the keyword), as POV-Ray
    /// 3.7 reads it (`Parse_Object_Mods`, `Parse_Bound_Clip`): objects, then
    /// transforms that move all of them; a second block adds its objects
    /// to the first's; `bounded_by { clipped_by }` (or the reverse) makes
    /// the two lists the same objects, which POV-Ray refuses where the list
    /// already has objects, and after which it adds to neither.
    fn bound_or_clip(&mut self, obj: &mut Obj, word: &str, loc: Loc) -> Result<()> {
        self.expect('{')?;
        let bounds = word == "bounded_by";
        let other = if bounds { "clipped_by" } else { "bounded_by" };
        let (mine, theirs) = if bounds {
            (&obj.bounded_by, &obj.clipped_by)
        } else {
            (&obj.clipped_by, &obj.bounded_by)
        };
        if self.eat_word(word)? {
            // A list copied onto itself changes nothing.
            return self.expect('}');
        }
        let linked = self.eat_word(other)?;
        let (list, transform) = if linked {
            if !mine.is_empty() {
                return Err(self.error_at(
                    loc,
                    format!(
                        "`{word} {{ {other} }}` after `{word}` objects: POV-Ray refuses this too"
                    ),
                ));
            }
            self.expect('}')?;
            // The other list, given in the object's own space, placed in
            // its parent's as the statements of a block are.
            let list: Vec<Obj> = theirs.iter().map(|c| placed(c, obj.transform)).collect();
            (list, DAffine3::IDENTITY)
        } else {
            // Linked lists are the same objects, both not empty.
            if obj.bound_is_clip {
                return Err(self.error_at(
                    loc,
                    format!(
                        "`{word}` objects after `bounded_by {{ clipped_by }}` (or the reverse) linked the two: POV-Ray refuses this too"
                    ),
                ));
            }
            self.bound_clip_objects()?
        };
        let local = obj.local();
        let list: Vec<Obj> = list
            .into_iter()
            .map(|mut o| {
                o.apply(local * transform);
                o
            })
            .collect();
        if linked {
            obj.bound_is_clip = !list.is_empty();
        }
        let mine = if bounds {
            &mut obj.bounded_by
        } else {
            &mut obj.clipped_by
        };
        if linked {
            *mine = list;
        } else {
            mine.extend(list);
        }
        Ok(())
    }

    /// The objects of a `bounded_by` or `clipped_by` block and the
    /// transforms after them (which move them all), up to its `}`.
    fn bound_clip_objects(&mut self) -> Result<(Vec<Obj>, DAffine3)> {
        let mut list = Vec::new();
        let mut transform = DAffine3::IDENTITY;
        let is_transform = |w: Option<&str>| {
            matches!(
                w,
                Some("translate" | "rotate" | "scale" | "matrix" | "transform")
            )
        };
        while self.peek()? != Some(Tok::Punct('}')) && !is_transform(self.peek_word()?.as_deref()) {
            if let Some(o) = self.object_statement()? {
                list.push(o);
            }
        }
        while let Some(w) = self.peek_word()? {
            match self.transform_item(&w)? {
                Some(t) => transform = t * transform,
                None => break,
            }
        }
        self.expect('}')?;
        Ok((list, transform))
    }
}

/// `o`, given in the space of an object whose transform is `t`, in that
/// object's parent space.
fn placed(o: &Obj, t: DAffine3) -> Obj {
    let mut o = o.clone();
    o.apply(t);
    o
}

/// The polynomial of a POV-Ray `poly` of order `n`: its coefficients belong
/// to the monomials x^i y^j z^k (i + j + k ≤ n) in POV-Ray's order, by
/// falling power of x, then of y, then of z.
pub fn poly_terms(n: u32, v: &[f64]) -> Trivariate {
    let mut terms = Vec::with_capacity(v.len());
    let mut index = 0;
    for i in (0..=n).rev() {
        for j in (0..=n - i).rev() {
            for k in (0..=n - i - j).rev() {
                if v[index] != 0.0 {
                    terms.push(([i as u8, j as u8, k as u8], v[index]));
                }
                index += 1;
            }
        }
    }
    Trivariate::from_terms(terms)
}

/// Whether a pigment lets all light through (POV-Ray's `Clear`).
pub fn clear(p: &Pigment) -> bool {
    // Filtered light takes the pigment's colour: only a white filter (or
    // transmit, which is uncoloured) lets all of it through.
    matches!(p, Pigment::Colour(c)
        if c[3] + c[4] >= 1.0 && (c[3] == 0.0 || c[..3].iter().all(|&v| v >= 1.0)))
}
