//! Tokens of POV-Ray's scene language: numbers, words, strings, `#`
//! directives and punctuation, each with the line and column it starts at.
//! Comments (`//` to the end of the line, `/* */` nested, as POV-Ray nests
//! them) are dropped here.

/// Where a token starts: 1-based line and column (in characters) of its file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct At {
    pub line: u32,
    pub column: u32,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Tok {
    Number(f64),
    Word(String),
    Str(String),
    /// `#declare` and the like: the word after `#`.
    Directive(String),
    /// One character of punctuation, or `<=`, `>=`, `!=` as 'l', 'g', 'n'.
    Punct(char),
}

#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    pub tok: Tok,
    pub at: At,
}

/// A lexing error: where, and what.
#[derive(Debug, PartialEq)]
pub struct LexError {
    pub at: At,
    pub message: String,
}

/// The words that make a directive after `#`, POV-Ray 3.7's.
const DIRECTIVES: &[&str] = &[
    "declare",
    "local",
    "undef",
    "include",
    "version",
    "if",
    "ifdef",
    "ifndef",
    "else",
    "elseif",
    "end",
    "switch",
    "case",
    "range",
    "break",
    "default",
    "while",
    "for",
    "macro",
    "debug",
    "warning",
    "error",
    "fopen",
    "fclose",
    "read",
    "write",
    "render",
    "statistics",
];

/// The tokens of `text`.
pub fn tokens(text: &str) -> Result<Vec<Token>, LexError> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let (mut i, mut line, mut col) = (0usize, 1u32, 1u32);
    // Advances over `n` characters, keeping line and column.
    let step = |i: &mut usize, line: &mut u32, col: &mut u32, n: usize| {
        for _ in 0..n {
            if chars.get(*i) == Some(&'\n') {
                *line += 1;
                *col = 1;
            } else {
                *col += 1;
            }
            *i += 1;
        }
    };
    while i < chars.len() {
        let c = chars[i];
        let at = At { line, column: col };
        let next = chars.get(i + 1).copied();
        if c.is_whitespace() {
            step(&mut i, &mut line, &mut col, 1);
        } else if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                step(&mut i, &mut line, &mut col, 1);
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0usize;
            loop {
                match (chars.get(i), chars.get(i + 1)) {
                    (Some('/'), Some('*')) => {
                        depth += 1;
                        step(&mut i, &mut line, &mut col, 2);
                    }
                    (Some('*'), Some('/')) => {
                        depth -= 1;
                        step(&mut i, &mut line, &mut col, 2);
                        if depth == 0 {
                            break;
                        }
                    }
                    (Some(_), _) => step(&mut i, &mut line, &mut col, 1),
                    (None, _) => {
                        return Err(LexError {
                            at,
                            message: "this comment is never closed (`*/`)".into(),
                        });
                    }
                }
            }
        } else if c.is_ascii_digit() || (c == '.' && next.is_some_and(|n| n.is_ascii_digit())) {
            let start = i;
            let mut end = i;
            while end < chars.len() && (chars[end].is_ascii_digit() || chars[end] == '.') {
                end += 1;
            }
            if end < chars.len() && matches!(chars[end], 'e' | 'E') {
                let mut e = end + 1;
                if e < chars.len() && matches!(chars[e], '+' | '-') {
                    e += 1;
                }
                if e < chars.len() && chars[e].is_ascii_digit() {
                    end = e;
                    while end < chars.len() && chars[end].is_ascii_digit() {
                        end += 1;
                    }
                }
            }
            let text: String = chars[start..end].iter().collect();
            let value = text.parse::<f64>().map_err(|_| LexError {
                at,
                message: format!("`{text}` is not a number"),
            })?;
            step(&mut i, &mut line, &mut col, end - start);
            out.push(Token {
                tok: Tok::Number(value),
                at,
            });
        } else if c.is_alphabetic() || c == '_' {
            let word = word_at(&chars, i);
            step(&mut i, &mut line, &mut col, word.chars().count());
            out.push(Token {
                tok: Tok::Word(word),
                at,
            });
        } else if c == '#' {
            step(&mut i, &mut line, &mut col, 1);
            while i < chars.len() && matches!(chars[i], ' ' | '\t') {
                step(&mut i, &mut line, &mut col, 1);
            }
            let word = if i < chars.len() && (chars[i].is_alphabetic() || chars[i] == '_') {
                word_at(&chars, i)
            } else {
                String::new()
            };
            // POV-Ray reads a `#` that no directive follows as if it were
            // not there (a macro's name after it calls the macro; a stray
            // one before a brace is passed over): so does the reader.
            if !DIRECTIVES.contains(&word.as_str()) {
                continue;
            }
            step(&mut i, &mut line, &mut col, word.chars().count());
            out.push(Token {
                tok: Tok::Directive(word),
                at,
            });
        } else if c == '"' {
            let mut text = String::new();
            step(&mut i, &mut line, &mut col, 1);
            loop {
                match chars.get(i) {
                    Some('"') => {
                        step(&mut i, &mut line, &mut col, 1);
                        break;
                    }
                    Some('\\') if i + 1 < chars.len() => {
                        text.push(match chars[i + 1] {
                            'n' => '\n',
                            't' => '\t',
                            other => other,
                        });
                        step(&mut i, &mut line, &mut col, 2);
                    }
                    Some('\n') | None => {
                        return Err(LexError {
                            at,
                            message: "this string is never closed (`\"`)".into(),
                        });
                    }
                    Some(&ch) => {
                        text.push(ch);
                        step(&mut i, &mut line, &mut col, 1);
                    }
                }
            }
            out.push(Token {
                tok: Tok::Str(text),
                at,
            });
        } else if "{}()[]<>,;+-*/=!.?:&|".contains(c) {
            let (p, n) = match (c, next) {
                ('<', Some('=')) => ('l', 2),
                ('>', Some('=')) => ('g', 2),
                ('!', Some('=')) => ('n', 2),
                _ => (c, 1),
            };
            step(&mut i, &mut line, &mut col, n);
            out.push(Token {
                tok: Tok::Punct(p),
                at,
            });
        } else {
            return Err(LexError {
                at,
                message: format!("unexpected character `{c}`"),
            });
        }
    }
    Ok(out)
}

fn word_at(chars: &[char], start: usize) -> String {
    chars[start..]
        .iter()
        .take_while(|c| c.is_alphanumeric() || **c == '_')
        .collect()
}

/// How a token reads in a message.
pub fn describe(tok: &Tok) -> String {
    match tok {
        Tok::Number(v) => format!("the number {v}"),
        Tok::Word(w) => format!("`{w}`"),
        Tok::Str(s) => format!("the string \"{s}\""),
        Tok::Directive(d) => format!("`#{d}`"),
        Tok::Punct('l') => "`<=`".into(),
        Tok::Punct('g') => "`>=`".into(),
        Tok::Punct('n') => "`!=`".into(),
        Tok::Punct(c) => format!("`{c}`"),
    }
}
