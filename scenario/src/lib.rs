//! Scenario files: a model and every one of its parameters, a seed and the
//! frames to emit, in TOML (`docs/scenarios.md`). A scenario is read and
//! checked once, at the door, into the core's types; an out-of-range,
//! mistyped or unknown value is an [`Error`] that names the file, the line
//! and the key, with what is allowed.
//!
//! The built-in presets are the scenario files in `scenarios/`, embedded
//! here with the grammars and masks they name ([`builtins`]); the firmware
//! turns the same files into `static` presets at build time
//! ([`codegen`]).
//!
//! ```
//! let horn = morphogen_scenario::builtin("ram-horn").unwrap();
//! let mut changed = horn.clone_with_sets(&[("horn.years".into(), "4".into())]).unwrap();
//! assert_eq!(changed.file().horn.as_ref().unwrap().years, 4);
//! let bad = horn.clone_with_sets(&[("horn.years".into(), "40".into())]).unwrap_err();
//! assert_eq!(bad.to_string(), "--set horn.years=40: horn.years: 40 is out of range (allowed: 1 to 8)");
//! # changed = changed;
//! ```
#![forbid(unsafe_code)]

pub mod body_files;
pub mod check;
pub mod codegen;
mod constants;
pub mod firmware;
pub mod mask;
pub mod run;
pub mod schema;
mod spelling;
pub mod store;
pub mod surface;
mod unsupported;
mod value;

use std::fmt;
use std::path::{Path, PathBuf};

use morphogen::preset::Preset;

pub use check::{BodyShape, Checked, Files, Invalid, UserBody};
pub use value::Range;

/// The embedded files: `scenarios/*.toml`, `scenarios/masks/*`,
/// `grammars/*`.
mod embedded {
    include!(concat!(env!("OUT_DIR"), "/embedded.rs"));
}

/// The most bytes a scenario file (or a file it names) may have.
pub const MAX_FILE_BYTES: u64 = 16 << 20;

/// The most values (counted by the commas between them, outside strings
/// and comments) a scenario file may hold.
pub const MAX_VALUES: usize = 1 << 16;

/// The line where `text` passes [`MAX_VALUES`] commas outside its strings
/// and comments, if it does.
fn past_max_values(text: &str) -> Option<usize> {
    let bytes = text.as_bytes();
    let (mut at, mut commas) = (0, 0);
    let find = |from: usize, pattern: &[u8]| {
        bytes
            .get(from..)
            .and_then(|rest| rest.windows(pattern.len()).position(|w| w == pattern))
            .map_or(bytes.len(), |p| from + p)
    };
    while let Some(&b) = bytes.get(at) {
        at = match b {
            b'#' => find(at, b"\n"),
            b'\'' if bytes[at..].starts_with(b"\'\'\'") => find(at + 3, b"\'\'\'") + 3,
            b'\'' => find(at + 1, b"'").min(find(at + 1, b"\n")) + 1,
            b'"' => {
                // A basic string ends at a quote no backslash escapes.
                let multi = bytes[at..].starts_with(b"\"\"\"");
                let mut i = at + if multi { 3 } else { 1 };
                while let Some(&c) = bytes.get(i) {
                    match c {
                        b'\\' => i += 2,
                        b'"' if !multi || bytes[i..].starts_with(b"\"\"\"") => break,
                        b'\n' if !multi => break,
                        _ => i += 1,
                    }
                }
                i + if multi { 3 } else { 1 }
            }
            b',' => {
                commas += 1;
                if commas > MAX_VALUES {
                    return Some(line_of(text, at));
                }
                at + 1
            }
            _ => at + 1,
        };
    }
    None
}

/// The most characters of a user's input a message repeats.
pub const QUOTED_CHARS: usize = 80;

/// `text` as a message repeats it: whole when short, else its first
/// [`QUOTED_CHARS`] characters and how many more there are (a megabyte key
/// makes a line, not a megabyte).
#[must_use]
pub fn quoted(text: &str) -> String {
    match text.char_indices().nth(QUOTED_CHARS) {
        None => text.to_string(),
        Some((end, _)) => format!(
            "{}… ({} more characters)",
            &text[..end],
            text[end..].chars().count()
        ),
    }
}

