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
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::time::Instant;

    const TORUS: &str = "(x^2+y^2+z^2+R^2-r^2)^2 - 4*R^2*(x^2+y^2)";

    fn consts() -> Vec<(&'static str, f64)> {
        vec![("R", 1.0), ("r", 0.25)]
    }

    fn ok(text: &str) -> Trivariate {
        parse(text, &consts()).unwrap_or_else(|e| panic!("{text:?}: {e}"))
    }

    fn err(text: &str) -> ParseError {
        match parse(text, &consts()) {
            Ok(p) => panic!("{text:?} parsed as {p}"),
            Err(e) => e,
        }
    }

    fn terms(list: &[([u8; 3], f64)]) -> Trivariate {
        Trivariate::from_terms(list.iter().copied())
    }

    #[test]
    fn torus_expands_to_the_known_polynomial() {
        for (big_r, r) in [(1.0, 0.25), (2.0, 0.5), (1.0, 0.02), (3.0, 1.0)] {
            let p = parse(TORUS, &[("R", big_r), ("r", r)]).unwrap();
            // (x²+y²+z²)² − 2(R²+r²)(x²+y²) + 2(R²−r²)z² + (R²−r²)², by hand.
            let (a, b) = (big_r * big_r, r * r);
            let want = terms(&[
                ([4, 0, 0], 1.0),
                ([2, 2, 0], 2.0),
                ([2, 0, 2], 2.0),
                ([2, 0, 0], -2.0 * (a + b)),
                ([0, 4, 0], 1.0),
                ([0, 2, 2], 2.0),
                ([0, 2, 0], -2.0 * (a + b)),
                ([0, 0, 4], 1.0),
                ([0, 0, 2], 2.0 * (a - b)),
                ([0, 0, 0], (a - b) * (a - b)),
            ]);
            assert_eq!(p.terms().len(), want.terms().len(), "{p}");
            for (got, want) in p.terms().iter().zip(want.terms()) {
                assert_eq!(got.0, want.0, "{p}");
                assert!(
                    (got.1 - want.1).abs() <= 1e-15 * want.1.abs().max(1.0),
                    "{p}: {got:?} vs {want:?}"
                );
            }
        }
    }

    #[test]
    fn goursat_tangle_cube() {
        let p = ok("x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8");
        assert_eq!(
            p,
            terms(&[
                ([4, 0, 0], 1.0),
                ([2, 0, 0], -5.0),
                ([0, 4, 0], 1.0),
                ([0, 2, 0], -5.0),
                ([0, 0, 4], 1.0),
                ([0, 0, 2], -5.0),
                ([0, 0, 0], 11.8),
            ])
        );
        assert_eq!(p.degree(), 4);
    }

    #[test]
    fn numbers() {
        let x = |c: f64| terms(&[([1, 0, 0], c)]);
        assert_eq!(ok("12*x"), x(12.0));
        assert_eq!(ok("1.5*x"), x(1.5));
        assert_eq!(ok(".5*x"), x(0.5));
        assert_eq!(ok("2.*x"), x(2.0));
        assert_eq!(ok("1e-3*x"), x(1e-3));
        assert_eq!(ok("2.5E+2*x"), x(250.0));
        assert_eq!(ok("x/4"), x(0.25));
        assert_eq!(ok("x / (R + 1) / 2"), x(0.25));
    }

    #[test]
    fn precedence_and_associativity() {
        let x2 = terms(&[([2, 0, 0], 1.0)]);
        assert_eq!(ok("-x^2"), x2.neg());
        assert_eq!(ok("(-x)^2"), x2);
        assert_eq!(ok("2^3^2*x"), terms(&[([1, 0, 0], 512.0)]));
        assert_eq!(ok("(2^3)^2*x"), terms(&[([1, 0, 0], 64.0)]));
        assert_eq!(ok("x^2^2"), terms(&[([4, 0, 0], 1.0)]));
        assert_eq!(ok("x*-y"), terms(&[([1, 1, 0], -1.0)]));
        assert_eq!(ok("-x*y"), terms(&[([1, 1, 0], -1.0)]));
        assert_eq!(ok("x - -y"), terms(&[([1, 0, 0], 1.0), ([0, 1, 0], 1.0)]));
        assert_eq!(ok("+x"), ok("x"));
        assert_eq!(ok("(x)"), ok("x"));
        assert_eq!(ok("((((x))))"), ok("x"));
        assert_eq!(ok("x - y - z"), ok("x - (y + z)"));
        assert_eq!(ok("x / 2 / 2"), ok("x / 4"));
        assert_eq!(
            ok("x + 2*y^2"),
            terms(&[([1, 0, 0], 1.0), ([0, 2, 0], 2.0)])
        );
        assert_eq!(ok("x^0 + z"), terms(&[([0, 0, 1], 1.0), ([0, 0, 0], 1.0)]));
        // Whitespace of every kind, including the newlines of a TOML string.
        assert_eq!(ok(" x\t*\n y "), terms(&[([1, 1, 0], 1.0)]));
        // An exponent may be a constant expression.
        assert_eq!(
            parse("x^(2*n) + y^n", &[("n", 2.0)]).unwrap(),
            terms(&[([4, 0, 0], 1.0), ([0, 2, 0], 1.0)])
        );
        // Division by a divisor whose x cancels is division by a constant.
        assert_eq!(ok("x/(x-x+2)"), terms(&[([1, 0, 0], 0.5)]));
    }

    #[test]
    fn longer_names() {
        let p = parse(
            "alpha*x^2 + R2*y_1",
            &[("alpha", 2.0), ("R2", 3.0), ("y_1", 4.0)],
        );
        assert_eq!(p.unwrap(), terms(&[([2, 0, 0], 2.0), ([0, 0, 0], 12.0)]));
        // Case matters: X is not x.
        let e = err("X + y");
        assert_eq!(e.column, 1);
        assert!(e.message.contains("did you mean 'x'?"), "{e}");
    }

    #[test]
    fn implicit_multiplication_is_an_error_at_the_second_factor() {
        let e = err("2x");
        assert_eq!(e.column, 2);
        assert!(e.message.contains("found 'x'"), "{e}");
        assert!(e.message.contains("implicit multiplication"), "{e}");
        assert_eq!(err("x y").column, 3);
        assert_eq!(err("(x)(y)").column, 4);
        assert_eq!(err("3 4*x").column, 3);
        assert_eq!(err("x + 2e").column, 6);
        let e = err("(x + 2 y)");
        assert_eq!(e.column, 8);
        assert!(e.message.contains("or ')'"), "{e}");
    }

    #[test]
    fn unbalanced_parentheses() {
        let e = err("(x + 1");
        assert_eq!(e.column, 7);
        assert_eq!(
            e.message,
            "expected ')' to close the '(' at column 1 but found the end of the expression"
        );
        let e = err("x^2 )");
        assert_eq!(e.column, 5);
        assert!(e.message.contains("no matching '('"), "{e}");
        let e = err("()");
        assert_eq!(e.column, 2);
        assert!(
            e.message
                .starts_with("expected a number, a name or '(' but found ')'")
        );
        assert_eq!(err("((x)").column, 5);
    }

    #[test]
    fn syntax_errors_name_column_and_expectation() {
        let e = err("x^2 + *3");
        assert_eq!(
            e.to_string(),
            "column 7: expected a number, a name or '(' but found '*'"
        );
        let e = err("x^2 +");
        assert_eq!(e.column, 6);
        assert!(
            e.message.ends_with("but found the end of the expression"),
            "{e}"
        );
        let e = err("x**2");
        assert_eq!(e.column, 3);
        assert!(e.message.contains("write '^'"), "{e}");
        let e = err("x + y # comment");
        assert_eq!(e.column, 7);
        assert!(e.message.contains("found '#'"), "{e}");
        let e = err("x + α");
        assert_eq!(e.column, 5, "columns count characters, not bytes");
        let e = err("x + 1.2.3");
        assert_eq!(e.column, 8);
    }

    #[test]
    fn empty_input() {
        assert_eq!(err("").to_string(), "column 1: the expression is empty");
        assert_eq!(err("  \n ").column, 1);
    }

    #[test]
    fn division_by_variables_or_zero() {
        let e = err("x/y");
        assert_eq!(e.column, 3);
        assert!(e.message.contains("cannot divide"), "{e}");
        let e = err("x/(1 + y^2)");
        assert_eq!(e.column, 3);
        let e = err("x/(R-1)");
        assert_eq!(e.column, 3);
        assert_eq!(e.message, "division by zero");
    }

    #[test]
    fn bad_exponents() {
        let e = err("x^-1");
        assert_eq!(e.column, 3);
        assert!(
            e.message.contains("non-negative integer but it is -1"),
            "{e}"
        );
        let e = err("x^2.5");
        assert_eq!(e.column, 3);
        assert!(e.message.contains("it is 2.5"), "{e}");
        let e = err("x^y");
        assert_eq!(e.column, 3);
        assert!(e.message.contains("must be a constant"), "{e}");
        let e = err("x + R^0.5");
        assert!(e.message.contains("it is 0.5"), "{e}");
    }

    #[test]
    fn unknown_names_suggest_the_closest() {
        let e = err("x^2 + rr");
        assert_eq!(e.column, 7);
        assert!(
            e.message
                .starts_with("unknown name 'rr': did you mean 'r'?"),
            "{e}"
        );
        assert!(e.message.contains("x, y, z, R, r"), "{e}");
        let e = err("x + banana");
        assert!(!e.message.contains("did you mean"), "{e}");
        // A constant that shadows a variable is ambiguous.
        let e = parse("x + y", &[("x", 1.0)]).unwrap_err();
        assert_eq!(e.column, 1);
        assert!(e.message.contains("rename the constant"), "{e}");
        let e = parse("x + a", &[("a", f64::INFINITY)]).unwrap_err();
        assert_eq!(e.column, 5);
    }

    #[test]
    fn degree_limit() {
        let e = err("x^17");
        assert_eq!(e.column, 2);
        assert!(e.message.contains("17") && e.message.contains("16"), "{e}");
        let e = err("x^8 * y^9");
        assert_eq!(e.column, 5);
        assert!(
            e.message.contains("degree 17") && e.message.contains("16"),
            "{e}"
        );
        let e = err("(x^2 + y)^9");
        assert!(e.message.contains("degree 18"), "{e}");
        // Exactly 16 is fine, and so is a huge power of a constant.
        assert_eq!(ok("(x^2+y^2+z^2-1)^8").degree(), 16);
        assert_eq!(ok("x + 2^100").terms()[1].1, 2f64.powi(100));
        assert!(err("x^1e30").message.contains("above the limit of 16"));
    }

    #[test]
    fn runaway_exponents_fail_fast() {
        let start = Instant::now();
        for text in [
            "(x+y+z)^1000",
            "(x+y+z)^4294967296",
            "((x+y)^8)^8",
            "(x+1)^9 * (y+1)^9",
        ] {
            let e = err(text);
            assert!(e.message.contains("limit of 16"), "{text}: {e}");
        }
        assert!(start.elapsed().as_millis() < 100, "{:?}", start.elapsed());
    }

    #[test]
    fn constant_or_zero_expressions_are_refused() {
        let e = err("R + 2*r");
        assert_eq!(
            e.to_string(),
            "column 1: the expression does not depend on x, y or z"
        );
        let e = err("x - x");
        assert_eq!(
            e.to_string(),
            "column 1: the expression is identically zero"
        );
        let e = err("0*x^2");
        assert!(e.message.contains("identically zero"), "{e}");
    }

    #[test]
    fn overflow_and_huge_literals() {
        let e = err("x * 1e400");
        assert_eq!(e.column, 5);
        assert!(e.message.contains("too large"), "{e}");
        // Constants must be f64 numbers; a polynomial's scale is kept apart,
        // so 1e400·x is the surface x = 0 (normalised), not an overflow.
        let e = err("1e200*1e200*x");
        assert_eq!(e.column, 6);
        assert!(e.message.contains("overflows"), "{e}");
        assert!(err("x + 10^400").message.contains("overflows"));
        let p = ok("1e200*x * 1e200");
        assert_eq!((p.terms().len(), p.terms()[0].0), (1, [1, 0, 0]), "{p}");
    }

    #[test]
    fn a_scale_factor_does_not_change_the_surface() {
        // k·F, normalised, is F normalised times k's mantissa: exactly F for
        // powers of two (also where k·F itself leaves the f64 range), every
        // coefficient in the same ratio to rounding otherwise.
        let f = ok(TORUS).normalized().0;
        for k in ["0.5^1070", "2^1000", "1e308", "1e-310", "-1e-300", "3"] {
            let g = ok(&format!("{k}*({TORUS})")).normalized().0;
            assert_eq!(g.terms().len(), f.terms().len(), "{k}: {g}");
            let ratio = g.terms()[0].1 / f.terms()[0].1;
            if k.contains('^') {
                assert_eq!(ratio, 1.0, "{k}");
            }
            for (a, b) in g.terms().iter().zip(f.terms()) {
                assert_eq!(a.0, b.0, "{k}");
                assert!(
                    (a.1 - ratio * b.1).abs() <= 1e-12 * a.1.abs(),
                    "{k}: {g} for {f}"
                );
            }
        }
    }

    #[test]
    fn deep_nesting_is_an_error_not_a_crash() {
        let text = format!("{}x{}", "(".repeat(100_000), ")".repeat(100_000));
        assert!(err(&text).message.contains("levels deep"));
        let text = format!("{}x", "-".repeat(100_000));
        assert!(err(&text).message.contains("levels deep"));
        let text = format!("x{}", "^1".repeat(100_000));
        assert!(err(&text).message.contains("levels deep"));
        let ok_depth = format!("{}x{}", "(".repeat(150), ")".repeat(150));
        assert_eq!(ok(&ok_depth), ok("x"));
    }

    #[test]
    fn display_round_trips_through_parse() {
        for text in [
            TORUS,
            "x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8",
            "-x*y*z/3 + 1e-30*z^7",
        ] {
            let p = ok(text);
            assert_eq!(ok(&p.to_string()), p, "{p}");
        }
    }

    // ---- property test: random expressions, printed, parsed, evaluated ----

    /// A small expression tree, evaluated independently of the parser.
    #[derive(Clone, Debug)]
    enum Ast {
        Num(f64),
        Var(usize),
        Const(usize),
        Neg(Box<Ast>),
        Add(Box<Ast>, Box<Ast>),
        Sub(Box<Ast>, Box<Ast>),
        Mul(Box<Ast>, Box<Ast>),
        /// Divisor: a nonzero number or constant.
        Div(Box<Ast>, Box<Ast>),
        Pow(Box<Ast>, u32),
    }

    const NAMES: [(&str, f64); 3] = [("R", 1.5), ("r2", 0.3), ("k_3", -2.0)];

    fn degree(a: &Ast) -> usize {
        match a {
            Ast::Num(_) | Ast::Const(_) => 0,
            Ast::Var(_) => 1,
            Ast::Neg(a) => degree(a),
            Ast::Add(a, b) | Ast::Sub(a, b) => degree(a).max(degree(b)),
            Ast::Mul(a, b) => degree(a) + degree(b),
            Ast::Div(a, _) => degree(a),
            Ast::Pow(a, n) => degree(a) * *n as usize,
        }
    }

    /// (value, Σ of absolute values): the second bounds the rounding error
    /// that cancellation can leave.
    fn eval(a: &Ast, p: [f64; 3]) -> (f64, f64) {
        match a {
            Ast::Num(v) => (*v, v.abs()),
            Ast::Var(i) => (p[*i], p[*i].abs()),
            Ast::Const(i) => (NAMES[*i].1, NAMES[*i].1.abs()),
            Ast::Neg(a) => {
                let (v, m) = eval(a, p);
                (-v, m)
            }
            Ast::Add(a, b) => {
                let ((u, m), (v, n)) = (eval(a, p), eval(b, p));
                (u + v, m + n)
            }
            Ast::Sub(a, b) => {
                let ((u, m), (v, n)) = (eval(a, p), eval(b, p));
                (u - v, m + n)
            }
            Ast::Mul(a, b) => {
                let ((u, m), (v, n)) = (eval(a, p), eval(b, p));
                (u * v, m * n)
            }
            Ast::Div(a, b) => {
                let ((u, m), (v, _)) = (eval(a, p), eval(b, p));
                (u / v, m / v.abs())
            }
            Ast::Pow(a, n) => {
                let (v, m) = eval(a, p);
                let mut value = 1.0;
                let mut magnitude = 1.0;
                for _ in 0..*n {
                    value *= v;
                    magnitude *= m;
                }
                (value, magnitude)
            }
        }
    }

    /// Precedence levels of the grammar: sum 1, product 2, unary 3, power 4,
    /// primary 5.
    fn level(a: &Ast) -> u8 {
        match a {
            Ast::Add(..) | Ast::Sub(..) => 1,
            Ast::Mul(..) | Ast::Div(..) => 2,
            Ast::Neg(_) => 3,
            Ast::Pow(..) => 4,
            Ast::Num(_) | Ast::Var(_) | Ast::Const(_) => 5,
        }
    }

    /// Prints with only the parentheses the grammar needs, so the parser's
    /// precedence and associativity are what the test exercises.
    fn print(a: &Ast, style: u8) -> String {
        let wrap = |child: &Ast, min: u8| {
            let text = print(child, style);
            if level(child) < min {
                format!("({text})")
            } else {
                text
            }
        };
        let (lo, hi) = if style.is_multiple_of(2) {
            ("", "")
        } else {
            (" ", " ")
        };
        match a {
            Ast::Num(v) if style >= 2 => format!("{v:e}"),
            Ast::Num(v) => format!("{v}"),
            Ast::Var(i) => ["x", "y", "z"][*i].to_owned(),
            Ast::Const(i) => NAMES[*i].0.to_owned(),
            Ast::Neg(a) => format!("-{}", wrap(a, 3)),
            Ast::Add(a, b) => format!("{}{lo}+{hi}{}", wrap(a, 1), wrap(b, 2)),
            Ast::Sub(a, b) => format!("{}{lo}-{hi}{}", wrap(a, 1), wrap(b, 2)),
            Ast::Mul(a, b) => format!("{}{lo}*{hi}{}", wrap(a, 2), wrap(b, 3)),
            Ast::Div(a, b) => format!("{}{lo}/{hi}{}", wrap(a, 2), wrap(b, 3)),
            Ast::Pow(a, n) => format!("{}^{n}", wrap(a, 5)),
        }
    }

    fn arb_ast() -> impl Strategy<Value = Ast> {
        let leaf = prop_oneof![
            1 => (0.0..5.0f64).prop_map(Ast::Num),
            1 => (0u32..10).prop_map(|k| Ast::Num(f64::from(k))),
            4 => (0usize..3).prop_map(Ast::Var),
            1 => (0usize..3).prop_map(Ast::Const),
        ];
        let divisor = prop_oneof![
            (0.1..5.0f64).prop_map(Ast::Num),
            (0usize..3).prop_map(Ast::Const),
        ];
        leaf.prop_recursive(6, 48, 2, move |inner| {
            prop_oneof![
                inner.clone().prop_map(|a| Ast::Neg(Box::new(a))),
                (inner.clone(), inner.clone())
                    .prop_map(|(a, b)| Ast::Mul(Box::new(a), Box::new(b))),
                (inner.clone(), inner.clone())
                    .prop_map(|(a, b)| Ast::Add(Box::new(a), Box::new(b))),
                (inner.clone(), inner.clone())
                    .prop_map(|(a, b)| Ast::Sub(Box::new(a), Box::new(b))),
                (inner.clone(), inner.clone())
                    .prop_map(|(a, b)| Ast::Mul(Box::new(a), Box::new(b))),
                (inner.clone(), divisor.clone())
                    .prop_map(|(a, b)| Ast::Div(Box::new(a), Box::new(b))),
                (inner.clone(), 0u32..5).prop_map(|(a, n)| Ast::Pow(Box::new(a), n)),
            ]
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]

        #[test]
        fn prop_printed_expressions_parse_to_their_value(
            ast in arb_ast().prop_filter("degree within the limit", |a| degree(a) <= MAX_DEGREE),
            style in 0u8..4,
            points in prop::collection::vec(prop::array::uniform3(-2.0..2.0f64), 4),
        ) {
            let text = print(&ast, style);
            match parse(&text, &NAMES) {
                Ok(poly) => {
                    prop_assert!(poly.degree() <= degree(&ast));
                    for &p in &points {
                        let (want, magnitude) = eval(&ast, p);
                        let got = poly.eval(p);
                        prop_assert!(
                            (got - want).abs() <= 1e-11 * magnitude.max(1e-300),
                            "{text}: at {p:?} the polynomial {poly} gives {got}, the tree {want}"
                        );
                    }
                }
                Err(e) => {
                    // Only a constant value may be refused; check it is one.
                    prop_assert!(
                        e.message.contains("does not depend") || e.message.contains("identically zero"),
                        "{text}: {e}"
                    );
                    let (first, _) = eval(&ast, points[0]);
                    for &p in &points[1..] {
                        let (v, magnitude) = eval(&ast, p);
                        prop_assert!((v - first).abs() <= 1e-11 * magnitude.max(1.0), "{text}: {e}");
                    }
                }
            }
        }

        #[test]
        fn prop_display_round_trips_exactly(
            list in prop::collection::vec(((0u8..=6, 0u8..=5, 0u8..=5), prop_oneof![-1e3..1e3f64, Just(1.0), Just(-1.0), -1e-30..1e-30f64, -1e30..1e30f64]), 1..20),
        ) {
            let poly = Trivariate::from_terms(list.into_iter().map(|((a, b, c), k)| ([a, b, c], k)));
            prop_assume!(poly.degree() > 0);
            let text = poly.to_string();
            prop_assert_eq!(parse(&text, &[]).unwrap(), poly, "{}", text);
        }

        #[test]
        fn prop_arbitrary_text_never_panics(text in "[xyzR0-9 .e+*/^()-]{0,40}") {
            let _ = parse(&text, &NAMES);
        }
    }
}
