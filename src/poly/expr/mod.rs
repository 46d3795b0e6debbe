//! Algebraic surfaces written as expressions in x, y, z, such as
//! `(x^2+y^2+z^2+R^2-r^2)^2 - 4*R^2*(x^2+y^2)`, parsed and expanded to a
//! [`Trivariate`] polynomial.
//!
//! # Grammar
//!
//! ```text
//! expr     = term { ("+" | "-") term }
//! term     = unary { ("*" | "/") unary }
//! unary    = ("-" | "+") unary | power
//! power    = primary [ "^" unary ]          (right-associative: 2^3^2 = 2^9)
//! primary  = number | name | "(" expr ")"
//! number   = digits [ "." digits ] [ ("e" | "E") [ "+" | "-" ] digits ]   (also ".5", "1.")
//! name     = (letter | "_") { letter | digit | "_" }                      (ASCII)
//! ```
//!
//! - Precedence, tightest first: `^`, unary minus and plus, `*` and `/`,
//!   binary `+` and `-`. So `-x^2` is `-(x^2)` and `-x*y` is `(-x)*y`;
//!   `x*-y` and `x^-1` are syntactically fine (the latter is then refused).
//! - Names are case-sensitive: `x`, `y`, `z` are the variables, any other
//!   name must be one of the scene's constants. A constant named x, y or z is
//!   refused where it is used, since it would be ambiguous.
//! - `/` divides only by a subexpression whose value is a nonzero constant
//!   (it may contain constants and even cancel out x, as in `(x-x+2)`).
//! - The exponent after `^` is any subexpression whose value is a
//!   non-negative integer constant: `x^3`, `x^(2*n)` with a constant `n = 2`.
//!   Negative or fractional exponents are refused, also on constant bases
//!   (write `1/R` or give the constant its value directly).
//! - No implicit multiplication: `2x`, `x y` and `(x)(y)` are errors; write `*`.
//! - Every subexpression's degree must stay within [`MAX_DEGREE`]; this is
//!   checked before multiplying, so `(x+y+z)^1000` fails at once. A power of
//!   a constant base has no such limit (`2^100` is fine).
//! - The whole expression must depend on x, y or z.
//! - Columns in errors count characters (not bytes) from 1 across the whole
//!   text, newlines included.

use std::fmt;

use crate::poly::MAX_DEGREE;
use crate::poly::trivariate::Trivariate;
use crate::poly::univariate::{log2_floor, scale_pow2_normal};

/// Why an expression was refused and where: the scene loader adds the file
/// and the key around it.
#[derive(Clone, Debug, PartialEq)]
pub struct ParseError {
    /// 1-based, in characters.
    pub column: usize,
    /// What was expected and what was found, or what is wrong with the value.
    pub message: String,
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "column {}: {}", self.column, self.message)
    }
}

impl std::error::Error for ParseError {}

/// Nesting deeper than this (parentheses, unary signs, exponents) is refused
/// rather than risking the stack: no real surface comes close.
const MAX_DEPTH: usize = 200;

/// Parses `text` and expands it to a polynomial in x, y, z. `constants` are
/// the scene's named constants; see the module documentation for the grammar
/// and the rules.
pub fn parse(text: &str, constants: &[(&str, f64)]) -> Result<Trivariate, ParseError> {
    let tokens = lex(text);
    if tokens.len() == 1 {
        return Err(error(1, "the expression is empty"));
    }
    let mut parser = Parser {
        tokens,
        pos: 0,
        constants,
        depth: 0,
    };
    let value = parser.expr()?;
    let token = parser.peek();
    match token.kind {
        Kind::End => {}
        Kind::RParen => {
            return Err(error(token.column, "this ')' has no matching '('"));
        }
        _ => return Err(parser.expected_operator(false)),
    }
    let Value { poly, exp, .. } = value;
    if poly.is_zero() {
        return Err(error(1, "the expression is identically zero"));
    }
    if poly.degree() == 0 {
        return Err(error(1, "the expression does not depend on x, y or z"));
    }
    // Back at the scale written where every coefficient is a normal f64
    // there (then exactly the plain f64 expansion); otherwise the same
    // surface at the normalised scale.
    let written = i32::try_from(exp).ok().filter(|&e| {
        poly.terms()
            .iter()
            .all(|&(_, c)| (-1022..=1023).contains(&(log2_floor(c) + e)))
    });
    Ok(written.map_or(poly.clone(), |e| poly.scaled_pow2(e)))
}

fn error(column: usize, message: impl Into<String>) -> ParseError {
    ParseError {
        column,
        message: message.into(),
    }
}

