//! The token stream of a POV-Ray scene with its language directives applied
//! as it is read: `#include` and macro calls (a stack of frames, each a file
//! or a macro's body, in `macros`), `#declare`/`#local`, the branches and
//! loops (`#if`, `#switch`, `#while`, `#for`, in `flow`), `#version`,
//! `#default`. What the subset does not run (file I/O, a macro or loop that
//! needs what is outside the subset) is skipped whole, balanced by its
//! `#end`, with a warning where it would have acted: a macro is named when
//! it is called, not where an include defines it.

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::rc::Rc;

use super::flow::Block;
use super::lex::{self, At, Tok, Token};
use super::value::Value;
use crate::error::{Error, Result};

/// POV-Ray's own include files, as Debian's `povray-includes` installs them.
pub const SYSTEM_INCLUDE: &str = "/usr/share/povray-3.7/include";

/// Includes nest at most this deep (POV-Ray's own limit is 32 too): a file
/// that includes itself is refused instead of exhausting the stack.
const MAX_INCLUDE_DEPTH: usize = 32;

/// What reading a declared value met, told where the name is used: an
/// include declares much that a scene never uses. Kept as counts: a
/// value built by loops of thousands of passes (benchmark.pov's lathe
/// mesh, from arrays) and named in another loop's every pass was a list
/// copied at each use, quadratic in time and memory.
#[derive(Clone, Debug, Default)]
struct Deferred {
    warnings: Vec<String>,
    skipped: Tally,
    read: Tally,
}

/// How many of each kind were read or skipped, for `sturmray info`.
pub type Tally = BTreeMap<String, usize>;

/// `now` less `before`, the counts `before` (taken earlier) does not hold.
fn since(now: &Tally, before: &Tally) -> Tally {
    now.iter()
        .filter_map(|(k, &n)| {
            let more = n - before.get(k).copied().unwrap_or(0);
            (more > 0).then(|| (k.clone(), more))
        })
        .collect()
}

/// Adds the counts of `more` to `into`.
fn add(into: &mut Tally, more: &Tally) {
    for (k, n) in more {
        *into.entry(k.clone()).or_default() += n;
    }
}

/// Where a token is: its file (an index into `Parser::files`) and position.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Loc {
    pub file: u16,
    pub at: At,
}

pub(super) struct Frame {
    pub(super) file: u16,
    pub(super) tokens: Rc<Vec<Token>>,
    pub(super) pos: usize,
    /// Where this frame's tokens end: the file's end, or a macro body's
    /// `#end`.
    pub(super) end: usize,
    /// The branches and loops this file has open, innermost last.
    pub(super) blocks: Vec<Block>,
    /// The names local to this include file or macro body (its `#local`s
    /// and parameters), each with the value it had before (None:
    /// undeclared), given back where the frame ends.
    pub(super) locals: Vec<(String, Option<Value>)>,
    /// A macro's parameters given as a bare identifier, each with that
    /// identifier: POV-Ray passes such an argument by reference, so the
    /// parameter's value when the body ends is given back to it.
    pub(super) refs: Vec<(String, String)>,
}

/// The reader's state: the token stream and what the directives declared.
pub struct Parser {
    pub files: Vec<PathBuf>,
    frames: Vec<Frame>,
    symbols: HashMap<String, Value>,
    /// The warnings (and skipped keywords) met while reading a declared
    /// value, given only where the name is used: an include file declares
    /// much that a scene never uses.
    deferred: HashMap<String, Deferred>,
    include_dirs: Vec<PathBuf>,
    pub warnings: Vec<String>,
    /// What was read, by kind, for `sturmray info`.
    pub read: Tally,
    /// What was skipped, by keyword.
    pub skipped: Tally,
    /// `image_width`, `image_height`.
    pub size: (u32, u32),
    /// Where the last token taken was, for errors at the end of a file.
    last: Loc,
    /// While a directive's own expression is read (an `#if` condition, a
    /// declared number): a directive after it in the same file ends the
    /// expression instead of running inside it. The depth of frames it was
    /// set at: a macro called in the expression runs its own directives.
    hold: Option<usize>,
    /// How deep expressions and objects nest at this point of the read.
    nesting: usize,
    /// How many times loops have gone round and macros been called,
    /// against [`super::flow::MAX_PASSES`].
    pub(super) passes: u64,
    /// The states of the random streams `seed` has made, by number (see
    /// `functions.rs`).
    pub(super) streams: Vec<u32>,
    /// The array elements made or copied so far (see `arrays`).
    pub(super) array_items: usize,
    /// The parts of declared objects copied so far (see `Parser::copy_object`).
    pub(super) object_parts: usize,
    /// The language version the last `#version` set: POV-Ray's own, 3.7,
    /// until one does. Its value at the end decides the gamma rules.
    pub(super) version: f64,
}

