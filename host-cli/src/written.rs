//! The files a command wrote, as it reports them: one line a file, but a
//! numbered series (`day_00.png` … `day_35.png`, a frame's OBJ per frame)
//! in one line with its count and size, where the first of it came.

use std::collections::HashMap;
use std::fs;
use std::path::{Path, PathBuf};

use indicatif::{DecimalBytes, HumanCount};

use crate::say;

/// A series is reported in one line from this many files.
const SERIES: usize = 3;

/// What files of one series share: their folder, and the name around its
/// last run of digits (`cells_day` and `.csv`), whatever its width.
#[derive(Debug, PartialEq, Eq, Hash)]
struct Pattern<'a> {
    folder: Option<&'a Path>,
    before: &'a str,
    after: &'a str,
}

impl<'a> Pattern<'a> {
    /// The pattern of `path`, if its name has digits.
    fn of(path: &'a Path) -> Option<Pattern<'a>> {
        let name = path.file_name()?.to_str()?;
        let end = name.rfind(|c: char| c.is_ascii_digit())? + 1;
        let start = name[..end]
            .rfind(|c: char| !c.is_ascii_digit())
            .map_or(0, |i| i + 1);
        Some(Pattern {
            folder: path.parent(),
            before: &name[..start],
            after: &name[end..],
        })
    }
}

/// The lines that report `paths` (in their order): a file a line, each
/// series of three or more files with one pattern as
/// `DIR/day_00.png … day_35.png (36 files, 1.20 MB)` where its first file
/// was.
#[must_use]
pub fn lines(paths: &[PathBuf]) -> Vec<String> {
    let patterns: Vec<Option<Pattern<'_>>> = paths.iter().map(|p| Pattern::of(p)).collect();
    let mut series: HashMap<&Pattern<'_>, Vec<&PathBuf>> = HashMap::new();
    for (path, pattern) in paths.iter().zip(&patterns) {
        if let Some(pattern) = pattern {
            series.entry(pattern).or_default().push(path);
        }
    }
    let mut lines = Vec::new();
    for (path, pattern) in paths.iter().zip(&patterns) {
        match pattern.as_ref().and_then(|p| series.get(p)) {
            Some(series) if series.len() >= SERIES => {
                if std::ptr::eq(series[0], path) {
                    lines.push(series_line(series));
                }
            }
            _ => lines.push(path.display().to_string()),
        }
    }
    lines
}

/// `DIR/day_00.png … day_35.png (36 files, 1.20 MB)`.
fn series_line(series: &[&PathBuf]) -> String {
    let (first, last) = (series[0], series[series.len() - 1]);
    let bytes: u64 = series
        .iter()
        .filter_map(|p| fs::metadata(p).ok())
        .map(|m| m.len())
        .sum();
    format!(
        "{} … {} ({} files, {})",
        first.display(),
        last.file_name().unwrap_or_default().to_string_lossy(),
        HumanCount(series.len() as u64),
        DecimalBytes(bytes)
    )
}

/// Prints `paths` as `  wrote LINE`, a line each of [`lines`].
///
/// # Errors
/// When standard output cannot be written.
pub fn say_wrote(paths: &[PathBuf]) -> anyhow::Result<()> {
    for line in lines(paths) {
        say!("  wrote {line}")?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paths(names: &[&str]) -> Vec<PathBuf> {
        names.iter().map(|n| Path::new("out/x").join(n)).collect()
    }

    #[test]
    fn a_numbered_series_is_one_line_where_its_first_file_was() {
        let written = paths(&[
            "stream.bin",
            "cells_day00.csv",
            "day_00.png",
            "cells_day10.csv",
            "day_10.png",
            "cells_day35.csv",
            "day_35.png",
            "mosaic.png",
        ]);
        assert_eq!(
            lines(&written),
            [
                "out/x/stream.bin",
                "out/x/cells_day00.csv … cells_day35.csv (3 files, 0 B)",
                "out/x/day_00.png … day_35.png (3 files, 0 B)",
                "out/x/mosaic.png",
            ]
        );
    }

    #[test]
    fn fewer_than_three_alike_and_names_without_digits_stay_a_line_each() {
        let written = paths(&["e1-bend.png", "e2-bend.png", "bend.png", "frame_9.obj"]);
        assert_eq!(
            lines(&written),
            [
                "out/x/e1-bend.png",
                "out/x/e2-bend.png",
                "out/x/bend.png",
                "out/x/frame_9.obj"
            ]
        );
    }

    #[test]
    fn a_series_is_in_one_folder_and_its_numbers_may_widen() {
        let written: Vec<PathBuf> = ["a/f_1.obj", "b/f_2.obj", "a/f_3.obj", "a/f_10.obj"]
            .iter()
            .map(PathBuf::from)
            .collect();
        assert_eq!(
            lines(&written),
            ["a/f_1.obj … f_10.obj (3 files, 0 B)", "b/f_2.obj"]
        );
    }

    #[test]
    fn a_series_line_counts_the_bytes_of_its_files() {
        let dir = tempfile::tempdir().unwrap();
        let written: Vec<PathBuf> = (0..1200)
            .map(|k| dir.path().join(format!("frame_{k:04}.obj")))
            .collect();
        for path in &written {
            std::fs::write(path, [b'v'; 1500]).unwrap();
        }
        let line = format!(
            "{}/frame_0000.obj … frame_1199.obj (1,200 files, 1.80 MB)",
            dir.path().display()
        );
        assert_eq!(lines(&written), [line]);
    }
}
