//! Charts of a run's tables: curves over one x axis against a left y scale
//! and, for a quantity of another size, a right one; with ticks, axis
//! titles with their units, a title and a legend. Drawn with `plotters`
//! into an RGB buffer (encoded here with `png`) or into an SVG string, and
//! written atomically.
//!
//! Text needs no system font: DejaVu Sans, embedded by the `dejavu` crate,
//! is registered with plotters' `ab_glyph` text renderer as `sans-serif`
//! ([`font`] hands the same face to other writers, such as
//! [`super::animation`]). The same chart therefore gives the same bytes on
//! every machine that runs the same build.
//!
//! ```no_run
//! use morphogen_cli::outputs::chart::{Axis, Chart, Series, write_png};
//!
//! let curve: Vec<(f64, f64)> = (0..=365).map(|d| (f64::from(d), f64::from(d) / 365.0)).collect();
//! let chart = Chart::new("Growth", Axis::new("time", "days"), Axis::new("size", "mm"))
//!     .with_series(Series::line("size", curve));
//! write_png(&chart, std::path::Path::new("growth.png"), 800, 500)?;
//! # Ok::<(), anyhow::Error>(())
//! ```

use std::ops::Range;
use std::path::Path;
use std::sync::OnceLock;

use ab_glyph::FontRef;
use anyhow::{Context, Result, anyhow, bail};
use plotters::chart::DualCoordChartContext;
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use crate::atomic::write_atomic;

/// The largest width or height of a chart, in pixels: a picture of
/// `MAX_SIDE²` RGB pixels is 800 MB.
pub const MAX_SIDE: u32 = 16_384;

/// The font family name under which [`font`] is registered with plotters.
const FAMILY: &str = "sans-serif";

/// Series colours in order (Okabe & Ito's colour-blind-safe palette, the
/// yellow left out for being too light on white).
const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
    RGBColor(230, 159, 0),
    RGBColor(0, 0, 0),
];

/// The colour of the `index`th series of a chart, as RGB.
#[must_use]
pub fn series_colour(index: usize) -> [u8; 3] {
    let RGBColor(r, g, b) = PALETTE[index % PALETTE.len()];
    [r, g, b]
}

/// The embedded text face (DejaVu Sans, Bitstream Vera licence), parsed
/// once.
///
/// # Errors
/// Never in practice: only if the embedded font were unreadable.
pub fn font() -> Result<&'static FontRef<'static>> {
    static FONT: OnceLock<Option<FontRef<'static>>> = OnceLock::new();
    FONT.get_or_init(|| FontRef::try_from_slice(dejavu::sans::regular()).ok())
        .as_ref()
        .ok_or_else(|| anyhow!("the embedded DejaVu Sans font cannot be read"))
}

/// Registers [`font`] with plotters as `sans-serif`, once per process.
fn register_font() -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font(FAMILY, FontStyle::Normal, dejavu::sans::regular()).is_ok()
    });
    if ok {
        Ok(())
    } else {
        bail!("the embedded DejaVu Sans font cannot be registered with plotters")
    }
}

/// One axis: what it measures, in which unit, over which range.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// What the axis measures, e.g. `time`.
    pub label: String,
    /// Its unit, e.g. `days`; empty for a pure number.
    pub unit: String,
    /// The range shown; `None` fits the data of the series on this axis
    /// (the y axes with 5 % room above and below).
    pub range: Option<(f64, f64)>,
}

impl Axis {
    /// An axis fitted to its data.
    #[must_use]
    pub fn new(label: impl Into<String>, unit: impl Into<String>) -> Axis {
        Axis {
            label: label.into(),
            unit: unit.into(),
            range: None,
        }
    }

    /// The same axis showing `from..to` exactly.
    #[must_use]
    pub fn with_range(mut self, from: f64, to: f64) -> Axis {
        self.range = Some((from, to));
        self
    }

    /// The axis title: `label (unit)`, or the label alone without a unit.
    #[must_use]
    pub fn title(&self) -> String {
        if self.unit.is_empty() {
            self.label.clone()
        } else {
            format!("{} ({})", self.label, self.unit)
        }
    }
}

