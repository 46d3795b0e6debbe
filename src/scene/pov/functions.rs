//! The built-in functions of POV-Ray's expressions the subset evaluates:
//! `sqrt`, `sin`, `pow`, `max`, `vlength`, `vcross`, `vaxis_rotate`,
//! `select` and the like,
//! and the random streams of `seed` and `rand`.

use super::parse::{Loc, Parser};
use super::value::Value;
use crate::error::Result;
use crate::scene::solids::rotation;

impl Parser {
    /// A call of a built-in function `name`, if it is one.
    pub(super) fn function(&mut self, name: &str, loc: Loc) -> Result<Option<Value>> {
        let arity = match name {
            "abs" | "acos" | "asin" | "atan" | "ceil" | "cos" | "cosh" | "degrees" | "exp"
            | "floor" | "int" | "ln" | "log" | "radians" | "sin" | "sinh" | "sqrt" | "tan"
            | "tanh" | "vlength" | "vnormalize" | "sqr" | "seed" | "rand" => 1,
            "atan2" | "div" | "mod" | "pow" | "vcross" | "vdot" | "max" | "min" | "vrotate" => 2,
            "select" | "vaxis_rotate" => 3,
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
        match name {
            "seed" => return Ok(Some(self.seed(self.scalar(&args[0], loc)?))),
            "rand" => return self.rand(self.scalar(&args[0], loc)?, loc).map(Some),
            _ => {}
        }
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
            // A about the axis B by F degrees, turning as `vrotate` turns
            // about x, y and z (POV-Ray's axis rotation matrix is this one,
            // for its row vectors).
            "vaxis_rotate" => {
                let axis = vec3(self, &args[1])?.normalize_or_zero();
                if axis == glam::DVec3::ZERO {
                    return Err(self.error_at(loc, "`vaxis_rotate` needs an axis that is not zero"));
                }
                let turn = glam::DMat3::from_axis_angle(axis, f(2)?.to_radians());
                out(turn * vec3(self, &args[0])?)
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
}

/// POV-Ray 3.7's random streams: `seed(n)` starts a stream and gives its
/// number (0 for a scene's first, counted in the order they are made), and
/// `rand(s)` steps stream s and gives its next number in [0, 1]. The
/// generator is the linear congruence x <- 1812433253 x + 12345 mod 2^32,
/// and a number is x / (2^32 - 1); a seed is cut to a C `int` first, as
/// POV-Ray converts it, so a fraction is truncated and a seed outside the
/// `int` range (or NaN) starts from -2^31. Checked against POV-Ray 3.7's
/// `#debug` output for several seeds (see the tests), so a scene that
/// scatters objects with `rand` places them where POV-Ray does.
impl Parser {
    fn seed(&mut self, n: f64) -> Value {
        let start =
            if n.is_nan() || n <= f64::from(i32::MIN) - 1.0 || n >= f64::from(i32::MAX) + 1.0 {
                i32::MIN
            } else {
                n.trunc() as i32
            };
        // The bits of the C int, as POV-Ray's unsigned state takes them.
        self.streams.push(start as u32);
        Value::Float(self.streams.len() as f64 - 1.0)
    }

    fn rand(&mut self, stream: f64, loc: Loc) -> Result<Value> {
        let index = stream.trunc();
        let Some(state) = (index >= 0.0)
            .then(|| self.streams.get_mut(index as usize))
            .flatten()
        else {
            return Err(self.error_at(
                loc,
                format!(
                    "`rand({stream})`: no random stream has that number \
                     (a stream is made by `seed`: `#declare S = seed(1); rand(S)`)"
                ),
            ));
        };
        *state = state.wrapping_mul(1_812_433_253).wrapping_add(12_345);
        Ok(Value::Float(f64::from(*state) / f64::from(u32::MAX)))
    }
}
