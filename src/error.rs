//! Input validation errors shared by every module that reads user files.

use std::fmt;

/// A value that breaks a documented rule of an input file or flag: the one
/// input error of every layer (the user can fix it; the CLI exits with 2).
///
/// Displayed as one line: `invalid <field> = <value>: allowed <allowed>`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("invalid {field} = {value}: allowed {allowed}")]
pub struct InputError {
    /// Dotted path of the offending field, e.g. `beam.length_nm` or `modes[2].zeta_sd`.
    pub field: String,
    /// The offending value as written (or a short description of it).
    pub value: String,
    /// The allowed range or set, e.g. `> 0` or `one of: simply-supported, clamped-clamped`.
    pub allowed: String,
}

impl InputError {
    pub fn new(field: impl Into<String>, value: impl fmt::Display, allowed: impl Into<String>) -> Self {
        Self { field: field.into(), value: value.to_string(), allowed: allowed.into() }
    }

    /// The same error with `prefix.` put in front of the field path.
    pub fn within(mut self, prefix: &str) -> Self {
        self.field = if self.field.is_empty() { prefix.to_string() } else { format!("{prefix}.{}", self.field) };
        self
    }
}

/// A number as a user wrote it, short: plain when that takes at most 12
/// characters and no more than 3 beyond the scientific form, otherwise
/// scientific with the digits that round-trip (`1e308`, not 309 digits;
/// `2.5e-300`; `-1e9`, not `-1000000000`, issue 69).
pub fn fmt_num(value: f64) -> String {
    let plain = value.to_string();
    let scientific = format!("{value:e}");
    if plain.len() <= 12 && plain.len() <= scientific.len() + 3 {
        plain
    } else {
        scientific
    }
}

/// Checks `value > 0` and finite.
///
/// These checks run on every forward evaluation of a calibration (through
/// `BeamSpec::validate`): the test is inlined and the error built out of line
/// (`#[cold]`), so a passing check costs a comparison, not a call.
#[inline]
pub fn positive(field: &str, value: f64) -> Result<(), InputError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(violation(field, value, "> 0 (finite)"))
    }
}

/// The error of a failed [`positive`] / [`non_negative`] check.
#[cold]
#[inline(never)]
fn violation(field: &str, value: f64, allowed: &str) -> InputError {
    InputError::new(field, fmt_num(value), allowed)
}

/// Checks `value >= 0` and finite.
#[inline]
pub fn non_negative(field: &str, value: f64) -> Result<(), InputError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(violation(field, value, ">= 0 (finite)"))
    }
}

/// Parses YAML into `T`, turning serde's message (unknown field, missing field,
/// unknown variant, wrong type, syntax, alias bombs) into a one-line
/// [`InputError`] that names the full field path, the value and what is allowed.
pub fn parse_yaml<T: serde::de::DeserializeOwned>(text: &str) -> Result<T, InputError> {
    serde_yaml::from_str(text).map_err(|e| enum_error::<T>("", &e.to_string(), text))
}

/// What serde_yaml expects where an enum is given a list or a mapping (it
/// reads those as a tagged variant); no user writes a tag there.
const ENUM_TAG: &str = "a YAML tag starting with '!'";

/// [`serde_error`], with the names an enum field allows when the message is
/// serde_yaml's about a list or a mapping given to it ([`ENUM_TAG`]; issue
/// 69: "allowed a YAML tag starting with '!', not a list").
fn enum_error<T: serde::de::DeserializeOwned>(prefix: &str, msg: &str, text: &str) -> InputError {
    let mut e = serde_error(prefix, msg, text);
    if let Some(names) = msg.contains(ENUM_TAG).then(|| enum_names::<T>(msg, text)).flatten() {
        e.allowed = e.allowed.replacen(ENUM_TAG, &clip_list(&names, LIST_CHARS), 1);
    }
    e
}