/// Which y scale a series is read against.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Side {
    /// The left y axis, [`Chart::y`].
    #[default]
    Left,
    /// The right y axis, [`Chart::y2`].
    Right,
}

/// How a series' points are joined.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Style {
    /// Straight lines from point to point.
    #[default]
    Line,
    /// A dot at each point, unjoined.
    Points,
    /// A staircase: each value held until the next point's x.
    Steps,
}

/// A named list of `(x, y)` points. Points with a non-finite coordinate
/// are left out, and a line or staircase is broken there.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// The legend entry (none when empty).
    pub name: String,
    /// The points in the order they are joined.
    pub points: Vec<(f64, f64)>,
    /// The y scale the points are read against.
    pub side: Side,
    /// How the points are drawn.
    pub style: Style,
    /// Its colour (RGB); `None`: the palette's, by position.
    pub colour: Option<[u8; 3]>,
}

impl Series {
    /// A line through `points`, on the left axis.
    #[must_use]
    pub fn line(name: impl Into<String>, points: Vec<(f64, f64)>) -> Series {
        Series {
            name: name.into(),
            points,
            side: Side::Left,
            style: Style::Line,
            colour: None,
        }
    }

    /// The same series in colour `rgb`.
    #[must_use]
    pub fn with_colour(mut self, rgb: [u8; 3]) -> Series {
        self.colour = Some(rgb);
        self
    }

    /// Dots at `points`, on the left axis.
    #[must_use]
    pub fn points(name: impl Into<String>, points: Vec<(f64, f64)>) -> Series {
        Series {
            style: Style::Points,
            ..Series::line(name, points)
        }
    }

    /// A staircase through `points`, on the left axis.
    #[must_use]
    pub fn steps(name: impl Into<String>, points: Vec<(f64, f64)>) -> Series {
        Series {
            style: Style::Steps,
            ..Series::line(name, points)
        }
    }

    /// The same series read against the right axis.
    #[must_use]
    pub fn on_right(mut self) -> Series {
        self.side = Side::Right;
        self
    }

    /// The runs of consecutive finite points, as they are drawn.
    fn runs(&self) -> Vec<Vec<(f64, f64)>> {
        let mut runs = Vec::new();
        let mut run = Vec::new();
        for &(x, y) in &self.points {
            if x.is_finite() && y.is_finite() {
                if self.style == Style::Steps
                    && let Some(&(_, held)) = run.last()
                {
                    run.push((x, held));
                }
                run.push((x, y));
            } else if !run.is_empty() {
                runs.push(std::mem::take(&mut run));
            }
        }
        if !run.is_empty() {
            runs.push(run);
        }
        runs
    }
}

/// A chart: a title, an x axis, a left y axis, an optional right y axis,
/// and the series drawn against them, in legend order.
#[derive(Debug, Clone, PartialEq)]
pub struct Chart {
    /// The caption above the plot; empty for none.
    pub title: String,
    /// The horizontal axis, shared by all series.
    pub x: Axis,
    /// The left vertical axis.
    pub y: Axis,
    /// The right vertical axis, for series of another size or unit.
    pub y2: Option<Axis>,
    /// The series, drawn and listed in this order.
    pub series: Vec<Series>,
}

impl Chart {
    /// A chart with no series and no right axis.
    #[must_use]
    pub fn new(title: impl Into<String>, x: Axis, y: Axis) -> Chart {
        Chart {
            title: title.into(),
            x,
            y,
            y2: None,
            series: Vec::new(),
        }
    }

    /// The same chart with a right y axis.
    #[must_use]
    pub fn with_y2(mut self, y2: Axis) -> Chart {
        self.y2 = Some(y2);
        self
    }

    /// The same chart with `series` added last.
    #[must_use]
    pub fn with_series(mut self, series: Series) -> Chart {
        self.series.push(series);
        self
    }

