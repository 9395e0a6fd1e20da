//! The pictures of a mismatch (`verify --report DIR`, `review`): the
//! model's own pictures ([`outputs::write`]) of the expected and of the
//! actual stream, each drawn from its records up to the end of the first
//! frame that differs, and for every picture that is not the same on both
//! sides, their difference: unchanged pixels faded, changed ones red.
//! Pictures the same on both sides are not kept.

use std::fs;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use morphogen::stream::{Decoded, Decoder, Record};
use morphogen_scenario::Scenario;

use crate::outputs::{self, Kinds};

/// The folder beside a pending stream that holds its pictures.
pub const REPORT_DIR: &str = "report";

/// The three folders of a report, each with the model's file names.
pub const SIDES: [&str; 3] = ["expected", "actual", "difference"];

/// The colour of a pixel that differs, in a difference picture.
const CHANGED: [u8; 3] = [230, 0, 0];

/// One picture that differs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Picture {
    /// Its file name in each of the [`SIDES`] folders.
    pub name: String,
    /// Pixels that differ (one side's pixels past the other's edge
    /// included).
    pub pixels: u64,
}

/// The pictures drawn for a mismatch.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Pictures {
    /// The folder holding `expected/`, `actual/` and `difference/`.
    pub dir: PathBuf,
    /// The first frame that differs (the expected stream's numbering),
    /// if the difference is in a frame.
    pub frame: Option<u32>,
    /// The pictures that differ, by name (none: the streams differ in
    /// records no picture shows).
    pub differing: Vec<Picture>,
}

impl Pictures {
    /// The difference picture of `picture`.
    #[must_use]
    pub fn difference(&self, picture: &Picture) -> PathBuf {
        self.dir.join("difference").join(&picture.name)
    }

    /// One line naming the pictures: those that differ (at most `shown`)
    /// and where the three sides are.
    #[must_use]
    pub fn line(&self, shown: usize) -> String {
        let frame = self
            .frame
            .map_or(String::new(), |f| format!(" of frame {f}"));
        if self.differing.is_empty() {
            return format!(
                "pictures{frame}: every picture is the same on both sides ({})",
                self.dir.display()
            );
        }
        let mut names: Vec<String> = self
            .differing
            .iter()
            .take(shown)
            .map(|p| format!("{} ({} pixels)", p.name, p.pixels))
            .collect();
        if self.differing.len() > shown {
            names.push(format!("{} more", self.differing.len() - shown));
        }
        format!(
            "pictures{frame} differ: {}; expected/, actual/ and difference/ in {}",
            names.join(", "),
            self.dir.display()
        )
    }
}

/// The bytes of `d`'s frame in `stream`.
fn raw<'s>(stream: &'s [u8], d: &Decoded) -> &'s [u8] {
    &stream[d.offset..d.offset + d.len]
}

/// The first record after the header that differs between the two
/// streams (record by record), if any.
fn first_difference(expected: &[u8], e: &[Decoded], actual: &[u8], a: &[Decoded]) -> Option<usize> {
    (1..e.len().max(a.len())).find(|&i| match (e.get(i), a.get(i)) {
        (Some(x), Some(y)) => raw(expected, x) != raw(actual, y),
        _ => true,
    })
}

/// The readable records of `decoded` up to the end of the frame that
/// holds record `index` (the next `FrameStart` after it, or the end).
fn through_frame(decoded: &[Decoded], index: usize) -> Vec<Record> {
    let end = decoded
        .iter()
        .enumerate()
        .skip(index + 1)
        .find(|(_, d)| matches!(d.result, Ok(Record::FrameStart { .. })))
        .map_or(decoded.len(), |(i, _)| i);
    decoded[..end]
        .iter()
        .filter_map(|d| d.result.as_ref().ok().cloned())
        .collect()
}

/// The frame that holds record `index` of `decoded`: the last
/// `FrameStart` at or before it.
fn frame_of(decoded: &[Decoded], index: usize) -> Option<u32> {
    decoded
        .iter()
        .take(index + 1)
        .rev()
        .find_map(|d| match d.result {
            Ok(Record::FrameStart { frame, .. }) => Some(frame),
            _ => None,
        })
}

/// Draws the pictures of `expected` (the fixture, made from `blessed`)
/// and `actual` (made from `run`) into `dir`, replacing the pictures a
/// report left there before; keeps those that differ and their
/// differences.
///
/// # Errors
/// When a picture cannot be drawn, read back or written.
pub fn draw(
    (blessed, expected): (&Scenario, &[u8]),
    (run, actual): (&Scenario, &[u8]),
    dir: &Path,
) -> Result<Pictures> {
    let e: Vec<Decoded> = Decoder::new(expected).collect();
    let a: Vec<Decoded> = Decoder::new(actual).collect();
    clear(dir)?;
    let Some(index) = first_difference(expected, &e, actual, &a) else {
        return Ok(Pictures {
            dir: dir.to_path_buf(),
            frame: None,
            differing: Vec::new(),
        });
    };
    let png = Kinds::parse("png")?;
    let (expected_dir, actual_dir) = (dir.join(SIDES[0]), dir.join(SIDES[1]));
    for (scenario, decoded, side) in [(blessed, &e, &expected_dir), (run, &a, &actual_dir)] {
        fs::create_dir_all(side).with_context(|| format!("cannot create {}", side.display()))?;
        outputs::write(scenario, &through_frame(decoded, index)[..], side, png)?;
    }
    let difference_dir = dir.join(SIDES[2]);
    fs::create_dir_all(&difference_dir)
        .with_context(|| format!("cannot create {}", difference_dir.display()))?;
    let mut names: Vec<String> = [&expected_dir, &actual_dir]
        .iter()
        .flat_map(|side| files(side))
        .collect();
    names.sort();
    names.dedup();
    let mut differing = Vec::new();
    for name in names {
        let (e_path, a_path) = (expected_dir.join(&name), actual_dir.join(&name));
        let is_png = Path::new(&name).extension().is_some_and(|x| x == "png");
        let (e_pic, a_pic) = if is_png {
            (read_rgb(&e_path)?, read_rgb(&a_path)?)
        } else {
            (None, None)
        };
        if !is_png || e_pic == a_pic {
            remove(&e_path)?;
            remove(&a_path)?;
            continue;
        }
        let (picture, pixels) = difference(e_pic.as_ref(), a_pic.as_ref());
        outputs::picture::save_rgb(
            picture.width,
            picture.height,
            &picture.rgb,
            &difference_dir.join(&name),
        )?;
        differing.push(Picture { name, pixels });
    }
    Ok(Pictures {
        dir: dir.to_path_buf(),
        frame: frame_of(&e, index),
        differing,
    })
}

