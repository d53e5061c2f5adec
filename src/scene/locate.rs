//! Source positions for scene fields: a tolerant RON scanner that maps a [`FieldPath`] such as
//! `objects[2].shape.radius` to the line and column of its value, and a position back to the
//! path of the field that encloses it.
//!
//! ron reports positions for syntax and type errors but keeps none for values once they are
//! deserialized, so [`super::validate`]'s violations are located here instead. The scanner
//! understands the RON surface the scene format uses: comments (`//`, nested `/* */`),
//! strings with escapes, raw strings (`r#"..."#`), character literals, `#![enable(...)]`
//! attributes, struct and variant names before parentheses (`Scene(`, `Sphere(`, `Point(`),
//! tuples, lists and maps. A variant or struct name is transparent to paths: the path of the
//! radius in `shape: Sphere(centre: (0, 0, 0), radius: 1)` is `shape.radius`.
//!
//! It never panics and accepts any text: on malformed input it recovers by closing groups at
//! the next closing bracket, so positions stay meaningful near the error. Lines and columns
//! are 1-based and columns count characters (not bytes), exactly as ron's `Position` does.

mod lex;

use std::fmt;
use std::ops::Range;

use lex::{is_ident_char, tokenize, Pos, Tok, Token};

/// One step of a [`FieldPath`]: a struct field name or an index into a list or tuple.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Segment {
    /// A named field, e.g. `radius`.
    Field(String),
    /// A 0-based position in a list or tuple, e.g. the `2` of `objects[2]`.
    Index(usize),
}

/// The path from the scene root to one value, displayed like `objects[2].shape.radius`.
///
/// # Examples
/// ```
/// use penumbra::scene::locate::FieldPath;
/// let path = FieldPath::root().field("objects").index(2).field("shape").field("radius");
/// assert_eq!(path.to_string(), "objects[2].shape.radius");
/// assert_eq!(FieldPath::parse("objects[2].shape.radius"), Some(path));
/// ```
#[derive(Debug, Clone, Default, PartialEq, Eq, Hash)]
pub struct FieldPath {
    segments: Vec<Segment>,
}

impl FieldPath {
    /// The empty path: the scene itself.
    pub fn root() -> Self {
        Self::default()
    }

    /// This path extended by a field name.
    pub fn field(mut self, name: &str) -> Self {
        self.segments.push(Segment::Field(name.to_owned()));
        self
    }

    /// This path extended by a list or tuple index.
    pub fn index(mut self, index: usize) -> Self {
        self.segments.push(Segment::Index(index));
        self
    }

    /// The segments from the root down.
    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    /// Whether this is the root path.
    pub fn is_empty(&self) -> bool {
        self.segments.is_empty()
    }

    /// The last segment, if any.
    pub fn last(&self) -> Option<&Segment> {
        self.segments.last()
    }

    /// Parses the display form (`objects[2].shape.radius`); `None` if it is malformed.
    pub fn parse(text: &str) -> Option<Self> {
        let mut path = Self::root();
        if text.is_empty() {
            return Some(path);
        }
        for (i, part) in text.split('.').enumerate() {
            let (name, mut rest) = part.split_at(part.find('[').unwrap_or(part.len()));
            if name.is_empty() && (i > 0 || rest.is_empty()) {
                return None;
            }
            if !name.chars().all(is_ident_char) {
                return None;
            }
            if !name.is_empty() {
                path = path.field(name);
            }
            while let Some(tail) = rest.strip_prefix('[') {
                let close = tail.find(']')?;
                path = path.index(tail[..close].parse().ok()?);
                rest = &tail[close + 1..];
            }
            if !rest.is_empty() {
                return None;
            }
        }
        Some(path)
    }
}

impl fmt::Display for FieldPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, segment) in self.segments.iter().enumerate() {
            match segment {
                Segment::Field(name) if i == 0 => f.write_str(name)?,
                Segment::Field(name) => write!(f, ".{name}")?,
                Segment::Index(index) => write!(f, "[{index}]")?,
            }
        }
        Ok(())
    }
}

