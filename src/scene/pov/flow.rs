//! POV-Ray's control flow as the reader runs it: `#if`/`#ifdef`/`#ifndef`
//! with `#else`/`#elseif`, and the loops `#while` and `#for` with `#break`.
//! A loop's body is read again from the token stream each time round, as
//! POV-Ray reads it, so what it declares or places takes each pass's values.

use super::lex::{Tok, Token};
use super::parse::{Loc, Parser};
use super::value::{STRING_FUNCTIONS, Value};
use crate::error::Result;

/// Loops go round and macros are called at most this many times in all
/// over one scene: a loop whose condition never turns false, or a macro
/// that calls itself twice over, stops the read with an error at it
/// instead of running on for ever.
pub const MAX_PASSES: u64 = 1_000_000;

/// Names a loop's body may use that the reader cannot evaluate: POV-Ray's
/// functions outside the subset, and the keywords that declare values it
/// skips.
const NOT_RUN: &[&str] = &[
    "trace",
    "inside",
    "eval_pigment",
    "min_extent",
    "max_extent",
    "vturbulence",
    "file_exists",
    "bitwise_and",
    "bitwise_or",
    "bitwise_xor",
    "strcmp",
    "strlen",
    "val",
    "asc",
    "spline",
    "function",
];

/// How many macros' bodies one look at whether a body runs follows: past
/// them, the others it calls are taken to run.
const MAX_SCAN_MACROS: usize = 64;

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
    /// A `#switch` running from the clause that matched.
    Switch,
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
            match self.skip_to_end(&["else", "elseif"], loc)?.as_deref() {
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
            self.skip_to_end(&[], loc)?;
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
            self.skip_to_end(&[], loc)?;
            self.count("#for");
            return Ok(());
        }
        self.open_block(Block::For(l), loc)
    }

    /// `#end`: closes the innermost open construct, or goes round its loop
    /// again.
    pub(super) fn end_block(&mut self, loc: Loc) -> Result<()> {
        match self.close_block(loc, "end")? {
            Block::If | Block::Switch => Ok(()),
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
    /// construct is skipped to its `#end`. In a `#switch` running from an
    /// earlier clause, an `#else` is passed, as POV-Ray falls through.
    pub(super) fn end_branch(&mut self, loc: Loc, name: &str) -> Result<()> {
        match self.close_block(loc, name)? {
            Block::If => {
                self.skip_to_end(&[], loc)?;
                Ok(())
            }
            Block::Switch if name == "else" => self.open_block(Block::Switch, loc),
            _ => Err(self.error_at(loc, format!("`#{name}` without an `#if` it belongs to"))),
        }
    }

    /// `#switch (value)`: runs from the first `#case (v)` with v equal to
    /// the value, or `#range (lo, hi)` holding it, or else the `#else`, to
    /// a `#break` or the `#end`; later clauses met on the way are passed.
    pub(super) fn start_switch(&mut self, loc: Loc) -> Result<()> {
        let value = self.held_float()?;
        loop {
            let taken = match self
                .skip_to_end(&["case", "range", "else"], loc)?
                .as_deref()
            {
                None => return Ok(()),
                Some("case") => self.held_float()? == value,
                Some("range") => {
                    let (lo, hi) = self.held(|p| {
                        p.expect('(')?;
                        let lo = p.float()?;
                        p.expect(',')?;
                        let hi = p.float()?;
                        p.expect(')')?;
                        Ok((lo, hi))
                    })?;
                    (lo..=hi).contains(&value)
                }
                _ => true,
            };
            if taken {
                return self.open_block(Block::Switch, loc);
            }
        }
    }

    /// `#case` or `#range` met in a `#switch` running from an earlier
    /// clause: passed (its value read and dropped), as POV-Ray falls
    /// through.
    pub(super) fn fall_through(&mut self, loc: Loc, name: &str) -> Result<()> {
        if !matches!(self.open_blocks().last(), Some(Block::Switch)) {
            return Err(self.error_at(loc, format!("`#{name}` outside a `#switch`")));
        }
        self.held(|p| {
            p.expect('(')?;
            p.float()?;
            while p.eat(',')? {
                p.float()?;
            }
            p.expect(')')
        })
    }

    /// `#break`: leaves the innermost loop or `#switch`, past its `#end`
    /// (and the `#end`s of the branches open inside it).
    pub(super) fn break_loop(&mut self, loc: Loc) -> Result<()> {
        loop {
            let block = self.close_block(loc, "break")?;
            self.skip_to_end(&[], loc)?;
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
                Block::Switch => return Ok(()),
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
        self.skip_to_end(&[], loc)?;
        Ok(true)
    }

    /// The first name in the body ahead (up to the `#end` that closes it)
    /// that the reader cannot evaluate (see [`Parser::unrunnable_in`]).
    fn unrunnable(&self) -> Option<String> {
        self.unrunnable_in(self.ahead(), &mut Vec::new())
    }

    /// The first name in `tokens` (up to an `#end` that closes nothing
    /// opened in them) that the reader cannot evaluate: a function outside
    /// the subset, a value it skipped (an array, a spline, a function), the
    /// keyword that declares one, or a macro whose body uses one. `seen`
    /// holds the macros whose bodies this walk has looked at, each once
    /// (a macro that calls itself included), at most [`MAX_SCAN_MACROS`].
    pub(super) fn unrunnable_in(&self, tokens: &[Token], seen: &mut Vec<String>) -> Option<String> {
        let mut open = 0usize;
        for token in tokens {
            match &token.tok {
                Tok::Directive(d) => match d.as_str() {
                    "if" | "ifdef" | "ifndef" | "while" | "switch" | "macro" | "for" => open += 1,
                    "end" if open == 0 => return None,
                    "end" => open -= 1,
                    _ => {}
                },
                Tok::Word(w) if NOT_RUN.contains(&w.as_str()) => return Some(w.clone()),
                Tok::Word(w) => match self.symbol(w) {
                    Some(Value::Unsupported(kind))
                        if kind.ends_with("()")
                            || NOT_RUN.contains(&kind.as_str())
                            || STRING_FUNCTIONS.contains(&kind.as_str()) =>
                    {
                        return Some(w.clone());
                    }
                    Some(Value::Macro(m)) if seen.len() < MAX_SCAN_MACROS && !seen.contains(w) => {
                        seen.push(w.clone());
                        if let Some(inner) = self.unrunnable_in(m.body(), seen) {
                            return Some(inner);
                        }
                    }
                    _ => {}
                },
                _ => {}
            }
        }
        None
    }

    /// Counts one more pass of a loop or call of a macro (`at`), refusing
    /// one past [`MAX_PASSES`].
    pub(super) fn pass(&mut self, at: Loc) -> Result<()> {
        self.passes += 1;
        if self.passes > MAX_PASSES {
            return Err(self.error_at(
                at,
                format!(
                    "loops and macro calls have gone round {MAX_PASSES} times: \
                     does this one ever end?"
                ),
            ));
        }
        Ok(())
    }
}
