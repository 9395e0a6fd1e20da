//! Numbered series of files (`frame_007.obj`, `day_35.png`): how they are
//! named, and which files an earlier run left in a series that this run
//! wrote anew (`frame_016.obj` … after a run of 16 frames, where the one
//! before had 32), so that a folder never mixes two runs' frames.

use std::collections::HashSet;
use std::fs;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

/// A series of numbered files: the name before the number and after it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FileSeries {
    stem: &'static str,
    ext: &'static str,
}

impl FileSeries {
    /// A mesh per frame: `frame_007.obj` (horns, bodies, bones).
    pub const FRAMES: FileSeries = FileSeries::new("frame_", ".obj");
    /// A body's side view per frame: `side_007.png`.
    pub const SIDES: FileSeries = FileSeries::new("side_", ".png");
    /// A bone's picture per frame: `bone_007.png`.
    pub const BONES: FileSeries = FileSeries::new("bone_", ".png");
    /// A mosaic's Voronoi picture per day: `day_05.png`.
    pub const DAYS: FileSeries = FileSeries::new("day_", ".png");
    /// A mosaic's cells per day: `cells_day05.csv`.
    pub const CELLS: FileSeries = FileSeries::new("cells_day", ".csv");
    /// A mosaic's shaded object per day: `surface_day05.png`.
    pub const SURFACES: FileSeries = FileSeries::new("surface_day", ".png");
    /// Every series `run` writes.
    pub const ALL: [FileSeries; 6] = [
        FileSeries::FRAMES,
        FileSeries::SIDES,
        FileSeries::BONES,
        FileSeries::DAYS,
        FileSeries::CELLS,
        FileSeries::SURFACES,
    ];

    const fn new(stem: &'static str, ext: &'static str) -> FileSeries {
        FileSeries { stem, ext }
    }

    /// Whether `name` is a file of this series, at any width.
    fn has(self, name: &str) -> bool {
        name.strip_prefix(self.stem)
            .and_then(|rest| rest.strip_suffix(self.ext))
            .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
    }
}

/// How the files of a series are numbered: every number as wide as the
/// last one's, and at least as wide as the default presets' names
/// (`frame_007.obj`, `day_35.png`), so that the names sort in the series'
/// order (`day_0099.png` before `day_1000.png`).
#[derive(Debug, Clone, Copy)]
pub struct Numbering {
    width: usize,
}

impl Numbering {
    /// For the numbers up to `last`, at least `min` digits wide.
    fn up_to(last: u64, min: usize) -> Numbering {
        let digits = last.max(1).ilog10() as usize + 1;
        Numbering {
            width: digits.max(min),
        }
    }

    /// For `count` frames numbered from 0: `frame_007.obj`.
    #[must_use]
    pub fn frames(count: usize) -> Numbering {
        Numbering::up_to(count.saturating_sub(1) as u64, 3)
    }

    /// For a mosaic's days 0 to `days`: `day_05.png`.
    #[must_use]
    pub fn days(days: u16) -> Numbering {
        Numbering::up_to(u64::from(days), 2)
    }

    /// File `n` of `series`, `n` zero-padded to the width.
    #[must_use]
    pub fn name(self, series: FileSeries, n: impl std::fmt::Display) -> String {
        format!("{}{}", self.stem(series, n), series.ext)
    }

    /// File `n` of `series` without its extension, which its kind adds.
    #[must_use]
    pub fn stem(self, series: FileSeries, n: impl std::fmt::Display) -> String {
        format!("{}{n:0width$}", series.stem, width = self.width)
    }
}

/// The files (not folders) in `dir` that belong to a series of which
/// this run wrote some (`written`) but that it did not write: an earlier
/// run's, sorted by name. A series this run did not write (`--only`) is
/// left alone.
///
/// # Errors
/// When `dir` cannot be listed.
pub fn stale(dir: &Path, written: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let names: HashSet<&str> = written
        .iter()
        .filter(|p| p.parent() == Some(dir))
        .filter_map(|p| p.file_name()?.to_str())
        .collect();
    let renewed: Vec<FileSeries> = FileSeries::ALL
        .into_iter()
        .filter(|s| names.iter().any(|n| s.has(n)))
        .collect();
    if renewed.is_empty() {
        return Ok(Vec::new());
    }
    let listing = fs::read_dir(dir).with_context(|| format!("cannot list {}", dir.display()))?;
    let mut stale = Vec::new();
    for entry in listing {
        let entry = entry.with_context(|| format!("cannot list {}", dir.display()))?;
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        let is_dir = entry.file_type().is_ok_and(|t| t.is_dir());
        if !is_dir && !names.contains(name) && renewed.iter().any(|s| s.has(name)) {
            stale.push(entry.path());
        }
    }
    stale.sort();
    Ok(stale)
}

/// Removes `paths`.
///
/// # Errors
/// When one cannot be removed.
pub fn remove(paths: &[PathBuf]) -> Result<()> {
    for path in paths {
        fs::remove_file(path).with_context(|| format!("cannot remove {}", path.display()))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_series_is_numbered_as_wide_as_its_last_number() {
        let frames = Numbering::frames;
        let obj = FileSeries::FRAMES;
        assert_eq!(frames(10).name(obj, 7), "frame_007.obj");
        assert_eq!(frames(1000).name(obj, 999), "frame_999.obj");
        assert_eq!(frames(1001).name(obj, 7), "frame_0007.obj");
        assert_eq!(frames(1).name(obj, 0), "frame_000.obj");
        assert_eq!(frames(0).name(obj, 0), "frame_000.obj");
        assert_eq!(Numbering::days(35).name(FileSeries::DAYS, 5), "day_05.png");
        assert_eq!(
            Numbering::days(4096).name(FileSeries::DAYS, 35),
            "day_0035.png"
        );
    }

    #[test]
    fn a_name_is_of_a_series_at_any_width_and_only_with_digits() {
        assert!(FileSeries::FRAMES.has("frame_7.obj"));
        assert!(FileSeries::FRAMES.has("frame_0007.obj"));
        assert!(!FileSeries::FRAMES.has("frame_.obj"));
        assert!(!FileSeries::FRAMES.has("frame_07a.obj"));
        assert!(!FileSeries::FRAMES.has("frame_007.obj.tmp"));
        assert!(FileSeries::CELLS.has("cells_day05.csv"));
        // `day_` is not `surface_day`'s or `cells_day`'s.
        assert!(!FileSeries::DAYS.has("surface_day05.png"));
        assert!(!FileSeries::DAYS.has("cells_day05.csv"));
    }

    #[test]
    fn an_earlier_runs_files_of_a_renewed_series_are_stale() {
        let dir = tempfile::tempdir().unwrap();
        let dir = dir.path();
        let touch = |name: &str| {
            fs::write(dir.join(name), b"x").unwrap();
            dir.join(name)
        };
        // An earlier run: 4 frames, their OBJ and side views, 2 days.
        for k in 0..4 {
            touch(&format!("frame_{k:03}.obj"));
            touch(&format!("side_{k:03}.png"));
        }
        touch("day_00.png");
        touch("notes_001.txt");
        touch("frame_0001.obj");
        // A folder of a series' name is not a file of it.
        fs::create_dir(dir.join("frame_009.obj")).unwrap();
        // This run: 2 frames' OBJ, no side views (`--only obj`).
        let written = vec![touch("frame_000.obj"), touch("frame_001.obj")];
        let names: Vec<String> = stale(dir, &written)
            .unwrap()
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["frame_0001.obj", "frame_002.obj", "frame_003.obj"]);
    }
}
