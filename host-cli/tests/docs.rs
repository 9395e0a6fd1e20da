//! README.md, every docs/*.md (a new one too) and every other tracked
//! Markdown file held to the project they describe, so that what they say
//! stays true:
//!
//! - every relative link, and every repository path named in code (a
//!   backtick span or a code block), exists; outputs that a command shown
//!   creates are listed in `CREATED`, each with the reason;
//! - every count of presets, MCU presets, firmware streams, fixtures,
//!   cylinders (a built-in body's, a user's limit, an MCU's), fuzz targets,
//!   browser tests and scenarios sent that they state is the project's,
//!   computed here from the scenario crate, the core and the repository's
//!   files (`CLAIMS`); a count of such things, or an "all N", that no claim
//!   checks fails, to be checked or said without a number;
//! - every `morphogen …` command line they show parses with the binary
//!   under test (run to argument parsing, `--help` appended), every flag it
//!   names is in its subcommand's help, every file it reads exists, every
//!   preset it names is one, `cargo morphogen` is an alias, and every
//!   `cargo bench`/`cargo test` target they name is a target;
//! - every `--only` list names kinds `run --only` takes, and a synopsis's
//!   list names them all;
//!
//! and no tracked file names a work session or an issue by its number.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    reason = "a test stops at the first thing that is not as it expects"
)]

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use regex::Regex;

mod markdown;
use markdown::{blocks, prose};

/// Paths the documents name that the repository does not hold: what a
/// command they show creates, or a reader's own file. (prefix, reason)
const CREATED: &[(&str, &str)] = &[
    (
        "fixtures/my-horn",
        "docs/golden-files.md: `morphogen bless` writes it in the reader's project",
    ),
    (
        "scenarios/my-horn.toml",
        "docs/golden-files.md: its first command writes it in the reader's project",
    ),
    (
        "fixtures/my-curve",
        "README.md: the mismatch example's fixture of a reader's scenario file",
    ),
    (
        "grammars/my.lsys",
        "docs/lsystems.md: the reader's own grammar",
    ),
    (
        "firmware-example/target/",
        "scripts/firmware-check.sh writes its report and screens there",
    ),
    (
        "fuzz/target",
        "scripts/fuzz.sh builds both fuzz crates and writes their logs there",
    ),
    (
        "fuzz/corpus/",
        "libFuzzer writes the inputs it adds there (ignored by git)",
    ),
    (
        "web/dist/",
        "scripts/web-build.sh writes the page's WebAssembly build there",
    ),
];

/// Whether a file a command reads is the reader's own (`my.toml`,
/// `my-horn.toml`, `my.lsys`): the documents' convention for "yours".
fn readers_own(path: &str) -> bool {
    let name = path.rsplit('/').next().unwrap_or(path);
    name.starts_with("my.") || name.starts_with("my-")
}

fn repository() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// README.md, docs/*.md (a new one too, before it is tracked) and every
/// other tracked Markdown file, relative to the repository, with their
/// text.
fn documents() -> Vec<(String, String)> {
    let mut names: Vec<String> = fs::read_dir(repository().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".md"))
        .map(|n| format!("docs/{n}"))
        .collect();
    names.sort();
    names.insert(0, "README.md".to_string());
    for other in tracked() {
        if other.ends_with(".md") && !names.contains(&other) && !other.starts_with("fixtures/") {
            names.push(other);
        }
    }
    names
        .into_iter()
        .map(|n| {
            let text = fs::read_to_string(repository().join(&n)).unwrap();
            (n, text)
        })
        .collect()
}

/// The files git tracks, relative to the repository.
fn tracked() -> Vec<String> {
    let o = Command::new("git")
        .args(["ls-files", "-z"])
        .current_dir(repository())
        .output()
        .expect("git ls-files: the test reads the repository's tracked files");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8(o.stdout)
        .unwrap()
        .split('\0')
        .filter(|s| !s.is_empty())
        .map(str::to_owned)
        .collect()
}

/// The paragraphs of a document's prose, lines joined by spaces, each with
/// its first line's number: a sentence wrapped over lines reads whole.
fn paragraphs(markdown: &str) -> Vec<(usize, String)> {
    let mut out: Vec<(usize, String)> = Vec::new();
    let mut open = false;
    for (number, line) in prose(markdown) {
        if line.trim().is_empty() {
            open = false;
        } else if open {
            let last = out.last_mut().unwrap();
            last.1.push(' ');
            last.1.push_str(line.trim());
        } else {
            out.push((number, line.trim().to_string()));
            open = true;
        }
    }
    out
}

/// Every piece of a document a check reads: its prose paragraphs and each
/// line of its code blocks, with line numbers.
fn pieces(markdown: &str) -> Vec<(usize, String)> {
    let mut all = paragraphs(markdown);
    for block in blocks(markdown) {
        for (i, line) in block.lines.iter().enumerate() {
            all.push((block.line + 1 + i, line.clone()));
        }
    }
    all
}