/// Expressions and objects nest at most this deep: far beyond any scene a
/// person writes, far below what the reader's recursion can take.
const MAX_NESTING: usize = 256;

impl Parser {
    /// A parser at the start of the scene file `path`, which `#include`
    /// resolves against its own folder, then `include_dirs`, then
    /// POV-Ray's installed includes.
    pub fn new(path: &Path, include_dirs: &[PathBuf], size: (u32, u32)) -> Result<Parser> {
        let mut dirs: Vec<PathBuf> = path.parent().map(Path::to_path_buf).into_iter().collect();
        dirs.extend(include_dirs.iter().cloned());
        dirs.push(PathBuf::from(SYSTEM_INCLUDE));
        let mut parser = Parser {
            files: Vec::new(),
            frames: Vec::new(),
            symbols: HashMap::new(),
            deferred: HashMap::new(),
            include_dirs: dirs,
            warnings: Vec::new(),
            read: Tally::new(),
            skipped: Tally::new(),
            size,
            last: Loc::default(),
            hold: None,
            nesting: 0,
            passes: 0,
            streams: Vec::new(),
            version: 3.7,
            array_items: 0,
            object_parts: 0,
        };
        parser.open(path)?;
        Ok(parser)
    }

    fn open(&mut self, path: &Path) -> Result<()> {
        let text = crate::io::input::read_text(path)?;
        let file = self.files.len() as u16;
        self.files.push(path.to_owned());
        let tokens = lex::tokens(&text).map_err(|e| Error::Syntax {
            path: path.to_owned(),
            line: e.at.line as usize,
            column: e.at.column as usize,
            message: e.message,
        })?;
        self.push_frame(Frame {
            file,
            end: tokens.len(),
            tokens: Rc::new(tokens),
            pos: 0,
            blocks: Vec::new(),
            locals: Vec::new(),
            refs: Vec::new(),
        })
    }

    /// Reads `frame` (an include file or a macro's body) next, up to its
    /// end, then goes on where the reader was.
    pub(super) fn push_frame(&mut self, frame: Frame) -> Result<()> {
        if self.frames.len() >= MAX_INCLUDE_DEPTH {
            return Err(self.error(format!(
                "includes and macro calls nest deeper than {MAX_INCLUDE_DEPTH} \
                 (does a file include itself, or a macro call itself without end?)"
            )));
        }
        self.frames.push(frame);
        Ok(())
    }

    /// Where the next token is (or the last one, at the end).
    pub fn here(&self) -> Loc {
        match self.frames.last() {
            Some(f) if f.pos < f.end => Loc {
                file: f.file,
                at: f.tokens[f.pos].at,
            },
            _ => self.last,
        }
    }

    /// "file:line:column" of `loc`.
    pub fn place(&self, loc: Loc) -> String {
        format!(
            "{}:{}:{}",
            self.files[loc.file as usize].display(),
            loc.at.line,
            loc.at.column
        )
    }

    /// A syntax error at the next token.
    pub fn error(&self, message: impl Into<String>) -> Error {
        self.error_at(self.here(), message)
    }

    pub fn error_at(&self, loc: Loc, message: impl Into<String>) -> Error {
        Error::Syntax {
            path: self.files[loc.file as usize].clone(),
            line: loc.at.line as usize,
            column: loc.at.column as usize,
            message: message.into(),
        }
    }

    /// A warning about what is at `loc`.
    pub fn warn(&mut self, loc: Loc, message: impl AsRef<str>) {
        let text = format!("{}: {}", self.place(loc), message.as_ref());
        if !self.warnings.contains(&text) {
            self.warnings.push(text);
        }
    }

