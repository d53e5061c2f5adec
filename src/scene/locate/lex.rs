//! The token scanner under [`super`]: splits RON text into brackets, punctuation, identifiers
//! and literals with their line, column and byte range, skipping whitespace and comments.
//! Any text scans without panicking; unterminated strings and comments run to the end.

use std::ops::Range;

/// A position: 1-based line and character column, plus the byte offset.
#[derive(Debug, Clone, Copy)]
pub(super) struct Pos {
    pub(super) line: usize,
    pub(super) col: usize,
    pub(super) offset: usize,
}

impl Pos {
    pub(super) fn line_col(self) -> (usize, usize) {
        (self.line, self.col)
    }

    pub(super) fn before_eq(self, other: Pos) -> bool {
        (self.line, self.col) <= (other.line, other.col)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Tok {
    Ident,
    /// A number, string, character or any other literal.
    Literal,
    Open(char),
    Close,
    Comma,
    Colon,
    Other(char),
}

#[derive(Debug, Clone)]
pub(super) struct Token {
    pub(super) kind: Tok,
    /// Position of the first character.
    pub(super) start: Pos,
    /// Position of the last character.
    pub(super) last: Pos,
    /// Byte range in the source.
    pub(super) bytes: Range<usize>,
}

struct Lexer<'t> {
    text: &'t str,
    chars: std::iter::Peekable<std::str::CharIndices<'t>>,
    line: usize,
    col: usize,
    /// Position of the last character consumed.
    last: Pos,
}

impl<'t> Lexer<'t> {
    fn new(text: &'t str) -> Self {
        let origin = Pos { line: 1, col: 1, offset: 0 };
        Self { text, chars: text.char_indices().peekable(), line: 1, col: 1, last: origin }
    }

    fn here(&mut self) -> Pos {
        let offset = self.chars.peek().map_or(self.text.len(), |&(i, _)| i);
        Pos { line: self.line, col: self.col, offset }
    }

    fn peek(&mut self) -> Option<char> {
        self.chars.peek().map(|&(_, c)| c)
    }

    /// The character after the next one.
    fn peek2(&self) -> Option<char> {
        let mut ahead = self.chars.clone();
        ahead.next();
        ahead.next().map(|(_, c)| c)
    }

    fn bump(&mut self) -> Option<char> {
        let here = self.here();
        let (_, c) = self.chars.next()?;
        self.last = here;
        if c == '\n' {
            self.line += 1;
            self.col = 1;
        } else {
            self.col += 1;
        }
        Some(c)
    }

    fn bump_while(&mut self, keep: impl Fn(char) -> bool) {
        while self.peek().is_some_and(&keep) {
            self.bump();
        }
    }

    /// Skips whitespace and comments; an unclosed block comment runs to the end.
    fn skip_trivia(&mut self) {
        loop {
            match (self.peek(), self.peek2()) {
                (Some(c), _) if c.is_whitespace() => {
                    self.bump();
                }
                (Some('/'), Some('/')) => self.bump_while(|c| c != '\n'),
                (Some('/'), Some('*')) => {
                    self.bump();
                    self.bump();
                    let mut depth = 1usize;
                    while depth > 0 {
                        match (self.bump(), self.peek()) {
                            (None, _) => return,
                            (Some('/'), Some('*')) => {
                                self.bump();
                                depth += 1;
                            }
                            (Some('*'), Some('/')) => {
                                self.bump();
                                depth -= 1;
                            }
                            _ => {}
                        }
                    }
                }
                _ => return,
            }
        }
    }

    /// A quoted string whose opening `"` is next; `\` escapes the following character.
    fn string(&mut self) {
        self.bump();
        while let Some(c) = self.bump() {
            match c {
                '\\' => {
                    self.bump();
                }
                '"' => return,
                _ => {}
            }
        }
    }

