//! Painter's order for a plant of any size: its items sorted by depth,
//! stably (equal depths keep their stream order), in memory while they fit
//! [`BUDGET`] bytes, else as sorted runs spilled to anonymous temporary
//! files beside the outputs and merged back (an external merge sort, so
//! a plant's memory does not grow with its size).

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::fs::File;
use std::io::{self, BufReader, BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use super::Item;
use crate::outputs::raster::depth_key as key;

/// The bytes of items held before they are sorted and spilled as a run.
pub(crate) const BUDGET: usize = 1 << 20;

/// Items being sorted back to front.
#[derive(Debug)]
pub(super) struct Sort {
    dir: PathBuf,
    held: Vec<(f64, Item)>,
    bytes: usize,
    /// The bytes held before a spill: [`BUDGET`] but in tests.
    budget: usize,
    runs: Vec<File>,
}

/// The memory an item holds, about.
fn weight(item: &Item) -> usize {
    let points = match item {
        Item::Segment { .. } => 0,
        Item::Polygon { points, .. } => points.len(),
    };
    size_of::<(f64, Item)>() + points * size_of::<[f64; 3]>()
}

impl Sort {
    /// Nothing to sort yet; runs go to `dir`.
    pub(super) fn new(dir: &Path) -> Sort {
        Sort {
            dir: dir.to_path_buf(),
            held: Vec::new(),
            bytes: 0,
            budget: BUDGET,
            runs: Vec::new(),
        }
    }

    /// Adds the next item in stream order.
    ///
    /// # Errors
    /// When a run cannot be spilled.
    pub(super) fn push(&mut self, item: Item) -> Result<()> {
        self.bytes += weight(&item);
        self.held.push((item.depth(), item));
        if self.bytes > self.budget {
            self.spill()?;
        }
        Ok(())
    }

    /// Sorts the held items and writes them out as one run.
    fn spill(&mut self) -> Result<()> {
        let cannot = || format!("cannot write a temporary file in {}", self.dir.display());
        self.held.sort_by(|x, y| x.0.total_cmp(&y.0));
        let file = tempfile::tempfile_in(&self.dir).with_context(cannot)?;
        let mut out = BufWriter::with_capacity(1 << 16, file);
        for (depth, item) in self.held.drain(..) {
            write(&mut out, depth, &item).with_context(cannot)?;
        }
        let mut file = out
            .into_inner()
            .map_err(io::IntoInnerError::into_error)
            .with_context(cannot)?;
        file.seek(SeekFrom::Start(0)).with_context(cannot)?;
        self.runs.push(file);
        self.bytes = 0;
        Ok(())
    }

    /// Hands every item to `draw`, back to front (the stable sort of all
    /// items by depth).
    ///
    /// # Errors
    /// When a run cannot be written or read back.
    pub(super) fn drain(mut self, draw: &mut dyn FnMut(&Item)) -> Result<()> {
        if self.runs.is_empty() {
            self.held.sort_by(|x, y| x.0.total_cmp(&y.0));
            self.held.iter().for_each(|(_, item)| draw(item));
            return Ok(());
        }
        if !self.held.is_empty() {
            self.spill()?;
        }
        self.held = Vec::new();
        let cannot = || format!("cannot sort through {}", self.dir.display());
        // At most FAN_IN runs are read at once: the first ones are merged
        // into one run first, in their place, which keeps the order.
        while self.runs.len() > FAN_IN {
            let first: Vec<File> = self.runs.drain(..FAN_IN).collect();
            let file = tempfile::tempfile_in(&self.dir).with_context(cannot)?;
            let mut out = BufWriter::with_capacity(1 << 16, file);
            merge(first, &mut |depth, item| write(&mut out, depth, item)).with_context(cannot)?;
            let mut file = out
                .into_inner()
                .map_err(io::IntoInnerError::into_error)
                .with_context(cannot)?;
            file.seek(SeekFrom::Start(0)).with_context(cannot)?;
            self.runs.insert(0, file);
        }
        let runs = std::mem::take(&mut self.runs);
        merge(runs, &mut |_, item| {
            draw(item);
            Ok(())
        })
        .with_context(cannot)
    }
}

/// Runs merged at once, at most.
const FAN_IN: usize = 16;

/// Hands the items of the sorted `runs` to `each` by depth; of equal
/// depths, those of the earlier run first (so consecutive runs of a stable
/// sort merge into its stable sort).
fn merge(runs: Vec<File>, each: &mut dyn FnMut(f64, &Item) -> io::Result<()>) -> io::Result<()> {
    let mut runs: Vec<BufReader<File>> = runs
        .into_iter()
        .map(|f| BufReader::with_capacity(1 << 14, f))
        .collect();
    let mut heads: Vec<Option<(f64, Item)>> = Vec::with_capacity(runs.len());
    let mut next = BinaryHeap::with_capacity(runs.len());
    for (k, run) in runs.iter_mut().enumerate() {
        let head = read(run)?;
        if let Some((depth, _)) = &head {
            next.push(Reverse((key(*depth), k)));
        }
        heads.push(head);
    }
    while let Some(Reverse((_, k))) = next.pop() {
        if let Some((depth, item)) = heads[k].take() {
            each(depth, &item)?;
        }
        if let Some(head) = read(&mut runs[k])? {
            next.push(Reverse((key(head.0), k)));
            heads[k] = Some(head);
        }
    }
    Ok(())
}

const SEGMENT: u8 = 0;
const POLYGON: u8 = 1;

fn put(out: &mut impl Write, values: &[f64]) -> io::Result<()> {
    values
        .iter()
        .try_for_each(|v| out.write_all(&v.to_le_bytes()))
}

/// Writes one item of a run, its depth first; every float bit for bit.
fn write(out: &mut impl Write, depth: f64, item: &Item) -> io::Result<()> {
    match item {
        Item::Segment {
            a,
            b,
            width,
            colour,
        } => {
            out.write_all(&[SEGMENT])?;
            put(out, &[depth])?;
            put(out, a)?;
            put(out, b)?;
            put(out, &[*width])?;
            out.write_all(&colour.to_le_bytes())
        }
        Item::Polygon { points, colour } => {
            out.write_all(&[POLYGON])?;
            put(out, &[depth])?;
            out.write_all(&colour.to_le_bytes())?;
            let n = u32::try_from(points.len()).map_err(io::Error::other)?;
            out.write_all(&n.to_le_bytes())?;
            points.iter().try_for_each(|p| put(out, p))
        }
    }
}

fn float(input: &mut impl Read) -> io::Result<f64> {
    let mut b = [0u8; 8];
    input.read_exact(&mut b)?;
    Ok(f64::from_le_bytes(b))
}

fn point(input: &mut impl Read) -> io::Result<[f64; 3]> {
    Ok([float(input)?, float(input)?, float(input)?])
}

fn colour(input: &mut impl Read) -> io::Result<u16> {
    let mut b = [0u8; 2];
    input.read_exact(&mut b)?;
    Ok(u16::from_le_bytes(b))
}

/// Reads the next item of a run and its depth; `None` at the run's end.
fn read(input: &mut impl Read) -> io::Result<Option<(f64, Item)>> {
    let mut tag = [0u8; 1];
    match input.read_exact(&mut tag) {
        Err(e) if e.kind() == io::ErrorKind::UnexpectedEof => return Ok(None),
        r => r?,
    }
    let depth = float(input)?;
    let item = match tag[0] {
        SEGMENT => Item::Segment {
            a: point(input)?,
            b: point(input)?,
            width: float(input)?,
            colour: colour(input)?,
        },
        POLYGON => {
            let colour = colour(input)?;
            let mut n = [0u8; 4];
            input.read_exact(&mut n)?;
            let points = (0..u32::from_le_bytes(n))
                .map(|_| point(input))
                .collect::<io::Result<_>>()?;
            Item::Polygon { points, colour }
        }
        other => return Err(io::Error::other(format!("a run holds tag {other}"))),
    };
    Ok(Some((depth, item)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A segment at depth `z`, told apart by its colour.
    fn at(z: f64, colour: u16) -> Item {
        Item::Segment {
            a: [0.0, 0.0, z],
            b: [1.0, -0.0, z],
            width: 0.5,
            colour,
        }
    }

    fn order(sort: Sort) -> Vec<(u16, u64)> {
        let mut seen = Vec::new();
        sort.drain(&mut |item| match item {
            Item::Segment { colour, a, .. } => seen.push((*colour, a[2].to_bits())),
            Item::Polygon { colour, points } => seen.push((*colour, points.len() as u64)),
        })
        .unwrap();
        seen
    }

    #[test]
    fn spilled_runs_merge_into_the_stable_sort() {
        let dir = tempfile::tempdir().unwrap();
        let mut items = Vec::new();
        let mut seed = 11u64;
        for i in 0..20_000u32 {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            // Few distinct depths (many ties), both zeros, negatives.
            let z = match (seed >> 40) % 9 {
                0 => -0.0,
                1 => 0.0,
                k => (k as f64 - 4.5) / 3.0,
            };
            let item = if i % 5 == 0 {
                Item::Polygon {
                    points: (0..(i % 7)).map(|_| [0.0, 0.0, z]).collect(),
                    colour: i as u16,
                }
            } else {
                at(z, i as u16)
            };
            items.push(item);
        }
        let mut memory = Sort::new(dir.path());
        memory.held = items.iter().map(|i| (i.depth(), i.clone())).collect();
        let want = order(memory);
        let mut spilled = Sort::new(dir.path());
        spilled.budget = 4 << 10;
        for item in items {
            spilled.push(item).unwrap();
        }
        // More runs than are merged at once, twice over.
        assert!(
            spilled.runs.len() > FAN_IN * FAN_IN,
            "{} runs",
            spilled.runs.len()
        );
        assert_eq!(order(spilled), want);
        // The runs were anonymous: nothing is left in the folder.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }
}
