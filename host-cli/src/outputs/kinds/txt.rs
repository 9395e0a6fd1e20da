//! Texts of the run (`summary.txt`): written with any kind, as they are.

use std::path::{Path, PathBuf};

use anyhow::Result;

use super::{Format, Product};
use crate::atomic::write_atomic;

/// The format.
pub(super) const FORMAT: &dyn Format = &Txt;

struct Txt;

impl Format for Txt {
    fn takes(&self, product: Product) -> bool {
        product == Product::Text
    }

    fn text(&self, text: &str, dir: &Path, stem: &str) -> Result<Option<PathBuf>> {
        let path = dir.join(format!("{stem}.txt"));
        write_atomic(&path, text.as_bytes())?;
        Ok(Some(path))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A text is written as it is, as `STEM.txt`.
    #[test]
    fn a_text_is_written_as_it_is() {
        let dir = tempfile::tempdir().unwrap();
        let path = FORMAT.text("a\nb\n", dir.path(), "summary").unwrap();
        assert_eq!(path, Some(dir.path().join("summary.txt")));
        let read = std::fs::read_to_string(dir.path().join("summary.txt")).unwrap();
        assert_eq!(read, "a\nb\n");
    }
}
