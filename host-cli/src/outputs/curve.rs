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

use super::chart::{Axis, Chart, Series, write_chart};
use super::kinds::{Kind, Kinds};
use super::text::{self, Whole};
use crate::atomic::OutputFile;
use crate::records::{Place, Records};

/// The `(x, y)` samples of one series.
type Samples = Vec<(Fx, Fx)>;

/// The samples of the growth and the daily series, in one pass: the
/// points of the plot's two lines (a few hundred, one a day).
fn series<R: Records + ?Sized>(records: &R) -> Result<(Samples, Samples)> {
    let (mut growth, mut daily) = (Vec::new(), Vec::new());
    records.visit(Place::START, |_, r| {
        if let Record::Sample { series, x, y } = r {
            match *series {
                SERIES_GROWTH => growth.push((*x, *y)),
                SERIES_DAILY => daily.push((*x, *y)),
                _ => {}
            }
        }
        Ok(())
    })?;
    Ok((growth, daily))
}

fn real((x, y): (Fx, Fx)) -> (f64, f64) {
    (f64::from_fx(x), f64::from_fx(y))
}

/// Writes `growth.csv`, `growth.png` and `growth.svg` (those of `kinds`).
///
/// # Errors
/// When a file cannot be written.
pub fn write<R: Records + ?Sized>(records: &R, dir: &Path, kinds: Kinds) -> Result<Vec<PathBuf>> {
    let (growth, daily) = series(records)?;
    let mut written = Vec::new();
    if kinds.has(Kind::Csv) {
        let csv_path = dir.join("growth.csv");
        OutputFile::write_with(&csv_path, |file| {
            file.write_all(b"day,growth,daily_increment\n")?;
            let mut line = Vec::with_capacity(64);
            for (g, d) in growth.iter().zip(&daily) {
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
        })?;
        written.push(csv_path);
    }
    let days = growth.last().map_or(365.0, |p| f64::from_fx(p.0));
    let chart = Chart::new(
        "Seasonal growth",
        Axis::new("time", "days").with_range(0.0, days.max(1.0)),
        Axis::new("growth f(t)", "fraction of the year's growth").with_range(0.0, 1.05),
    )
    .with_y2(Axis::new("daily increment", "fraction a day"))
    .with_series(Series::line("f(t)", growth.into_iter().map(real).collect()))
    .with_series(Series::line("daily increment", daily.into_iter().map(real).collect()).on_right());
    write_chart(&chart, dir, "growth", (900, 500), kinds, &mut written)?;
    Ok(written)
}
