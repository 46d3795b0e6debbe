//! Values of POV-Ray's language and the expressions that make numbers,
//! vectors and colours: `+ - * /`, comparisons and `& | !` (for `#if`),
//! `< … >` vectors, `x y z`, `pi`, `image_width`, the common functions, and
//! colours (`rgb`, `rgbf`, `rgbt`, `rgbft`, `color red … green …`).

use glam::DAffine3;

use super::lex::Tok;
use super::object::Obj;
use super::parse::Parser;
use super::texture::{Interior, Pigment, Texture};
use crate::error::Result;
use crate::shading::Finish;
use crate::suggest;

/// What a name can be declared as.
#[derive(Clone, Debug)]
pub enum Value {
    Float(f64),
    /// 2 to 5 numbers; a colour is 5: red, green, blue, filter, transmit.
    Vector(Vec<f64>),
    /// A string (read, not used: strings name fonts and files).
    Str,
    Object(Box<Obj>),
    Texture(Box<Texture>),
    Pigment(Pigment),
    Finish(Finish),
    /// An interior's index of refraction.
    Interior(Interior),
    Transform(DAffine3),
    /// A declared camera, which `camera { NAME … }` starts from.
    Camera(Box<super::camera::CameraSpec>),
    /// A declared `sky_sphere`'s colour, which `sky_sphere { NAME … }`
    /// starts from.
    Sky(glam::DVec3),
    /// A declared colour map.
    ColourMap(super::patterns::ColourMap),
    /// An array, shared: a macro's parameter is the caller's array.
    Array(super::arrays::SharedArray),
    /// A `#macro`: its body and parameters.
    Macro(std::rc::Rc<super::macros::Macro>),
    /// Something outside the subset (its keyword), skipped where declared
    /// and warned about where used.
    Unsupported(String),
}

/// The object keywords a declaration or a scene can start with.
pub const OBJECT_KEYWORDS: &[&str] = &[
    "sphere",
    "box",
    "cylinder",
    "cone",
    "plane",
    "torus",
    "disc",
    "quadric",
    "cubic",
    "quartic",
    "poly",
    "mesh",
    "mesh2",
    "triangle",
    "smooth_triangle",
    "union",
    "intersection",
    "difference",
    "merge",
    "object",
    "light_source",
    "light_group",
];

/// Keywords of objects and values outside the subset: skipped with a warning.
pub const UNSUPPORTED: &[&str] = &[
    "isosurface",
    "parametric",
    "blob",
    "height_field",
    "julia_fractal",
    "lathe",
    "prism",
    "sor",
    "superellipsoid",
    "sphere_sweep",
    "text",
    "bicubic_patch",
    "polygon",
    "function",
    "spline",
    "media",
    "rainbow",
    "material",
    "normal",
    "density",
    "color_map",
    "colour_map",
    "pigment_map",
    "normal_map",
    "texture_map",
    "photons",
    "radiosity",
    "ovus",
];

pub(super) const COLOUR_WORDS: &[&str] = &[
    "rgb", "rgbf", "rgbt", "rgbft", "srgb", "srgbf", "srgbt", "srgbft",
];

/// The weights of red, green and blue in a colour's `.gray` (POV-Ray 3.7's
/// `RED2GRAY`, `GREEN2GRAY`, `BLUE2GRAY`).
const GREY: [f64; 3] = [0.297, 0.589, 0.114];

