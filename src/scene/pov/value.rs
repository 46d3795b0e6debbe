//! Values of POV-Ray's language and the expressions that make numbers,
//! vectors and colours: `+ - * /`, comparisons and `& | !` (for `#if`),
//! `< … >` vectors, `x y z`, `pi`, `image_width`, the common functions, and
//! colours (`rgb`, `rgbf`, `rgbt`, `rgbft`, `color red … green …`).

use glam::DAffine3;

use super::lex::Tok;
use super::object::Obj;
use super::parse::Parser;
use super::texture::{Pigment, Texture};
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
    Interior(f64),
    Transform(DAffine3),
    /// A `#macro`: calling it is outside the subset.
    Macro,
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
    "union",
    "intersection",
    "difference",
    "merge",
    "object",
    "light_source",
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
    "triangle",
    "smooth_triangle",
    "function",
    "array",
    "spline",
    "media",
    "fog",
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

const COLOUR_WORDS: &[&str] = &[
    "rgb", "rgbf", "rgbt", "rgbft", "srgb", "srgbf", "srgbt", "srgbft",
];

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
                    while self.peek_word()?.as_deref() == Some("texture") {
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
                    self.skip_warning(loc, "camera", "a declared camera is not used");
                    self.skip_block()?;
                    return Ok(Value::Unsupported("camera".into()));
                }
                _ => {}
            }
            if matches!(w, "color_map" | "colour_map") {
                self.next()?;
                self.expect('{')?;
                let colours = self.map_colours()?;
                self.expect('}')?;
                return Ok(Value::Vector(super::texture::mean(&colours).to_vec()));
            }
            if UNSUPPORTED.contains(&w) || STRING_FUNCTIONS.contains(&w) {
                self.next()?;
                self.skip_parens()?;
                if self.peek()? == Some(Tok::Punct('[')) {
                    while !matches!(self.next()?, Tok::Punct(']')) {}
                }
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

    /// A 3-vector; a number n stands for <n, n, n>, as in POV-Ray.
    pub fn vector(&mut self) -> Result<glam::DVec3> {
        let loc = self.here();
        match self.expression(false)? {
            Value::Float(v) => Ok(glam::DVec3::splat(v)),
            Value::Vector(v) if v.len() >= 3 => Ok(glam::DVec3::new(v[0], v[1], v[2])),
            Value::Vector(v) => Err(self.error_at(
                loc,
                format!("expected a vector of 3 numbers, found {}", v.len()),
            )),
            _ => Err(self.error_at(loc, "expected a vector <x, y, z>")),
        }
    }

    /// An expression; `in_vector` leaves `<` and `>` to the vector's brackets.
    pub fn expression(&mut self, in_vector: bool) -> Result<Value> {
        let cond = self.or(in_vector)?;
        if self.eat('?')? {
            let a = self.expression(in_vector)?;
            self.expect(':')?;
            let b = self.expression(in_vector)?;
            return Ok(if truth(&cond) { a } else { b });
        }
        Ok(cond)
    }

    fn or(&mut self, in_vector: bool) -> Result<Value> {
        let mut a = self.and(in_vector)?;
        while self.eat('|')? {
            let b = self.and(in_vector)?;
            a = Value::Float(f64::from(u8::from(truth(&a) || truth(&b))));
        }
        Ok(a)
    }

    fn and(&mut self, in_vector: bool) -> Result<Value> {
        let mut a = self.comparison(in_vector)?;
        while self.eat('&')? {
            let b = self.comparison(in_vector)?;
            a = Value::Float(f64::from(u8::from(truth(&a) && truth(&b))));
        }
        Ok(a)
    }

    fn comparison(&mut self, in_vector: bool) -> Result<Value> {
        let mut a = self.sum()?;
        loop {
            let op = match self.peek()? {
                Some(Tok::Punct(c)) if "=ln".contains(c) || (!in_vector && "<>g".contains(c)) => c,
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

    fn sum(&mut self) -> Result<Value> {
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
        // `.x`, `.red` and the like pick one component.
        while self.peek()? == Some(Tok::Punct('.')) {
            self.next()?;
            let name = self.word()?;
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
        match self.next()? {
            Tok::Number(v) => Ok(Value::Float(v)),
            Tok::Punct('(') => {
                let v = self.expression(false)?;
                self.expect(')')?;
                Ok(v)
            }
            Tok::Punct('<') => {
                let mut items = vec![self.scalar_in_vector()?];
                while self.eat(',')? {
                    items.push(self.scalar_in_vector()?);
                }
                self.expect('>')?;
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

    fn scalar_in_vector(&mut self) -> Result<f64> {
        let loc = self.here();
        let v = self.expression(true)?;
        self.scalar(&v, loc)
    }

    /// A word in an expression: a declared name, a constant, a function or
    /// a colour.
    fn word_value(&mut self, w: &str, loc: super::parse::Loc) -> Result<Value> {
        if let Some(v) = self.symbol(w) {
            return match v.clone() {
                Value::Macro => {
                    self.skip_warning(loc, w, "a macro is not run (its call is skipped)");
                    self.skip_parens()?;
                    Ok(Value::Float(0.0))
                }
                Value::Unsupported(k) => Err(self.error_at(
                    loc,
                    format!("`{w}` was declared as `{k}`, which is not supported, and a value is needed here"),
                )),
                v @ (Value::Float(_) | Value::Vector(_)) => Ok(v),
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
            "version" => Ok(Value::Float(3.7)),
            "color" | "colour" => self.colour_rest(None),
            w if COLOUR_WORDS.contains(&w) || matches!(w, "red" | "green" | "blue") => {
                self.colour_rest(Some((w.to_owned(), loc)))
            }
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

    /// A call of a built-in function `name`, if it is one.
    fn function(&mut self, name: &str, loc: super::parse::Loc) -> Result<Option<Value>> {
        let arity = match name {
            "abs" | "acos" | "asin" | "atan" | "ceil" | "cos" | "cosh" | "degrees" | "exp"
            | "floor" | "int" | "ln" | "log" | "radians" | "sin" | "sinh" | "sqrt" | "tan"
            | "tanh" | "vlength" | "vnormalize" | "sqr" => 1,
            "atan2" | "div" | "mod" | "pow" | "vcross" | "vdot" | "max" | "min" | "vrotate" => 2,
            "select" => 3,
            _ => return Ok(None),
        };
        self.expect('(')?;
        let mut args = vec![self.expression(false)?];
        while self.eat(',')? {
            args.push(self.expression(false)?);
        }
        self.expect(')')?;
        let variadic = matches!(name, "max" | "min" | "select");
        if args.len() != arity && !(variadic && args.len() >= arity.min(2)) {
            return Err(self.error_at(
                loc,
                format!("`{name}` takes {arity} argument(s), found {}", args.len()),
            ));
        }
        let vec3 = |p: &Parser, v: &Value| -> Result<glam::DVec3> {
            match v {
                Value::Vector(c) if c.len() >= 3 => Ok(glam::DVec3::new(c[0], c[1], c[2])),
                Value::Float(f) => Ok(glam::DVec3::splat(*f)),
                _ => Err(p.error_at(loc, format!("`{name}` takes vectors"))),
            }
        };
        let out = |v: glam::DVec3| Value::Vector(v.to_array().to_vec());
        let f = |i: usize| self.scalar(&args[i], loc);
        Ok(Some(match name {
            "vlength" => Value::Float(vec3(self, &args[0])?.length()),
            "vnormalize" => out(vec3(self, &args[0])?.normalize_or_zero()),
            "vcross" => out(vec3(self, &args[0])?.cross(vec3(self, &args[1])?)),
            "vdot" => Value::Float(vec3(self, &args[0])?.dot(vec3(self, &args[1])?)),
            "vrotate" => {
                let r = vec3(self, &args[1])? * (std::f64::consts::PI / 180.0);
                out(rotation(r).transform_vector3(vec3(self, &args[0])?))
            }
            "select" => {
                let c = f(0)?;
                let pick = if c < 0.0 {
                    1
                } else if c == 0.0 || args.len() == 3 {
                    2
                } else {
                    3
                };
                args[pick.min(args.len() - 1)].clone()
            }
            "max" | "min" => {
                let mut m = f(0)?;
                for i in 1..args.len() {
                    let v = f(i)?;
                    m = if name == "max" { m.max(v) } else { m.min(v) };
                }
                Value::Float(m)
            }
            _ => {
                let a = f(0)?;
                let b = if arity == 2 { f(1)? } else { 0.0 };
                Value::Float(match name {
                    "abs" => a.abs(),
                    "acos" => a.acos(),
                    "asin" => a.asin(),
                    "atan" => a.atan(),
                    "ceil" => a.ceil(),
                    "cos" => a.cos(),
                    "cosh" => a.cosh(),
                    "degrees" => a.to_degrees(),
                    "exp" => a.exp(),
                    "floor" => a.floor(),
                    "int" => a.trunc(),
                    "ln" => a.ln(),
                    "log" => a.log10(),
                    "radians" => a.to_radians(),
                    "sin" => a.sin(),
                    "sinh" => a.sinh(),
                    "sqrt" => a.sqrt(),
                    "sqr" => a * a,
                    "tan" => a.tan(),
                    "tanh" => a.tanh(),
                    "atan2" => a.atan2(b),
                    "div" => (a / b).trunc(),
                    "mod" => a % b,
                    _ => a.powf(b),
                })
            }
        }))
    }

    /// A number from a value that must be one.
    fn scalar(&self, v: &Value, loc: super::parse::Loc) -> Result<f64> {
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

    /// A colour: after `color`/`colour` (already taken, `first` None) or
    /// starting with the colour word `first`; then any `red`, `green`,
    /// `blue`, `filter`, `transmit` that change one component.
    pub fn colour_rest(&mut self, first: Option<(String, super::parse::Loc)>) -> Result<Value> {
        let mut c = [0.0f64; 5];
        let mut word = first;
        if word.is_none()
            && let Some(w) = self.peek_word()?
            && (COLOUR_WORDS.contains(&w.as_str())
                || matches!(w.as_str(), "red" | "green" | "blue" | "filter" | "transmit"))
        {
            let loc = self.here();
            self.next()?;
            word = Some((w, loc));
        }
        match word {
            None => {
                let loc = self.here();
                let v = self.sum()?;
                c = self.as_colour(&v, loc)?;
            }
            Some((w, loc)) => {
                let w = if w.starts_with("srgb") {
                    self.warn(loc, format!("`{w}` is read as linear `{}`", &w[1..]));
                    w[1..].to_owned()
                } else {
                    w
                };
                self.colour_word(&w, &mut c, loc)?;
            }
        }
        while let Some(w) = self.peek_word()? {
            if !(COLOUR_WORDS.contains(&w.as_str())
                || matches!(w.as_str(), "red" | "green" | "blue" | "filter" | "transmit"))
            {
                break;
            }
            let loc = self.here();
            self.next()?;
            self.colour_word(&w, &mut c, loc)?;
        }
        Ok(Value::Vector(c.to_vec()))
    }

    fn colour_word(&mut self, w: &str, c: &mut [f64; 5], loc: super::parse::Loc) -> Result<()> {
        let component = |w: &str| match w {
            "red" => 0,
            "green" => 1,
            "blue" => 2,
            "filter" => 3,
            _ => 4,
        };
        if matches!(w, "red" | "green" | "blue" | "filter" | "transmit") {
            c[component(w)] = self.float()?;
            return Ok(());
        }
        let n = match w {
            "rgb" => 3,
            "rgbf" | "rgbt" => 4,
            _ => 5,
        };
        let vloc = self.here();
        let v = self.sum()?;
        let values: Vec<f64> = match v {
            Value::Float(f) => vec![f; n],
            Value::Vector(v) if v.len() >= n => v[..n].to_vec(),
            _ => {
                return Err(self.error_at(vloc, format!("`{w}` takes a vector of {n} numbers")));
            }
        };
        let _ = loc;
        *c = [0.0; 5];
        c[..3].copy_from_slice(&values[..3]);
        match w {
            "rgbf" => c[3] = values[3],
            "rgbt" => c[4] = values[3],
            "rgbft" => {
                c[3] = values[3];
                c[4] = values[4];
            }
            _ => {}
        }
        Ok(())
    }

    /// A value as a colour: 3 numbers are rgb, 4 rgbf, 5 rgbft; a number
    /// is grey.
    pub fn as_colour(&self, v: &Value, loc: super::parse::Loc) -> Result<[f64; 5]> {
        let mut c = [0.0; 5];
        match v {
            Value::Float(f) => c[..3].copy_from_slice(&[*f; 3]),
            Value::Vector(v) if v.len() >= 3 => c[..v.len()].copy_from_slice(v),
            _ => return Err(self.error_at(loc, "expected a colour")),
        }
        Ok(c)
    }
}

/// POV-Ray's rotation by `r` (radians) about x, then y, then z.
pub fn rotation(r: glam::DVec3) -> DAffine3 {
    DAffine3::from_rotation_z(r.z) * DAffine3::from_rotation_y(r.y) * DAffine3::from_rotation_x(r.x)
}

/// String functions: a declaration made with one is a string, outside the subset.
const STRING_FUNCTIONS: &[&str] = &[
    "concat", "str", "chr", "substr", "strupr", "strlwr", "vstr", "datetime",
];

fn truth(v: &Value) -> bool {
    match v {
        Value::Float(f) => *f != 0.0,
        Value::Vector(v) => v.iter().any(|x| *x != 0.0),
        _ => true,
    }
}