    /// Warns that `keyword` at `loc` is outside the subset and was skipped.
    pub fn skip_warning(&mut self, loc: Loc, keyword: &str, what: &str) {
        *self.skipped.entry(keyword.to_owned()).or_default() += 1;
        self.warn(loc, format!("`{keyword}` is not supported: {what}"));
    }

    /// Counts one `kind` read, for `info`.
    pub fn count(&mut self, kind: &str) {
        *self.read.entry(kind.to_owned()).or_default() += 1;
    }

    /// The raw token at the top of the stream, without running directives.
    pub(super) fn raw(&mut self) -> Option<Token> {
        loop {
            let frame = self.frames.last_mut()?;
            if frame.pos < frame.end {
                return Some(frame.tokens[frame.pos].clone());
            }
            if !frame.blocks.is_empty() {
                return None;
            }
            let ended = self.frames.pop().expect("a frame was at the top");
            let given_back: Vec<(String, Option<Value>)> = ended
                .refs
                .iter()
                .map(|(param, caller)| (caller.clone(), self.symbols.get(param).cloned()))
                .collect();
            for (name, before) in ended.locals.into_iter().rev() {
                match before {
                    Some(value) => self.symbols.insert(name, value),
                    None => self.symbols.remove(&name),
                };
            }
            for (caller, value) in given_back {
                if let Some(value) = value {
                    self.symbols.insert(caller, value);
                }
            }
        }
    }

    /// Whether the raw token at the top of the stream is the punctuation `c`.
    pub(super) fn raw_is(&mut self, c: char) -> bool {
        matches!(self.raw(), Some(Token { tok: Tok::Punct(p), .. }) if p == c)
    }

    /// The raw token after the one at the top of the stream, in the same
    /// file or macro body.
    pub(super) fn raw_after(&self) -> Option<&Tok> {
        let frame = self.frames.last()?;
        (frame.pos + 1 < frame.end).then(|| &frame.tokens[frame.pos + 1].tok)
    }

    pub(super) fn advance(&mut self) {
        let frame = self.frames.last_mut().expect("a token was peeked");
        self.last = Loc {
            file: frame.file,
            at: frame.tokens[frame.pos].at,
        };
        frame.pos += 1;
    }

    /// The next token, after running any directives before it; None at the
    /// end of the scene.
    pub fn peek(&mut self) -> Result<Option<Tok>> {
        loop {
            let Some(token) = self.raw() else {
                if let Some(f) = self.frames.last()
                    && !f.blocks.is_empty()
                {
                    return Err(self.error(
                        "this file ends inside an `#if`, `#while` or `#for` (a missing `#end`)",
                    ));
                }
                return Ok(None);
            };
            match token.tok {
                Tok::Directive(_) if self.holding() => return Ok(None),
                Tok::Directive(name) => {
                    self.advance();
                    let loc = self.last;
                    self.directive(&name, loc)?;
                }
                // Held, a call is run only where an operand is read (see
                // `primary`): here it may be the lookahead after a value.
                Tok::Word(name) if !self.holding() && self.calls_macro(&name) => {
                    self.advance();
                    let loc = self.last;
                    self.call_macro(&name, loc)?;
                }
                // An array's element, wherever a declared value may stand.
                Tok::Word(name) if !self.holding() && self.indexes_array(&name) => {
                    self.advance();
                    let loc = self.last;
                    self.substitute_element(&name, loc)?;
                }
                tok => return Ok(Some(tok)),
            }
        }
    }

    /// Takes the next token.
    pub fn next(&mut self) -> Result<Tok> {
        match self.peek()? {
            Some(tok) => {
                self.advance();
                if let Tok::Word(w) = &tok {
                    self.used(w);
                }
                Ok(tok)
            }
            None => Err(self.error("unexpected end of the scene")),
        }
    }

    /// What reading the value declared as `name` met (warnings, skipped
    /// and read keywords), now given where the name is used.
    fn used(&mut self, name: &str) {
        self.warnings_of(name);
        if let Some(d) = self.deferred.get(name) {
            add(&mut self.skipped, &d.skipped);
            add(&mut self.read, &d.read);
        }
    }