impl Parser {
    /// The right-hand side of `#declare NAME =`.
    pub fn value(&mut self) -> Result<Value> {
        let loc = self.here();
        let word = self.peek_word()?;
        if let Some(w) = word.as_deref() {
            if OBJECT_KEYWORDS.contains(&w) {
                return Ok(match self.object_statement()? {
                    Some(obj) => Value::Object(Box::new(obj)),
                    None => Value::Unsupported(w.to_owned()),
                });
            }
            match w {
                "texture" => {
                    self.next()?;
                    let texture = self.texture_block()?;
                    // Layers over the first: POV-Ray's layered texture.
                    // Looked for in the raw tokens: a directive or a macro
                    // call after the declaration may use its name, so
                    // neither runs here.
                    while matches!(self.raw().map(|t| t.tok), Some(Tok::Word(w)) if w == "texture")
                    {
                        let at = self.here();
                        self.skip_warning(
                            at,
                            "texture",
                            "a layered texture: only its first layer is drawn",
                        );
                        self.next()?;
                        self.texture_block()?;
                    }
                    return Ok(Value::Texture(Box::new(texture)));
                }
                "pigment" => {
                    self.next()?;
                    return Ok(Value::Pigment(self.pigment_block()?));
                }
                "finish" => {
                    self.next()?;
                    return Ok(Value::Finish(self.finish_block(None)?));
                }
                "interior" => {
                    self.next()?;
                    return Ok(Value::Interior(self.interior_block()?));
                }
                "transform" => {
                    self.next()?;
                    return Ok(Value::Transform(self.transform_block()?));
                }
                "camera" => {
                    self.next()?;
                    return Ok(Value::Camera(Box::new(self.camera_block()?)));
                }
                "array" => {
                    self.next()?;
                    return self.array_value(loc);
                }
                "sky_sphere" => {
                    self.next()?;
                    return Ok(match self.sky_sphere_block()? {
                        Some(colour) => Value::Sky(colour),
                        None => Value::Unsupported("sky_sphere without a pigment".into()),
                    });
                }
                _ => {}
            }
            if matches!(w, "color_map" | "colour_map") {
                self.next()?;
                return Ok(Value::ColourMap(self.colour_map_block()?));
            }
            if UNSUPPORTED.contains(&w) || STRING_FUNCTIONS.contains(&w) {
                self.next()?;
                self.skip_parens()?;
                self.skip_brackets()?;
                if self.peek()? == Some(Tok::Punct('{')) {
                    self.skip_block()?;
                }
                return Ok(Value::Unsupported(w.to_owned()));
            }
            if let Some(v) = self.symbol(w)
                && !matches!(v, Value::Float(_) | Value::Vector(_))
            {
                let v = v.clone();
                self.next()?;
                if matches!(v, Value::Macro(_)) {
                    let why = self.not_run(w);
                    self.skip_warning(loc, w, &format!("{why}: its call is skipped"));
                    self.skip_parens()?;
                    return Ok(Value::Unsupported(format!("{w}()")));
                }
                return Ok(v);
            }
        }
        if let Some(Tok::Str(_)) = self.peek()? {
            self.next()?;
            return Ok(Value::Str);
        }
        self.held(|p| p.expression(false))
    }

    /// A number.
    pub fn float(&mut self) -> Result<f64> {
        let loc = self.here();
        match self.expression(false)? {
            Value::Float(v) => Ok(v),
            Value::Vector(v) => Ok(v[0]),
            _ => Err(self.error_at(loc, "expected a number")),
        }
    }

    /// A 3-vector; a number n stands for <n, n, n>, and a 2-vector <a, b>
    /// for <a, b, 0>, as in POV-Ray (the missing component is zero, as in
    /// its vector arithmetic; checked against POV-Ray 3.7's render of a
    /// `translate <1, 0.5>`).
    pub fn vector(&mut self) -> Result<glam::DVec3> {
        let loc = self.here();
        match self.expression(false)? {
            Value::Float(v) => Ok(glam::DVec3::splat(v)),
            Value::Vector(v) => Ok(glam::DVec3::new(
                v[0],
                v[1],
                v.get(2).copied().unwrap_or(0.0),
            )),
            _ => Err(self.error_at(loc, "expected a vector <x, y, z>")),
        }
    }

