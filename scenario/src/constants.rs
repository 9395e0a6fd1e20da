//! A grammar's settings and constants set from outside its text: keys of
//! `[lsystem]` besides `grammar` (`delta = 30`, `--set lsystem.delta=30`),
//! as L-Py's `extern` variables are. Each replaces the value of its
//! `name = value` line (a setting the grammar leaves at its default gets a
//! line of its own at the end), so the grammar that runs, and its digest,
//! are those of the text edited by hand (`docs/lsystems.md`, *Settings*).

use std::collections::BTreeMap;

use morphogen::lsys::SETTINGS;

use crate::value::{Result, invalid, note, shown};

/// A `name = value` line of a grammar: where its value is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Assignment<'t> {
    /// The name.
    pub name: &'t str,
    /// The line, from 1.
    pub line: usize,
    /// Byte offsets of the value in the text (without blanks or comment).
    pub value: std::ops::Range<usize>,
}

/// Every `name = value` line of `text`, as the grammar parser reads one:
/// before a `#` comment, a name, `=` not followed by `=`, and no `->` on
/// the line.
pub(crate) fn assignments(text: &str) -> Vec<Assignment<'_>> {
    let mut found = Vec::new();
    let mut start = 0;
    for (i, raw) in text.split('\n').enumerate() {
        let line_start = start;
        start += raw.len() + 1;
        let content = raw.split('#').next().unwrap_or("");
        let content = content.strip_suffix('\r').unwrap_or(content);
        if content.contains("->") {
            continue;
        }
        let body = content.trim_start_matches([' ', '\t']);
        let name_len = body
            .bytes()
            .position(|b| !(b.is_ascii_alphanumeric() || b == b'_'))
            .unwrap_or(body.len());
        let (name, rest) = body.split_at(name_len);
        if name.is_empty() || name.as_bytes()[0].is_ascii_digit() {
            continue;
        }
        let after = rest.trim_start_matches([' ', '\t']);
        let Some(value) = after.strip_prefix('=').filter(|v| !v.starts_with('=')) else {
            continue;
        };
        let value_start = line_start + content.len() - value.len();
        let trimmed = value.trim_matches([' ', '\t']);
        let lead = value.len() - value.trim_start_matches([' ', '\t']).len();
        found.push(Assignment {
            name,
            line: i + 1,
            value: value_start + lead..value_start + lead + trimmed.len(),
        });
    }
    found
}

/// The range a value of the setting or constant `name` may take from
/// outside: low, high, whole. The settings' are the parser's
/// (`docs/lsystems.md`); a constant may be any I16F16 number.
pub(crate) fn range(name: &str) -> (f64, f64, bool) {
    match name {
        "n" => (0.0, 255.0, true),
        "plants" => (1.0, 16.0, true),
        "animate" => (0.0, 1.0, true),
        "delta" => (-3600.0, 3600.0, false),
        _ => (-32767.0, 32767.0, false),
    }
}

/// One number from outside for `key`, within `range(name)`, as grammar text.
fn number(key: &str, name: &str, value: &toml::Value) -> Result<String> {
    let (lo, hi, whole) = range(name);
    let allowed = if whole {
        format!("a whole number from {lo} to {hi}")
    } else {
        format!("a number from {lo} to {hi}")
    };
    let v = match value {
        toml::Value::Integer(i) => *i as f64,
        toml::Value::Float(f) if !whole || f.fract() == 0.0 => *f,
        toml::Value::Float(f) => {
            return invalid(
                key,
                format!("{} is not whole (allowed: {allowed})", shown(*f)),
            );
        }
        other => {
            return invalid(
                key,
                format!("{} is not a number (allowed: {allowed})", other.type_str()),
            );
        }
    };
    if !v.is_finite() || v < lo || v > hi {
        return invalid(
            key,
            format!("{} is out of range (allowed: {allowed})", shown(v)),
        );
    }
    // Display never uses an exponent, which the grammar does not read.
    Ok(format!("{v}"))
}

/// The value text of `name` set to `value` from outside (`tropism` is
/// three numbers).
fn value_text(key: &str, name: &str, value: &toml::Value) -> Result<String> {
    if name != "tropism" {
        return number(key, name, value);
    }
    match value.as_array() {
        Some(xyz) if xyz.len() == 3 => {
            let mut parts = Vec::with_capacity(3);
            for (i, v) in xyz.iter().enumerate() {
                parts.push(number(&format!("{key}[{i}]"), name, v)?);
            }
            Ok(parts.join(", "))
        }
        _ => invalid(
            key,
            "the tropism vector is three numbers (allowed: [x, y, z], each -32767 to 32767)",
        ),
    }
}

