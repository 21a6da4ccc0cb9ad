//! Reading and writing layout text. No file system here: callers pass strings.
//!
//! A layout file is untrusted input. [`parse`] reports every problem it can find in one go,
//! each with a line and column and, where it concerns a field, its JSON path.

use super::bounds::{CHAIN_MAX, NESTING_MAX};
use super::types::{FORMAT, Layout, VERSION};
use super::validate::validate;
use jsonc_parser::ast;
use jsonc_parser::common::Ranged;
use serde_json::Value;
use std::fmt;

/// One problem in a layout text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Diagnostic {
    /// 1-based line and column of the offending text.
    pub line: usize,
    pub column: usize,
    /// JSON path of the field, e.g. `trees[0].root.radius`; `None` for syntax errors.
    pub path: Option<String>,
    pub message: String,
}

/// The longest path and message a diagnostic prints (a chain of arrows at its limit has a
/// path of 3,000 characters; serde's messages quote the offending value whole).
const PATH_SHOWN: usize = 160;
const MESSAGE_SHOWN: usize = 400;

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}: ", self.line, self.column)?;
        if let Some(p) = &self.path {
            write!(f, "{}: ", short_path(p))?;
        }
        f.write_str(&super::printable(&self.message, MESSAGE_SHOWN))
    }
}

/// A long JSON path with its middle left out: its start and its end say where it is.
fn short_path(p: &str) -> String {
    let n = p.chars().count();
    if n <= PATH_SHOWN {
        return super::printable(p, PATH_SHOWN);
    }
    let head: String = p.chars().take(PATH_SHOWN / 2).collect();
    let tail: String = p.chars().skip(n - PATH_SHOWN / 2).collect();
    format!(
        "{}…{}",
        super::printable(&head, PATH_SHOWN),
        super::printable(&tail, PATH_SHOWN)
    )
}

/// Every problem found in one file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{}", .0.iter().map(|d| d.to_string()).collect::<Vec<_>>().join("\n"))]
pub struct Diagnostics(pub Vec<Diagnostic>);

/// The layout's JSON Schema, generated from the types.
pub fn schema() -> Value {
    serde_json::to_value(schemars::schema_for!(Layout)).expect("a schema is always JSON")
}

/// Serialises a layout: pretty-printed, stable (same document → same bytes), newline-ended.
pub fn to_json(layout: &Layout) -> String {
    let mut s = serde_json::to_string_pretty(layout).expect("a layout always serialises");
    s.push('\n');
    s
}

/// Parses a layout file's bytes: UTF-8 (a leading byte order mark is allowed, as JSON's RFC
/// 8259 lets a reader do), then as [`parse`]. A file in another encoding (UTF-16 or UTF-32,
/// found by its byte order mark or by the zero bytes around its first character) or with
/// bytes that are not UTF-8 is refused with the encoding, or the line and column of the
/// first bad byte.
pub fn parse_bytes(bytes: &[u8]) -> Result<Layout, Diagnostics> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    if let Some(encoding) = other_encoding(bytes) {
        return Err(one(
            1,
            1,
            format!(
                "this file is {encoding}; windloom reads layouts as UTF-8: save it as UTF-8 \
                 (in most editors: Save As, Encoding)"
            ),
        ));
    }
    match std::str::from_utf8(bytes) {
        Ok(text) => parse(text),
        Err(e) => {
            // The prefix is valid UTF-8 by construction.
            let before = std::str::from_utf8(&bytes[..e.valid_up_to()]).unwrap_or_default();
            let (line, column) = line_col(before, before.len());
            let byte = bytes[e.valid_up_to()];
            Err(one(
                line,
                column,
                format!(
                    "byte 0x{byte:02X} is not UTF-8 text; windloom reads layouts as UTF-8 (was \
                     it saved as Latin-1 or Windows-1252?)"
                ),
            ))
        }
    }
}