    /// The ranges drawn: x, left y, right y (the left one when there is
    /// no right axis).
    fn ranges(&self) -> Result<(Range<f64>, Range<f64>, Range<f64>)> {
        if self.y2.is_none()
            && let Some(s) = self.series.iter().find(|s| s.side == Side::Right)
        {
            bail!(
                "series \"{}\" is on the right axis but the chart has none",
                s.name
            );
        }
        let finite = |side: Option<Side>| {
            self.series
                .iter()
                .filter(move |s| side.is_none_or(|side| s.side == side))
                .flat_map(|s| s.points.iter().copied())
                .filter(|(x, y)| x.is_finite() && y.is_finite())
        };
        let x = fit(&self.x, finite(None).map(|p| p.0), 0.0)?;
        let y = fit(&self.y, finite(Some(Side::Left)).map(|p| p.1), 0.05)?;
        let y2 = match &self.y2 {
            Some(axis) => fit(axis, finite(Some(Side::Right)).map(|p| p.1), 0.05)?,
            None => y.clone(),
        };
        Ok((x, y, y2))
    }
}

/// The range of `axis`: its own, else that of `values` widened by
/// `room` of its length on each side; `0..1` without values, and a
/// width of 1 around a single value.
fn fit(axis: &Axis, values: impl Iterator<Item = f64>, room: f64) -> Result<Range<f64>> {
    if let Some((from, to)) = axis.range {
        if !(from.is_finite() && to.is_finite() && from < to) {
            bail!(
                "the range of axis \"{}\" must be finite and increasing, not {from}..{to}",
                axis.label
            );
        }
        return Ok(from..to);
    }
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    Ok(if lo > hi {
        0.0..1.0
    } else if lo == hi {
        lo - 0.5..hi + 0.5
    } else {
        let pad = (hi - lo) * room;
        lo - pad..hi + pad
    })
}

/// Formats the tick values of an axis spanning `span`: with the decimals
/// a tenth of the span needs, trailing zeros cut (`50`, `0.5`, `0.004`).
fn tick_format(span: f64) -> impl Fn(&f64) -> String {
    // span > 0 and finite (see `fit`): the log is finite; at most 12 decimals.
    let decimals = (-(span / 10.0).log10()).ceil().clamp(0.0, 12.0) as usize + 1;
    move |value: &f64| {
        let text = format!("{value:.decimals$}");
        // `decimals` ≥ 1: there is a point to cut back to.
        let text = text.trim_end_matches('0').trim_end_matches('.');
        if text == "-0" {
            "0".to_string()
        } else {
            text.to_string()
        }
    }
}

fn drawing<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> anyhow::Error {
    anyhow!("cannot draw the chart: {e}")
}

fn check_size(width: u32, height: u32) -> Result<()> {
    if width < 64 || height < 64 || width > MAX_SIDE || height > MAX_SIDE {
        bail!("a chart must be 64 to {MAX_SIDE} pixels a side, not {width}×{height}");
    }
    Ok(())
}