/// Why a scenario cannot be used: where, which key, what is wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Error {
    /// The file (or `built-in NAME`).
    pub origin: String,
    /// Where the value is: a line of the file, or a `--set`.
    pub place: Place,
    /// The dotted key (empty for the file as a whole).
    pub key: String,
    /// What is wrong, with what is allowed.
    pub message: String,
}

/// Where a bad value came from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Place {
    /// A line of the file (from 1).
    Line(usize),
    /// A `--set KEY=VALUE` on the command line.
    Set(String),
    /// The file as a whole.
    File,
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.place {
            Place::Line(line) => write!(f, "{}:{line}: ", self.origin)?,
            Place::Set(set) => write!(f, "--set {}: ", quoted(set))?,
            Place::File => write!(f, "{}: ", self.origin)?,
        }
        if !self.key.is_empty() {
            write!(f, "{}: ", quoted(&self.key))?;
        }
        f.write_str(&self.message)
    }
}

impl std::error::Error for Error {}

/// Files named by a scenario on disk, relative to its folder.
#[derive(Debug)]
struct Folder(PathBuf);

impl Files for Folder {
    fn read(&self, path: &str) -> Result<Vec<u8>, String> {
        read_limited(&self.0.join(path))
    }
}

/// Files named by a built-in scenario: the embedded ones.
#[derive(Debug)]
struct Embedded(&'static str);

impl Files for Embedded {
    fn read(&self, path: &str) -> Result<Vec<u8>, String> {
        let mut parts: Vec<&str> = self.0.rsplit_once('/').map_or(vec![], |(d, _)| vec![d]);
        for seg in path.split('/') {
            match seg {
                "." | "" => {}
                ".." => {
                    parts.pop();
                }
                s => parts.push(s),
            }
        }
        let key = parts.join("/");
        embedded::FILES
            .iter()
            .find(|(p, _)| *p == key)
            .map(|(_, bytes)| bytes.to_vec())
            .ok_or_else(|| format!("no built-in file {key}"))
    }
}

/// No included files (for a scenario whose includes are all inline).
#[derive(Debug)]
struct NoFiles;

impl Files for NoFiles {
    fn read(&self, path: &str) -> Result<Vec<u8>, String> {
        Err(format!("{path}: this scenario can name no files"))
    }
}

/// Reads a file of at most `limit` bytes (`limit_name` in the error),
/// never more: a regular file (a symlink to one is followed); a FIFO, a
/// device or a folder is refused by its type before it is opened, where
/// opening or reading it would block or never end.
///
/// # Errors
/// Why it cannot be read, that it is not a regular file, or that it is
/// bigger than `limit`.
pub fn read_at_most(path: &Path, limit: u64, limit_name: &str) -> Result<Vec<u8>, String> {
    use std::io::Read;
    let file = open_regular(path)?;
    let mut bytes = Vec::new();
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| e.to_string())?;
    if bytes.len() as u64 > limit {
        return Err(format!("more than {limit} bytes ({limit_name})"));
    }
    Ok(bytes)
}

/// Reads a file of at most [`MAX_FILE_BYTES`], as [`read_at_most`].
///
/// # Errors
/// Why it cannot be read, that it is not a regular file, or that it is
/// too big.
pub fn read_limited(path: &Path) -> Result<Vec<u8>, String> {
    read_at_most(path, MAX_FILE_BYTES, "scenario::MAX_FILE_BYTES")
}

/// Opens `path` for reading when it is a regular file (or a symlink to
/// one).
///
/// # Errors
/// Why it cannot be opened, or what it is instead of a regular file.
pub fn open_regular(path: &Path) -> Result<std::fs::File, String> {
    let kind = std::fs::metadata(path)
        .map_err(|e| e.to_string())?
        .file_type();
    if !kind.is_file() {
        return Err(format!("not a regular file but {}", file_kind(kind)));
    }
    std::fs::File::open(path).map_err(|e| e.to_string())
}

