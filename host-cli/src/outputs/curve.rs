//! `growth-curve`: a CSV of the daily samples and a PNG plot of f(t)
//! (blue) and the daily increment (orange, scaled to the plot), with a
//! grid line at the start of each month.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Result;
use morphogen::fx::Fx;
use morphogen::growth_curve::{SERIES_DAILY, SERIES_GROWTH};
use morphogen::stream::Record;

use super::plot::{Plot, rgb};
use super::text::{self, Whole};
use crate::atomic::OutputFile;
use crate::records::{Place, Records};

/// First day of each month in a non-leap year.
const MONTH_STARTS: [f64; 12] = [
    0.0, 31.0, 59.0, 90.0, 120.0, 151.0, 181.0, 212.0, 243.0, 273.0, 304.0, 334.0,
];

/// The `(x, y)` samples of one series.
type Series = Vec<(Fx, Fx)>;

/// The samples of the growth and the daily series, in one pass: the
/// points of the plot's two lines (a few hundred, one a day).
fn series<R: Records + ?Sized>(records: &R) -> Result<(Series, Series)> {
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
    let f = |v: Fx| f64::from(v.to_bits()) / 65_536.0;
    (f(x), f(y))
}

/// Writes `growth.csv` and `growth.png`.
///
/// # Errors
/// When a file cannot be written.
pub fn write<R: Records + ?Sized>(records: &R, dir: &Path) -> Result<Vec<PathBuf>> {
    let (growth, daily) = series(records)?;
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
    let growth: Vec<(f64, f64)> = growth.into_iter().map(real).collect();
    let daily: Vec<(f64, f64)> = daily.into_iter().map(real).collect();

    let days = growth.last().map_or(365.0, |p| p.0);
    let mut plot = Plot::new(800, 400, (0.0, days), (0.0, 1.05))?;
    plot.grid(&MONTH_STARTS, &[0.25, 0.5, 0.75, 1.0]);
    let peak = daily.iter().map(|p| p.1).fold(f64::MIN_POSITIVE, f64::max);
    let scaled: Vec<(f64, f64)> = daily.iter().map(|&(x, y)| (x, y / peak)).collect();
    plot.line(&scaled, rgb(230, 130, 30), 2.0);
    plot.line(&growth, rgb(30, 90, 200), 2.5);
    let png_path = dir.join("growth.png");
    plot.save(&png_path)?;
    Ok(vec![csv_path, png_path])
}
