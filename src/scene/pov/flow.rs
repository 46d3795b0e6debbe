//! POV-Ray's control flow as the reader runs it: `#if`/`#ifdef`/`#ifndef`
//! with `#else`/`#elseif`, and the loops `#while` and `#for` with `#break`.
//! A loop's body is read again from the token stream each time round, as
//! POV-Ray reads it, so what it declares or places takes each pass's values.

use super::lex::Tok;
use super::parse::{Loc, Parser};
use super::value::Value;
use crate::error::Result;

/// Loops run at most this many times in all over one scene: a loop whose
/// condition never turns false stops the read with an error at it, instead
/// of running on for ever.
pub const MAX_LOOP_PASSES: u64 = 1_000_000;

/// Names a loop's body may use that the reader cannot evaluate: POV-Ray's
/// functions outside the subset, and the keywords that declare values it
/// skips.
const NOT_RUN: &[&str] = &[
    "rand",
    "seed",
    "trace",
    "inside",
    "eval_pigment",
    "min_extent",
    "max_extent",
    "vaxis_rotate",
    "vturbulence",
    "dimension_size",
    "dimensions",
    "file_exists",
    "bitwise_and",
    "bitwise_or",
    "bitwise_xor",
    "strcmp",
    "strlen",
    "val",
    "asc",
    "array",
    "spline",
    "function",
];

/// A construct open in a file: closed by its `#end`.
#[derive(Clone, Debug)]
pub enum Block {
    /// An `#if`-like branch being taken.
    If,
    /// A `#while` whose condition held: at its `#end` the reader goes back
    /// to the `#while` token, at `at` in the file, to test it again.
    While { at: usize, loc: Loc },
    /// A `#for` going round.
    For(ForLoop),
}

/// A `#for`: its variable, last value and step, where the body starts, and
/// where the loop is.
#[derive(Clone, Debug)]
pub struct ForLoop {
    var: String,
    end: f64,
    step: f64,
    body: usize,
    loc: Loc,
}

impl ForLoop {
    /// True once the variable at `v` has gone past the end in the step's
    /// direction.
    fn passed(&self, v: f64) -> bool {
        if self.step > 0.0 {
            v > self.end
        } else {
            v < self.end
        }
    }
}

impl Parser {
    /// After `#if`-like at `loc`: go on in the branch taken, or skip to the
    /// `#else` (taken) or `#end`.
    pub(super) fn branch(&mut self, taken: bool, loc: Loc) -> Result<()> {
        let mut taken = taken;
        while !taken {
            match self.skip_to_end(true, loc)?.as_deref() {
                None => return Ok(()),
                Some("else") => taken = true,
                _ => taken = self.held_float()? != 0.0,
            }
        }
        self.open_block(Block::If, loc)
    }

    /// `#while (condition)`, whose `#` was the token before this one.
    pub(super) fn start_while(&mut self, loc: Loc) -> Result<()> {
        let at = self.position() - 1;
        if self.skips_unrunnable("#while", loc)? {
            return Ok(());
        }
        if self.held_float()? != 0.0 {
            self.open_block(Block::While { at, loc }, loc)
        } else {
            self.skip_to_end(false, loc)?;
            self.count("#while");
            Ok(())
        }
    }

    /// `#for (Name, Start, End [, Step])`: Name runs from Start by Step
    /// (1 if not given) while it has not passed End.
    pub(super) fn start_for(&mut self, loc: Loc) -> Result<()> {
        if self.skips_unrunnable("#for", loc)? {
            return Ok(());
        }
        let (var, start, end, step) = self.held(|p| {
            p.expect('(')?;
            let var = p.word()?;
            p.expect(',')?;
            let start = p.float()?;
            p.expect(',')?;
            let end = p.float()?;
            let step = if p.eat(',')? { p.float()? } else { 1.0 };
            p.expect(')')?;
            Ok((var, start, end, step))
        })?;
        if step == 0.0 || !step.is_finite() {
            return Err(self.error_at(loc, format!("#for with a step of {step} never ends")));
        }
        self.set(&var, Value::Float(start));
        let l = ForLoop {
            var,
            end,
            step,
            body: self.position(),
            loc,
        };
        if l.passed(start) {
            self.skip_to_end(false, loc)?;
            self.count("#for");
            return Ok(());
        }
        self.open_block(Block::For(l), loc)
    }