/// The 1-based line and column of the value at `path` in the RON `text`.
///
/// When the field is absent (defaulted), the position of the nearest enclosing value that is
/// present is returned instead (for a missing `objects[1].transform.scale`, the start of
/// `objects[1].transform` or else of `objects[1]`). `None` only when `text` holds no value.
///
/// # Examples
/// ```
/// use penumbra::scene::locate::{position_of, FieldPath};
/// let text = "Scene(\n  camera: (fov_deg: 45),\n)";
/// let path = FieldPath::root().field("camera").field("fov_deg");
/// assert_eq!(position_of(text, &path), Some((2, 21)));
/// ```
pub fn position_of(text: &str, path: &FieldPath) -> Option<(usize, usize)> {
    let root = parse(text)?;
    let mut node = &root;
    for segment in path.segments() {
        let Some(item) = node.child(segment) else { break };
        match &item.value {
            Some(value) => node = value,
            None => return Some(item.start.line_col()),
        }
    }
    Some(node.start.line_col())
}

/// The path of the innermost field or element whose source contains the 1-based `line` and
/// `col`; a position on a field's name yields that field. The root path when nothing matches.
///
/// # Examples
/// ```
/// use penumbra::scene::locate::path_at;
/// let text = "Scene(\n  objects: [(shape: Sphere(radius: 1))],\n)";
/// assert_eq!(path_at(text, 2, 36).to_string(), "objects[0].shape.radius");
/// ```
pub fn path_at(text: &str, line: usize, col: usize) -> FieldPath {
    let mut path = FieldPath::root();
    let Some(root) = parse(text) else { return path };
    let at = Pos { line, col, offset: 0 };
    let mut node = &root;
    while let NodeKind::Group(items) = &node.kind {
        let Some((segment, item)) = enclosing_item(items, at) else { break };
        path.segments.push(segment);
        match &item.value {
            Some(value) if value.start.before_eq(at) => node = value,
            _ => break,
        }
    }
    path
}

/// The item of a group whose source contains `at`, with its path segment. In a struct (a
/// group with named fields) an unnamed item is a syntax error, not an element, and is skipped.
fn enclosing_item(items: &[Item], at: Pos) -> Option<(Segment, &Item)> {
    let is_struct = items.iter().any(|item| item.key.is_some());
    let mut index = 0;
    for item in items {
        let named_if_struct = item.key.is_some() || !is_struct;
        if named_if_struct && item.start.before_eq(at) && at.before_eq(item.end) {
            let segment = match &item.key {
                Some(key) => Segment::Field(key.clone()),
                None => Segment::Index(index),
            };
            return Some((segment, item));
        }
        index += usize::from(item.key.is_none());
    }
    None
}

/// The source text of the value at `path`, if that field is present.
///
/// # Examples
/// ```
/// use penumbra::scene::locate::{value_source, FieldPath};
/// let text = "(camera: (width: 6.4))";
/// let path = FieldPath::root().field("camera").field("width");
/// assert_eq!(value_source(text, &path), Some("6.4"));
/// ```
pub fn value_source<'t>(text: &'t str, path: &FieldPath) -> Option<&'t str> {
    let root = parse(text)?;
    let mut node = &root;
    for segment in path.segments() {
        node = node.child(segment)?.value.as_ref()?;
    }
    text.get(node.bytes.clone())
}

/// Groups nested deeper than this are skipped as a whole (ron's own limit is 128).
const MAX_DEPTH: usize = 256;

#[derive(Debug)]
struct Node {
    start: Pos,
    /// Position of the last character.
    end: Pos,
    bytes: Range<usize>,
    kind: NodeKind,
}

#[derive(Debug)]
enum NodeKind {
    Scalar,
    /// A parenthesised, bracketed or braced group, with or without a name before it.
    Group(Vec<Item>),
}

/// A field (`name: value`) or an element of a group.
#[derive(Debug)]
struct Item {
    key: Option<String>,
    start: Pos,
    end: Pos,
    /// `None` when the source has a key but no value after it.
    value: Option<Node>,
}

impl Node {
    fn child(&self, segment: &Segment) -> Option<&Item> {
        let NodeKind::Group(items) = &self.kind else { return None };
        match segment {
            Segment::Field(name) => items.iter().find(|item| item.key.as_deref() == Some(name)),
            Segment::Index(index) => items.iter().filter(|item| item.key.is_none()).nth(*index),
        }
    }
}

struct Parser<'t> {
    text: &'t str,
    tokens: Vec<Token>,
    next: usize,
}