    /// The warnings reading the value declared as `name` met, given here.
    pub(super) fn warnings_of(&mut self, name: &str) {
        if let Some(d) = self.deferred.get(name) {
            for w in &d.warnings {
                if !self.warnings.contains(w) {
                    self.warnings.push(w.clone());
                }
            }
        }
    }

    /// Takes the next token if it is the punctuation `c`.
    pub fn eat(&mut self, c: char) -> Result<bool> {
        if self.peek()? == Some(Tok::Punct(c)) {
            self.advance();
            return Ok(true);
        }
        Ok(false)
    }

    /// Takes the punctuation `c`, or fails naming what was there.
    pub fn expect(&mut self, c: char) -> Result<()> {
        if self.eat(c)? {
            return Ok(());
        }
        let found = self.peek()?;
        Err(self.error(format!(
            "expected `{c}`, found {}",
            found.map_or("the end of the scene".into(), |t| lex::describe(&t))
        )))
    }

    /// The next token if it is a word.
    pub fn peek_word(&mut self) -> Result<Option<String>> {
        Ok(match self.peek()? {
            Some(Tok::Word(w)) => Some(w),
            _ => None,
        })
    }

    /// Takes the next token if it is the word `w`.
    pub fn eat_word(&mut self, w: &str) -> Result<bool> {
        if self.peek_word()?.as_deref() == Some(w) {
            self.advance();
            return Ok(true);
        }
        Ok(false)
    }

    /// The value `name` was declared with.
    pub fn symbol(&self, name: &str) -> Option<&Value> {
        self.symbols.get(name)
    }

    /// Every declared name, for suggestions: not the names `A[2]` that
    /// stand for array elements read (see `arrays`).
    pub fn symbol_names(&self) -> impl Iterator<Item = &str> {
        self.symbols
            .keys()
            .map(String::as_str)
            .filter(|name| !name.contains('['))
    }

    /// Skips a balanced `{ … }` (the next token must be `{`), running no
    /// directives in it.
    pub fn skip_block(&mut self) -> Result<()> {
        self.expect('{')?;
        let mut depth = 1usize;
        while depth > 0 {
            let Some(token) = self.raw() else {
                return Err(self.error("this block is never closed (`}`)"));
            };
            self.advance();
            match token.tok {
                Tok::Punct('{') => depth += 1,
                Tok::Punct('}') => depth -= 1,
                _ => {}
            }
        }
        Ok(())
    }

    /// Skips the `[ … ]` groups that come next (an array's sizes or an
    /// element's indices), each balanced.
    pub fn skip_brackets(&mut self) -> Result<()> {
        while self.peek()? == Some(Tok::Punct('[')) {
            self.skip_group('[', ']')?;
        }
        Ok(())
    }

    /// Skips the rest of a map's entry, up to and with the `]` that closes
    /// it, over any groups inside it.
    pub fn skip_entry(&mut self) -> Result<()> {
        loop {
            match self.peek()? {
                Some(Tok::Punct(']')) => {
                    self.next()?;
                    return Ok(());
                }
                Some(Tok::Punct('[')) => self.skip_group('[', ']')?,
                Some(Tok::Punct('{')) => self.skip_group('{', '}')?,
                Some(Tok::Punct('(')) => self.skip_group('(', ')')?,
                Some(_) => {
                    self.next()?;
                }
                None => return Err(self.error("this `[` is never closed")),
            }
        }
    }

    /// Skips a balanced `( … )` if one is next.
    pub fn skip_parens(&mut self) -> Result<()> {
        if self.peek()? == Some(Tok::Punct('(')) {
            self.skip_group('(', ')')?;
        }
        Ok(())
    }

    /// Skips raw tokens from the `open` that is next to the `close` that
    /// balances it.
    fn skip_group(&mut self, open: char, close: char) -> Result<()> {
        let mut depth = 0usize;
        loop {
            let Some(token) = self.raw() else {
                return Err(self.error(format!("this `{open}` is never closed")));
            };
            self.advance();
            match token.tok {
                Tok::Punct(c) if c == open => depth += 1,
                Tok::Punct(c) if c == close => {
                    depth -= 1;
                    if depth == 0 {
                        return Ok(());
                    }
                }
                _ => {}
            }
        }
    }