    /// `#end`: closes the innermost open construct, or goes round its loop
    /// again.
    pub(super) fn end_block(&mut self, loc: Loc) -> Result<()> {
        match self.close_block(loc, "end")? {
            Block::If => Ok(()),
            Block::While { at, loc: opened } => {
                self.pass(opened)?;
                self.jump(at);
                Ok(())
            }
            Block::For(l) => {
                let now = match self.symbol(&l.var) {
                    Some(Value::Float(v)) => *v,
                    _ => {
                        return Err(self.error_at(
                            l.loc,
                            format!(
                                "the #for variable `{}` is no longer a number at its #end",
                                l.var
                            ),
                        ));
                    }
                };
                let next = now + l.step;
                self.set(&l.var, Value::Float(next));
                if l.passed(next) {
                    self.count("#for");
                    return Ok(());
                }
                self.pass(l.loc)?;
                self.jump(l.body);
                let opened = l.loc;
                self.open_block(Block::For(l), opened)
            }
        }
    }

    /// `#else` or `#elseif` met in a branch being taken: the rest of the
    /// construct is skipped to its `#end`.
    pub(super) fn end_branch(&mut self, loc: Loc, name: &str) -> Result<()> {
        match self.close_block(loc, name)? {
            Block::If => {
                self.skip_to_end(false, loc)?;
                Ok(())
            }
            _ => Err(self.error_at(loc, format!("`#{name}` inside a loop, not an `#if`"))),
        }
    }

    /// `#break`: leaves the innermost loop, past its `#end` (and the `#end`s
    /// of the branches open inside it).
    pub(super) fn break_loop(&mut self, loc: Loc) -> Result<()> {
        loop {
            let block = self.close_block(loc, "break")?;
            self.skip_to_end(false, loc)?;
            match block {
                Block::If => {}
                Block::While { .. } => {
                    self.count("#while");
                    return Ok(());
                }
                Block::For(_) => {
                    self.count("#for");
                    return Ok(());
                }
            }
        }
    }

    /// Skips the loop `#name` opened at `loc` whole, with a warning, when
    /// its body needs what the reader does not run (`rand`, a macro, an
    /// array): run, it would stop the read, and before loops ran the whole
    /// loop was skipped so. True if it was skipped.
    fn skips_unrunnable(&mut self, name: &str, loc: Loc) -> Result<bool> {
        let Some(what) = self.unrunnable() else {
            return Ok(false);
        };
        self.skip_warning(
            loc,
            name,
            &format!("skipped up to its #end: its body uses `{what}`, which is not run"),
        );
        self.skip_to_end(false, loc)?;
        Ok(true)
    }

    /// The first name in the body ahead (up to the `#end` that closes it)
    /// that the reader cannot evaluate: a function outside the subset, a
    /// macro, a value it skipped (an array, a spline, a function), or the
    /// keyword that declares one.
    fn unrunnable(&self) -> Option<String> {
        let mut depth = 0usize;
        for token in self.ahead() {
            match &token.tok {
                Tok::Directive(d) => match d.as_str() {
                    "if" | "ifdef" | "ifndef" | "while" | "switch" | "macro" | "for" => depth += 1,
                    "end" if depth == 0 => return None,
                    "end" => depth -= 1,
                    _ => {}
                },
                Tok::Word(w) if NOT_RUN.contains(&w.as_str()) || self.unrunnable_name(w) => {
                    return Some(w.clone());
                }
                _ => {}
            }
        }
        None
    }

    /// True if `name` is a macro, or was declared as a value the reader
    /// skipped that an expression would need (a shape outside the subset
    /// is only left out where it is placed, so it is not one).
    fn unrunnable_name(&self, name: &str) -> bool {
        match self.symbol(name) {
            Some(Value::Macro) => true,
            Some(Value::Unsupported(kind)) => {
                kind.ends_with("()") || NOT_RUN.contains(&kind.as_str())
            }
            _ => false,
        }
    }

    /// Counts one more pass of a loop, refusing one past [`MAX_LOOP_PASSES`].
    fn pass(&mut self, opened: Loc) -> Result<()> {
        self.loop_passes += 1;
        if self.loop_passes > MAX_LOOP_PASSES {
            return Err(self.error_at(
                opened,
                format!(
                    "loops have run {MAX_LOOP_PASSES} times: does this one's condition ever turn false?"
                ),
            ));
        }
        Ok(())
    }
}