/// Parses the first value of `text` (after any `#![...]` attributes).
fn parse(text: &str) -> Option<Node> {
    let mut parser = Parser { text, tokens: tokenize(text), next: 0 };
    while parser.peek_kind() == Some(Tok::Other('#')) {
        parser.next += 1;
        if parser.peek_kind() == Some(Tok::Other('!')) {
            parser.next += 1;
        }
        if let Some(Tok::Open(_)) = parser.peek_kind() {
            parser.group(0);
        }
    }
    parser.value(0)
}

impl Parser<'_> {
    fn peek_kind(&self) -> Option<Tok> {
        self.tokens.get(self.next).map(|t| t.kind)
    }

    fn token(&self, index: usize) -> Option<&Token> {
        self.tokens.get(index)
    }

    fn value(&mut self, depth: usize) -> Option<Node> {
        let first = self.token(self.next)?.clone();
        match first.kind {
            Tok::Ident if matches!(self.token(self.next + 1).map(|t| t.kind), Some(Tok::Open('('))) => {
                self.next += 1;
                let mut group = self.group(depth);
                group.start = first.start;
                group.bytes.start = first.bytes.start;
                Some(group)
            }
            Tok::Open(_) => Some(self.group(depth)),
            Tok::Ident | Tok::Literal | Tok::Other(_) => {
                self.next += 1;
                Some(Node { start: first.start, end: first.last, bytes: first.bytes, kind: NodeKind::Scalar })
            }
            Tok::Close | Tok::Comma | Tok::Colon => None,
        }
    }

    /// The group whose opening bracket is the next token, up to its closing bracket (any
    /// closing bracket closes it) or the end of the text.
    fn group(&mut self, depth: usize) -> Node {
        let Some(open) = self.token(self.next).cloned() else {
            let end = Pos { line: 1, col: 1, offset: 0 };
            return Node { start: end, end, bytes: 0..0, kind: NodeKind::Scalar };
        };
        self.next += 1;
        let mut node = Node {
            start: open.start,
            end: open.last,
            bytes: open.bytes.clone(),
            kind: NodeKind::Group(Vec::new()),
        };
        if depth >= MAX_DEPTH {
            self.skip_balanced(&mut node);
            return node;
        }
        let mut items = Vec::new();
        while let Some(token) = self.token(self.next).cloned() {
            match token.kind {
                Tok::Close => {
                    self.next += 1;
                    node.end = token.last;
                    node.bytes.end = token.bytes.end;
                    node.kind = NodeKind::Group(items);
                    return node;
                }
                Tok::Comma | Tok::Colon => self.next += 1,
                _ => items.push(self.item(depth)),
            }
        }
        self.close_at_end(&mut node);
        node.kind = NodeKind::Group(items);
        node
    }

    /// A field or element; the next token starts a value.
    fn item(&mut self, depth: usize) -> Item {
        let key_token = self.token(self.next).cloned();
        let keyed = matches!(self.token(self.next + 1).map(|t| t.kind), Some(Tok::Colon));
        if let (Some(key), true) = (key_token, keyed) {
            self.next += 2;
            let value = self.value(depth + 1);
            let end = value.as_ref().map_or(key.last, |v| v.end);
            let name = match key.kind {
                Tok::Ident => self.text.get(key.bytes.clone()).map(|k| k.trim_start_matches("r#").to_owned()),
                _ => None,
            };
            // A map entry (`"key": value`) is indexed by position, like a list element.
            return Item { key: name, start: key.start, end, value };
        }
        let value = self.value(depth + 1);
        let (start, end) = value.as_ref().map_or_else(|| (self.eof(), self.eof()), |v| (v.start, v.end));
        Item { key: None, start, end, value }
    }

    /// Skips a group too deep to record, counting brackets without recursion.
    fn skip_balanced(&mut self, node: &mut Node) {
        let mut open = 1usize;
        while let Some(token) = self.token(self.next).cloned() {
            self.next += 1;
            match token.kind {
                Tok::Open(_) => open += 1,
                Tok::Close => open -= 1,
                _ => {}
            }
            if open == 0 {
                node.end = token.last;
                node.bytes.end = token.bytes.end;
                return;
            }
        }
        self.close_at_end(node);
    }

    fn close_at_end(&self, node: &mut Node) {
        if let Some(last) = self.tokens.last() {
            node.end = last.last;
            node.bytes.end = last.bytes.end;
        }
    }

    fn eof(&self) -> Pos {
        self.tokens.last().map_or(Pos { line: 1, col: 1, offset: 0 }, |t| t.last)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn path(text: &str) -> FieldPath {
        FieldPath::parse(text).unwrap_or_else(|| panic!("bad path {text}"))
    }

    const TEXT: &str = r##"#![enable(implicit_some)]
// A comment with (brackets] and "quotes
Scene( /* nested /* block */ comment ) */
    camera: (position: (0, 1, -5), look_at: (0, 0, 0), fov_deg: 45),
    materials: [
        (name: "a \"q\" (", kd: (1, 0.5, 0)),
        (name: r#"raw "(" str"#, kd: (0, 0, 0), ks: 0.5),
    ],
    objects: [
        (shape: Sphere(centre: (0, 0, 0), radius: 1), material: "a"),
        (name: "é€", shape: Polygon(vertices: [(0, 0, 0), (1, 0, 0), (1, 1, 0)]), material: 'x'),
    ],
)"##;

    #[test]
    fn finds_values_after_comments_strings_and_names() {
        assert_eq!(position_of(TEXT, &path("camera.fov_deg")), Some((4, 65)));
        assert_eq!(position_of(TEXT, &path("materials[1].ks")), Some((7, 53)));
        assert_eq!(position_of(TEXT, &path("objects[0].shape.radius")), Some((10, 51)));
        assert_eq!(position_of(TEXT, &path("objects[0].shape")), Some((10, 17)));
        // Columns count characters: `é€` are two columns although five bytes.
        assert_eq!(position_of(TEXT, &path("objects[1].shape.vertices[2]")), Some((11, 70)));
        assert_eq!(position_of(TEXT, &path("objects[1].material")), Some((11, 93)));
    }

    #[test]
    fn absent_fields_fall_back_to_the_nearest_present_ancestor() {
        assert_eq!(position_of(TEXT, &path("camera.up")), Some((4, 13)));
        assert_eq!(position_of(TEXT, &path("objects[0].transform.scale")), Some((10, 9)));
        assert_eq!(position_of(TEXT, &path("objects[7].shape")), Some((9, 14)));
        assert_eq!(position_of(TEXT, &FieldPath::root()), Some((3, 1)));
        assert_eq!(position_of("  // only a comment", &path("camera")), None);
    }

    #[test]
    fn path_at_names_the_enclosing_field() {
        assert_eq!(path_at(TEXT, 10, 51).to_string(), "objects[0].shape.radius");
        assert_eq!(path_at(TEXT, 10, 45).to_string(), "objects[0].shape.radius");
        assert_eq!(path_at(TEXT, 11, 74).to_string(), "objects[1].shape.vertices[2][1]");
        assert_eq!(path_at(TEXT, 6, 20).to_string(), "materials[0].name");
        assert_eq!(path_at(TEXT, 8, 5).to_string(), "materials");
        assert_eq!(path_at(TEXT, 1, 1).to_string(), "");
        assert_eq!(path_at(TEXT, 99, 1).to_string(), "");
    }

    #[test]
    fn value_source_returns_the_exact_text() {
        assert_eq!(value_source(TEXT, &path("materials[0].name")), Some(r#""a \"q\" (""#));
        assert_eq!(value_source(TEXT, &path("objects[0].shape.centre")), Some("(0, 0, 0)"));
        assert_eq!(value_source(TEXT, &path("camera.up")), None);
    }

    #[test]
    fn paths_round_trip_through_display() {
        for text in ["", "camera", "objects[2].shape.radius", "a[1][2].b"] {
            assert_eq!(path(text).to_string(), text);
        }
        for bad in [".a", "a..b", "a[", "a[x]", "a]b"] {
            assert_eq!(FieldPath::parse(bad), None, "{bad}");
        }
    }

    #[test]
    fn malformed_text_never_panics() {
        let nasty =
            ["", "(", ")", "r#", "r#\"", "'", "b'", "\"\\", "/*", "/* /*", "a: (: ,]", "#![", "-", "(((("];
        for text in nasty {
            let _ = position_of(text, &path("a[0].b"));
            let _ = path_at(text, 1, 2);
            let _ = value_source(text, &path("a"));
        }
        let deep = "(".repeat(100_000);
        assert_eq!(position_of(&deep, &path("a")), Some((1, 1)));
    }
}