/// Draws `chart` on `root`, a `width × height` area.
fn draw<DB: DrawingBackend>(chart: &Chart, root: &DrawingArea<DB, Shift>) -> Result<()> {
    register_font()?;
    let (x, y, y2) = chart.ranges()?;
    let (width, height) = root.dim_in_pixel();
    // Text a twenty-eighth of the shorter side, 14 to 36 (plotters draws
    // glyphs 1/1.24 of that: 11 to 29 px).
    let text_px = (width.min(height) / 28).clamp(14, 36);
    let text = (FAMILY, text_px).into_font().color(&BLACK);
    let title = (FAMILY, text_px * 3 / 2).into_font().color(&BLACK);
    let margin = text_px;
    let label_area = text_px * 5;

    root.fill(&WHITE).map_err(drawing)?;
    let mut builder = ChartBuilder::on(root);
    builder
        .margin(margin)
        .x_label_area_size(text_px * 3)
        .y_label_area_size(label_area);
    if !chart.title.is_empty() {
        builder.caption(&chart.title, title);
    }
    if chart.y2.is_some() {
        builder.right_y_label_area_size(label_area);
    } else {
        builder.margin_right(margin * 2);
    }
    let x_ticks = tick_format(x.end - x.start);
    let y_ticks = tick_format(y.end - y.start);
    let y2_ticks = tick_format(y2.end - y2.start);
    let mut ctx = builder
        .build_cartesian_2d(x.clone(), y)
        .map_err(drawing)?
        .set_secondary_coord(x, y2);

    ctx.configure_mesh()
        .x_desc(chart.x.title())
        .y_desc(chart.y.title())
        .x_label_formatter(&x_ticks)
        .y_label_formatter(&y_ticks)
        .label_style(text.clone())
        .axis_desc_style(text.clone())
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(205, 205, 205))
        .draw()
        .map_err(drawing)?;
    if let Some(y2) = &chart.y2 {
        ctx.configure_secondary_axes()
            .y_desc(y2.title())
            .y_label_formatter(&y2_ticks)
            .label_style(text.clone())
            .axis_desc_style(text.clone())
            .draw()
            .map_err(drawing)?;
    }

    plot_series(&mut ctx, chart, text_px)?;
    if !chart.series.is_empty() {
        ctx.configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(120, 120, 120))
            .label_font(text)
            .draw()
            .map_err(drawing)?;
    }
    root.present().map_err(drawing)?;
    Ok(())
}

/// The chart's axes on both sides, over the same x.
type Dual<'a, DB> = DualCoordChartContext<
    'a,
    DB,
    Cartesian2d<RangedCoordf64, RangedCoordf64>,
    Cartesian2d<RangedCoordf64, RangedCoordf64>,
>;

/// Draws each of `chart`'s series on its axis, with its legend entry
/// (a key `text_px`·1.5 long).
fn plot_series<DB: DrawingBackend>(
    ctx: &mut Dual<'_, DB>,
    chart: &Chart,
    text_px: u32,
) -> Result<()> {
    for (i, series) in chart.series.iter().enumerate() {
        let colour = series
            .colour
            .map_or(PALETTE[i % PALETTE.len()], |[r, g, b]| RGBColor(r, g, b));
        let stroke = colour.stroke_width(2);
        let runs = series.runs();
        let anno = match (series.style, series.side) {
            (Style::Points, Side::Left) => ctx.draw_series(dots(&runs, colour)).map_err(drawing)?,
            (Style::Points, Side::Right) => ctx
                .draw_secondary_series(dots(&runs, colour))
                .map_err(drawing)?,
            (_, Side::Left) => ctx
                .draw_series(runs.into_iter().map(|run| PathElement::new(run, stroke)))
                .map_err(drawing)?,
            (_, Side::Right) => ctx
                .draw_secondary_series(runs.into_iter().map(|run| PathElement::new(run, stroke)))
                .map_err(drawing)?,
        };
        // A series without a name (the markers of a line named already)
        // has no legend entry.
        if series.name.is_empty() {
            continue;
        }
        let name = if series.side == Side::Right {
            format!("{} (right axis)", series.name)
        } else {
            series.name.clone()
        };
        // text_px ≤ 36, so the key length fits any integer.
        let key = i32::try_from(text_px * 3 / 2).unwrap_or(18);
        match series.style {
            Style::Points => anno
                .label(name)
                .legend(move |(x, y)| Circle::new((x + key / 2, y), 3, colour.filled())),
            Style::Line | Style::Steps => anno
                .label(name)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + key, y)], stroke)),
        };
    }
    Ok(())
}

fn dots(runs: &[Vec<(f64, f64)>], colour: RGBColor) -> Vec<Circle<(f64, f64), i32>> {
    runs.iter()
        .flatten()
        .map(|&p| Circle::new(p, 3, colour.filled()))
        .collect()
}