    /// A raw string after its `r`: `hashes` `#`s, a `"`, and text up to `"` plus as many `#`s.
    fn raw_string(&mut self, hashes: usize) {
        for _ in 0..=hashes {
            self.bump();
        }
        while let Some(c) = self.bump() {
            if c == '"' {
                let mut seen = 0;
                while seen < hashes && self.peek() == Some('#') {
                    self.bump();
                    seen += 1;
                }
                if seen == hashes {
                    return;
                }
            }
        }
    }

    /// A character literal whose opening `'` is next; gives up at the end of the line.
    fn char_literal(&mut self) {
        self.bump();
        if self.peek() == Some('\\') {
            self.bump();
        }
        self.bump();
        while let Some(c) = self.peek() {
            if c == '\n' {
                return;
            }
            self.bump();
            if c == '\'' {
                return;
            }
        }
    }

    /// The number of `#` after the next character, and the character after them.
    fn hashes_after_next(&self) -> (usize, Option<char>) {
        let mut ahead = self.chars.clone();
        ahead.next();
        let mut hashes = 0;
        for (_, c) in ahead {
            if c != '#' {
                return (hashes, Some(c));
            }
            hashes += 1;
        }
        (hashes, None)
    }

    fn next_token(&mut self) -> Option<Token> {
        self.skip_trivia();
        let start = self.here();
        let c = self.peek()?;
        let kind = match c {
            '(' | '[' | '{' => {
                self.bump();
                Tok::Open(c)
            }
            ')' | ']' | '}' => {
                self.bump();
                Tok::Close
            }
            ',' => {
                self.bump();
                Tok::Comma
            }
            ':' => {
                self.bump();
                Tok::Colon
            }
            '"' => {
                self.string();
                Tok::Literal
            }
            '\'' => {
                self.char_literal();
                Tok::Literal
            }
            'b' if matches!(self.peek2(), Some('"' | '\'')) => {
                self.bump();
                match self.peek() {
                    Some('"') => self.string(),
                    _ => self.char_literal(),
                }
                Tok::Literal
            }
            'b' if self.peek2() == Some('r') => {
                self.bump();
                self.raw_or_ident()
            }
            'r' => self.raw_or_ident(),
            c if c.is_alphabetic() || c == '_' => {
                self.bump_while(is_ident_char);
                Tok::Ident
            }
            c if c.is_ascii_digit() || (matches!(c, '+' | '-' | '.') && self.starts_number()) => {
                self.number();
                Tok::Literal
            }
            c => {
                self.bump();
                Tok::Other(c)
            }
        };
        let bytes = start.offset..self.here().offset;
        Some(Token { kind, start, last: self.last, bytes })
    }

    /// After a sign or dot: whether a number (or `inf`/`NaN`) follows.
    fn starts_number(&self) -> bool {
        self.peek2().is_some_and(|c| c.is_alphanumeric() || c == '.')
    }

    fn number(&mut self) {
        let mut prev = '\0';
        if let Some(c) = self.bump() {
            prev = c;
        }
        while let Some(c) = self.peek() {
            let exponent_sign = matches!(c, '+' | '-') && matches!(prev, 'e' | 'E');
            if !(is_ident_char(c) || c == '.' || exponent_sign) {
                return;
            }
            self.bump();
            prev = c;
        }
    }

    /// At an `r`: a raw string (`r"..."`, `r#"..."#`), a raw identifier (`r#name`) or a
    /// plain identifier starting with `r`.
    fn raw_or_ident(&mut self) -> Tok {
        match self.hashes_after_next() {
            (hashes, Some('"')) => {
                self.bump();
                self.raw_string(hashes);
                Tok::Literal
            }
            (1, Some(c)) if is_ident_char(c) => {
                self.bump();
                self.bump();
                self.bump_while(is_ident_char);
                Tok::Ident
            }
            _ => {
                self.bump_while(is_ident_char);
                Tok::Ident
            }
        }
    }
}

pub(super) fn is_ident_char(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

pub(super) fn tokenize(text: &str) -> Vec<Token> {
    let mut lexer = Lexer::new(text);
    std::iter::from_fn(|| lexer.next_token()).collect()
}
