//! Colours of POV-Ray's language: `rgb`, `rgbf`, `rgbt`, `rgbft` (and the
//! `srgb` forms, read as linear with a warning), `color red … green …`, and
//! values as colours: five numbers, red, green, blue, filter, transmit.

use super::parse::{Loc, Parser};
use super::value::{COLOUR_WORDS, Value};
use crate::error::Result;

impl Parser {
    /// A colour: after `color`/`colour` (already taken, `first` None) or
    /// starting with the colour word `first`; then any `red`, `green`,
    /// `blue`, `filter`, `transmit` that change one component.
    pub fn colour_rest(&mut self, first: Option<(String, Loc)>) -> Result<Value> {
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
                self.colour_word(&w, &mut c)?;
            }
        }
        // Components may follow and change it (`rgb 1 filter 0.5`); another
        // `rgb` starts the next colour, as in a checker's `rgb 1 rgb 0`.
        while let Some(w) = self.peek_word()? {
            if !matches!(w.as_str(), "red" | "green" | "blue" | "filter" | "transmit") {
                break;
            }
            self.next()?;
            self.colour_word(&w, &mut c)?;
        }
        Ok(Value::Vector(c.to_vec()))
    }

    fn colour_word(&mut self, w: &str, c: &mut [f64; 5]) -> Result<()> {
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
    pub fn as_colour(&self, v: &Value, loc: Loc) -> Result<[f64; 5]> {
        let mut c = [0.0; 5];
        match v {
            Value::Float(f) => c[..3].copy_from_slice(&[*f; 3]),
            Value::Vector(v) if v.len() >= 3 => c[..v.len()].copy_from_slice(v),
            _ => return Err(self.error_at(loc, "expected a colour")),
        }
        Ok(c)
    }
}