#[derive(Clone, Debug, PartialEq)]
enum Kind {
    Number(f64),
    Name,
    Plus,
    Minus,
    Star,
    Slash,
    Caret,
    LParen,
    RParen,
    /// A character no token starts with; reported by the parser, so the
    /// first problem in reading order is the one named.
    Other,
    End,
}

#[derive(Clone, Debug)]
struct Token {
    kind: Kind,
    text: String,
    column: usize,
}

impl Token {
    fn describe(&self) -> String {
        match self.kind {
            Kind::End => "the end of the expression".to_owned(),
            _ => format!("'{}'", self.text),
        }
    }
}

/// Splits the text into tokens, ending with `End` (whose column is one past
/// the last character). Never fails: odd characters become `Other`.
fn lex(text: &str) -> Vec<Token> {
    let chars: Vec<char> = text.chars().collect();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_whitespace() {
            i += 1;
            continue;
        }
        let start = i;
        let is_digit_at = |k: usize| chars.get(k).is_some_and(char::is_ascii_digit);
        let kind = if c.is_ascii_digit() || (c == '.' && is_digit_at(i + 1)) {
            while is_digit_at(i) {
                i += 1;
            }
            if chars.get(i) == Some(&'.') {
                i += 1;
                while is_digit_at(i) {
                    i += 1;
                }
            }
            // An exponent only when digits follow; otherwise the `e` starts a
            // name, and `2e` reads as implicit multiplication, reported there.
            if matches!(chars.get(i), Some('e' | 'E')) {
                let sign = usize::from(matches!(chars.get(i + 1), Some('+' | '-')));
                if is_digit_at(i + 1 + sign) {
                    i += 1 + sign;
                    while is_digit_at(i) {
                        i += 1;
                    }
                }
            }
            let literal: String = chars[start..i].iter().collect();
            // The lexed shape is always valid f64 syntax; a huge literal
            // parses as infinity and is refused where it is used.
            Kind::Number(literal.parse().unwrap_or(f64::NAN))
        } else if c.is_ascii_alphabetic() || c == '_' {
            while chars
                .get(i)
                .is_some_and(|&c| c.is_ascii_alphanumeric() || c == '_')
            {
                i += 1;
            }
            Kind::Name
        } else {
            i += 1;
            match c {
                '+' => Kind::Plus,
                '-' => Kind::Minus,
                '*' => Kind::Star,
                '/' => Kind::Slash,
                '^' => Kind::Caret,
                '(' => Kind::LParen,
                ')' => Kind::RParen,
                _ => Kind::Other,
            }
        };
        tokens.push(Token {
            kind,
            text: chars[start..i].iter().collect(),
            column: start + 1,
        });
    }
    tokens.push(Token {
        kind: Kind::End,
        text: String::new(),
        column: chars.len() + 1,
    });
    tokens
}

/// A parsed subexpression, poly·2^exp with poly normalised
/// ([`Trivariate::normalized`]), and the column it starts at, for errors
/// about the operand as a whole (a divisor, an exponent).
///
/// Why the separate power of two: k·F is the same surface as F for any
/// finite k ≠ 0, and carrying k's scale apart keeps every intermediate
/// coefficient a normal f64. Plain f64 expansion overflowed for
/// 1e308·(… + 11.8), and made 1e-310·F's coefficients subnormal, which the
/// threads that parse scenes read as zero ("identically zero"). Powers of
/// two are exact, so expressions within range expand exactly as before.
struct Value {
    poly: Trivariate,
    exp: i64,
    column: usize,
}

impl Value {
    fn new(poly: Trivariate, exp: i64, column: usize) -> Value {
        let (poly, shift) = poly.normalized();
        let exp = if poly.is_zero() {
            0
        } else {
            exp - i64::from(shift)
        };
        Value { poly, exp, column }
    }

    /// The value, if it does not depend on x, y or z: ±∞ beyond the f64
    /// range, 0 below the normal range.
    fn constant(&self) -> Option<f64> {
        let c = self.poly.constant_value()?;
        Some(scale_pow2_normal(c, clamp_exp(self.exp)))
    }

    /// self ± other (sign ±1), aligned on the larger scale; a term more
    /// than 2^1022 below the larger side's largest is negligible and goes.
    fn add(self, other: Value, sign: f64) -> Value {
        if other.poly.is_zero() {
            return self;
        }
        if self.poly.is_zero() {
            return Value {
                poly: other.poly.scale(sign),
                ..other
            };
        }
        let exp = self.exp.max(other.exp);
        let a = self.poly.scaled_pow2(clamp_exp(self.exp - exp));
        let b = other.poly.scaled_pow2(clamp_exp(other.exp - exp));
        let sum = if sign > 0.0 { a.add(&b) } else { a.sub(&b) };
        Value::new(sum, exp, self.column)
    }
}