fn one(line: usize, column: usize, message: String) -> Diagnostics {
    Diagnostics(vec![Diagnostic {
        line,
        column,
        path: None,
        message,
    }])
}

/// The name of the encoding of a JSON text that is not UTF-8, from its byte order mark or
/// the zero bytes around its first (ASCII) character, as RFC 4627 detected it.
fn other_encoding(b: &[u8]) -> Option<&'static str> {
    let at = |i: usize| b.get(i).copied();
    let nz = |i: usize| at(i).is_some_and(|x| x != 0);
    match (at(0), at(1), at(2), at(3)) {
        (Some(0xFF), Some(0xFE), Some(0), Some(0)) => Some("UTF-32 (little-endian)"),
        (Some(0), Some(0), Some(0xFE), Some(0xFF)) => Some("UTF-32 (big-endian)"),
        (Some(0xFF), Some(0xFE), ..) => Some("UTF-16 (little-endian)"),
        (Some(0xFE), Some(0xFF), ..) => Some("UTF-16 (big-endian)"),
        (_, Some(0), Some(0), Some(0)) if nz(0) => Some("UTF-32 (little-endian)"),
        (Some(0), Some(0), Some(0), _) if nz(3) => Some("UTF-32 (big-endian)"),
        (_, Some(0), ..) if nz(0) => Some("UTF-16 (little-endian)"),
        (Some(0), ..) if nz(1) => Some("UTF-16 (big-endian)"),
        _ => None,
    }
}

/// Refuses a text that nests deeper than [`NESTING_MAX`], at the bracket or field that goes
/// past it, before anything recursive reads it. Levels are counted as the parser that
/// locates fields counts them: each open object, array, and field of an object.
fn check_nesting(text: &str) -> Result<(), Diagnostics> {
    use jsonc_parser::tokens::Token;
    // Each open container, and whether an object is inside one of its fields (after `key:`).
    let mut stack: Vec<(bool, bool)> = Vec::new();
    let mut fields = 0usize;
    let mut tokens = jsonc_parser::Scanner::new(text, &Default::default());
    while let Ok(Some(token)) = tokens.scan() {
        match token {
            Token::OpenBrace | Token::OpenBracket => {
                stack.push((matches!(token, Token::OpenBrace), false));
            }
            Token::CloseBrace | Token::CloseBracket => {
                if let Some((_, true)) = stack.pop() {
                    fields -= 1;
                }
            }
            Token::Colon => {
                if let Some((true, in_field)) = stack.last_mut()
                    && !*in_field
                {
                    *in_field = true;
                    fields += 1;
                }
            }
            Token::Comma => {
                if let Some((true, in_field)) = stack.last_mut()
                    && *in_field
                {
                    *in_field = false;
                    fields -= 1;
                }
            }
            _ => {}
        }
        if stack.len() + fields > NESTING_MAX {
            let (line, column) = line_col(text, tokens.token_start());
            let path = path_at(text, tokens.token_start());
            return Err(Diagnostics(vec![Diagnostic {
                line,
                column,
                path: (!path.is_empty()).then_some(path),
                message: format!(
                    "nested deeper than the {NESTING_MAX} levels a layout may have (each open \
                     object, array and field counts one; a chain of arrows holds at most \
                     {CHAIN_MAX})"
                ),
            }]));
        }
    }
    Ok(())
}

/// 1-based line and column (in characters) of byte `offset`.
fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().unwrap_or("").chars().count() + 1;
    (line, col)
}

