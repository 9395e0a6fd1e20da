//! `growth-curve`: a CSV of the daily samples and a chart
//! (`growth.png`, `growth.svg`) of f(t) on the left axis and the daily
//! increment on the right one, over the days of the year.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Result;
use morphogen::fx::Fx;
use morphogen::fx::Real as _;
use morphogen::growth_curve::{SERIES_DAILY, SERIES_GROWTH};
use morphogen::stream::Record;
use morphogen_stream_text::text::{self, Whole};

use super::chart::{Axis, Chart, Series};
use super::driver::{self, Closing, Products, Rgb};
use super::kinds::Kinds;
use crate::atomic::OutputFile;
use crate::records::Records;

/// The `(x, y)` samples of one series.
type Samples = Vec<(Fx, Fx)>;

/// The samples of the growth and the daily series: the points of the
/// plot's two lines (a few hundred, one a day).
#[derive(Debug, Default)]
pub(super) struct Curve {
    growth: Samples,
    daily: Samples,
}

/// Gathers a curve's samples, handing them over at the frame's end.
#[derive(Debug, Default)]
pub(super) struct Sampler(Curve);

impl Products for Curve {
    type Frame = Curve;
    type Framer = Sampler;
    type Picture = Rgb;
    type Measure = ();

    fn push(framer: &mut Sampler, r: &Record) -> Result<Option<Curve>> {
        match r {
            Record::Sample { series, x, y } => match *series {
                SERIES_GROWTH => framer.0.growth.push((*x, *y)),
                SERIES_DAILY => framer.0.daily.push((*x, *y)),
                _ => {}
            },
            Record::FrameEnd { .. } => return Ok(Some(std::mem::take(&mut framer.0))),
            _ => {}
        }
        Ok(None)
    }

    fn survey(&mut self, frame: Curve) -> Result<()> {
        self.growth.extend(frame.growth);
        self.daily.extend(frame.daily);
        Ok(())
    }

    fn index(_frame: &Curve) -> i64 {
        0
    }

    /// Writes `growth.csv`, `growth.png` and `growth.svg` (those of
    /// `kinds`).
    fn close(self, dir: &Path, kinds: Kinds, _run: Closing<()>) -> Result<Vec<PathBuf>> {
        let Curve { growth, daily } = self;
        let mut written = Vec::new();
        written.extend(kinds.table(dir, "growth", |path| write_csv(&growth, &daily, path))?);
        let days = growth.last().map_or(365.0, |p| f64::from_fx(p.0));
        let chart = Chart::new(
            "Seasonal growth",
            Axis::new("time", "days").with_range(0.0, days.max(1.0)),
            Axis::new("growth f(t)", "fraction of the year's growth").with_range(0.0, 1.05),
        )
        .with_y2(Axis::new("daily increment", "fraction a day"))
        .with_series(Series::line("f(t)", growth.into_iter().map(real).collect()))
        .with_series(
            Series::line("daily increment", daily.into_iter().map(real).collect()).on_right(),
        );
        written.extend(kinds.chart(&chart, dir, "growth", (900, 500))?);
        Ok(written)
    }
}

/// Writes `growth.csv`: a line a day, its growth and daily increment.
///
/// # Errors
/// When the file cannot be written.
fn write_csv(growth: &Samples, daily: &Samples, path: &Path) -> Result<()> {
    OutputFile::write_with(path, |file| {
        file.write_all(b"day,growth,daily_increment\n")?;
        let mut line = Vec::with_capacity(64);
        for (g, d) in growth.iter().zip(daily) {
            line.clear();
            for (k, v) in [g.0, g.1, d.1].into_iter().enumerate() {
                if k > 0 {
                    line.push(b',');
                }
                text::fx(&mut line, v, Whole::Bare);
            }
            line.push(b'\n');
            file.write_all(&line)?;
        }
        Ok(())
    })
}

fn real((x, y): (Fx, Fx)) -> (f64, f64) {
    (f64::from_fx(x), f64::from_fx(y))
}

/// Writes `growth.csv`, `growth.png` and `growth.svg` (those of `kinds`).
///
/// # Errors
/// When the records cannot be read or a file cannot be written.
pub fn write<R: Records + ?Sized>(records: &R, dir: &Path, kinds: Kinds) -> Result<Vec<PathBuf>> {
    driver::write(Curve::default(), records, dir, kinds)
}
