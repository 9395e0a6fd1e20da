//! `--rig WxH:ws2812`: the bytes a chain of WS2812 LEDs wired as a W×H
//! matrix receives for each frame of a run, beside the rig's picture.
//!
//! A frame is the rig's picture ([`crate::rig`]) read in the chain's order
//! — `serpentine` (the default: the first LED at the top left, even rows
//! left to right, odd rows right to left, as most matrix panels are wired)
//! or `progressive` (every row left to right) — each colour corrected as
//! `smart-leds` does it on the device, gamma first, then the brightness
//! (`brightness(gamma(pixels), b)`), and sent green, red, blue: 3·W·H
//! bytes per frame, the frames one after the other in
//! `rig-WxH-ws2812.bin`.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use smart_leds::RGB8;

use crate::atomic::OutputFile;

/// How the chain runs through the matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// The first LED at the top left; even rows left to right, odd rows
    /// right to left.
    Serpentine,
    /// The first LED at the top left; every row left to right.
    Progressive,
}

/// A WS2812 chain wired as a matrix: its layout and its brightness
/// (0 to 255, as `smart_leds::brightness` takes it; 255 leaves the
/// gamma-corrected colours as they are).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Chain {
    /// How the chain runs through the matrix.
    pub layout: Layout,
    /// The brightness the device applies after the gamma correction.
    pub brightness: u8,
}

impl Chain {
    /// Parses the options after `ws2812` in `--rig WxH:ws2812[:LAYOUT][:B]`
    /// (`serpentine` or `progressive`; a brightness 0 to 255), in any
    /// order, each at most once.
    ///
    /// # Errors
    /// An option that is neither, or one given twice.
    pub fn parse(options: &[&str]) -> Result<Chain> {
        let (mut layout, mut brightness) = (None, None);
        for option in options.iter().map(|o| o.trim()) {
            let given = match option.to_ascii_lowercase().as_str() {
                "serpentine" => layout.replace(Layout::Serpentine).is_some(),
                "progressive" => layout.replace(Layout::Progressive).is_some(),
                number => match number.parse::<u8>() {
                    Ok(b) => brightness.replace(b).is_some(),
                    Err(_) => bail!(
                        "unknown ws2812 option {option:?}: a layout (serpentine, progressive) or a brightness 0 to 255 (e.g. 16x16:ws2812:progressive:64)"
                    ),
                },
            };
            if given {
                bail!("the ws2812 option {option:?} repeats a layout or a brightness given before");
            }
        }
        Ok(Chain {
            layout: layout.unwrap_or(Layout::Serpentine),
            brightness: brightness.unwrap_or(u8::MAX),
        })
    }

    /// The pixel `(x, y)` that LED `i` of a `width`-wide matrix shows.
    #[must_use]
    pub fn pixel(self, i: u32, width: u32) -> (u32, u32) {
        let (row, along) = (i / width, i % width);
        match self.layout {
            Layout::Serpentine if row % 2 == 1 => (width - 1 - along, row),
            Layout::Serpentine | Layout::Progressive => (along, row),
        }
    }

    /// The bytes the chain receives for a `width × height` picture whose
    /// pixel `(x, y)` is `colour(x, y)` (red, green, blue): every LED in
    /// chain order, gamma-corrected, dimmed, green, red, blue.
    #[must_use]
    pub fn bytes(
        self,
        (width, height): (u32, u32),
        colour: impl Fn(u32, u32) -> [u8; 3],
    ) -> Vec<u8> {
        let pixels = (0..width * height).map(|i| {
            let (x, y) = self.pixel(i, width);
            let [r, g, b] = colour(x, y);
            RGB8::new(r, g, b)
        });
        smart_leds::brightness(smart_leds::gamma(pixels), self.brightness)
            .flat_map(|c| [c.g, c.r, c.b])
            .collect()
    }
}

/// `rig-WxH-ws2812.bin` being written, a frame at a time.
#[derive(Debug)]
pub struct ChainFile {
    chain: Chain,
    out: OutputFile,
    path: PathBuf,
}

impl ChainFile {
    /// Starts the file `name` in `dir`.
    ///
    /// # Errors
    /// When the file cannot be created.
    pub fn create(dir: &Path, name: &str, chain: Chain) -> Result<ChainFile> {
        let path = dir.join(name);
        Ok(ChainFile {
            chain,
            out: OutputFile::create(&path)?,
            path,
        })
    }

    /// Appends the bytes of a frame: a `size` picture whose pixel
    /// `(x, y)` is `colour(x, y)` ([`Chain::bytes`]).
    ///
    /// # Errors
    /// When the file cannot be written.
    pub fn frame(&mut self, size: (u32, u32), colour: impl Fn(u32, u32) -> [u8; 3]) -> Result<()> {
        self.out
            .write_all(&self.chain.bytes(size, colour))
            .with_context(|| format!("cannot write {}", self.path.display()))
    }

    /// Ends the file; returns its path.
    ///
    /// # Errors
    /// When the file cannot be written.
    pub fn finish(self) -> Result<PathBuf> {
        self.out.finish()?;
        Ok(self.path)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_serpentine_chain_turns_back_on_odd_rows() {
        let chain = Chain::parse(&[]).unwrap();
        let order: Vec<_> = (0..6).map(|i| chain.pixel(i, 3)).collect();
        assert_eq!(order, [(0, 0), (1, 0), (2, 0), (2, 1), (1, 1), (0, 1)]);
        let rows = Chain::parse(&["progressive"]).unwrap();
        let order: Vec<_> = (0..6).map(|i| rows.pixel(i, 3)).collect();
        assert_eq!(order, [(0, 0), (1, 0), (2, 0), (0, 1), (1, 1), (2, 1)]);
    }

    #[test]
    fn bytes_are_gamma_then_brightness_in_grb_order() {
        // Rows of a 2×2 picture.
        let rows = [
            [[255, 0, 0], [0, 255, 128]],
            [[10, 20, 30], [255, 255, 255]],
        ];
        let picture = |x: u32, y: u32| rows[y as usize][x as usize];
        let full = Chain::parse(&["serpentine"]).unwrap();
        // Gamma 8-bit table: 255 → 255, 128 → 37, 0..=27 → 0, 30 → 1.
        assert_eq!(
            full.bytes((2, 2), picture),
            [0, 255, 0, 255, 0, 37, 255, 255, 255, 0, 0, 1]
        );
        // Brightness 64 after the gamma: c·65/256.
        let dim = Chain::parse(&["64"]).unwrap();
        assert_eq!(dim.bytes((2, 2), picture)[..6], [0, 64, 0, 64, 0, 9]);
    }

    #[test]
    fn options_parse_or_explain() {
        let c = Chain::parse(&["Progressive", "32"]).unwrap();
        assert_eq!((c.layout, c.brightness), (Layout::Progressive, 32));
        let e = Chain::parse(&["zigzag"]).unwrap_err().to_string();
        assert!(e.contains("serpentine, progressive"), "{e}");
        let e = Chain::parse(&["10", "20"]).unwrap_err().to_string();
        assert!(e.contains("repeats"), "{e}");
        assert!(Chain::parse(&["256"]).is_err());
    }
}