    /// Skips raw tokens to the `#end` that closes the construct just
    /// opened; stops after a directive of the same level named in `stops`
    /// (`#else` of an `#if`, `#case` of a `#switch`) instead, returning its
    /// name.
    pub(super) fn skip_to_end(&mut self, stops: &[&str], opened: Loc) -> Result<Option<String>> {
        let mut depth = 0usize;
        loop {
            // The file the directive is in may have ended already.
            let token = self
                .frames
                .last()
                .filter(|frame| frame.pos < frame.end)
                .and_then(|frame| frame.tokens.get(frame.pos).cloned());
            let Some(token) = token else {
                return Err(self.error_at(opened, "this directive is never closed by `#end`"));
            };
            self.advance();
            let Tok::Directive(name) = token.tok else {
                continue;
            };
            match name.as_str() {
                "if" | "ifdef" | "ifndef" | "while" | "switch" | "macro" | "for" => depth += 1,
                "end" if depth == 0 => return Ok(None),
                "end" => depth -= 1,
                _ if depth == 0 && stops.contains(&name.as_str()) => return Ok(Some(name)),
                _ => {}
            }
        }
    }

    /// Runs the directive `#name` found at `loc`. A directive may stand
    /// inside another's value (`#declare I = #end`, a loop's end in the
    /// middle of a declaration of the loop's body): each is one level of
    /// nesting, so a loop that so declares on every pass stops with an error
    /// instead of overflowing the stack.
    fn directive(&mut self, name: &str, loc: Loc) -> Result<()> {
        self.nested(|p| p.run_directive(name, loc))
    }

    fn run_directive(&mut self, name: &str, loc: Loc) -> Result<()> {
        match name {
            "declare" | "local" => self.declare(loc, name == "local"),
            "undef" => {
                let name = self.word()?;
                self.symbols.remove(&name);
                Ok(())
            }
            "include" => {
                let file = match self.next()? {
                    Tok::Str(s) => s,
                    _ => {
                        return Err(
                            self.error_at(loc, "expected a file name in quotes after #include")
                        );
                    }
                };
                let path = self.resolve(&file).ok_or_else(|| {
                    self.error_at(
                        loc,
                        format!(
                            "cannot find the include file \"{file}\" (searched {}; add a folder with --pov-include)",
                            self.include_dirs
                                .iter()
                                .map(|d| d.display().to_string())
                                .collect::<Vec<_>>()
                                .join(", ")
                        ),
                    )
                })?;
                self.count("#include");
                self.open(&path)
            }
            "version" => {
                self.version = self.held_float()?;
                self.eat(';')?;
                Ok(())
            }
            "if" => {
                let taken = self.held_float()? != 0.0;
                self.branch(taken, loc)
            }
            "ifdef" | "ifndef" => {
                self.expect('(')?;
                let word = self.word()?;
                self.expect(')')?;
                let defined = self.symbols.contains_key(&word);
                self.branch(defined == (name == "ifdef"), loc)
            }
            // Met while taking a branch: the rest up to `#end` is not taken.
            "elseif" | "else" => self.end_branch(loc, name),
            "end" => self.end_block(loc),
            "while" => self.start_while(loc),
            "for" => self.start_for(loc),
            "break" => self.break_loop(loc),
            "macro" => self.define_macro(loc),
            "switch" => self.start_switch(loc),
            "case" | "range" => self.fall_through(loc, name),
            "debug" | "warning" => {
                self.skip_value()?;
                Ok(())
            }
            "error" => {
                let message = match self.next()? {
                    Tok::Str(s) => s,
                    _ => "(no message)".into(),
                };
                Err(self.error_at(loc, format!("the scene stops with #error: {message}")))
            }
            "default" => self.default_block(loc),
            "fopen" | "fclose" | "read" | "write" => {
                self.skip_warning(
                    loc,
                    &format!("#{name}"),
                    "file input and output are skipped",
                );
                match name {
                    "fopen" => {
                        self.next()?;
                        self.next()?;
                        self.next()?;
                    }
                    "fclose" => {
                        self.next()?;
                    }
                    _ => self.skip_parens()?,
                }
                Ok(())
            }
            other => {
                self.skip_warning(loc, &format!("#{other}"), "skipped");
                Ok(())
            }
        }
    }