/// Draws `chart` as `width × height` RGB pixels, row by row.
///
/// # Errors
/// When a side is outside 64..=[`MAX_SIDE`], a series is on a right axis
/// the chart lacks, an axis range is not finite and increasing, or
/// drawing fails.
pub fn render_rgb(chart: &Chart, width: u32, height: u32) -> Result<Vec<u8>> {
    check_size(width, height)?;
    let bytes = usize::try_from(u64::from(width) * u64::from(height) * 3)
        .context("the chart does not fit in memory")?;
    let mut rgb = vec![0u8; bytes];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (width, height)).into_drawing_area();
        draw(chart, &root)?;
    }
    Ok(rgb)
}

/// Draws `chart` as a `width × height` SVG document; its text stays text
/// (family `sans-serif`), laid out with the embedded font's metrics.
///
/// # Errors
/// As [`render_rgb`].
pub fn render_svg(chart: &Chart, width: u32, height: u32) -> Result<String> {
    check_size(width, height)?;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
        draw(chart, &root)?;
    }
    Ok(svg)
}

/// Writes `chart` as a `width × height` RGB PNG at `path`, whole or not
/// at all.
///
/// # Errors
/// As [`render_rgb`], or when the file cannot be written.
pub fn write_png(chart: &Chart, path: &Path, width: u32, height: u32) -> Result<()> {
    let rgb = render_rgb(chart, width, height)?;
    super::picture::save_plot(width, height, &rgb, path)
        .with_context(|| format!("cannot write the chart {}", path.display()))
}