/// Every key that an object of the text holds twice, at the second one, naming the first:
/// JSON readers differ on which one counts, and rewriting the file (`fmt`, a save) would
/// drop one. The text has parsed as JSON.
fn duplicate_keys(text: &str, ast: Option<&ast::Value<'_>>) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let mut stack: Vec<(&ast::Value<'_>, String)> =
        ast.map(|v| (v, String::new())).into_iter().collect();
    while let Some((v, path)) = stack.pop() {
        match v {
            ast::Value::Object(o) => {
                let mut seen: std::collections::HashMap<&str, usize> = Default::default();
                for p in &o.properties {
                    let key = p.name.as_str();
                    let child = if path.is_empty() {
                        key.to_string()
                    } else {
                        format!("{path}.{key}")
                    };
                    if let Some(&first) = seen.get(key) {
                        let (line, column) = line_col(text, p.start());
                        let (fl, fc) = line_col(text, first);
                        out.push(Diagnostic {
                            line,
                            column,
                            path: Some(child.clone()),
                            message: format!(
                                "duplicate key `{}` (first at {fl}:{fc}); keep one of them",
                                super::quote(key)
                            ),
                        });
                    } else {
                        seen.insert(key, p.start());
                    }
                    stack.push((&p.value, child));
                }
            }
            ast::Value::Array(a) => {
                for (i, e) in a.elements.iter().enumerate() {
                    stack.push((e, format!("{path}[{i}]")));
                }
            }
            _ => {}
        }
    }
    out
}

/// Parses, migrates and validates a layout text.
pub fn parse(text: &str) -> Result<Layout, Diagnostics> {
    check_nesting(text)?;
    let mut de = serde_json::Deserializer::from_str(text);
    // The nesting is bounded above, far below what the stack holds.
    de.disable_recursion_limit();
    let read = serde::Deserialize::deserialize(&mut de).and_then(|v: Value| de.end().map(|()| v));
    let mut value: Value = read.map_err(|e| {
        let (line, column) = (e.line().max(1), e.column().max(1));
        let at = offset_of(text, line, column);
        let path = path_at(text, at);
        let mut message = strip_position(&e.to_string());
        let rest = text[at..].trim_start_matches('-');
        if ["NaN", "Infinity", "inf"]
            .iter()
            .any(|w| rest.starts_with(w))
        {
            message.push_str(": NaN and infinities are not numbers in JSON; write a finite number");
        }
        Diagnostics(vec![Diagnostic {
            line,
            column,
            path: (!path.is_empty()).then_some(path),
            message,
        }])
    })?;
    let locator = Locator::new(text);
    let duplicates = duplicate_keys(text, locator.ast.as_ref());
    if !duplicates.is_empty() {
        return Err(sorted(duplicates));
    }
    let diag = |path: &str, message: String| locator.diagnostic(path, message);

    // Header: format and version decide whether we can read the rest at all.
    let Some(root) = value.as_object() else {
        return Err(Diagnostics(vec![diag(
            "",
            "a layout must be a JSON object".into(),
        )]));
    };
    match root.get("format") {
        Some(Value::String(s)) if s == FORMAT => {}
        Some(other) => {
            return Err(Diagnostics(vec![diag(
                "format",
                format!("must be \"{FORMAT}\", got {other}: this is not a windloom layout"),
            )]));
        }
        None => {
            return Err(Diagnostics(vec![diag(
                "",
                format!("missing field `format` (\"{FORMAT}\"): this is not a windloom layout"),
            )]));
        }
    }
    let version = match root.get("version") {
        Some(v) => match v.as_u64() {
            Some(n) => n,
            None => {
                return Err(Diagnostics(vec![diag(
                    "version",
                    format!("must be a whole number, got {v}"),
                )]));
            }
        },
        None => {
            return Err(Diagnostics(vec![diag(
                "",
                "missing field `version`".into(),
            )]));
        }
    };
    if version > u64::from(VERSION) {
        return Err(Diagnostics(vec![diag(
            "version",
            format!(
                "version {version} was made by a newer windloom; this build reads versions up to {VERSION}"
            ),
        )]));
    }
    if version < 1 {
        return Err(Diagnostics(vec![diag(
            "version",
            format!("version {version} does not exist: layout versions start at 1"),
        )]));
    }
    migrate(&mut value, version as u32).map_err(|m| Diagnostics(vec![diag("version", m)]))?;

    // Structure: every unknown field, found by walking the value beside the schema.
    let schema = schema();
    let mut diags = Vec::new();
    let mut unknown = Vec::new();
    find_unknown_fields(&schema, &schema, &value, "", &mut unknown);
    for u in &unknown {
        diags.push(locator.key_diagnostic(&u.path, &u.key, u.message()));
    }
    // Keep going without them so type and value errors are reported in the same run: a
    // likely misspelling stands in for the field it resembles (if that one is absent), so the
    // misspelling does not also show up as a missing field.
    for u in &unknown {
        move_key(&mut value, &u.path, &u.key, u.suggestion());
    }

    let mut layout: Layout = match serde_path_to_error::deserialize(&value) {
        Ok(l) => l,
        Err(e) => {
            let path = e.path().to_string();
            let path = if path == "." { String::new() } else { path };
            diags.push(diag(&path, e.inner().to_string()));
            return Err(sorted(diags));
        }
    };
    for issue in validate(&layout) {
        diags.push(diag(&issue.path, issue.message));
    }
    super::portable::normalize_paths(&mut layout);
    if diags.is_empty() {
        Ok(layout)
    } else {
        Err(sorted(diags))
    }
}