    /// An expression. Comparisons and `? :` are read only `in_parens`, as
    /// POV-Ray does: elsewhere `<` starts the next vector (`box { <0, 0, 0>
    /// <1, 1, 1> }`, without a comma, is a box in POV-Ray) and `>` closes one.
    pub fn expression(&mut self, in_parens: bool) -> Result<Value> {
        self.nested(|p| p.conditional(in_parens))
    }

    fn conditional(&mut self, in_parens: bool) -> Result<Value> {
        let cond = self.or(in_parens)?;
        if in_parens && self.eat('?')? {
            let a = self.expression(in_parens)?;
            self.expect(':')?;
            let b = self.expression(in_parens)?;
            return Ok(if truth(&cond) { a } else { b });
        }
        Ok(cond)
    }

    fn or(&mut self, in_parens: bool) -> Result<Value> {
        let mut a = self.and(in_parens)?;
        while self.eat('|')? {
            let b = self.and(in_parens)?;
            a = Value::Float(f64::from(u8::from(truth(&a) || truth(&b))));
        }
        Ok(a)
    }

    fn and(&mut self, in_parens: bool) -> Result<Value> {
        let mut a = self.comparison(in_parens)?;
        while self.eat('&')? {
            let b = self.comparison(in_parens)?;
            a = Value::Float(f64::from(u8::from(truth(&a) && truth(&b))));
        }
        Ok(a)
    }

    fn comparison(&mut self, in_parens: bool) -> Result<Value> {
        let mut a = self.sum()?;
        loop {
            let op = match self.peek()? {
                Some(Tok::Punct(c)) if in_parens && "=ln<>g".contains(c) => c,
                _ => return Ok(a),
            };
            let loc = self.here();
            self.next()?;
            let b = self.sum()?;
            let (x, y) = (self.scalar(&a, loc)?, self.scalar(&b, loc)?);
            let r = match op {
                '=' => x == y,
                'n' => x != y,
                '<' => x < y,
                '>' => x > y,
                'l' => x <= y,
                _ => x >= y,
            };
            a = Value::Float(f64::from(u8::from(r)));
        }
    }

    pub(super) fn sum(&mut self) -> Result<Value> {
        let mut a = self.product()?;
        loop {
            let loc = self.here();
            let op = if self.eat('+')? {
                '+'
            } else if self.eat('-')? {
                '-'
            } else {
                return Ok(a);
            };
            let b = self.product()?;
            a = self.arith(a, b, op, loc)?;
        }
    }

    fn product(&mut self) -> Result<Value> {
        let mut a = self.unary()?;
        loop {
            let loc = self.here();
            let op = if self.eat('*')? {
                '*'
            } else if self.eat('/')? {
                '/'
            } else {
                return Ok(a);
            };
            let b = self.unary()?;
            a = self.arith(a, b, op, loc)?;
        }
    }

    fn unary(&mut self) -> Result<Value> {
        self.nested(Parser::unary_inner)
    }

    fn unary_inner(&mut self) -> Result<Value> {
        let loc = self.here();
        if self.eat('-')? {
            let v = self.unary()?;
            return self.arith(Value::Float(0.0), v, '-', loc);
        }
        if self.eat('+')? {
            return self.unary();
        }
        if self.eat('!')? {
            let v = self.unary()?;
            return Ok(Value::Float(f64::from(u8::from(!truth(&v)))));
        }
        let mut v = self.primary()?;
        // `.x`, `.red` and the like pick one component; `.gray` weighs a
        // colour's three, as POV-Ray's GREY_SCALE does.
        while self.peek()? == Some(Tok::Punct('.')) {
            self.next()?;
            let name = self.word()?;
            if matches!(name.as_str(), "gray" | "grey") {
                let rgb = match v {
                    Value::Vector(c) if c.len() >= 3 => [c[0], c[1], c[2]],
                    Value::Float(f) => [f; 3],
                    _ => {
                        return Err(self.error_at(
                            loc,
                            format!("`.{name}` of a value without three components"),
                        ));
                    }
                };
                v = Value::Float(GREY[0] * rgb[0] + GREY[1] * rgb[1] + GREY[2] * rgb[2]);
                continue;
            }
            let index = match name.as_str() {
                "x" | "u" | "red" => 0,
                "y" | "v" | "green" => 1,
                "z" | "blue" => 2,
                "t" | "filter" => 3,
                "transmit" => 4,
                _ => return Err(self.error_at(loc, format!("unknown component `.{name}`"))),
            };
            v = match v {
                Value::Vector(c) if index < c.len() => Value::Float(c[index]),
                Value::Float(f) => Value::Float(f),
                _ => return Err(self.error_at(loc, format!("`.{name}` of a value without it"))),
            };
        }
        Ok(v)
    }