/// The backtick spans of a prose paragraph.
fn spans(paragraph: &str) -> Vec<String> {
    let span = Regex::new(r"`([^`]+)`").unwrap();
    span.captures_iter(paragraph)
        .map(|c| c[1].to_string())
        .collect()
}

// ---- paths -------------------------------------------------------------

/// A word of code as a repository path, or `None` when it is not one: its
/// first component is not a top-level entry of the repository, or it is a
/// pattern (`fixtures/<preset>/`, `frame_NNN.obj`, `scenarios/*.toml`).
fn as_repository_path(word: &str, top: &BTreeSet<String>) -> Option<String> {
    let word = word
        .trim_start_matches(['(', '"', '\'', '['])
        .trim_end_matches([',', ';', ':', ')', '"', '\'', ']', '.']);
    let word = word.split('#').next().unwrap_or_default();
    let (first, _) = word.split_once('/')?;
    let pattern = ['<', '>', '*', '…', '{', '}', '$', '|', '='];
    if !top.contains(first) || word.contains(pattern) || word.contains("NN") {
        return None;
    }
    Some(word.to_string())
}

/// `path` (relative to the repository, `..` and `.` allowed) as git
/// tracks it: a tracked file or a folder holding one. Files a build or a
/// run left in the work tree do not count, so the test says the same in a
/// fresh clone.
fn is_tracked(path: &str, tracked: &BTreeSet<String>) -> bool {
    let mut parts: Vec<&str> = Vec::new();
    for part in path.split('/') {
        match part {
            "" | "." => {}
            ".." => {
                parts.pop();
            }
            _ => parts.push(part),
        }
    }
    let path = parts.join("/");
    let folder = format!("{path}/");
    tracked.contains(&path)
        || tracked
            .range(folder.clone()..)
            .next()
            .is_some_and(|t| t.starts_with(&folder))
}

fn created(path: &str) -> bool {
    CREATED.iter().any(|(prefix, _)| path.starts_with(prefix))
}

#[test]
fn every_path_the_documents_name_exists() {
    let tracked: BTreeSet<String> = tracked().into_iter().collect();
    let top: BTreeSet<String> = tracked
        .iter()
        .filter_map(|p| p.split('/').next().map(str::to_owned))
        .collect();
    let link = Regex::new(r"\]\(([^)\s]+)\)").unwrap();
    let at_a_line = Regex::new(r"\.\w+:\d+$").unwrap();
    let mut wrong = Vec::new();
    let mut checked = 0;
    for (doc, text) in documents() {
        let folder = doc.rsplit_once('/').map_or("", |(f, _)| f);
        for (line, paragraph) in paragraphs(&text) {
            for target in link.captures_iter(&paragraph).map(|c| c[1].to_string()) {
                if target.contains("://")
                    || target.starts_with('#')
                    || target.starts_with("mailto:")
                {
                    continue;
                }
                let file = target.split('#').next().unwrap_or_default();
                checked += 1;
                if !is_tracked(&format!("{folder}/{file}"), &tracked) {
                    wrong.push(format!(
                        "{doc}:{line}: link to {target}, which git does not track"
                    ));
                }
            }
        }
        let mut code: Vec<(usize, String)> = paragraphs(&text)
            .into_iter()
            .flat_map(|(line, p)| spans(&p).into_iter().map(move |s| (line, s)))
            .collect();
        for block in blocks(&text) {
            for (i, l) in block.lines.iter().enumerate() {
                code.push((block.line + 1 + i, l.clone()));
            }
        }
        for (line, piece) in code {
            for word in piece.split_whitespace() {
                let Some(path) = as_repository_path(word, &top) else {
                    continue;
                };
                checked += 1;
                if at_a_line.is_match(&path) {
                    wrong.push(format!(
                        "{doc}:{line}: `{path}` names a line, which moves with every edit: name the item"
                    ));
                } else if !is_tracked(&path, &tracked) && !created(&path) {
                    wrong.push(format!(
                        "{doc}:{line}: `{path}` is not a file or folder git tracks"
                    ));
                }
            }
        }
    }
    assert!(
        checked > 50,
        "only {checked} paths found: the reading is wrong"
    );
    assert!(wrong.is_empty(), "\n{}", wrong.join("\n"));
}

// ---- counts ------------------------------------------------------------