/// What a file that is not a regular file is, in words.
#[must_use]
pub fn file_kind(kind: std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if kind.is_char_device() || kind.is_block_device() {
            return "a device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    if kind.is_dir() {
        "a folder"
    } else if kind.is_file() {
        "a regular file"
    } else {
        "not a file"
    }
}

/// `bytes` as text, or where it stops being UTF-8: `LINE:COLUMN: …`.
///
/// # Errors
/// The line and column (from 1) of the first byte that is not UTF-8.
pub fn utf8(bytes: Vec<u8>) -> Result<String, String> {
    String::from_utf8(bytes).map_err(|e| {
        let good = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        let line = good.iter().filter(|&&b| b == b'\n').count() + 1;
        let start = good.iter().rposition(|&b| b == b'\n').map_or(0, |p| p + 1);
        let column = String::from_utf8_lossy(&good[start..]).chars().count() + 1;
        let byte = e.as_bytes()[good.len()];
        format!("{line}:{column}: not UTF-8 text (byte {byte:#04x})")
    })
}

/// A read and checked scenario.
#[derive(Debug, Clone)]
pub struct Scenario {
    origin: String,
    /// The text as given, before any `--set`.
    text: String,
    sets: Vec<(String, String)>,
    file: schema::File,
    checked: Checked,
    /// Where named files are found: a folder, or the embedded files of
    /// this built-in.
    base: Base,
}

#[derive(Debug, Clone)]
enum Base {
    Folder(PathBuf),
    Embedded(&'static str),
    None,
}

impl Base {
    fn files(&self) -> Box<dyn Files> {
        match self {
            Base::Folder(p) => Box::new(Folder(p.clone())),
            Base::Embedded(key) => Box::new(Embedded(key)),
            Base::None => Box::new(NoFiles),
        }
    }
}

impl Scenario {
    /// Reads the scenario file `path` and applies `sets` (dotted keys).
    ///
    /// # Errors
    /// An unreadable file, or the first bad value with its line and key.
    pub fn load(path: &Path, sets: &[(String, String)]) -> Result<Scenario, Error> {
        let origin = path.display().to_string();
        let bytes = read_limited(path).map_err(|message| Error {
            origin: origin.clone(),
            place: Place::File,
            key: String::new(),
            message: format!("cannot read: {message}"),
        })?;
        let text = utf8(bytes).map_err(|message| Error {
            origin: origin.clone(),
            place: Place::File,
            key: String::new(),
            message,
        })?;
        let folder = path
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."))
            .to_path_buf();
        Scenario::parse(&origin, &text, Base::Folder(folder), sets)
    }

    /// Reads a scenario from `text` whose includes are all inline (as
    /// [`Scenario::self_contained`] writes it).
    ///
    /// # Errors
    /// The first bad value with its line and key.
    pub fn from_text(origin: &str, text: &str) -> Result<Scenario, Error> {
        Scenario::parse(origin, text, Base::None, &[])
    }

    /// Reads a scenario from `text` whose named files are relative to
    /// `folder`.
    ///
    /// # Errors
    /// The first bad value with its line and key.
    pub fn from_text_in(origin: &str, text: &str, folder: &Path) -> Result<Scenario, Error> {
        Scenario::parse(origin, text, Base::Folder(folder.to_path_buf()), &[])
    }

