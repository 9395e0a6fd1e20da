//! `csv`: tables (`*.csv`), a header line and a line a row.

use std::path::{Path, PathBuf};

use anyhow::Result;

use super::{Format, Kind, Product};

/// The kind.
pub(super) const KIND: Kind = Kind {
    name: "csv",
    about: "tables",
    by_default: true,
    format: &Csv,
};

struct Csv;

impl Format for Csv {
    fn takes(&self, product: Product) -> bool {
        product == Product::Table
    }

    fn table(
        &self,
        dir: &Path,
        stem: &str,
        write: &mut dyn FnMut(&Path) -> Result<()>,
    ) -> Result<Option<PathBuf>> {
        let path = dir.join(format!("{stem}.csv"));
        write(&path)?;
        Ok(Some(path))
    }
}