    fn primary(&mut self) -> Result<Value> {
        let loc = self.here();
        // A macro called where an operand is read: its body's tokens stand
        // in the call's place, as POV-Ray substitutes them.
        if let Some(Tok::Word(w)) = self.peek()?
            && self.calls_macro(&w)
        {
            self.advance();
            self.call_macro(&w, loc)?;
            return self.primary();
        }
        match self.next()? {
            Tok::Number(v) => Ok(Value::Float(v)),
            Tok::Punct('(') => {
                let v = self.expression(true)?;
                self.expect(')')?;
                Ok(v)
            }
            Tok::Punct('<') => {
                let items = self.numbers_to_bracket()?;
                if !(2..=5).contains(&items.len()) {
                    return Err(self.error_at(
                        loc,
                        format!("a vector has 2 to 5 numbers, this one {}", items.len()),
                    ));
                }
                Ok(Value::Vector(items))
            }
            Tok::Word(w) => self.word_value(&w, loc),
            other => Err(self.error_at(
                loc,
                format!(
                    "expected a number or a vector, found {}",
                    super::lex::describe(&other)
                ),
            )),
        }
    }

    /// The numbers of a `< … >` after its `<`, up to and with its `>`.
    /// Commas are optional, as in POV-Ray: `<1 2 3>` is `<1, 2, 3>`, and
    /// `<1 -2 3>` is `<-1, 3>`, since `1 -2` is a difference.
    pub(super) fn numbers_to_bracket(&mut self) -> Result<Vec<f64>> {
        let mut items = Vec::new();
        loop {
            let loc = self.here();
            let v = self.expression(false)?;
            items.push(self.scalar(&v, loc)?);
            // A comma before the `>` is allowed too, as POV-Ray allows it.
            self.eat(',')?;
            if self.eat('>')? {
                return Ok(items);
            }
        }
    }