    /// A number read with directives after it held back.
    pub(super) fn held_float(&mut self) -> Result<f64> {
        self.held(Parser::float)
    }

    /// True while a directive met now would end a held expression.
    fn holding(&self) -> bool {
        self.hold.is_some_and(|depth| self.frames.len() <= depth)
    }

    /// A declared value read with directives after it held back when it is
    /// an expression (a block's directives run as it is read).
    pub fn held<T>(&mut self, read: impl FnOnce(&mut Parser) -> Result<T>) -> Result<T> {
        let before = self.hold;
        self.hold = Some(self.frames.len());
        let v = read(self);
        self.hold = before;
        v
    }

    /// How many files and macro bodies are open.
    pub(super) fn frames_open(&self) -> usize {
        self.frames.len()
    }

    /// Where the reader is in the file it reads now.
    pub(super) fn position(&self) -> usize {
        self.frames.last().map_or(0, |f| f.pos)
    }

    /// The current file's tokens from the reader's position on, as they
    /// stand, no directive run.
    pub(super) fn ahead(&self) -> &[Token] {
        self.frames.last().map_or(&[], |f| &f.tokens[f.pos..f.end])
    }

    /// The file the reader is in now, and its tokens.
    pub(super) fn current_file(&self) -> Option<(u16, Rc<Vec<Token>>)> {
        self.frames.last().map(|f| (f.file, Rc::clone(&f.tokens)))
    }

    /// Goes on reading the current file at token `pos` (a loop's start).
    pub(super) fn jump(&mut self, pos: usize) {
        if let Some(frame) = self.frames.last_mut() {
            frame.pos = pos;
        }
    }

    /// The constructs open in the current file, innermost last.
    pub(super) fn open_blocks(&self) -> &[Block] {
        self.frames.last().map_or(&[], |f| &f.blocks)
    }

    /// Opens `block` in the current file (`loc` is its directive).
    pub(super) fn open_block(&mut self, block: Block, loc: Loc) -> Result<()> {
        match self.frames.last_mut() {
            Some(frame) => {
                frame.blocks.push(block);
                Ok(())
            }
            None => Err(self.error_at(
                loc,
                "the scene ends inside an `#if`, `#while` or `#for` (a missing `#end`)",
            )),
        }
    }

    /// Closes the innermost construct open in the current file, for the
    /// directive `#name` at `loc`.
    pub(super) fn close_block(&mut self, loc: Loc, name: &str) -> Result<Block> {
        match self.frames.last_mut().and_then(|f| f.blocks.pop()) {
            Some(block) => Ok(block),
            None => Err(self.error_at(
                loc,
                format!(
                    "`#{name}` without an `#if`, `#ifdef`, `#ifndef`, `#while` or `#for` \
                     before it in this file"
                ),
            )),
        }
    }

    /// `#declare NAME = value [;]`, or `#local` with `local`.
    fn declare(&mut self, loc: Loc, local: bool) -> Result<()> {
        // The frame a `#local` belongs to: reading its value may end that
        // frame (no `;` after it) or call a macro.
        let scope = local.then_some(self.frames.len());
        // Read as it stands: `NAME[i]` here is the element to declare, not
        // one to read, and a macro's name is declared anew, not called.
        let mut name = self.raw_word()?;
        // `#declare deprecated [once] "why" NAME = …`: the note is given
        // where the name is used, as the value's own warnings are.
        let mut deprecated = None;
        if name == "deprecated" && !matches!(self.peek()?, Some(Tok::Punct('='))) {
            self.eat_word("once")?;
            deprecated = match self.next()? {
                Tok::Str(why) => Some(why),
                _ => {
                    return Err(
                        self.error_at(self.last, "expected the deprecation's message in quotes")
                    );
                }
            };
            name = self.raw_word()?;
        }
        if self.peek()? == Some(Tok::Punct('[')) {
            return self.declare_element(&name, loc);
        }
        self.expect('=')?;
        let marks = (self.warnings.len(), self.skipped.clone(), self.read.clone());
        let value = self.value()?;
        let value = self.copied(value, loc)?;
        // What ran while the value was read (directives, macro calls) is
        // counted once, here; what it made is counted where it is used.
        let (ran, made): (Tally, Tally) = since(&self.read, &marks.2)
            .into_iter()
            .partition(|(kind, _)| kind.starts_with('#') || kind == "macro call");
        let mut deferred = Deferred {
            warnings: self.warnings.split_off(marks.0),
            skipped: since(&self.skipped, &marks.1),
            read: made,
        };
        (self.skipped, self.read) = (marks.1, marks.2);
        add(&mut self.read, &ran);
        if let Some(why) = deprecated {
            let note = format!("{}: `{name}` is deprecated: {why}", self.place(loc));
            deferred.warnings.push(note);
        }
        if deferred.warnings.is_empty() && deferred.skipped.is_empty() && deferred.read.is_empty() {
            self.deferred.remove(&name);
        } else {
            self.deferred.insert(name.clone(), deferred);
        }
        // Declared before the `;` is looked for: looking ahead runs the
        // directives after it, which may use the name.
        self.bind(name, value, scope);
        // A directive next means no `;`, and is left to run after this
        // declaration: run while looking for the `;`, a loop's `#end`
        // would run the loop's next pass inside this declaration, one level
        // deeper on every pass of a loop whose body ends in a declaration
        // without `;` (an object's), until the stack ran out.
        if !matches!(self.raw().map(|t| t.tok), Some(Tok::Directive(_))) {
            self.eat(';')?;
        }
        Ok(())
    }