/// Removes the pictures of an earlier report in `dir` (only files in its
/// [`SIDES`] folders, then the folders if empty).
///
/// # Errors
/// When one cannot be removed.
pub fn clear(dir: &Path) -> Result<()> {
    for side in SIDES {
        let side = dir.join(side);
        for name in files(&side) {
            remove(&side.join(name))?;
        }
        let _ = fs::remove_dir(&side);
    }
    let _ = fs::remove_dir(dir);
    Ok(())
}

/// The names of the regular files in `dir` (none if it cannot be read).
fn files(dir: &Path) -> Vec<String> {
    fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
        .filter_map(|e| e.file_name().into_string().ok())
        .collect()
}

fn remove(path: &Path) -> Result<()> {
    match fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            Err(e).with_context(|| format!("cannot remove {}", path.display()))
        }
        _ => Ok(()),
    }
}

/// A picture as RGB bytes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Rgb {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Three bytes a pixel, row by row.
    pub rgb: Vec<u8>,
}

impl Rgb {
    fn pixel(&self, x: u32, y: u32) -> Option<[u8; 3]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = 3 * (y as usize * self.width as usize + x as usize);
        self.rgb.get(i..i + 3).map(|p| [p[0], p[1], p[2]])
    }
}

/// The PNG at `path` as RGB (none if there is no file).
fn read_rgb(path: &Path) -> Result<Option<Rgb>> {
    let file = match fs::File::open(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        other => other.with_context(|| format!("cannot open {}", path.display()))?,
    };
    let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
    decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let mut reader = decoder
        .read_info()
        .with_context(|| format!("cannot read {}", path.display()))?;
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader
        .next_frame(&mut buf)
        .with_context(|| format!("cannot read {}", path.display()))?;
    let channels = info.color_type.samples();
    let rgb = buf[..info.buffer_size()]
        .chunks_exact(channels)
        .flat_map(|p| match channels {
            1 | 2 => [p[0], p[0], p[0]],
            _ => [p[0], p[1], p[2]],
        })
        .collect();
    Ok(Some(Rgb {
        width: info.width,
        height: info.height,
        rgb,
    }))
}

/// The difference of two pictures over both their extents, and how many
/// pixels differ: a pixel the same on both sides is drawn faded to a
/// quarter of its contrast with white, one that is not (or is on one side
/// only) in red.
#[must_use]
pub fn difference(expected: Option<&Rgb>, actual: Option<&Rgb>) -> (Rgb, u64) {
    let size = |p: Option<&Rgb>| p.map_or((0, 0), |p| (p.width, p.height));
    let ((ew, eh), (aw, ah)) = (size(expected), size(actual));
    let (width, height) = (ew.max(aw), eh.max(ah));
    let mut rgb = Vec::with_capacity(3 * width as usize * height as usize);
    let mut pixels = 0;
    for y in 0..height {
        for x in 0..width {
            let e = expected.and_then(|p| p.pixel(x, y));
            let a = actual.and_then(|p| p.pixel(x, y));
            match (e, a) {
                (Some(e), Some(a)) if e == a => {
                    let luma =
                        (299 * u32::from(e[0]) + 587 * u32::from(e[1]) + 114 * u32::from(e[2]))
                            / 1000;
                    let faded = (255 - (255 - luma) / 4) as u8;
                    rgb.extend([faded; 3]);
                }
                _ => {
                    pixels += 1;
                    rgb.extend(CHANGED);
                }
            }
        }
    }
    (Rgb { width, height, rgb }, pixels)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn picture(width: u32, height: u32, rgb: &[[u8; 3]]) -> Rgb {
        Rgb {
            width,
            height,
            rgb: rgb.concat(),
        }
    }

    #[test]
    fn a_difference_fades_what_is_the_same_and_reds_what_is_not() {
        let (b, w) = ([0, 0, 0], [255, 255, 255]);
        let expected = picture(2, 1, &[b, w]);
        let actual = picture(3, 1, &[w, w, b]);
        let (d, pixels) = difference(Some(&expected), Some(&actual));
        // The first pixel changed, the second is white on both sides, the
        // third is past the expected picture's edge.
        assert_eq!(pixels, 2);
        assert_eq!((d.width, d.height), (3, 1));
        assert_eq!(d.rgb, [CHANGED, w, CHANGED].concat());
        let (d, pixels) = difference(Some(&expected), Some(&expected));
        assert_eq!(pixels, 0);
        // Black fades to a light grey.
        assert_eq!(d.rgb[..3], [192, 192, 192]);
    }
}