/// The project's counts that the documents state.
#[derive(Debug)]
struct Project {
    /// Built-in presets (`morphogen list`, `scenarios/*.toml`).
    presets: usize,
    /// Presets that fit an MCU (`morphogen list` without "host only"; the
    /// browser times these).
    mcu: usize,
    /// Streams the firmware (`firmware-example`, default features) sends.
    streams: usize,
    /// Fixture folders with a `stream.bin`.
    fixtures: usize,
    /// The horse's cylinders (`body::quadruped::HORSE_CYLINDERS`).
    cylinders: usize,
    /// The cylinders a user's body may have on the host
    /// (`body_files::USER_CYLINDERS`).
    user_cylinders: usize,
    /// The cylinders a body may have on an MCU (`body::MAX_CYLINDERS`).
    mcu_cylinders: usize,
    /// The cylinders a vertex may lie in (`body::MAX_BINDINGS`).
    bindings: usize,
    /// cargo-fuzz targets of `core/fuzz` and `fuzz`.
    fuzz_targets: usize,
    /// Playwright tests of `web/tests`.
    browser_tests: usize,
    /// Scenarios the firmware check sends with `morphogen send`.
    sent: usize,
}

fn count_lines(path: &Path, starting: &str) -> usize {
    fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| l.starts_with(starting))
        .count()
}