/// An exponent difference as i32, saturated far beyond where any f64
/// scaling saturates anyway.
fn clamp_exp(e: i64) -> i32 {
    e.clamp(-4096, 4096) as i32
}

struct Parser<'a> {
    tokens: Vec<Token>,
    pos: usize,
    constants: &'a [(&'a str, f64)],
    depth: usize,
}

impl Parser<'_> {
    fn peek(&self) -> &Token {
        &self.tokens[self.pos]
    }

    fn advance(&mut self) -> Token {
        let token = self.tokens[self.pos].clone();
        if self.pos + 1 < self.tokens.len() {
            self.pos += 1;
        }
        token
    }

    fn expr(&mut self) -> Result<Value, ParseError> {
        let mut left = self.term()?;
        loop {
            let sign = match self.peek().kind {
                Kind::Plus => 1.0,
                Kind::Minus => -1.0,
                _ => return Ok(left),
            };
            let op = self.advance();
            let right = self.term()?;
            left = finite(left.add(right, sign), op.column)?;
        }
    }

    fn term(&mut self) -> Result<Value, ParseError> {
        let mut left = self.unary()?;
        loop {
            let kind = self.peek().kind.clone();
            if !matches!(kind, Kind::Star | Kind::Slash) {
                return Ok(left);
            }
            let op = self.advance();
            if kind == Kind::Star && self.peek().kind == Kind::Star {
                return Err(error(
                    self.peek().column,
                    "expected a number, a name or '(' but found '*' ('**' is not a power: write '^')",
                ));
            }
            let right = self.unary()?;
            let poly = if kind == Kind::Star {
                left.poly.checked_mul(&right.poly).ok_or_else(|| {
                    degree_error(
                        op.column,
                        "product",
                        left.poly.degree() + right.poly.degree(),
                    )
                })?
            } else {
                // The divisor's normalised value: its scale goes to exp.
                let divisor = right.poly.constant_value().ok_or_else(|| {
                    error(
                        right.column,
                        "cannot divide by an expression in x, y or z (only by constants)",
                    )
                })?;
                if right.poly.is_zero() {
                    return Err(error(right.column, "division by zero"));
                }
                left.poly.div_scalar(divisor)
            };
            let exp = if kind == Kind::Star {
                left.exp + right.exp
            } else {
                left.exp - right.exp
            };
            left = finite(Value::new(poly, exp, left.column), op.column)?;
        }
    }

    fn unary(&mut self) -> Result<Value, ParseError> {
        let column = self.peek().column;
        if self.depth >= MAX_DEPTH {
            return Err(error(
                column,
                format!("the expression nests more than {MAX_DEPTH} levels deep"),
            ));
        }
        self.depth += 1;
        let result = match self.peek().kind {
            Kind::Minus => {
                self.advance();
                self.unary().map(|v| Value {
                    poly: v.poly.neg(),
                    column,
                    ..v
                })
            }
            Kind::Plus => {
                self.advance();
                self.unary().map(|v| Value { column, ..v })
            }
            _ => self.power(),
        };
        self.depth -= 1;
        result
    }

    fn power(&mut self) -> Result<Value, ParseError> {
        let base = self.primary()?;
        if self.peek().kind != Kind::Caret {
            return Ok(base);
        }
        let caret = self.advance();
        let exponent = self.unary()?;
        let n = exponent.constant().ok_or_else(|| {
            error(
                exponent.column,
                "the exponent must be a constant, not depend on x, y or z",
            )
        })?;
        if !(n >= 0.0 && n.fract() == 0.0) {
            return Err(error(
                exponent.column,
                format!("the exponent must be a non-negative integer but it is {n}"),
            ));
        }
        let poly = if let Some(c) = base.poly.constant_value() {
            // A constant base has no degree to run away with; powf on an
            // integral exponent is exact where the result is representable.
            Trivariate::constant(c.powf(n))
        } else {
            let degree = base.poly.degree();
            if n > MAX_DEGREE as f64 {
                // Also covers exponents too large for any integer type.
                let message = if n <= 1e12 {
                    format!(
                        "this power has degree {}, above the limit of {MAX_DEGREE}",
                        degree as u64 * n as u64
                    )
                } else {
                    format!("the exponent {n} gives a degree above the limit of {MAX_DEGREE}")
                };
                return Err(error(caret.column, message));
            }
            base.poly
                .checked_pow(n as u32)
                .ok_or_else(|| degree_error(caret.column, "power", degree * n as usize))?
        };
        // The scale of the power: exp·n (n <= MAX_DEGREE unless the base is
        // a constant), refused where even that overflows.
        let exp = base
            .exp
            .checked_mul(n as i64)
            .filter(|e| e.unsigned_abs() < 1 << 40)
            .ok_or_else(|| error(caret.column, OVERFLOW))?;
        finite(Value::new(poly, exp, base.column), caret.column)
    }

    fn primary(&mut self) -> Result<Value, ParseError> {
        let token = self.advance();
        let column = token.column;
        let poly = match token.kind {
            Kind::Number(v) => {
                if !v.is_finite() {
                    return Err(error(
                        column,
                        format!("the number '{}' is too large for f64", token.text),
                    ));
                }
                Trivariate::constant(v)
            }
            Kind::Name => self.name(&token)?,
            Kind::LParen => return self.parenthesised(column),
            _ => {
                let hint = if token.kind == Kind::RParen {
                    " (an empty pair of parentheses, or an operator missing its right side?)"
                } else {
                    ""
                };
                return Err(error(
                    column,
                    format!(
                        "expected a number, a name or '(' but found {}{hint}",
                        token.describe()
                    ),
                ));
            }
        };
        Ok(Value::new(poly, 0, column))
    }

    /// The inside of "(" … ")", the "(" at `column` already read.
    fn parenthesised(&mut self, column: usize) -> Result<Value, ParseError> {
        let inner = self.expr()?;
        let close = self.peek();
        if close.kind != Kind::RParen {
            return Err(if close.kind == Kind::End {
                error(
                    close.column,
                    format!(
                        "expected ')' to close the '(' at column {column} but found {}",
                        close.describe()
                    ),
                )
            } else {
                self.expected_operator(true)
            });
        }
        self.advance();
        Ok(Value { column, ..inner })
    }

    /// A variable or a scene constant.
    fn name(&self, token: &Token) -> Result<Trivariate, ParseError> {
        let name = token.text.as_str();
        let constant = self.constants.iter().find(|(n, _)| *n == name);
        let axis = ["x", "y", "z"].iter().position(|&v| v == name);
        match (axis, constant) {
            (Some(_), Some(_)) => Err(error(
                token.column,
                format!(
                    "'{name}' is a variable, but the scene also defines a constant '{name}': rename the constant"
                ),
            )),
            (Some(axis), None) => Ok(Trivariate::variable(axis)),
            (None, Some(&(_, v))) => {
                if v.is_finite() {
                    Ok(Trivariate::constant(v))
                } else {
                    Err(error(
                        token.column,
                        format!("the constant '{name}' is {v}, not a finite number"),
                    ))
                }
            }
            (None, None) => Err(error(token.column, self.unknown_name(name))),
        }
    }

    fn unknown_name(&self, name: &str) -> String {
        let known: Vec<&str> = ["x", "y", "z"]
            .into_iter()
            .chain(self.constants.iter().map(|&(n, _)| n))
            .collect();
        let mut message = format!("unknown name '{name}'");
        if let Some(best) = crate::suggest::closest(name, known.iter().copied()) {
            message.push_str(&format!(": did you mean '{best}'?"));
        }
        const SHOWN: usize = 12;
        let mut list = known[..known.len().min(SHOWN)].join(", ");
        if known.len() > SHOWN {
            list.push_str(", ...");
        }
        message.push_str(&format!(" (the variables and constants are {list})"));
        message
    }

    /// After a complete operand, only an operator (or ')' inside parentheses,
    /// or the end) may follow; anything else is most likely an attempt at
    /// implicit multiplication.
    fn expected_operator(&self, in_parentheses: bool) -> ParseError {
        let token = self.peek();
        let wanted = if in_parentheses {
            "an operator (+ - * / ^) or ')'"
        } else {
            "an operator (+ - * / ^) or the end of the expression"
        };
        let hint = match token.kind {
            Kind::Number(_) | Kind::Name | Kind::LParen => {
                " (implicit multiplication is not allowed: write '*')"
            }
            _ => "",
        };
        error(
            token.column,
            format!("expected {wanted} but found {}{hint}", token.describe()),
        )
    }
}

fn degree_error(column: usize, what: &str, degree: usize) -> ParseError {
    error(
        column,
        format!("this {what} has degree {degree}, above the limit of {MAX_DEGREE}"),
    )
}

const OVERFLOW: &str = "a coefficient overflows f64 here (the numbers are too large)";

/// Refuses overflow where it arises: a coefficient that is not finite (a
/// power of a constant), or a constant beyond f64 (a divisor or an
/// exponent must be a number; a polynomial's own scale is kept apart).
fn finite(value: Value, column: usize) -> Result<Value, ParseError> {
    let constant_overflows = value.constant().is_some_and(|c| !c.is_finite());
    if value.poly.is_finite() && !constant_overflows {
        Ok(value)
    } else {
        Err(error(column, OVERFLOW))
    }
}

#[cfg(test)]
mod tests;
