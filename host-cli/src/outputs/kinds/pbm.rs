//! 1-bit pictures of the run (`mask.pbm`): written with any kind, as
//! plain PBM (P1) by the scenario crate's mask writer (`mask::to_pbm`),
//! which `--mask` reads back.

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use morphogen::mosaic::Mask;
use morphogen_scenario::mask::to_pbm;

use super::{Format, Pixels, Product};
use crate::atomic::write_atomic;

/// The format.
pub(super) const FORMAT: &dyn Format = &Pbm;

struct Pbm;

impl Format for Pbm {
    fn takes(&self, product: Product) -> bool {
        product == Product::Bitmap
    }

    fn picture(&self, pixels: &Pixels<'_>, dir: &Path, stem: &str) -> Result<Option<PathBuf>> {
        let Pixels::Bits { size: (w, h), bits } = *pixels else {
            bail!("{stem}.pbm: a PBM holds pixels of a bit each");
        };
        let mask = Mask {
            width: u16::try_from(w)?,
            height: u16::try_from(h)?,
            bits,
        };
        let path = dir.join(format!("{stem}.pbm"));
        write_atomic(&path, to_pbm(&mask).as_bytes())?;
        Ok(Some(path))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 1-bit picture is written 0 for white, a row a line; pixels of
    /// more than a bit are refused.
    #[test]
    fn bits_are_written_as_plain_pbm() {
        let dir = tempfile::tempdir().unwrap();
        let bits = Pixels::Bits {
            size: (3, 2),
            bits: &[0b1010_0000, 0b0110_0000],
        };
        let path = FORMAT.picture(&bits, dir.path(), "mask").unwrap().unwrap();
        assert_eq!(
            std::fs::read_to_string(path).unwrap(),
            "P1\n# morphogen mosaic mask: white (0) allows foreground cells\n3 2\n0 1 0\n1 0 0\n"
        );
        let rgb = Pixels::Rgb {
            size: (1, 1),
            rgb: &[0; 3],
        };
        assert!(FORMAT.picture(&rgb, dir.path(), "rgb").is_err());
    }
}