    fn parse(
        origin: &str,
        text: &str,
        base: Base,
        sets: &[(String, String)],
    ) -> Result<Scenario, Error> {
        let err = |place, key: &str, message: String| Error {
            origin: origin.to_string(),
            place,
            key: key.to_string(),
            message,
        };
        // Checked before parsing: a parser holds every value, and 8 million
        // of them in a 16 MB file took 4 GB.
        if let Some(line) = past_max_values(text) {
            return Err(err(
                Place::Line(line),
                "",
                format!(
                    "more than {MAX_VALUES} values (scenario::MAX_VALUES; the presets have at most 160)"
                ),
            ));
        }
        let original = toml_edit::Document::parse(text).map_err(|e| {
            let line = e.span().map_or(1, |s| line_of(text, s.start));
            err(Place::Line(line), "", format!("not TOML: {}", e.message()))
        })?;
        let mut doc: toml_edit::DocumentMut = text
            .parse()
            .map_err(|e: toml_edit::TomlError| err(Place::File, "", e.message().to_string()))?;
        for (key, value) in sets {
            set(&mut doc, key, value)
                .map_err(|m| err(Place::Set(shown_set(key, value)), key, m))?;
        }
        let edited = doc.to_string();
        // A bad value is located at the `--set` that gave it (the last one
        // for the key, one of its parents or one of its children), or else
        // at its line in the file as written.
        let nested = |outer: &str, inner: &str| {
            inner
                .strip_prefix(outer)
                .is_some_and(|rest| rest.starts_with(['.', '[']))
        };
        let set_for =
            |key: &str, k: &str| key == k || nested(k, key) || (!key.is_empty() && nested(key, k));
        let locate = |key: &str| -> Place {
            if let Some((k, v)) = sets.iter().rev().find(|(k, _)| set_for(key, k)) {
                return Place::Set(shown_set(k, v));
            }
            match span_of(&original, key) {
                Some(at) => Place::Line(line_of(text, at)),
                None => Place::File,
            }
        };
        let de = toml::Deserializer::parse(&edited)
            .map_err(|e| err(Place::File, "", e.message().to_string()))?;
        let file: schema::File = serde_path_to_error::deserialize(de).map_err(|e| {
            let key = e.path().to_string();
            let key = if key == "." { String::new() } else { key };
            let (key, message) = explain(&key, e.inner().message());
            err(locate(&key), &key, message)
        })?;
        let files = base.files();
        let checked = check::check(&file, files.as_ref())
            .map_err(|Invalid { key, message }| err(locate(&key), &key, message))?;
        Ok(Scenario {
            origin: origin.to_string(),
            text: text.to_string(),
            sets: sets.to_vec(),
            file,
            checked,
            base,
        })
    }

    /// The same scenario with more `sets` applied after its own.
    ///
    /// # Errors
    /// The first bad value.
    pub fn clone_with_sets(&self, sets: &[(String, String)]) -> Result<Scenario, Error> {
        let mut all = self.sets.clone();
        all.extend_from_slice(sets);
        Scenario::parse(&self.origin, &self.text, self.base.clone(), &all)
    }

    /// Every number of the scenario with the range its check allows, in
    /// the order checked (`docs/scenarios.md` gives the same ranges): the
    /// keys a `--set` or a control may change, with their bounds.
    #[must_use]
    pub fn ranges(&self) -> Vec<Range> {
        let files = self.base.files();
        value::ranges(|| check::check(&self.file, files.as_ref())).1
    }

    /// Whether this is a built-in preset exactly as shipped (no `--set`).
    #[must_use]
    pub fn is_builtin(&self) -> bool {
        matches!(self.base, Base::Embedded(_)) && self.sets.is_empty()
    }

    /// The file as read (after `--set`s).
    #[must_use]
    pub fn file(&self) -> &schema::File {
        &self.file
    }

    /// Its name (the stream header's).
    #[must_use]
    pub fn name(&self) -> &str {
        &self.file.name
    }

    /// Its one-line summary.
    #[must_use]
    pub fn summary(&self) -> &str {
        &self.file.summary
    }

    /// Its default seed.
    #[must_use]
    pub fn seed(&self) -> u64 {
        self.file.seed
    }

    /// Where it was read from.
    #[must_use]
    pub fn origin(&self) -> &str {
        &self.origin
    }

    /// The checked model.
    #[must_use]
    pub fn checked(&self) -> &Checked {
        &self.checked
    }