/// The names the enum at the field serde_yaml's message `msg` points at
/// allows (serde's "one of `a`, `b`"): `text` parsed again with a name no enum has
/// in that place, whose refusal lists them.
fn enum_names<T: serde::de::DeserializeOwned>(msg: &str, text: &str) -> Option<String> {
    let msg = msg.lines().next()?.trim();
    let body = msg.rfind(" at line ").map_or(msg, |i| &msg[..i]);
    let (path, _) = split_path(body);
    let mut doc: serde_yaml::Value = serde_yaml::from_str(text).ok()?;
    let mut node = &mut doc;
    for segment in path.split('.').filter(|s| !s.is_empty()) {
        let mut parts = segment.split('[');
        let key = parts.next()?;
        if !key.is_empty() {
            node = node.get_mut(key)?;
        }
        for index in parts {
            node = node.get_mut(index.strip_suffix(']')?.parse::<usize>().ok()?)?;
        }
    }
    *node = serde_yaml::Value::String("?".into());
    let again = serde_yaml::to_string(&doc).ok()?;
    let refusal = serde_yaml::from_str::<T>(&again).err()?.to_string();
    let (_, what) = split_path(refusal.lines().next()?);
    backticked(what, "unknown variant `").map(|_| expected(what).split(" at line ").next().unwrap_or("").to_string())
}

/// [`parse_yaml`] for an already parsed YAML value found at `prefix` (e.g.
/// `parameters.delta`): the error's field path starts with `prefix`.
pub fn from_yaml_value<T: serde::de::DeserializeOwned>(
    prefix: &str,
    value: serde_yaml::Value,
) -> Result<T, InputError> {
    // Through text, so that serde_yaml tracks the path inside the value
    // (`from_value` reports none: `parameters.delta.prior.mean` became `parameters.delta.mean`).
    let text = serde_yaml::to_string(&value).map_err(|e| serde_error(prefix, &e.to_string(), ""))?;
    serde_yaml::from_str(&text).map_err(|e| enum_error::<T>(prefix, &e.to_string(), &text))
}

/// Largest finite `f64`, as written in messages.
const F64_MAX_TEXT: &str = "1.7976931348623157e308";

/// The field of an error about the whole YAML document (a CSV given as a
/// beam file, a list where a mapping belongs); the CLI names the file.
pub const TOP_LEVEL: &str = "YAML document";

/// Most characters of a value as written in a message (issue 69: a CSV given
/// to `--beam` printed its 889 characters).
pub const VALUE_CHARS: usize = 40;

/// Most characters of a list of accepted names in a message.
pub const LIST_CHARS: usize = 110;

/// `value` cut to [`VALUE_CHARS`] characters, with `…` and its length when cut.
pub fn clip(value: &str) -> String {
    let n = value.chars().count();
    if n <= VALUE_CHARS {
        value.to_string()
    } else {
        format!("{}… ({n} characters)", value.chars().take(VALUE_CHARS).collect::<String>())
    }
}

/// `value` in backticks, cut as [`clip`] cuts it: `` `abc` `` or
/// `` `first 40 characters…` (N characters) ``.
pub fn clip_quoted(value: &str) -> String {
    let n = value.chars().count();
    if n <= VALUE_CHARS {
        format!("`{value}`")
    } else {
        format!("`{}…` ({n} characters)", value.chars().take(VALUE_CHARS).collect::<String>())
    }
}

/// A list of accepted names (serde's "one of `a`, `b`, …") cut to about
/// `max` characters: the first names, then `…` and how many there are.
pub fn clip_list(list: &str, max: usize) -> String {
    if list.chars().count() <= max {
        return list.to_string();
    }
    let items: Vec<&str> = list.split(", ").collect();
    let mut out = String::new();
    for item in &items {
        if out.chars().count() + item.chars().count() + 2 > max {
            break;
        }
        if !out.is_empty() {
            out.push_str(", ");
        }
        out.push_str(item);
    }
    format!("{out}, … ({} in all)", items.len())
}

/// Most characters of a YAML parser's complaint in a message (the rest of
/// the line, with a 40-character value and a file name, stays under 200).
const COMPLAINT_CHARS: usize = 120;