/// `text` with `constants` (name → value, from the `[lsystem]` table)
/// written in; `table` names the keys (`lsystem`) and `file` the grammar in
/// messages.
///
/// # Errors
/// A name that is neither a setting nor a constant of the grammar (with
/// the closest of them), or a value that is not a number in range.
pub(crate) fn apply(
    text: &str,
    constants: &BTreeMap<String, toml::Value>,
    table: &str,
    file: &str,
) -> Result<String> {
    if constants.is_empty() {
        return Ok(text.to_string());
    }
    let defined = assignments(text);
    let mut edits: Vec<(std::ops::Range<usize>, String)> = Vec::new();
    let mut appended = String::new();
    for (name, value) in constants {
        let key = format!("{table}.{name}");
        let line = defined.iter().find(|a| a.name == name);
        if line.is_none() && !SETTINGS.contains(&name.as_str()) {
            return invalid(key, unknown(name, &defined, file));
        }
        let new = value_text(&key, name, value)?;
        match line {
            Some(a) => edits.push((a.value.clone(), new)),
            None => appended.push_str(&format!("{name} = {new}\n")),
        }
    }
    edits.sort_by_key(|(at, _)| at.start);
    let mut out = String::with_capacity(text.len() + appended.len() + 16);
    let mut at = 0;
    for (range, new) in edits {
        out.push_str(&text[at..range.start]);
        out.push_str(&new);
        at = range.end;
    }
    out.push_str(&text[at..]);
    if !appended.is_empty() {
        if !out.is_empty() && !out.ends_with('\n') {
            out.push('\n');
        }
        out.push_str(&appended);
    }
    Ok(out)
}

/// The message for `name`, neither a setting nor defined by the grammar.
fn unknown(name: &str, defined: &[Assignment<'_>], file: &str) -> String {
    let mut names: Vec<&str> = defined.iter().map(|a| a.name).collect();
    let defaults: Vec<&str> = SETTINGS
        .into_iter()
        .filter(|s| !names.contains(s))
        .collect();
    names.extend(defaults);
    let hint = names
        .iter()
        .map(|n| (strsim::damerau_levenshtein(name, n), *n))
        .filter(|&(d, _)| d <= 2.max(name.len() / 3))
        .min()
        .map_or(String::new(), |(_, n)| format!(" (did you mean `{n}`?)"));
    format!(
        "unknown setting or constant{hint}: {file} defines no `{name}` (allowed: {})",
        names.join(", ")
    )
}

/// Notes every constant of a parsed grammar with its value and range, as
/// `TABLE.NAME`: what a control for it may offer.
pub(crate) fn note_all(table: &str, defined: &[(String, f64)]) {
    for (name, value) in defined {
        let (lo, hi, whole) = range(name);
        note(&format!("{table}.{name}"), *value, lo, hi, whole);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn assignments_are_the_lines_the_parser_reads_as_such() {
        let text = "n = 5   # steps\r\n  delta=22.5\naxiom: F\nF : x == 1 -> F\na == b\nx = 1 -> F\nr1 = r * 2\n";
        let found: Vec<(&str, usize, &str)> = assignments(text)
            .into_iter()
            .map(|a| (a.name, a.line, &text[a.value]))
            .collect();
        assert_eq!(
            found,
            [("n", 1, "5"), ("delta", 2, "22.5"), ("r1", 7, "r * 2")]
        );
    }

    #[test]
    fn constants_replace_their_lines_and_settings_are_appended() {
        let text = "n = 5 # steps\ndelta = 22.5\nr = 2\naxiom: F(r)";
        let set = |pairs: &[(&str, toml::Value)]| {
            let map = pairs
                .iter()
                .map(|(k, v)| (k.to_string(), v.clone()))
                .collect();
            apply(text, &map, "lsystem", "g.lsys")
        };
        let edited = set(&[
            ("delta", toml::Value::Integer(30)),
            ("r", toml::Value::Float(-0.5)),
            ("elasticity", toml::Value::Float(0.25)),
            (
                "tropism",
                toml::Value::Array(vec![0.into(), (-1).into(), 0.into()]),
            ),
        ])
        .unwrap();
        assert_eq!(
            edited,
            "n = 5 # steps\ndelta = 30\nr = -0.5\naxiom: F(r)\nelasticity = 0.25\ntropism = 0, -1, 0\n"
        );
        let e = set(&[("detla", 30.into())]).unwrap_err();
        assert_eq!(e.key, "lsystem.detla");
        assert!(
            e.message.starts_with(
                "unknown setting or constant (did you mean `delta`?): g.lsys defines no `detla`"
            ),
            "{}",
            e.message
        );
        let e = set(&[("n", 2.5.into())]).unwrap_err();
        assert_eq!(
            e.message,
            "2.5 is not whole (allowed: a whole number from 0 to 255)"
        );
        let e = set(&[("r", "x".into())]).unwrap_err();
        assert!(
            e.message.starts_with("string is not a number"),
            "{}",
            e.message
        );
        let e = set(&[("r", 1e9.into())]).unwrap_err();
        assert!(
            e.message.starts_with("1e9 is out of range"),
            "{}",
            e.message
        );
    }
}
