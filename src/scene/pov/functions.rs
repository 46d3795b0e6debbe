//! The built-in functions of POV-Ray's expressions the subset evaluates:
//! `sqrt`, `sin`, `pow`, `max`, `vlength`, `vcross`, `select` and the like.

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
}