/// Writes `chart` as a `width × height` SVG at `path`, whole or not at
/// all.
///
/// # Errors
/// As [`render_svg`], or when the file cannot be written.
pub fn write_svg(chart: &Chart, path: &Path, width: u32, height: u32) -> Result<()> {
    let svg = render_svg(chart, width, height)?;
    write_atomic(path, svg.as_bytes())
        .with_context(|| format!("cannot write the chart {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A logistic growth curve over a year, with its daily increment on
    /// the right axis.
    fn sigmoid() -> Chart {
        let f = |t: f64| 1.0 / (1.0 + (-(t - 180.0) / 30.0).exp());
        let curve: Vec<(f64, f64)> = (0..=365).map(|d| (f64::from(d), f(f64::from(d)))).collect();
        let increment: Vec<(f64, f64)> = (1..=365)
            .map(|d| (f64::from(d), f(f64::from(d)) - f(f64::from(d - 1))))
            .collect();
        Chart::new(
            "Sigmoid growth",
            Axis::new("time", "days"),
            Axis::new("f(t)", ""),
        )
        .with_y2(Axis::new("daily increment", "1/day"))
        .with_series(Series::line("f(t)", curve))
        .with_series(Series::line("daily increment", increment).on_right())
    }

    fn decode(path: &Path) -> (u32, u32, Vec<u8>) {
        let decoder = png::Decoder::new(std::fs::File::open(path).unwrap());
        let mut reader = decoder.read_info().unwrap();
        let mut rgb = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut rgb).unwrap();
        assert_eq!(info.color_type, png::ColorType::Rgb);
        assert_eq!(info.bit_depth, png::BitDepth::Eight);
        rgb.truncate(info.buffer_size());
        (info.width, info.height, rgb)
    }

    /// The rows at which `colour` appears in columns `columns`.
    fn rows_of(rgb: &[u8], width: u32, colour: [u8; 3], columns: Range<usize>) -> Vec<usize> {
        rgb.chunks_exact(3)
            .enumerate()
            .filter(|(i, p)| columns.contains(&(i % width as usize)) && *p == colour)
            .map(|(i, _)| i / width as usize)
            .collect()
    }

    #[test]
    fn a_png_chart_decodes_draws_both_scales_and_is_the_same_twice() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a.png"), dir.path().join("b.png"));
        write_png(&sigmoid(), &a, 800, 500).unwrap();
        write_png(&sigmoid(), &b, 800, 500).unwrap();
        let bytes = std::fs::read(&a).unwrap();
        assert_eq!(bytes, std::fs::read(&b).unwrap());
        // Only the two charts: the temporary files were renamed.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);

        let (width, height, rgb) = decode(&a);
        assert_eq!((width, height), (800, 500));
        assert_eq!(rgb, render_rgb(&sigmoid(), 800, 500).unwrap());
        // In the right 40 % (t ≈ 220..365, past the legend) the curve
        // climbs from about 0.8 to 1 of the left scale, and the
        // increment falls from about 2/3 of the right scale to 0: both
        // span many rows. On the left scale the increment (≤ 0.009)
        // would lie flat on the bottom.
        let right = 480..760;
        for (i, name) in [(0, "f(t)"), (1, "increment")] {
            let rows = rows_of(&rgb, width, series_colour(i), right.clone());
            assert!(rows.len() > 200, "{name}: {} pixels", rows.len());
            let span = rows.iter().max().unwrap() - rows.iter().min().unwrap();
            assert!(span > 40, "{name} spans {span} rows");
        }
        let increment = rows_of(&rgb, width, series_colour(1), right);
        let span = increment.iter().max().unwrap() - increment.iter().min().unwrap();
        assert!(span > 150, "the increment spans only {span} rows");
    }

    #[test]
    fn the_title_is_drawn_as_text() {
        // Black pixels in the middle of the top band: the title's glyphs.
        let black_on_top = |chart: &Chart| {
            let rgb = render_rgb(chart, 800, 500).unwrap();
            rgb.chunks_exact(3)
                .enumerate()
                .filter(|(i, p)| {
                    let (x, y) = (i % 800, i / 800);
                    (400..520).contains(&x) && y < 40 && p.iter().all(|&c| c < 60)
                })
                .count()
        };
        let titled = black_on_top(&sigmoid());
        let untitled = black_on_top(&Chart {
            title: String::new(),
            ..sigmoid()
        });
        assert!(titled > 40, "{titled} black pixels in the title band");
        assert_eq!(untitled, 0);
    }

    #[test]
    fn an_svg_chart_keeps_its_labels_and_legend_as_text() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a.svg"), dir.path().join("b.svg"));
        write_svg(&sigmoid(), &a, 800, 500).unwrap();
        write_svg(&sigmoid(), &b, 800, 500).unwrap();
        let svg = std::fs::read_to_string(&a).unwrap();
        assert_eq!(svg, std::fs::read_to_string(&b).unwrap());
        assert!(svg.starts_with("<svg"), "{}", &svg[..40]);
        // Each text element's content, which plotters puts on its own line.
        let texts: Vec<&str> = svg
            .split("<text")
            .skip(1)
            .filter_map(|t| t.split_once('>'))
            .filter_map(|(_, rest)| rest.split_once("</text>"))
            .map(|(text, _)| text.trim())
            .collect();
        for text in [
            "Sigmoid growth",
            "time (days)",
            "f(t)",
            "daily increment (1/day)",
            "daily increment (right axis)",
            "0",
            "350",
            "0.5",
            "0.004",
        ] {
            assert!(texts.contains(&text), "no {text:?} in {texts:?}");
        }
        // The two curves are the only long polylines.
        let long = svg
            .split("<polyline")
            .skip(1)
            .filter(|p| {
                p.split_once("points=\"")
                    .is_some_and(|(_, pts)| pts.split(' ').count() > 300)
            })
            .count();
        assert_eq!(long, 2);
    }

    #[test]
    fn styles_break_at_gaps_and_steps_hold_their_value() {
        let points = vec![
            (0.0, 1.0),
            (1.0, 2.0),
            (f64::NAN, 0.0),
            (3.0, 4.0),
            (4.0, 5.0),
        ];
        assert_eq!(
            Series::line("l", points.clone()).runs(),
            vec![vec![(0.0, 1.0), (1.0, 2.0)], vec![(3.0, 4.0), (4.0, 5.0)]]
        );
        assert_eq!(
            Series::steps("s", points).runs(),
            vec![
                vec![(0.0, 1.0), (1.0, 1.0), (1.0, 2.0)],
                vec![(3.0, 4.0), (4.0, 4.0), (4.0, 5.0)]
            ]
        );
        let chart = Chart::new("", Axis::new("x", ""), Axis::new("y", ""))
            .with_series(Series::points("p", vec![(2.0, 3.0), (4.0, 7.0)]));
        let (x, y, y2) = chart.ranges().unwrap();
        assert_eq!((x, y.clone(), y2), (2.0..4.0, 2.8..7.2, y));
        let empty = Chart::new(
            "",
            Axis::new("x", ""),
            Axis::new("y", "").with_range(-1.0, 1.0),
        );
        assert_eq!(empty.ranges().unwrap(), (0.0..1.0, -1.0..1.0, -1.0..1.0));
        let single = Chart::new("", Axis::new("x", ""), Axis::new("y", ""))
            .with_series(Series::points("p", vec![(2.0, 3.0)]));
        assert_eq!(single.ranges().unwrap().0, 1.5..2.5);
        // Every style draws.
        let all = chart
            .with_series(Series::steps("s", vec![(2.0, 3.0), (3.0, 5.0)]))
            .with_series(Series::line("l", vec![(2.0, 7.0), (4.0, 3.0)]));
        let rgb = render_rgb(&all, 300, 200).unwrap();
        for i in 0..3 {
            assert!(
                rgb.chunks_exact(3).any(|p| p == series_colour(i)),
                "series {i}"
            );
        }
    }

    #[test]
    fn ticks_show_the_decimals_their_axis_needs() {
        let days = tick_format(365.0);
        assert_eq!([days(&0.0), days(&50.0), days(&350.0)], ["0", "50", "350"]);
        let unit = tick_format(1.05);
        assert_eq!(
            [unit(&0.1), unit(&0.30000000000000004), unit(&1.0)],
            ["0.1", "0.3", "1"]
        );
        let small = tick_format(0.0088);
        assert_eq!(
            [small(&0.001), small(&-0.0), small(&0.0045)],
            ["0.001", "0", "0.0045"]
        );
    }

    /// Writes example pictures into the temporary folder, to look at:
    /// `cargo test -p morphogen-cli --lib outputs -- --ignored`.
    #[test]
    #[ignore = "writes examples to look at"]
    fn write_examples_to_tmp() {
        let tmp = std::env::temp_dir();
        write_png(&sigmoid(), &tmp.join("charts-sigmoid.png"), 800, 500).unwrap();
        write_svg(&sigmoid(), &tmp.join("charts-sigmoid.svg"), 800, 500).unwrap();
        let f = |t: f64| (t / 10.0).sin();
        let styles = Chart::new("Styles", Axis::new("step", ""), Axis::new("value", "mm"))
            .with_series(Series::points(
                "points",
                (0..40).map(|i| (f64::from(i), f(f64::from(i)))).collect(),
            ))
            .with_series(Series::steps(
                "steps",
                (0..40)
                    .step_by(4)
                    .map(|i| (f64::from(i), 0.5 * f(f64::from(i) + 10.0)))
                    .collect(),
            ))
            .with_series(Series::line(
                "gap",
                vec![
                    (0.0, -1.0),
                    (10.0, -0.5),
                    (f64::NAN, 0.0),
                    (20.0, -0.5),
                    (39.0, -1.0),
                ],
            ));
        write_png(&styles, &tmp.join("charts-styles.png"), 640, 400).unwrap();
    }

    #[test]
    fn bad_charts_are_refused_and_leave_no_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.png");
        let lonely = Chart::new("", Axis::new("x", ""), Axis::new("y", ""))
            .with_series(Series::line("r", vec![(0.0, 1.0)]).on_right());
        let e = write_png(&lonely, &path, 400, 300).unwrap_err();
        assert!(
            format!("{e:#}").contains("\"r\" is on the right axis"),
            "{e:#}"
        );
        let e = write_png(&sigmoid(), &path, 20, 300).unwrap_err();
        assert!(format!("{e:#}").contains("not 20×300"), "{e:#}");
        let reversed = Chart::new(
            "",
            Axis::new("x", "").with_range(1.0, 0.0),
            Axis::new("y", ""),
        );
        let e = write_svg(&reversed, &path, 400, 300).unwrap_err();
        assert!(format!("{e:#}").contains("finite and increasing"), "{e:#}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }
}