fn project() -> Project {
    let root = repository();
    let builtins = morphogen_scenario::builtins();
    let list = Command::new(env!("CARGO_BIN_EXE_morphogen"))
        .arg("list")
        .output()
        .unwrap();
    assert!(list.status.success());
    let listed = String::from_utf8(list.stdout).unwrap();
    assert_eq!(listed.lines().count(), builtins.len(), "{listed}");
    let host_only = listed.lines().filter(|l| l.contains("(host only")).count();
    let mcu = builtins
        .iter()
        .filter(|s| s.with_preset(|p| p.model.fits_mcu()))
        .count();
    assert_eq!(mcu, builtins.len() - host_only, "{listed}");
    let fixtures = fs::read_dir(root.join("fixtures"))
        .unwrap()
        .filter(|e| e.as_ref().unwrap().path().join("stream.bin").exists())
        .count();
    let browser_tests = fs::read_dir(root.join("web/tests"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.to_string_lossy().ends_with(".spec.js"))
        .map(|p| count_lines(&p, "test("))
        .sum();
    Project {
        presets: builtins.len(),
        mcu,
        streams: morphogen_scenario::firmware::builtin_presets(false).len(),
        fixtures,
        cylinders: morphogen::body::quadruped::HORSE_CYLINDERS.len(),
        user_cylinders: morphogen_scenario::body_files::USER_CYLINDERS,
        mcu_cylinders: morphogen::body::MAX_CYLINDERS,
        bindings: morphogen::body::MAX_BINDINGS,
        fuzz_targets: count_lines(&root.join("core/fuzz/Cargo.toml"), "[[bin]]")
            + count_lines(&root.join("fuzz/Cargo.toml"), "[[bin]]"),
        browser_tests,
        sent: sent_by_the_firmware_check(),
    }
}

/// The scenarios `scripts/firmware-check.sh` sends to the firmware: the
/// words of its `for scenario in …; do` loop.
fn sent_by_the_firmware_check() -> usize {
    let script = fs::read_to_string(repository().join("scripts/firmware-check.sh")).unwrap();
    let words = script
        .lines()
        .find_map(|l| l.strip_prefix("for scenario in "))
        .and_then(|l| l.strip_suffix("; do"))
        .expect("scripts/firmware-check.sh: a `for scenario in …; do` loop");
    words.split_whitespace().count()
}

/// A number as the documents write it: digits (`1,552`, `2 048`) or a word.
const NUMBER: &str = r"(\d[\d,]*|\b(?:one|two|three|four|five|six|seven|eight|nine|ten|eleven|twelve|thirteen|fourteen|fifteen|sixteen|seventeen|eighteen|nineteen|twenty)\b)";

fn number(text: &str) -> usize {
    let words = [
        "zero",
        "one",
        "two",
        "three",
        "four",
        "five",
        "six",
        "seven",
        "eight",
        "nine",
        "ten",
        "eleven",
        "twelve",
        "thirteen",
        "fourteen",
        "fifteen",
        "sixteen",
        "seventeen",
        "eighteen",
        "nineteen",
        "twenty",
    ];
    words
        .iter()
        .position(|w| w.eq_ignore_ascii_case(text))
        .unwrap_or_else(|| text.replace(',', "").parse().unwrap())
}

/// A sentence the documents use to state a count, and the count it must
/// be. `{N}` is the number; the first `{N}` is the one checked.
struct Claim {
    pattern: &'static str,
    what: &'static str,
    expected: fn(&Project) -> usize,
}

/// In order, the specific before the general: the first claim whose
/// pattern takes a number checks it.
const CLAIMS: &[Claim] = &[
    Claim {
        pattern: r"{N}\s+presets,\s+the\s+slowest",
        what: "MCU presets (timed in the browser)",
        expected: |p| p.mcu,
    },
    Claim {
        pattern: r"{N}\s+MCU\s+presets",
        what: "MCU presets",
        expected: |p| p.mcu,
    },
    Claim {
        pattern: r"\d+\s+of\s+{N}\*\*",
        what: "presets (a figure measured over every preset)",
        expected: |p| p.presets,
    },
    Claim {
        pattern: r"{N}\s+presets\s+(?:it\s+streams|here)",
        what: "streams the firmware sends",
        expected: |p| p.streams,
    },
    Claim {
        pattern: r"(?:all|every one of the)\s+{N}\s+presets",
        what: "presets",
        expected: |p| p.presets,
    },
    Claim {
        pattern: r"{N}\s+(?:built-in\s+)?presets",
        what: "presets",
        expected: |p| p.presets,
    },
    Claim {
        pattern: r"{N}\s+(?:golden\s+)?fixtures",
        what: "fixtures (fixtures/*/stream.bin)",
        expected: |p| p.fixtures,
    },
    Claim {
        pattern: r"ends with one line \(`{N} ok, 1 mismatch",
        what: "presets less the one mismatch (verify checks every fixture)",
        expected: |p| p.fixtures - 1,
    },
    Claim {
        pattern: r"{N}\s+streams",
        what: "streams the firmware sends (scenario::firmware::builtin_presets)",
        expected: |p| p.streams,
    },
    Claim {
        pattern: r"--streams\s+{N}",
        what: "streams the firmware sends",
        expected: |p| p.streams,
    },
    Claim {
        pattern: r"(?:all|quadrupeds\s+of)\s+{N}\s+cylinders",
        what: "the horse's (and the cow's) cylinders",
        expected: |p| p.cylinders,
    },
    Claim {
        pattern: r"in\s+more\s+than\s+{N}\s+cylinders",
        what: "cylinders a vertex may lie in (body::MAX_BINDINGS)",
        expected: |p| p.bindings,
    },
    Claim {
        pattern: r"a\s+body\s+of\s+at\s+most\s+{N}\s+(?:cylinders|runs)",
        what: "cylinders of a body on an MCU (body::MAX_CYLINDERS)",
        expected: |p| p.mcu_cylinders,
    },
    Claim {
        pattern: r"(?:at\s+most|up\s+to|≤|more\s+than)\s+{N}\s+cylinders",
        what: "cylinders of a user's body (body_files::USER_CYLINDERS)",
        expected: |p| p.user_cylinders,
    },
    Claim {
        pattern: r"bytes\s+\({N}\s+cylinders\)",
        what: "cylinders of a body on an MCU (body::MAX_CYLINDERS)",
        expected: |p| p.mcu_cylinders,
    },
    Claim {
        pattern: r"{N}\s+(?:fuzz\s+)?targets\s+×",
        what: "fuzz targets (core/fuzz and fuzz)",
        expected: |p| p.fuzz_targets,
    },
    Claim {
        pattern: r"CI\s+sends\s+{N}",
        what: "scenarios sent (scripts/firmware-check.sh)",
        expected: |p| p.sent,
    },
    Claim {
        pattern: r"sends\s+{N}\s+scenarios",
        what: "scenarios sent (scripts/firmware-check.sh)",
        expected: |p| p.sent,
    },
    Claim {
        pattern: r"{N}\s+Playwright\s+tests",
        what: "Playwright tests (web/tests/*.spec.js)",
        expected: |p| p.browser_tests,
    },
];

/// A count of one of these, or an "all N" whose noun is left out, that no
/// claim checks fails.
const COUNTED: &[&str] = &[
    r"{N}\s+(?:MCU\s+|built-in\s+|golden\s+|firmware\s+|fuzz\s+|Playwright\s+)?(?:presets|streams|fixtures|cylinders|targets|tests|models|pictures|scenarios|scenario files|grammars|kinds|outputs|subcommands|jobs|papers)\b",
    r"\ball\s+(\d[\d,]*)(?:\s|[,;.)])",
];

fn with_number(pattern: &str) -> Regex {
    Regex::new(&format!(r"(?i){}", pattern.replacen("{N}", NUMBER, 1))).unwrap()
}

#[test]
fn every_count_the_documents_state_is_the_projects() {
    let project = project();
    assert!(
        project.presets > 1 && project.mcu > 1 && project.streams > 1,
        "{project:?}"
    );
    assert_eq!(
        project.cylinders,
        morphogen::body::quadruped::COW_CYLINDERS.len(),
        "the documents say the two built-in bodies have as many cylinders"
    );
    let counted: Vec<Regex> = COUNTED.iter().map(|c| with_number(c)).collect();
    let claims: Vec<(Regex, &Claim)> = CLAIMS.iter().map(|c| (with_number(c.pattern), c)).collect();
    let (mut wrong, mut checked) = (Vec::new(), 0);
    for (doc, text) in documents() {
        for (line, piece) in pieces(&text) {
            let mut covered: Vec<(usize, usize)> = Vec::new();
            for (regex, claim) in &claims {
                for c in regex.captures_iter(&piece) {
                    let n = c.get(1).unwrap();
                    if covered.iter().any(|&(s, e)| s <= n.start() && n.end() <= e) {
                        continue;
                    }
                    covered.push((n.start(), n.end()));
                    checked += 1;
                    let (said, is) = (number(n.as_str()), (claim.expected)(&project));
                    if said != is {
                        wrong.push(format!(
                            "{doc}:{line}: says {said} {}, the project has {is}: «{}»",
                            claim.what, &c[0]
                        ));
                    }
                }
            }
            for c in counted.iter().flat_map(|r| r.captures_iter(&piece)) {
                let n = c.get(1).unwrap();
                if !covered.iter().any(|&(s, e)| s <= n.start() && n.end() <= e) {
                    wrong.push(format!(
                        "{doc}:{line}: «{}» is a count no claim of tests/docs.rs checks: add one, or say it without a number",
                        &c[0]
                    ));
                }
            }
        }
    }
    assert!(
        checked >= 5,
        "only {checked} counts found: the reading is wrong"
    );
    assert!(wrong.is_empty(), "{project:?}\n{}", wrong.join("\n"));
}

// ---- commands ----------------------------------------------------------

/// The commands of a line of shell: split at `&&`, `||`, `|` and `;`, a
/// comment cut off, each as its words.
fn commands(line: &str) -> Vec<Vec<String>> {
    let line = match line.find(" #") {
        Some(at) => &line[..at],
        None => line,
    };
    let line = line.trim().trim_start_matches("$ ");
    Regex::new(r"&&|\|\||\||;")
        .unwrap()
        .split(line)
        .map(|c| c.split_whitespace().map(str::to_owned).collect::<Vec<_>>())
        .filter(|w| !w.is_empty())
        .collect()
}

/// A `morphogen` command's arguments (`morphogen …` or `cargo morphogen
/// …`), to the first redirection.
fn morphogen_arguments(words: &[String]) -> Option<Vec<String>> {
    let rest = match words {
        [m, rest @ ..] if m == "morphogen" => rest,
        [c, m, rest @ ..] if c == "cargo" && m == "morphogen" => rest,
        _ => return None,
    };
    Some(
        rest.iter()
            .take_while(|w| !w.starts_with('>') && !w.starts_with("2>") && !w.starts_with('<'))
            .map(|w| w.trim_matches(['\'', '"']).to_string())
            .collect(),
    )
}

/// Whether a command is a synopsis rather than one to type: it has a
/// placeholder (`PRESET`, `FILE.toml`, `[--seed N]`, `a|b`, `…`).
fn is_synopsis(arguments: &[String]) -> bool {
    let placeholder = Regex::new(r"\b[A-Z][A-Z0-9]*\b|[\[\]|…]").unwrap();
    arguments.iter().any(|a| placeholder.is_match(a))
}

fn morphogen(args: &[&str]) -> (bool, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_morphogen"))
        .args(args)
        .current_dir(repository())
        .env_remove("MORPHOGEN_FIXTURES")
        .env_remove("CI")
        .output()
        .unwrap();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    (o.status.success(), text)
}

/// The flags a subcommand's help names (`--out`, `--set`, …).
fn flags_of(
    subcommand: &str,
    helps: &mut BTreeMap<String, Option<BTreeSet<String>>>,
) -> Option<BTreeSet<String>> {
    helps
        .entry(subcommand.to_string())
        .or_insert_with(|| {
            let asked: &[&str] = if subcommand.starts_with('-') {
                &["--help"]
            } else {
                &[subcommand, "--help"]
            };
            let (ok, help) = morphogen(asked);
            ok.then(|| {
                Regex::new(r"--[a-z][a-z0-9-]*")
                    .unwrap()
                    .find_iter(&help)
                    .map(|m| m.as_str().to_string())
                    .collect()
            })
        })
        .clone()
}

/// The flags of a subcommand that take a value (`--out <DIR>`).
fn valued_flags(subcommand: &str) -> BTreeSet<String> {
    let (_, help) = morphogen(&[subcommand, "--help"]);
    Regex::new(r"(--[a-z][a-z0-9-]*)[ =]<")
        .unwrap()
        .captures_iter(&help)
        .map(|c| c[1].to_string())
        .collect()
}

/// The preset names a command gives where a preset or a file goes: the
/// positional arguments of `run`, `show`, `send` (its first), `verify` and
/// `bless` (not `--accept`'s fixture names), without a `.` or `/`.
fn preset_arguments(arguments: &[String], valued: &BTreeSet<String>) -> Vec<String> {
    let Some(sub) = arguments.first() else {
        return Vec::new();
    };
    if !["run", "show", "send", "verify", "bless"].contains(&sub.as_str())
        || arguments.iter().any(|a| a == "--accept")
    {
        return Vec::new();
    }
    let mut positional = Vec::new();
    let mut words = arguments[1..].iter();
    while let Some(w) = words.next() {
        if w.starts_with('-') {
            if valued.contains(w.as_str()) {
                words.next();
            }
        } else {
            positional.push(w.clone());
        }
    }
    if sub == "send" || sub == "run" || sub == "show" {
        positional.truncate(1);
    }
    positional.retain(|p| !p.contains(['.', '/']));
    positional
}

/// The package folder of each workspace package, by its name.
fn packages() -> BTreeMap<String, PathBuf> {
    let name = Regex::new(r#"(?m)^\[package\]\s*\nname\s*=\s*"([^"]+)""#).unwrap();
    fs::read_dir(repository())
        .unwrap()
        .filter_map(|e| {
            let folder = e.unwrap().path();
            let manifest = fs::read_to_string(folder.join("Cargo.toml")).ok()?;
            let package = name.captures(&manifest)?[1].to_string();
            Some((package, folder))
        })
        .collect()
}

/// Whether `cargo bench|test -p PACKAGE --bench|--test NAME` names a target
/// that exists; `None` when the command names none.
fn cargo_target_exists(words: &[String], packages: &BTreeMap<String, PathBuf>) -> Option<bool> {
    if words.first().map(String::as_str) != Some("cargo") {
        return None;
    }
    let after = |flag: &str| {
        words
            .iter()
            .position(|w| w == flag)
            .and_then(|i| words.get(i + 1))
    };
    let package = after("-p")?;
    let (kind, folder) = match (after("--bench"), after("--test")) {
        (Some(b), _) => (b, "benches"),
        (None, Some(t)) => (t, "tests"),
        (None, None) => return None,
    };
    let Some(root) = packages.get(package) else {
        return Some(false);
    };
    let manifest = fs::read_to_string(root.join("Cargo.toml")).unwrap_or_default();
    Some(
        root.join(folder).join(format!("{kind}.rs")).exists()
            || root.join(folder).join(kind).join("main.rs").exists()
            || manifest.contains(&format!("name = \"{kind}\"")),
    )
}

/// The value flags whose value a command writes, not reads.
const WRITTEN: &[&str] = &["--out", "--report", "--junit", "--fixtures", "--dir"];

/// The lines of a document a command may stand on, in the document's
/// order, each with its line number and whether it is in a code block: the
/// backtick spans of its prose, and the lines of its shell blocks. A
/// synopsis (an untagged block) describes each command after two or more
/// spaces; the description is cut off.
fn command_lines(markdown: &str) -> Vec<(usize, String, bool)> {
    let mut lines: Vec<(usize, String, bool)> = Vec::new();
    for (line, paragraph) in paragraphs(markdown) {
        for span in spans(&paragraph) {
            lines.push((line, span, false));
        }
    }
    for block in blocks(markdown) {
        if !matches!(
            block.info.as_str(),
            "" | "sh" | "sh skip" | "console" | "bash"
        ) {
            continue;
        }
        for (i, l) in block.lines.iter().enumerate() {
            let l = match (block.info.is_empty(), l.trim_start().find("  ")) {
                (true, Some(at)) => {
                    let indent = l.len() - l.trim_start().len();
                    l[..indent + at].to_string()
                }
                _ => l.clone(),
            };
            lines.push((block.line + 1 + i, l, true));
        }
    }
    lines.sort_by_key(|l| l.0);
    lines
}

/// What the documents' commands are checked against (the workspace's
/// packages, git's files, the presets, the cargo alias, each subcommand's
/// help, asked once), and what the check found: the mistakes, and how many
/// commands it ran, synopses, cargo targets and preset names it read, so
/// that a reading that finds nothing fails too.
struct CommandCheck {
    packages: BTreeMap<String, PathBuf>,
    tracked: BTreeSet<String>,
    presets: BTreeSet<String>,
    /// `.cargo/config.toml`, which makes `cargo morphogen` an alias.
    alias: String,
    /// A word that names a file a command reads.
    file: Regex,
    /// A flag in a synopsis's continuation line.
    flag_word: Regex,
    helps: BTreeMap<String, Option<BTreeSet<String>>>,
    valued: BTreeMap<String, BTreeSet<String>>,
    wrong: Vec<String>,
    run: usize,
    synopses: usize,
    targets: usize,
    named_presets: usize,
}

impl CommandCheck {
    fn new() -> Self {
        let presets = morphogen_scenario::builtins()
            .iter()
            .map(|s| s.name().to_owned())
            .collect();
        Self {
            packages: packages(),
            tracked: tracked().into_iter().collect(),
            presets,
            alias: fs::read_to_string(repository().join(".cargo/config.toml")).unwrap_or_default(),
            file: Regex::new(r"^[\w./-]+\.(toml|obj|cylinders|txt|lsys|pbm|png|bin)$").unwrap(),
            flag_word: Regex::new(r"--[a-z][a-z0-9-]*").unwrap(),
            helps: BTreeMap::new(),
            valued: BTreeMap::new(),
            wrong: Vec::new(),
            run: 0,
            synopses: 0,
            targets: 0,
            named_presets: 0,
        }
    }

    /// Checks every command a document shows, and every synopsis's
    /// continuation line.
    fn document(&mut self, doc: &str, markdown: &str) {
        // What an earlier command of the document wrote (`> my-horn.toml`).
        let mut written: BTreeSet<String> = BTreeSet::new();
        let mut last_subcommand: Option<String> = None;
        for (line, code, in_block) in command_lines(markdown) {
            let at = format!("{doc}:{line}");
            // A synopsis's continuation line: `          [--seed N] …`.
            if in_block && code.starts_with(' ') && code.trim_start().starts_with('[') {
                if let Some(sub) = &last_subcommand {
                    self.continuation(&at, sub, &code);
                }
                continue;
            }
            for words in commands(&code) {
                self.cargo_command(&at, &words);
                if let Some(redirect) = words.iter().position(|w| w == ">") {
                    written.extend(words.get(redirect + 1).cloned());
                }
                let Some(arguments) = morphogen_arguments(&words) else {
                    continue;
                };
                let Some(sub) = arguments.first().cloned() else {
                    continue;
                };
                last_subcommand = Some(sub.clone());
                self.morphogen_command(&at, &sub, &arguments, in_block, &written);
            }
        }
    }

    /// A synopsis's continuation line names only flags of the subcommand
    /// above it.
    fn continuation(&mut self, at: &str, sub: &str, code: &str) {
        let known = flags_of(sub, &mut self.helps).unwrap_or_default();
        for flag in self.flag_word.find_iter(code) {
            if !known.contains(flag.as_str()) {
                self.wrong
                    .push(format!("{at}: `morphogen {sub}` has no {}", flag.as_str()));
            }
        }
    }

    /// A `cargo bench|test` target the command names exists, and `cargo
    /// morphogen` is an alias.
    fn cargo_command(&mut self, at: &str, words: &[String]) {
        if let Some(exists) = cargo_target_exists(words, &self.packages) {
            self.targets += 1;
            if !exists {
                self.wrong
                    .push(format!("{at}: no such target: {}", words.join(" ")));
            }
        }
        if words.starts_with(&["cargo".to_string(), "morphogen".to_string()])
            && !self.alias.contains("morphogen = ")
        {
            self.wrong.push(format!(
                "{at}: `cargo morphogen` is no alias of .cargo/config.toml"
            ));
        }
    }

    /// A `morphogen` command's subcommand is one and its help names every
    /// flag; a command to type (not a synopsis) names presets that are
    /// presets, reads files that exist, and parses.
    fn morphogen_command(
        &mut self,
        at: &str,
        sub: &str,
        arguments: &[String],
        in_block: bool,
        written: &BTreeSet<String>,
    ) {
        let Some(known) = flags_of(sub, &mut self.helps) else {
            self.wrong
                .push(format!("{at}: `morphogen {sub}` is no subcommand"));
            return;
        };
        for a in arguments {
            let flag = a.split('=').next().unwrap_or_default();
            if flag.starts_with("--") && !known.contains(flag) {
                self.wrong
                    .push(format!("{at}: `morphogen {sub}` has no {flag}"));
            }
        }
        if is_synopsis(arguments) {
            self.synopses += 1;
            return;
        }
        self.presets_named(at, sub, arguments);
        self.files_read(at, sub, arguments, written);
        self.parses(at, arguments, in_block);
    }

    /// Every preset the command names is one, or a reader's own.
    fn presets_named(&mut self, at: &str, sub: &str, arguments: &[String]) {
        let valued = self
            .valued
            .entry(sub.to_string())
            .or_insert_with(|| valued_flags(sub));
        for name in preset_arguments(arguments, valued) {
            self.named_presets += 1;
            if !self.presets.contains(&name) && !readers_own(&name) {
                self.wrong.push(format!(
                    "{at}: `morphogen {}`: {name} is no preset (`morphogen list`)",
                    arguments.join(" ")
                ));
            }
        }
    }

    /// Every file the command reads exists: git tracks it, an earlier
    /// command of the document wrote it, a command shown creates it, or it
    /// is a reader's own.
    fn files_read(
        &mut self,
        at: &str,
        sub: &str,
        arguments: &[String],
        written: &BTreeSet<String>,
    ) {
        for (i, a) in arguments.iter().enumerate() {
            let value_of_written = (i > 0 && WRITTEN.contains(&arguments[i - 1].as_str()))
                // `send SCENARIO PORT|FILE` writes to its last.
                || (sub == "send" && i + 1 == arguments.len() && i > 1);
            if self.file.is_match(a)
                && !value_of_written
                && !is_tracked(a, &self.tracked)
                && !written.contains(a)
                && !created(a)
                && !readers_own(a)
            {
                self.wrong.push(format!(
                    "{at}: `morphogen {}` reads {a}, which git does not track",
                    arguments.join(" ")
                ));
            }
        }
    }

    /// The command parses with the binary under test, `--help` appended;
    /// prose may name a flag without its value (`verify --stream`).
    fn parses(&mut self, at: &str, arguments: &[String], in_block: bool) {
        let mut with_help: Vec<&str> = arguments.iter().map(String::as_str).collect();
        with_help.push("--help");
        let (ok, out) = morphogen(&with_help);
        self.run += 1;
        let mention = !in_block
            && arguments.last().is_some_and(|f| f.starts_with("--"))
            && out.contains("a value is required for");
        if !ok && !mention {
            self.wrong.push(format!(
                "{at}: `morphogen {}` does not parse:\n{out}",
                arguments.join(" ")
            ));
        }
    }
}

/// Every `morphogen …` command line the documents show parses with the
/// binary under test, and names flags, presets, files and cargo targets
/// that are the project's (see `CommandCheck`).
#[test]
fn every_command_the_documents_show_parses() {
    let mut check = CommandCheck::new();
    for (doc, markdown) in documents() {
        check.document(&doc, &markdown);
    }
    let CommandCheck {
        wrong,
        run,
        synopses,
        targets,
        named_presets,
        ..
    } = check;
    assert!(
        run >= 10 && synopses >= 10 && targets >= 5 && named_presets >= 10,
        "{run} commands, {synopses} synopses, {targets} cargo targets, {named_presets} presets named: the reading is wrong"
    );
    assert!(wrong.is_empty(), "\n{}", wrong.join("\n"));
}

// ---- no session or issue numbers ---------------------------------------

#[test]
fn no_tracked_file_names_a_session_or_an_issue_by_number() {
    let root = repository();
    let numbered = Regex::new(concat!(
        r"(?i)\b(?:work\s+)?sessions?\s+#?\d+\b",
        r"|(?i)\b(?:issues?|tickets?|pull\s+requests?|PRs?)\s+#?\d+\b",
        r"|\(S\d+\)",
        r"|\(#\d+\)",
        r"|(?i)\b(?:see|fix(?:es|ed)?|close[sd]?|resolve[sd]?)\s+#\d+\b",
    ))
    .unwrap();
    let mut wrong = Vec::new();
    let mut read = 0;
    for path in tracked() {
        // Fixtures are data, written by `morphogen bless`.
        if path.starts_with("fixtures/") {
            continue;
        }
        let Ok(text) = fs::read_to_string(root.join(&path)) else {
            continue; // binary: pictures, meshes, streams
        };
        read += 1;
        for (number, line) in text.lines().enumerate() {
            if let Some(m) = numbered.find(line) {
                wrong.push(format!("{path}:{}: «{}»", number + 1, m.as_str()));
            }
        }
    }
    assert!(read > 100, "only {read} files read");
    assert!(
        wrong.is_empty(),
        "session or issue numbers belong in git, not in the project:\n{}",
        wrong.join("\n")
    );
}

// ---- output kinds ------------------------------------------------------

/// The kinds of file `run --only` takes, from its own message.
fn output_kinds() -> BTreeSet<String> {
    let (ok, out) = morphogen(&["run", "--only", "no-such-kind"]);
    assert!(!ok, "{out}");
    let allowed = out
        .split_once("(allowed: ")
        .and_then(|(_, rest)| rest.split_once(')'))
        .unwrap_or_else(|| panic!("`run --only` names no allowed kinds: {out}"))
        .0;
    allowed.split(", ").map(str::to_owned).collect()
}

#[test]
fn every_output_kind_the_documents_name_is_the_clis() {
    let kinds = output_kinds();
    assert!(kinds.len() > 3, "{kinds:?}");
    let only = Regex::new(r"--only[ =]([a-z0-9]+(?:,[a-z0-9]+)*)").unwrap();
    let (mut wrong, mut lists) = (Vec::new(), 0);
    for (doc, text) in documents() {
        let synopses: BTreeSet<usize> = blocks(&text)
            .iter()
            .filter(|b| b.info.is_empty())
            .flat_map(|b| b.line..=b.line + b.lines.len())
            .collect();
        for (line, piece) in pieces(&text) {
            for c in only.captures_iter(&piece) {
                lists += 1;
                let named: BTreeSet<String> = c[1].split(',').map(str::to_owned).collect();
                let unknown: Vec<&String> = named.difference(&kinds).collect();
                if !unknown.is_empty() {
                    wrong.push(format!("{doc}:{line}: `--only` takes no {unknown:?}"));
                }
                // A synopsis lists every kind.
                if synopses.contains(&line) && named != kinds {
                    wrong.push(format!(
                        "{doc}:{line}: the synopsis lists {named:?}, `run --only` takes {kinds:?}"
                    ));
                }
            }
        }
    }
    assert!(lists >= 2, "only {lists} `--only` lists found");
    assert!(wrong.is_empty(), "\n{}", wrong.join("\n"));
}
