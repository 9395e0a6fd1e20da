//! The kinds of output file `morphogen run` writes, as `--only` selects
//! them.

use std::fmt;

use anyhow::{Result, bail};

/// A kind of output file `run --only` selects.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Still pictures and chart bitmaps (`*.png` but `animation.png`).
    Png,
    /// Wavefront meshes (`*.obj`, with their `.mtl`).
    Obj,
    /// The binary glTF scene `model.glb`.
    Glb,
    /// The animated PNG `animation.png`.
    Anim,
    /// Charts as SVG.
    Svg,
    /// Tables (`*.csv`).
    Csv,
    /// `records.jsonl`.
    Jsonl,
    /// The last frame as pen strokes, `plot.svg` (not written by default).
    Plot,
}

impl Kind {
    /// Every kind, in the order `--only` lists them.
    pub const ALL: [Kind; 8] = [
        Kind::Png,
        Kind::Obj,
        Kind::Glb,
        Kind::Anim,
        Kind::Svg,
        Kind::Csv,
        Kind::Jsonl,
        Kind::Plot,
    ];

    /// The name `--only` knows it by.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Kind::Png => "png",
            Kind::Obj => "obj",
            Kind::Glb => "glb",
            Kind::Anim => "anim",
            Kind::Svg => "svg",
            Kind::Csv => "csv",
            Kind::Jsonl => "jsonl",
            Kind::Plot => "plot",
        }
    }

    const fn bit(self) -> u8 {
        1 << self as u8
    }
}

/// The kinds of output file a run writes (`stream.bin` always, and the
/// small text summaries `summary.txt` and `mask.pbm` with any kind).
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct Kinds(u8);

impl fmt::Debug for Kinds {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = Kind::ALL
            .iter()
            .filter(|k| self.has(**k))
            .map(|k| k.name())
            .collect();
        write!(f, "Kinds({})", names.join(","))
    }
}

impl Kinds {
    /// The kinds of a run without `--only`: every kind but
    /// [`Kind::Plot`].
    pub const DEFAULT: Kinds = Kinds(0x7f);

    /// Files of `kind` only.
    #[must_use]
    pub const fn only(kind: Kind) -> Kinds {
        Kinds(kind.bit())
    }

    /// The kinds of a comma-separated list (`png,obj`).
    ///
    /// # Errors
    /// When a name is not a kind's (the error lists the allowed ones) or
    /// the list is empty.
    pub fn parse(list: &str) -> Result<Kinds> {
        let mut bits = 0u8;
        for name in list.split(',').map(str::trim).filter(|n| !n.is_empty()) {
            let Some(kind) = Kind::ALL.iter().find(|k| k.name() == name) else {
                let allowed: Vec<&str> = Kind::ALL.iter().map(|k| k.name()).collect();
                bail!(
                    "--only: unknown output kind '{name}' (allowed: {})",
                    allowed.join(", ")
                );
            };
            bits |= kind.bit();
        }
        if bits == 0 {
            bail!("--only needs at least one output kind");
        }
        Ok(Kinds(bits))
    }

    /// Whether files of `kind` are written.
    #[must_use]
    pub const fn has(self, kind: Kind) -> bool {
        self.0 & kind.bit() != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_parse_and_name_the_allowed_ones() {
        let k = Kinds::parse("png,glb").unwrap();
        assert!(k.has(Kind::Png) && k.has(Kind::Glb) && !k.has(Kind::Obj));
        let e = Kinds::parse("png,gif").unwrap_err().to_string();
        assert!(
            e.contains("'gif'") && e.contains("png, obj, glb, anim, svg, csv, jsonl, plot"),
            "{e}"
        );
        let default = |k: &&Kind| Kinds::DEFAULT.has(**k);
        let named: Vec<&str> = Kind::ALL.iter().filter(default).map(|k| k.name()).collect();
        assert_eq!(named.join(","), "png,obj,glb,anim,svg,csv,jsonl");
        assert!(Kinds::parse("plot").unwrap().has(Kind::Plot));
    }
}