    /// Declares `name`, local to the frame `scope` deep (a `#local`, a
    /// macro's parameter) or not (None, `#declare`). As in POV-Ray (checked
    /// against 3.7's renders), a local in an include file or macro body
    /// holds to its end, where the value before it comes back; a
    /// `#declare` of a name a local holds changes that local. In the scene
    /// file itself `#local` is `#declare`. A local whose frame has already
    /// ended is out of scope, and dropped.
    pub(super) fn bind(&mut self, name: String, value: Value, scope: Option<usize>) {
        if let Some(depth) = scope {
            if depth > self.frames.len() {
                return;
            }
            if depth > 1
                && let Some(frame) = self.frames.get_mut(depth - 1)
                && !frame.locals.iter().any(|(n, _)| *n == name)
            {
                frame
                    .locals
                    .push((name.clone(), self.symbols.get(&name).cloned()));
            }
        }
        self.symbols.insert(name, value);
    }

    /// The include file `name`, searched in the include folders.
    fn resolve(&self, name: &str) -> Option<PathBuf> {
        let including = self
            .frames
            .last()
            .and_then(|f| self.files[f.file as usize].parent().map(Path::to_path_buf));
        including
            .into_iter()
            .chain(self.include_dirs.iter().cloned())
            .map(|d| d.join(name))
            .find(|p| p.is_file())
    }

    /// A word (a name), or an error.
    pub fn word(&mut self) -> Result<String> {
        match self.next()? {
            Tok::Word(w) => Ok(w),
            other => Err(self.error_at(
                self.last,
                format!("expected a name, found {}", lex::describe(&other)),
            )),
        }
    }

    /// Skips one value of a directive (a string, or an expression with
    /// strings in it): up to the next token that starts a new statement.
    fn skip_value(&mut self) -> Result<()> {
        self.skip_parens()?;
        if let Some(Tok::Str(_)) = self.raw().map(|t| t.tok) {
            self.advance();
        } else if let Some(Tok::Word(_)) = self.raw().map(|t| t.tok) {
            self.advance();
            self.skip_parens()?;
        }
        Ok(())
    }

    /// Declares `name` as `value` (the reader's own, such as `#default`'s).
    pub fn set(&mut self, name: &str, value: Value) {
        self.symbols.insert(name.to_owned(), value);
    }

    /// Reads one level deeper with `read` (a parenthesis, a vector, an
    /// object inside an object): past [`MAX_NESTING`] levels, an error.
    pub fn nested<T>(&mut self, read: impl FnOnce(&mut Parser) -> Result<T>) -> Result<T> {
        if self.nesting >= MAX_NESTING {
            return Err(self.error(format!("this nests deeper than {MAX_NESTING} levels")));
        }
        self.nesting += 1;
        let v = read(self);
        self.nesting -= 1;
        v
    }

    /// Where the last token taken was.
    pub fn last(&self) -> Loc {
        self.last
    }
}
