//! POV-Ray's macros as the reader runs them: `#macro Name(a, b) … #end`
//! keeps its body's tokens, and a call `Name(x, y)` reads that body next,
//! in place of the call, with the parameters declared local to it (as an
//! include file's `#local`s are). So a macro can stand wherever its body's
//! tokens can: a statement, an object, a texture, a value in an expression.

use std::rc::Rc;

use super::lex::{Tok, Token};
use super::parse::{Frame, Loc, Parser};
use super::value::Value;
use crate::error::Result;

/// A macro as defined: where its body is, and its parameters' names.
#[derive(Debug)]
pub struct Macro {
    file: u16,
    tokens: Rc<Vec<Token>>,
    params: Vec<String>,
    /// The body: tokens `body..end` of the file, `end` being its `#end`.
    body: usize,
    end: usize,
}

impl Macro {
    /// The body's tokens.
    pub fn body(&self) -> &[Token] {
        &self.tokens[self.body..self.end]
    }
}

impl Parser {
    /// `#macro Name(a, b, …) … #end`, after `#macro` at `loc`. The name
    /// and parameters are read as they stand: a macro of that name already
    /// declared is defined again, not called.
    pub(super) fn define_macro(&mut self, loc: Loc) -> Result<()> {
        let name = self.raw_word()?;
        if self.raw().map(|t| t.tok) != Some(Tok::Punct('(')) {
            return Err(self.error_at(loc, format!("expected `(` after `#macro {name}`")));
        }
        self.advance();
        let mut params = Vec::new();
        loop {
            match self.raw().map(|t| t.tok) {
                Some(Tok::Punct(')')) => {
                    self.advance();
                    break;
                }
                Some(Tok::Punct(',')) if !params.is_empty() => self.advance(),
                _ => params.push(self.raw_word()?),
            }
        }
        let body = self.position();
        self.skip_to_end(&[], loc)?;
        let end = self.position() - 1;
        let Some((file, tokens)) = self.current_file() else {
            return Err(self.error_at(loc, "this `#macro` is never closed by `#end`"));
        };
        self.set(
            &name,
            Value::Macro(Rc::new(Macro {
                file,
                tokens,
                params,
                body,
                end,
            })),
        );
        Ok(())
    }

    /// True if the word `name` at the reader's position is a call the
    /// reader runs: a macro followed by `(` whose body uses nothing the
    /// reader cannot evaluate. Other calls are left to the places that skip
    /// them with a warning, as before macros ran.
    pub(super) fn calls_macro(&self, name: &str) -> bool {
        let ahead = self.ahead();
        if !matches!(ahead.get(1).map(|t| &t.tok), Some(Tok::Punct('('))) {
            return false;
        }
        let Some(Value::Macro(m)) = self.symbol(name) else {
            return false;
        };
        // The arguments, to the `)` that closes them: one the reader skipped
        // (a spline, a function) would stop the body's read.
        let mut depth = 0usize;
        let mut args = ahead;
        for (i, token) in ahead.iter().enumerate().skip(1) {
            match token.tok {
                Tok::Punct('(') => depth += 1,
                Tok::Punct(')') => {
                    depth -= 1;
                    if depth == 0 {
                        args = &ahead[1..=i];
                        break;
                    }
                }
                _ => {}
            }
        }
        // A string argument (a file name, a text) is read and not kept, so
        // a body that tests or uses it would stop too.
        !args.iter().any(|t| matches!(t.tok, Tok::Str(_)))
            && self.unrunnable_in(args, &mut Vec::new()).is_none()
            && self
                .unrunnable_in(m.body(), &mut vec![name.to_owned()])
                .is_none()
    }

    /// Why the reader does not run the macro `name` (see `calls_macro`),
    /// for the warning of a call it skips: the first thing its body uses
    /// that the reader cannot evaluate, else its call's arguments.
    pub(super) fn not_run(&self, name: &str) -> String {
        let blocker = match self.symbol(name) {
            Some(Value::Macro(m)) => self.unrunnable_in(m.body(), &mut vec![name.to_owned()]),
            _ => None,
        };
        match blocker {
            Some(what) => format!("a macro is not run (it uses `{what}`)"),
            None => {
                "a macro is not run (its arguments hold a string or what the reader skips)".into()
            }
        }
    }

    /// Runs the call of the macro `name` at `loc` (its name taken): reads
    /// the arguments, then the body with the parameters bound to them.
    pub(super) fn call_macro(&mut self, name: &str, loc: Loc) -> Result<()> {
        let Some(Value::Macro(m)) = self.symbol(name).cloned() else {
            return Err(self.error_at(loc, format!("`{name}` is not a macro")));
        };
        self.expect('(')?;
        let mut args = Vec::new();
        let mut refs = Vec::new();
        if !self.eat(')')? {
            loop {
                // A bare declared name is passed by reference, as POV-Ray
                // passes it: what the body declares its parameter to be
                // becomes the name's value when the body ends.
                if let Some(Token {
                    tok: Tok::Word(w), ..
                }) = self.raw()
                    && matches!(self.raw_after(), Some(Tok::Punct(',' | ')')))
                    && self.symbol(&w).is_some()
                    && let Some(param) = m.params.get(args.len())
                {
                    refs.push((param.clone(), w));
                }
                args.push(self.value()?);
                if self.eat(')')? {
                    break;
                }
                self.expect(',')?;
            }
        }
        if args.len() != m.params.len() {
            return Err(self.error_at(
                loc,
                format!(
                    "the macro `{name}` takes {} argument(s), found {}",
                    m.params.len(),
                    args.len()
                ),
            ));
        }
        self.pass(loc)?;
        self.count("macro call");
        self.push_frame(Frame {
            file: m.file,
            tokens: Rc::clone(&m.tokens),
            pos: m.body,
            end: m.end,
            blocks: Vec::new(),
            locals: Vec::new(),
            refs,
        })?;
        let scope = Some(self.frames_open());
        for (param, arg) in m.params.iter().zip(args) {
            self.bind(param.clone(), arg, scope);
        }
        Ok(())
    }

    /// A name read as it stands, no directive run and no macro called.
    pub(super) fn raw_word(&mut self) -> Result<String> {
        match self.raw().map(|t| t.tok) {
            Some(Tok::Word(w)) => {
                self.advance();
                Ok(w)
            }
            _ => Err(self.error("expected a name")),
        }
    }
}