/// One serde_yaml message about `text` → `invalid <path> = <value>: allowed <range>`.
///
/// serde_yaml writes `[path: ]<what>[ at line L column C]`, where `path` is
/// the dotted field path with sequence indices (`modes[3].zeta_sd`). The
/// value slot holds what the document has there: a required field that is
/// not there is `''` (nothing written, as the CLI shows an empty flag
/// value), and a syntax error shows the line of `text` the parser stopped
/// at (issue 69: the slot held "(missing)" and "(not valid YAML …)").
pub fn serde_error(prefix: &str, msg: &str, text: &str) -> InputError {
    let msg = msg.lines().next().unwrap_or("").trim();
    let (body, location) = match msg.rfind(" at line ") {
        Some(i) => (&msg[..i], Some(msg[i + 1..].to_string())),
        None => (msg, None),
    };
    let (path, what) = split_path(body);
    let join = |p: &str, name: Option<&str>| {
        let mut parts: Vec<&str> = [prefix, p].into_iter().filter(|x| !x.is_empty()).collect();
        if let Some(n) = name {
            parts.push(n);
        }
        let joined = parts.join(".").replace(".[", "[");
        if joined.is_empty() {
            TOP_LEVEL.to_string()
        } else {
            joined
        }
    };
    let here = join(path, None);
    if let Some(name) = backticked(what, "unknown field `") {
        let allowed = format!("a known field: {}", clip_list(&expected(what), LIST_CHARS));
        return InputError::new(join(path, Some(&name)), name, allowed);
    }
    if let Some(name) = backticked(what, "missing field `") {
        return InputError::new(join(path, Some(&name)), "''", "a value; the field is required and the file has none");
    }
    if let Some(name) = backticked(what, "duplicate field `") {
        return InputError::new(join(path, Some(&name)), format!("{name} twice"), "each field once");
    }
    if let Some(name) = backticked(what, "unknown variant `") {
        return InputError::new(here, clip(&name), clip_list(&expected(what), LIST_CHARS));
    }
    if let Some(rest) = what.strip_prefix("invalid type: ").or_else(|| what.strip_prefix("invalid value: ")) {
        let (found, exp) = rest.split_once(", expected ").unwrap_or((rest, ""));
        // a list or a mapping where a value belongs: the file's text there
        // (issue 69: "(a list)", "(a mapping)" in the value slot)
        let kind = match found {
            "sequence" => Some("a list"),
            "map" => Some("a mapping"),
            _ => None,
        };
        if let Some(kind) = kind {
            let value = location.as_deref().and_then(|l| node_at(text, l)).unwrap_or_else(|| found_value(found));
            return InputError::new(here, value, format!("{}, not {kind}", expected_kind(exp)));
        }
        let value = clip(&found_value(found));
        if exp == "f64" && looks_like_overflowing_number(&value) {
            return InputError::new(here, value, format!("a finite number, |x| <= {F64_MAX_TEXT}"));
        }
        return InputError::new(here, value, expected_kind(exp));
    }
    if let Some(rest) = what.strip_prefix("invalid length ") {
        let (n, exp) = rest.split_once(", expected ").unwrap_or((rest, ""));
        return InputError::new(here, format!("{n} items"), exp.to_string());
    }
    // serde_yaml names no place for an alias bomb: the first line using an
    // alias, as written (issue 69: "(alias expansion)" in the value slot)
    if what.contains("repetition limit exceeded") {
        let value = first_alias_line(text).unwrap_or_else(|| "*…".to_string());
        return InputError::new(
            here,
            value,
            "aliases expanding to a bounded size (this document's expand without bound)",
        );
    }
    if what.contains("recursion limit exceeded") {
        let value = location.as_deref().and_then(|l| node_at(text, l)).unwrap_or_else(|| "[[[…".to_string());
        return InputError::new(here, value, "at most 128 nested levels (this value nests deeper)");
    }
    let at = location.map(|l| format!(" {l}")).unwrap_or_default();
    let complaint = clip_chars(&format!("{}{at}", what.replace('\n', " ")), COMPLAINT_CHARS);
    InputError::new(here, stopped_at(msg, text), format!("well-formed YAML: {complaint}"))
}

/// The line of `text` a YAML parser's message `msg` points at, as written
/// (cut to [`VALUE_CHARS`]): the first `line L` of the message whose line
/// holds text (serde_yaml names where it stopped, then where the construct
/// it was reading began: "found unexpected end of stream at line 2 column 1,
/// while scanning a quoted scalar at line 1 column 12"), `''` for none.
fn stopped_at(msg: &str, text: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    msg.match_indices("line ")
        .filter_map(|(i, _)| {
            msg[i + "line ".len()..].split(|c: char| !c.is_ascii_digit()).next()?.parse::<usize>().ok()
        })
        .filter_map(|l| lines.get(l.checked_sub(1)?).map(|t| t.trim()))
        .find(|t| !t.is_empty())
        .map_or_else(|| "''".to_string(), |t| format!("`{}`", clip(t)))
}