    /// A word in an expression: a declared name, a constant, a function or
    /// a colour.
    fn word_value(&mut self, w: &str, loc: super::parse::Loc) -> Result<Value> {
        if let Some(v) = self.symbol(w) {
            return match v.clone() {
                Value::Macro(_) => {
                    let why = self.not_run(w);
                    self.skip_warning(loc, w, &format!("{why}: its call is skipped"));
                    self.skip_parens()?;
                    Ok(Value::Float(0.0))
                }
                Value::Unsupported(k) => Err(self.error_at(
                    loc,
                    format!("`{w}` was declared as `{k}`, which is not supported, and a value is needed here"),
                )),
                v @ (Value::Float(_) | Value::Vector(_)) => Ok(v),
                // Held (an `#if` condition), an element is read here, not
                // put in the word's place as `peek` does.
                Value::Array(a) if self.peek()? == Some(Tok::Punct('[')) => {
                    match self.element(w, &a, loc)? {
                        (v @ (Value::Float(_) | Value::Vector(_)), _) => Ok(v),
                        (_, shown) => Err(self.error_at(loc, format!("`{shown}` is not a number or a vector"))),
                    }
                }
                _ => Err(self.error_at(loc, format!("`{w}` is not a number or a vector here"))),
            };
        }
        let v3 = |x: f64, y: f64, z: f64| Ok(Value::Vector(vec![x, y, z]));
        match w {
            "x" => v3(1.0, 0.0, 0.0),
            "y" => v3(0.0, 1.0, 0.0),
            "z" => v3(0.0, 0.0, 1.0),
            "t" => Ok(Value::Vector(vec![0.0, 0.0, 0.0, 1.0])),
            "u" => Ok(Value::Vector(vec![1.0, 0.0])),
            "v" => Ok(Value::Vector(vec![0.0, 1.0])),
            "pi" => Ok(Value::Float(std::f64::consts::PI)),
            "tau" => Ok(Value::Float(std::f64::consts::TAU)),
            "true" | "yes" | "on" => Ok(Value::Float(1.0)),
            "false" | "no" | "off" => Ok(Value::Float(0.0)),
            "image_width" => Ok(Value::Float(f64::from(self.size.0))),
            "image_height" => Ok(Value::Float(f64::from(self.size.1))),
            // A still: POV-Ray's clock is 0 without an animation.
            "clock" | "clock_delta" | "frame_number" | "initial_clock" | "final_clock" => {
                Ok(Value::Float(0.0))
            }
            "clock_on" => Ok(Value::Float(0.0)),
            "version" => Ok(Value::Float(self.version)),
            "color" | "colour" => self.colour_rest(None),
            w if COLOUR_WORDS.contains(&w) || matches!(w, "red" | "green" | "blue") => {
                self.colour_rest(Some((w.to_owned(), loc)))
            }
            "dimensions" | "dimension_size" => self.array_function(w, loc),
            "defined" => {
                self.expect('(')?;
                let name = self.word()?;
                self.expect(')')?;
                Ok(Value::Float(f64::from(u8::from(
                    self.symbol(&name).is_some(),
                ))))
            }
            _ => {
                if let Some(v) = self.function(w, loc)? {
                    return Ok(v);
                }
                let hint = suggest::closest(w, self.symbol_names())
                    .map_or(String::new(), |c| format!("; did you mean `{c}`?"));
                Err(self.error_at(loc, format!("unknown name `{w}`{hint}")))
            }
        }
    }

    /// A number from a value that must be one.
    pub(super) fn scalar(&self, v: &Value, loc: super::parse::Loc) -> Result<f64> {
        match v {
            Value::Float(f) => Ok(*f),
            _ => Err(self.error_at(loc, "expected a number, found a vector")),
        }
    }

    /// `a op b` with POV-Ray's promotion of a number to a vector of the
    /// other's size.
    fn arith(&self, a: Value, b: Value, op: char, loc: super::parse::Loc) -> Result<Value> {
        let apply = |x: f64, y: f64| match op {
            '+' => x + y,
            '-' => x - y,
            '*' => x * y,
            _ => x / y,
        };
        Ok(match (a, b) {
            (Value::Float(x), Value::Float(y)) => Value::Float(apply(x, y)),
            (Value::Vector(v), Value::Float(y)) => {
                Value::Vector(v.iter().map(|&x| apply(x, y)).collect())
            }
            (Value::Float(x), Value::Vector(v)) => {
                Value::Vector(v.iter().map(|&y| apply(x, y)).collect())
            }
            (Value::Vector(mut v), Value::Vector(mut w)) => {
                let n = v.len().max(w.len());
                v.resize(n, 0.0);
                w.resize(n, 0.0);
                Value::Vector(v.iter().zip(&w).map(|(&x, &y)| apply(x, y)).collect())
            }
            _ => return Err(self.error_at(loc, "arithmetic on something that is not a number")),
        })
    }
}

/// String functions: a declaration made with one is a string, outside the subset.
pub const STRING_FUNCTIONS: &[&str] = &[
    "concat", "str", "chr", "substr", "strupr", "strlwr", "vstr", "datetime",
];

fn truth(v: &Value) -> bool {
    match v {
        Value::Float(f) => *f != 0.0,
        Value::Vector(v) => v.iter().any(|x| *x != 0.0),
        _ => true,
    }
}