fn sorted(mut d: Vec<Diagnostic>) -> Diagnostics {
    d.sort_by_key(|d| (d.line, d.column));
    Diagnostics(d)
}

/// One step per format change: `MIGRATIONS[n - 1]` turns a version-`n` document into
/// version `n + 1`. Version 1 is the first format, so the table is empty for now.
type Migration = fn(&mut Value) -> Result<(), String>;
const MIGRATIONS: &[Migration] = &[];
const _: () = assert!(MIGRATIONS.len() as u32 == VERSION - 1);

/// Brings an older document (version `from`, 1 ≤ from ≤ VERSION) up to [`VERSION`].
fn migrate(value: &mut Value, from: u32) -> Result<(), String> {
    for step in &MIGRATIONS[(from - 1) as usize..] {
        step(value)?;
    }
    Ok(())
}

/// The byte offset of 1-based `line` and `column` (serde_json counts the column in bytes),
/// clamped to the text and to a character boundary.
fn offset_of(text: &str, line: usize, column: usize) -> usize {
    let start: usize = text
        .split_inclusive('\n')
        .take(line - 1)
        .map(str::len)
        .sum();
    let mut at = (start + column - 1).min(text.len());
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    at
}

/// The JSON path (`world.size[1]`) of the value being read at byte `offset` of a text that
/// may not parse: the objects' keys and the arrays' indices open at that point, from
/// jsonc-parser's tokens before it. Empty at the top level.
fn path_at(text: &str, offset: usize) -> String {
    use jsonc_parser::tokens::Token;
    enum Frame {
        Object(Option<String>),
        Array(usize),
    }
    let mut stack: Vec<Frame> = Vec::new();
    // In an object, a string before ':' is the key of the value that follows.
    let mut expect_key = false;
    let mut tokens = jsonc_parser::Scanner::new(text, &Default::default());
    while let Ok(Some(token)) = tokens.scan() {
        if tokens.token_start() >= offset {
            break;
        }
        match token {
            Token::String(key) if expect_key => {
                if let Some(Frame::Object(k)) = stack.last_mut() {
                    *k = Some(key.into_owned());
                }
                expect_key = false;
            }
            Token::OpenBrace => {
                stack.push(Frame::Object(None));
                expect_key = true;
            }
            Token::OpenBracket => stack.push(Frame::Array(0)),
            Token::CloseBrace | Token::CloseBracket => {
                stack.pop();
                expect_key = false;
            }
            Token::Comma => match stack.last_mut() {
                Some(Frame::Array(i)) => *i += 1,
                Some(Frame::Object(key)) => {
                    *key = None;
                    expect_key = true;
                }
                None => {}
            },
            _ => {}
        }
    }
    let mut path = String::new();
    for f in &stack {
        match f {
            Frame::Object(Some(key)) => {
                if !path.is_empty() {
                    path.push('.');
                }
                path.push_str(key);
            }
            Frame::Object(None) => break,
            Frame::Array(i) => path.push_str(&format!("[{i}]")),
        }
    }
    path
}