/// The node of `text` at a serde_yaml location `line L column C` (both
/// 1-based), as written: the rest of its line (cut to [`VALUE_CHARS`]), and
/// for a block node spanning more lines (a `- item` list, a `key: value`
/// mapping) `…` and how many lines it spans; `None` where the line has no
/// text there.
fn node_at(text: &str, location: &str) -> Option<String> {
    let mut numbers =
        location.split(|c: char| !c.is_ascii_digit()).filter(|t| !t.is_empty()).map(|t| t.parse::<usize>().ok());
    let (line, column) = (numbers.next()??, numbers.next()??);
    let lines: Vec<&str> = text.lines().collect();
    let first = lines.get(line.checked_sub(1)?)?;
    let node = first.chars().skip(column.checked_sub(1)?).collect::<String>();
    let node = node.trim_end();
    if node.is_empty() {
        return None;
    }
    let indent = |l: &str| l.chars().take_while(|c| *c == ' ').count();
    let block = !node.starts_with(['[', '{']);
    let more = if block {
        lines[line..]
            .iter()
            .take_while(|l| l.trim().is_empty() || indent(l) >= column - 1)
            .filter(|l| !l.trim().is_empty())
            .count()
    } else {
        0
    };
    let shown = clip_quoted(node);
    Some(if more > 0 { format!("{shown} … ({} lines)", more + 1) } else { shown })
}

/// The first line of `text` that uses an alias (`*name` of an `&name`
/// anchor), trimmed and cut to [`VALUE_CHARS`], in backticks.
fn first_alias_line(text: &str) -> Option<String> {
    let anchors: Vec<&str> = text
        .split('&')
        .skip(1)
        .filter_map(|t| t.split(|c: char| c.is_whitespace() || ",[]{}".contains(c)).next())
        .filter(|a| !a.is_empty())
        .collect();
    text.lines().find(|l| anchors.iter().any(|a| l.contains(&format!("*{a}")))).map(|l| clip_quoted(l.trim()))
}

/// `text` cut to `max` characters, ending in `…` when cut.
fn clip_chars(text: &str, max: usize) -> String {
    if text.chars().count() <= max {
        text.to_string()
    } else {
        format!("{}…", text.chars().take(max - 1).collect::<String>())
    }
}

/// Splits `path: rest` when the head is a field path (no spaces).
fn split_path(body: &str) -> (&str, &str) {
    match body.split_once(": ") {
        Some((p, rest)) if !p.is_empty() && !p.contains(' ') && !p.contains('`') => (p, rest),
        _ => ("", body),
    }
}

/// The name between `key` and the next backtick.
fn backticked(what: &str, key: &str) -> Option<String> {
    let start = what.find(key)? + key.len();
    what[start..].split('`').next().map(str::to_string)
}

/// What follows `expected ` in a serde message, or `no fields` for `there are no fields`.
fn expected(what: &str) -> String {
    if let Some(i) = what.find("expected ") {
        what[i + "expected ".len()..].to_string()
    } else if what.contains("there are no fields") {
        "no fields here".to_string()
    } else {
        what.to_string()
    }
}

/// serde's `string "x"`, `integer `3``, `floating point `2.5``, `sequence` → the value as written.
fn found_value(found: &str) -> String {
    for kind in ["string ", "integer ", "floating point ", "boolean ", "unit value", "char "] {
        if let Some(v) = found.strip_prefix(kind) {
            return v.trim_matches(|c| c == '"' || c == '`').to_string();
        }
    }
    match found {
        "sequence" => "[…]".to_string(),
        "map" => "{…}".to_string(),
        "unit value" => "(empty)".to_string(),
        other => other.to_string(),
    }
}

/// A plain-words range for serde's expected Rust type.
fn expected_kind(exp: &str) -> String {
    match exp {
        "f64" | "f32" => "a finite number".to_string(),
        "usize" | "u64" | "u32" => "a whole number >= 0".to_string(),
        "i64" | "i32" => "a whole number".to_string(),
        "a boolean" | "bool" => "true or false".to_string(),
        "a string" => "a string".to_string(),
        // the Rust type's name is no help to the user (issue 69: "(ShearDeformationYaml)")
        e if e.starts_with("struct ") => "a mapping of fields (name: value)".to_string(),
        e if e.starts_with("a sequence") => "a list".to_string(),
        "" => "a value of the documented type".to_string(),
        e => e.to_string(),
    }
}

/// `1e400`, `-2.5e999`: a number too large for f64 (serde_yaml reads it as a string).
fn looks_like_overflowing_number(v: &str) -> bool {
    let t = v.trim_start_matches(['+', '-']);
    let numeric = !t.is_empty()
        && t.chars().all(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '+' | '-'))
        && t.starts_with(|c: char| c.is_ascii_digit() || c == '.');
    numeric && v.parse::<f64>().is_ok_and(|x| x.is_infinite())
}