    /// Calls `f` with the core's [`Preset`] of this scenario.
    pub fn with_preset<R>(&self, f: impl FnOnce(&Preset<'_>) -> R) -> R {
        self.checked
            .with_preset(self.name(), self.summary(), self.seed(), f)
    }

    /// Whether its stream depends on the seed beyond the header: mosaics
    /// always, L-systems and bones when a production is stochastic, bones
    /// also when their wrap's V0 or ΔV is a range; the growth curve, horns
    /// and bodies draw no random numbers.
    #[must_use]
    pub fn uses_seed(&self) -> bool {
        let stochastic = |text: &str| {
            let mut grammar = Box::new(morphogen::lsys::Grammar::new());
            grammar.parse(text).is_ok() && grammar.is_stochastic()
        };
        match &self.checked {
            Checked::Mosaic { .. } => true,
            Checked::LSystem(text) => stochastic(text),
            Checked::Bones { grammar, wrap, .. } => {
                stochastic(grammar) || wrap.target_max.is_some() || wrap.step_max.is_some()
            }
            Checked::Curve(_) | Checked::Horn { .. } | Checked::Body { .. } => false,
        }
    }

    /// The text as given (comments and all), before any `--set`.
    #[must_use]
    pub fn text(&self) -> &str {
        &self.text
    }

    /// The scenario as one file: the text with the `--set`s applied and
    /// every named file (grammar, mask, mesh, cylinders) inline, so that it runs anywhere.
    #[must_use]
    pub fn self_contained(&self) -> String {
        let mut doc: toml_edit::DocumentMut = match self.text.parse() {
            Ok(doc) => doc,
            Err(_) => return self.text.clone(),
        };
        for (key, value) in &self.sets {
            let _ = set(&mut doc, key, value); // applied once already
        }
        let files = self.base.files();
        for key in INCLUDES {
            let (table, field) = key.split_once('.').unwrap_or(("", key));
            let Some(item) = doc.get_mut(table).and_then(|t| t.get_mut(field)) else {
                continue;
            };
            let Some(path) = item.as_str().map(str::to_string) else {
                continue;
            };
            let Ok(bytes) = files.read(&path) else {
                continue;
            };
            let text = match (key, mask::read(&bytes)) {
                ("mosaic.mask", Ok((width, height, bits))) => {
                    mask::to_pbm(&morphogen::mosaic::Mask {
                        width,
                        height,
                        bits: &bits,
                    })
                }
                _ => String::from_utf8_lossy(&bytes).into_owned(),
            };
            *item = toml_edit::value(inline_text(text));
        }
        doc.to_string()
    }
}

/// The keys whose value names a file (relative to the scenario file) or
/// holds it inline as `{ text = "…" }`.
pub const INCLUDES: [&str; 5] = [
    "lsystem.grammar",
    "bones.grammar",
    "mosaic.mask",
    "body.mesh",
    "body.cylinders",
];

/// The `--set` value that holds the file `bytes`, read from `name`, inline
/// for the include `key` (one of [`INCLUDES`]): a mask is read and written
/// as a plain PBM, any other file must be UTF-8 text; messages about it
/// name `name`.
///
/// # Errors
/// A mask that cannot be read, or text that is not UTF-8 (with its line
/// and column).
pub fn inline_value(key: &str, name: &str, bytes: Vec<u8>) -> Result<String, String> {
    if key == "mosaic.mask" {
        return mask::set_value(&bytes);
    }
    let mut inline = inline_text(utf8(bytes)?);
    inline.insert("name", name.into());
    Ok(inline.to_string())
}

/// How a `--set` is shown in a message: a file set inline by its name.
fn shown_set(key: &str, value: &str) -> String {
    let name = value.parse::<toml_edit::Value>().ok().and_then(|v| {
        v.as_inline_table()
            .and_then(|t| t.get("name"))
            .and_then(|n| n.as_str().map(str::to_string))
    });
    format!("{key}={}", name.as_deref().unwrap_or(value))
}

/// `{ text = "…" }`: a named file's contents in place of its path.
pub(crate) fn inline_text(text: String) -> toml_edit::InlineTable {
    let mut inline = toml_edit::InlineTable::new();
    inline.insert("text", text.into());
    inline
}

/// What the user sees for a serde error at `key`: unknown keys get a
/// did-you-mean.
fn explain(key: &str, message: &str) -> (String, String) {
    let Some(rest) = message.strip_prefix("unknown field `") else {
        return (key.to_string(), message.to_string());
    };
    let (field, rest) = rest.split_once('`').unwrap_or((rest, ""));
    let expected: Vec<&str> = rest.split('`').skip(1).step_by(2).collect();
    let full = if key.is_empty() {
        field.to_string()
    } else if key.ends_with(field) {
        key.to_string()
    } else {
        format!("{key}.{field}")
    };
    let best = expected
        .iter()
        .map(|e| (strsim::damerau_levenshtein(field, e), *e))
        .min();
    let hint = match best {
        Some((d, e)) if d <= 2.max(field.len() / 3) => format!(" (did you mean `{e}`?)"),
        _ => String::new(),
    };
    (
        full,
        format!("unknown key{hint} (allowed: {})", expected.join(", ")),
    )
}

/// Sets the dotted `key` (segments may carry `[i]`) to `value`, read as a
/// TOML value or else as a string.
fn set(doc: &mut toml_edit::DocumentMut, key: &str, value: &str) -> Result<(), String> {
    let parsed: toml_edit::Value = value
        .parse()
        .unwrap_or_else(|_| toml_edit::Value::from(value));
    let mut item = doc.as_item_mut();
    let segments: Vec<&str> = key.split('.').collect();
    for (n, seg) in segments.iter().enumerate() {
        // `name`, `name[i]`, `name[i][j]`…: a list of lists too.
        let (name, indices) = match seg.split_once('[') {
            Some((name, rest)) => {
                let indices = rest
                    .strip_suffix(']')
                    .map(|r| r.split("][").map(str::parse::<usize>).collect())
                    .and_then(Result::ok)
                    .ok_or_else(|| {
                        format!(
                            "{}: an index is [N], or [N][M] in a list of lists",
                            quoted(seg)
                        )
                    })?;
                (name, indices)
            }
            None => (*seg, Vec::new()),
        };
        if name.is_empty() {
            return Err("an empty key".into());
        }
        let last = n + 1 == segments.len();
        if last && indices.is_empty() {
            let table = item
                .as_table_like_mut()
                .ok_or_else(|| format!("{name}: its parent is not a table"))?;
            let kept = table
                .get(name)
                .and_then(|i| i.as_value())
                .map(|v| v.decor().clone());
            let mut v = parsed;
            if let Some(decor) = kept {
                *v.decor_mut() = decor;
            }
            table.insert(name, toml_edit::Item::Value(v));
            return Ok(());
        }
        item = item
            .get_mut(name)
            .filter(|i| !i.is_none())
            .ok_or_else(|| format!("no table {name} in the scenario"))?;
        let mut at = name.to_string();
        for (j, &i) in indices.iter().enumerate() {
            if last && j + 1 == indices.len() {
                let array = item
                    .as_array_mut()
                    .ok_or_else(|| format!("{at} is not a list"))?;
                let len = array.len();
                let slot = array
                    .get_mut(i)
                    .ok_or_else(|| format!("{at}[{i}]: the list has {len} items"))?;
                *slot = parsed;
                return Ok(());
            }
            item = item
                .get_mut(i)
                .ok_or_else(|| format!("{at}[{i}]: no such item"))?;
            at = format!("{at}[{i}]");
        }
    }
    Err("an empty key".into())
}

/// The byte offset of the value at the dotted `key` in `doc` (or of its
/// nearest enclosing item).
fn span_of(doc: &toml_edit::Document<&str>, key: &str) -> Option<usize> {
    let mut item = doc.as_item();
    let mut best = None;
    for seg in key.split('.').filter(|s| !s.is_empty()) {
        let (name, indices) = match seg.find('[') {
            Some(at) => (&seg[..at], &seg[at..]),
            None => (seg, ""),
        };
        let table = item.as_table_like()?;
        let (k, next) = table.get_key_value(name)?;
        best = k.span().map(|s| s.start).or(best);
        item = next;
        if let Some(at) = item.span().map(|s| s.start) {
            best = Some(at);
        }
        for i in indices
            .split(['[', ']'])
            .filter(|s| !s.is_empty())
            .filter_map(|i| i.parse::<usize>().ok())
        {
            match item.get(i) {
                Some(next) => {
                    item = next;
                    if let Some(at) = item.span().map(|s| s.start) {
                        best = Some(at);
                    }
                }
                None => return best,
            }
        }
    }
    best
}

fn line_of(text: &str, at: usize) -> usize {
    text.as_bytes()[..at.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// Every built-in scenario, in `morphogen list` order: by model (curve,
/// horn, L-system, body, bones, mosaic), then by file name. Read and
/// checked once per process.
///
/// # Panics
/// When a built-in file is invalid (a test checks that none is).
#[must_use]
pub fn builtins() -> Vec<Scenario> {
    static ALL: std::sync::OnceLock<Vec<Scenario>> = std::sync::OnceLock::new();
    ALL.get_or_init(|| {
        let mut all: Vec<Scenario> = embedded::FILES
            .iter()
            .filter(|(p, _)| p.starts_with("scenarios/") && p.ends_with(".toml"))
            .map(|&(path, bytes)| parse_builtin(path, bytes))
            .collect();
        all.sort_by_key(|s| (model_order(s.checked()), s.origin.clone()));
        all
    })
    .clone()
}

/// The built-in file `path` (`scenarios/NAME.toml`), read and checked.
///
/// # Panics
/// When it is invalid (a test checks that none is).
#[allow(
    clippy::panic,
    reason = "the built-in files are part of the build, checked by a test"
)]
fn parse_builtin(path: &'static str, bytes: &[u8]) -> Scenario {
    let text = String::from_utf8_lossy(bytes);
    let name = path
        .trim_start_matches("scenarios/")
        .trim_end_matches(".toml");
    Scenario::parse(
        &format!("built-in {name}"),
        &text,
        Base::Embedded(path),
        &[],
    )
    .unwrap_or_else(|e| panic!("built-in scenario {path}: {e}"))
}

fn model_order(c: &Checked) -> u8 {
    match c {
        Checked::Curve(_) => 0,
        Checked::Horn { .. } => 1,
        Checked::LSystem(_) => 2,
        Checked::Body { .. } => 3,
        Checked::Bones { .. } => 4,
        Checked::Mosaic { .. } => 5,
    }
}

/// The built-in scenario called `name`. A built-in's file is named after
/// it (a test checks that every one is), so only that file is read:
/// reading all of them takes ~15 ms, most of a small preset's `verify`.
#[must_use]
pub fn builtin(name: &str) -> Option<Scenario> {
    let path = format!("scenarios/{name}.toml");
    embedded::FILES
        .iter()
        .find(|(p, _)| *p == path)
        .map(|&(path, bytes)| parse_builtin(path, bytes))
        .filter(|s| s.name() == name)
}

/// The built-in whose name is closest to `name`, for a did-you-mean.
#[must_use]
pub fn closest_builtin(name: &str) -> Option<String> {
    builtins()
        .iter()
        .map(|s| {
            (
                strsim::damerau_levenshtein(name, s.name()),
                s.name().to_string(),
            )
        })
        .filter(|(d, _)| *d <= 3)
        .min()
        .map(|(_, n)| n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_of_too_many_values_is_refused_before_it_is_parsed() {
        let many = format!(
            "name = \"x\"\n[curve]\nz = [{}1]\n",
            "1,".repeat(MAX_VALUES + 1)
        );
        let e = Scenario::from_text("many.toml", &many).unwrap_err();
        assert_eq!((&e.place, e.key.as_str()), (&Place::Line(3), ""));
        assert!(e.message.starts_with("more than 65536 values"), "{e}");
        // Commas in strings and comments are not values.
        for quoted in [
            format!("# {}\n", ",".repeat(MAX_VALUES + 1)),
            format!("a = \"{}\"\n", ",\\\"".repeat(MAX_VALUES + 1)),
            format!("a = '{}'\n", ",".repeat(MAX_VALUES + 1)),
            format!("a = '''\n{}'''\n", ",'".repeat(MAX_VALUES + 1)),
            format!("a = \"\"\"\n{}\"\"\"\n", ",\"".repeat(MAX_VALUES + 1)),
        ] {
            assert_eq!(past_max_values(&quoted), None, "{}", &quoted[..20]);
        }
        assert_eq!(quoted("short"), "short");
        assert!(quoted(&"k".repeat(1000)).ends_with("k… (920 more characters)"));
    }
}