/// serde_json appends " at line L column C"; we print the position ourselves.
fn strip_position(msg: &str) -> String {
    match msg.rfind(" at line ") {
        Some(i) => msg[..i].to_string(),
        None => msg.to_string(),
    }
}

struct Unknown {
    path: String,
    key: String,
    valid: Vec<String>,
}

impl Unknown {
    /// The valid name closest to the unknown one, if it is close enough to be a misspelling.
    fn suggestion(&self) -> Option<&str> {
        self.valid
            .iter()
            .map(|v| (strsim::damerau_levenshtein(&self.key, v), v))
            .min()
            .filter(|(d, _)| *d <= 2.max(self.key.len() / 3))
            .map(|(_, v)| v.as_str())
    }

    fn message(&self) -> String {
        match self.suggestion() {
            Some(v) => format!(
                "unknown field `{}`, did you mean `{v}`?",
                super::quote(&self.key)
            ),
            None if self.valid.is_empty() => {
                format!("unknown field `{}`", super::quote(&self.key))
            }
            _ => format!(
                "unknown field `{}`, expected one of: {}",
                super::quote(&self.key),
                self.valid.join(", ")
            ),
        }
    }
}

fn resolve<'a>(root: &'a Value, mut s: &'a Value) -> &'a Value {
    while let Some(r) = s.get("$ref").and_then(Value::as_str) {
        let name = r.rsplit('/').next().unwrap_or_default();
        match root.get("$defs").and_then(|d| d.get(name)) {
            Some(t) => s = t,
            None => break,
        }
    }
    s
}

/// Picks the branch of a `oneOf`/`anyOf` that describes `value`: the object branch whose
/// constant tag matches, or the first object branch without a tag.
fn pick_branch<'a>(root: &'a Value, s: &'a Value, value: &Value) -> Option<&'a Value> {
    let branches = s
        .get("oneOf")
        .or_else(|| s.get("anyOf"))
        .and_then(Value::as_array)?;
    let obj = value.as_object()?;
    let mut untagged = None;
    for b in branches {
        let b = resolve(root, b);
        let Some(props) = b.get("properties").and_then(Value::as_object) else {
            continue;
        };
        let tag = props
            .iter()
            .find_map(|(k, p)| p.get("const").map(|c| (k, c)));
        match tag {
            Some((k, c)) if obj.get(k) == Some(c) => return Some(b),
            Some(_) => {}
            None => untagged = untagged.or(Some(b)),
        }
    }
    untagged
}

fn find_unknown_fields(root: &Value, s: &Value, value: &Value, path: &str, out: &mut Vec<Unknown>) {
    let s = resolve(root, s);
    if let Some(b) = pick_branch(root, s, value) {
        return find_unknown_fields(root, b, value, path, out);
    }
    match value {
        Value::Object(obj) => {
            let Some(props) = s.get("properties").and_then(Value::as_object) else {
                return;
            };
            let closed = s.get("additionalProperties") == Some(&Value::Bool(false));
            for (k, v) in obj {
                let child = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                match props.get(k) {
                    Some(ps) => find_unknown_fields(root, ps, v, &child, out),
                    None if closed => out.push(Unknown {
                        path: path.to_string(),
                        key: k.clone(),
                        valid: props.keys().cloned().collect(),
                    }),
                    None => {}
                }
            }
        }
        Value::Array(items) => {
            if let Some(is) = s.get("items") {
                for (i, v) in items.iter().enumerate() {
                    find_unknown_fields(root, is, v, &format!("{path}[{i}]"), out);
                }
            }
        }
        _ => {}
    }
}

/// Splits `a.b[2].c` into segments.
fn segments(path: &str) -> Vec<Seg> {
    let mut out = Vec::new();
    for part in path.split('.').filter(|p| !p.is_empty()) {
        let mut rest = part;
        if let Some(i) = rest.find('[') {
            if i > 0 {
                out.push(Seg::Key(rest[..i].to_string()));
            }
            rest = &rest[i..];
            while let Some(stripped) = rest.strip_prefix('[') {
                let end = stripped.find(']').unwrap_or(stripped.len());
                if let Ok(n) = stripped[..end].parse() {
                    out.push(Seg::Index(n));
                }
                rest = stripped.get(end + 1..).unwrap_or("");
            }
        } else {
            out.push(Seg::Key(rest.to_string()));
        }
    }
    out
}

enum Seg {
    Key(String),
    Index(usize),
}

/// Removes `key` from the object at `path`, putting its value under `rename` if given and free.
fn move_key(value: &mut Value, path: &str, key: &str, rename: Option<&str>) {
    let mut v = value;
    for seg in segments(path) {
        let next = match seg {
            Seg::Key(k) => v.get_mut(&k),
            Seg::Index(i) => v.get_mut(i),
        };
        match next {
            Some(n) => v = n,
            None => return,
        }
    }
    if let Some(o) = v.as_object_mut() {
        let taken = o.remove(key);
        if let (Some(new), Some(val)) = (rename, taken)
            && !o.contains_key(new)
        {
            o.insert(new.to_string(), val);
        }
    }
}

/// Maps JSON paths to line/column positions in the source text.
struct Locator<'a> {
    text: &'a str,
    ast: Option<ast::Value<'a>>,
}

impl<'a> Locator<'a> {
    fn new(text: &'a str) -> Self {
        let options = jsonc_parser::ParseOptions {
            allow_comments: false,
            allow_loose_object_property_names: false,
            allow_trailing_commas: false,
            ..Default::default()
        };
        let ast = jsonc_parser::parse_to_ast(text, &Default::default(), &options)
            .ok()
            .and_then(|r| r.value);
        Self { text, ast }
    }

    /// The deepest AST value along `path`, and the object property named `key` under it.
    fn find(&self, path: &str, key: Option<&str>) -> usize {
        let Some(mut v) = self.ast.as_ref() else {
            return 0;
        };
        let mut pos = v.start();
        for seg in segments(path) {
            let next = match (&seg, v) {
                (Seg::Key(k), ast::Value::Object(o)) => o
                    .properties
                    .iter()
                    .find(|p| p.name.as_str() == k)
                    .map(|p| &p.value),
                (Seg::Index(i), ast::Value::Array(a)) => a.elements.get(*i),
                _ => None,
            };
            match next {
                Some(n) => {
                    v = n;
                    pos = n.start();
                }
                None => return pos,
            }
        }
        if let (Some(k), ast::Value::Object(o)) = (key, v)
            && let Some(p) = o.properties.iter().find(|p| p.name.as_str() == k)
        {
            return p.start();
        }
        pos
    }

    fn line_col(&self, offset: usize) -> (usize, usize) {
        line_col(self.text, offset)
    }

    fn diagnostic(&self, path: &str, message: String) -> Diagnostic {
        let (line, column) = self.line_col(self.find(path, None));
        Diagnostic {
            line,
            column,
            path: (!path.is_empty()).then(|| path.to_string()),
            message,
        }
    }

    fn key_diagnostic(&self, path: &str, key: &str, message: String) -> Diagnostic {
        let (line, column) = self.line_col(self.find(path, Some(key)));
        let full = if path.is_empty() {
            key.to_string()
        } else {
            format!("{path}.{key}")
        };
        Diagnostic {
            line,
            column,
            path: Some(full),
            message,
        }
    }
}
