//! Display rigs: draws a stream's frames onto any `embedded-graphics`
//! [`DrawTarget`] — a 64×64 RGB LED matrix, a 128×64 OLED, or the host's
//! in-memory framebuffer behind `morphogen run … --rig WxH` — so that the
//! picture on the device and the PNG on the host come from the same code.
//!
//! What is drawn (DESIGN.md, "How data flows"):
//! - [`Record::Segment`]: a line, its width scaled like the model (≥ 1 px),
//!   in palette colour `colour`;
//! - [`Record::Cell`]: a Voronoi region — every pixel takes the type colour
//!   of the nearest cell of the frame (nearest in pixel space, ties to the
//!   cell that came first), as MClone displays its mosaics;
//! - [`Record::Ring`] and [`Record::Polygon`]: the closed polyline through
//!   the [`Record::Point`]s that follow (rings in the colour of their module);
//! - [`Record::Sample`]: a curve per series, joining successive samples;
//! - a lone [`Record::Point`] or a [`Record::MeshVertex`]: one pixel.
//!
//! [`Record::Triangle`]s and headers are not drawn.
//!
//! **The fixed view.** Model space is right-handed with y up and z towards
//! the viewer. Points are projected by the *cabinet* oblique projection of
//! technical drawing: `u = x − k·z`, `v = y − k·z` with `k = ½·cos 45°`
//! (depth drawn at half scale, down and to the left). It needs no
//! trigonometry and keeps 2D records (z = 0: cells, samples, flat drawings)
//! exactly as they are. A [`View`] then maps `(u, v)` to pixels, y down;
//! [`View::fit`] makes one from the [`Bounds`] of a stream. Cells are always
//! 2D `(u, v)`.
//!
//! **Bounded memory.** A [`Rig`] keeps the cells of the current frame in
//! storage its owner lends it (a `static` array of [`CellSlot`]s on a
//! device, a `Vec` on a host) — needed for the Voronoi fill, which happens
//! when the first non-cell record or the frame's end arrives — and a few
//! points; a frame with more cells than slots is [`RigError::Capacity`]. Since runs are deterministic,
//! a device can run a preset once into [`Bounds`] to fit the view, and again
//! into the rig (see [`Rig::sink`]).
//!
//! ```
//! use embedded_graphics::mock_display::MockDisplay;
//! use embedded_graphics::pixelcolor::Rgb888;
//! use embedded_graphics::prelude::*;
//! use morphogen::fx::Fx;
//! use morphogen::rig::{Bounds, CellSlot, Rig, View};
//! use morphogen::stream::Record;
//!
//! let records = [
//!     Record::FrameStart { frame: 0, time: Fx::ZERO },
//!     Record::Segment {
//!         a: [Fx::ZERO; 3],
//!         b: [Fx::from_int(3), Fx::ZERO, Fx::ZERO],
//!         width: Fx::DELTA,
//!         colour: 1,
//!     },
//!     Record::FrameEnd { frame: 0 },
//! ];
//! let mut bounds = Bounds::new();
//! records.iter().for_each(|r| bounds.include(r));
//! let mut display = MockDisplay::<Rgb888>::new();
//! display.set_allow_overdraw(true); // the frame start clears first
//! let mut screen = display.cropped(&embedded_graphics::primitives::Rectangle::new(
//!     Point::zero(),
//!     Size::new(4, 1),
//! ));
//! let palette = [Rgb888::WHITE, Rgb888::RED];
//! let mut cells = [CellSlot::EMPTY; 4];
//! let mut rig = Rig::new(View::fit(&bounds, Size::new(4, 1), 0), &palette, &mut cells);
//! for r in &records {
//!     rig.draw(r, &mut screen).unwrap();
//! }
//! display.assert_pattern(&["RRRR"]);
//! ```

use embedded_graphics::Pixel;
use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::geometry::{Point as Px, Size};
use embedded_graphics::pixelcolor::PixelColor;
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::{Line, PrimitiveStyle, Rectangle};

use crate::fx::Fx;
use crate::stream::{Record, Sink, SinkError};

/// The `embedded-graphics` this renderer draws with (0.8), so that users
/// name the same version.
pub use embedded_graphics;

/// Sub-pixel resolution of projected points: 1/16 px.
const SUBPIXEL_SHIFT: u32 = 4;
/// `k = ½·cos 45° = 0.353553…` of the cabinet projection, as I16F16 bits
/// (0.353553 · 65536 = 23170.5, rounded down).
const CABINET_K_BITS: i64 = 23_170;
/// Curves kept per frame ([`Record::Sample`] series `0..SERIES`); samples of
/// higher series are drawn as lone pixels.
pub const SERIES: usize = 8;
/// The widest line drawn, in pixels.
const MAX_LINE_WIDTH: i64 = 64;

/// Projects a model point onto the view plane, in I16F16 bits (see the
/// module documentation for the cabinet projection).
///
/// Range: inputs are `i32` bits, so `|u|, |v| ≤ 2^31 · 1.36 < 2^32` — far
/// inside `i64`.
#[must_use]
pub fn project(p: [Fx; 3]) -> [i64; 2] {
    let [x, y, z] = p.map(|c| i64::from(c.to_bits()));
    // Arithmetic shift = floor division: the same on every target.
    let depth = (z * CABINET_K_BITS) >> 16;
    [x - depth, y - depth]
}

/// The extent of a stream's projected geometry, for [`View::fit`]. Also a
/// [`Sink`], so a run can be measured without storing it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bounds {
    min: [i64; 2],
    max: [i64; 2],
    empty: bool,
    only_samples: bool,
}

impl Default for Bounds {
    fn default() -> Self {
        Bounds::new()
    }
}

impl Bounds {
    /// Nothing seen yet.
    #[must_use]
    pub const fn new() -> Bounds {
        Bounds {
            min: [i64::MAX; 2],
            max: [i64::MIN; 2],
            empty: true,
            only_samples: true,
        }
    }

    /// Whether no drawable record has been seen.
    #[must_use]
    pub const fn is_empty(&self) -> bool {
        self.empty
    }

    /// Lowest and highest projected `(u, v)`, in I16F16 bits.
    #[must_use]
    pub const fn extent(&self) -> Option<([i64; 2], [i64; 2])> {
        if self.empty {
            None
        } else {
            Some((self.min, self.max))
        }
    }

    fn add(&mut self, uv: [i64; 2]) {
        for (axis, value) in uv.into_iter().enumerate() {
            self.min[axis] = self.min[axis].min(value);
            self.max[axis] = self.max[axis].max(value);
        }
        self.empty = false;
    }

    /// Grows the bounds to hold what `record` draws.
    pub fn include(&mut self, record: &Record) {
        match record {
            Record::Segment { a, b, .. } => {
                self.add(project(*a));
                self.add(project(*b));
                self.only_samples = false;
            }
            Record::Point { p } | Record::MeshVertex { p, .. } => {
                self.add(project(*p));
                self.only_samples = false;
            }
            Record::Cell { p, .. } => {
                self.add(project([p[0], p[1], Fx::ZERO]));
                self.only_samples = false;
            }
            Record::Sample { x, y, .. } => self.add(project([*x, *y, Fx::ZERO])),
            _ => {}
        }
    }
}

impl Sink for Bounds {
    fn record(&mut self, record: &Record) -> Result<(), SinkError> {
        self.include(record);
        Ok(())
    }
}

/// Maps projected `(u, v)` (I16F16 bits) to pixels: x right, y down.
///
/// Pixel = `offset + (u − origin_u) · num_x / den_x` (and `(origin_v − v)`
/// for y), computed in 1/16 px with floor division.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct View {
    /// Projected `u` at the left edge and `v` at the top edge, in bits.
    pub origin: [i64; 2],
    /// Pixels per I16F16 bit as `num / den`, per axis (x, y).
    pub scale: [(i64, i64); 2],
    /// Where the origin lands, in 1/16 px.
    pub offset: [i64; 2],
}

impl View {
    /// One pixel per model unit, model origin at the top-left pixel.
    #[must_use]
    pub const fn unit() -> View {
        View {
            origin: [0, 0],
            scale: [(1, 1 << 16), (1, 1 << 16)],
            offset: [0, 0],
        }
    }

    /// The view that shows `bounds` centred on a `size` display, leaving
    /// `margin` pixels on each side. Geometry keeps its aspect ratio; a
    /// stream of [`Record::Sample`]s only (a chart) is stretched to fill
    /// both axes. Empty bounds give [`View::unit`].
    #[must_use]
    pub fn fit(bounds: &Bounds, size: Size, margin: u32) -> View {
        let Some((min, max)) = bounds.extent() else {
            return View::unit();
        };
        // Pixel spans between the first and last usable pixel centres.
        let avail = [size.width, size.height]
            .map(|s| i64::from(s.saturating_sub(1).saturating_sub(margin.saturating_mul(2))));
        let span = [max[0] - min[0], max[1] - min[1]];
        // Per axis, `avail / span` px per bit; a flat axis takes the other's.
        let mut scale = [0, 1].map(|a| (avail[a], span[a].max(1)));
        if !bounds.only_samples {
            // Keep the aspect: the smaller of the two ratios for both axes
            // (compare a/b < c/d as a·d < c·b; all factors < 2^33).
            let [x, y] = scale;
            let smaller = if span[1] == 0 || (span[0] != 0 && x.0 * y.1 <= y.0 * x.1) {
                x
            } else {
                y
            };
            scale = [smaller, smaller];
        }
        // Centre: the drawing is `span · scale` px wide; split the rest.
        let offset = [0, 1].map(|a| {
            let drawn = ((span[a] * scale[a].0) << SUBPIXEL_SHIFT).div_euclid(scale[a].1);
            let total = i64::from([size.width, size.height][a]) << SUBPIXEL_SHIFT;
            // Pixel centres sit at +8/16: the first usable centre is at
            // `margin + ½`, and the rest of the room is split evenly.
            let room = total - (1 << SUBPIXEL_SHIFT) - drawn;
            room / 2 + (1 << (SUBPIXEL_SHIFT - 1))
        });
        View {
            origin: [min[0], max[1]],
            scale,
            offset,
        }
    }

    /// `uv` in 1/16 px.
    fn subpixel(&self, uv: [i64; 2]) -> [i64; 2] {
        let d = [uv[0] - self.origin[0], self.origin[1] - uv[1]];
        [0, 1].map(|a| {
            let (num, den) = self.scale[a];
            // |d| < 2^33 and num ≤ 2^32 in fitted views; saturate beyond.
            let scaled = d[a]
                .saturating_mul(num)
                .saturating_mul(1 << SUBPIXEL_SHIFT)
                .div_euclid(den.max(1));
            scaled.saturating_add(self.offset[a])
        })
    }

    /// The pixel that shows `uv` (saturated to `i32`).
    fn pixel(&self, uv: [i64; 2]) -> PixelPos {
        let s = self.subpixel(uv);
        PixelPos(s.map(|c| c >> SUBPIXEL_SHIFT))
    }

    /// `length` model units as whole pixels along x, at least 1.
    fn width_px(&self, length: Fx) -> u32 {
        let (num, den) = self.scale[0];
        let px = i64::from(length.to_bits().max(0))
            .saturating_mul(num)
            .div_euclid(den.max(1));
        px.clamp(1, MAX_LINE_WIDTH) as u32
    }
}

/// A pixel position before clipping, in `i64`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct PixelPos([i64; 2]);

impl PixelPos {
    fn inside(self, area: &Rectangle) -> Option<Px> {
        let p = self.to_point();
        if area.contains(p) { Some(p) } else { None }
    }

    fn to_point(self) -> Px {
        let [x, y] = self
            .0
            .map(|c| c.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32);
        Px::new(x, y)
    }
}

/// Room for one cell of a frame, kept for the Voronoi fill (its position
/// in 1/16 px and its type): 24 bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CellSlot {
    at: [i64; 2],
    kind: u8,
}

impl CellSlot {
    /// An unused slot, to fill a (`static`) array with.
    pub const EMPTY: CellSlot = CellSlot {
        at: [0; 2],
        kind: 0,
    };
}

/// The polyline of a ring or polygon whose points are still arriving.
#[derive(Clone, Copy, Debug)]
struct OpenRun<C> {
    remaining: u16,
    colour: C,
    first: Option<PixelPos>,
    last: Option<PixelPos>,
}

/// Why a record could not be drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum RigError<E> {
    /// A frame holds more cells than the rig has [`CellSlot`]s.
    Capacity {
        /// The limit's name: `cell slots`.
        limit: &'static str,
        /// Its value.
        capacity: u32,
    },
    /// The draw target failed.
    Draw(E),
}

impl<E: core::fmt::Debug> core::fmt::Display for RigError<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            RigError::Capacity { limit, capacity } => write!(
                f,
                "a frame has more cells than the rig's {capacity} {limit}; lend it more"
            ),
            RigError::Draw(e) => write!(f, "the display failed: {e:?}"),
        }
    }
}

impl<E: core::fmt::Debug> core::error::Error for RigError<E> {}

/// Draws records onto a [`DrawTarget`] through a fixed [`View`], keeping
/// the cells of a frame in borrowed [`CellSlot`]s for the Voronoi fill. Colours come from
/// `palette` by index (modulo its length); an empty palette draws nothing.
///
/// Each [`Record::FrameStart`] clears the target to `palette[0]` (the
/// background) unless [`Rig::keep_frames`] was called.
#[derive(Debug)]
pub struct Rig<'p, C> {
    view: View,
    palette: &'p [C],
    clear: bool,
    cells: &'p mut [CellSlot],
    cell_count: usize,
    run: Option<OpenRun<C>>,
    curves: [Option<PixelPos>; SERIES],
}

impl<'p, C: PixelColor> Rig<'p, C> {
    /// A rig drawing through `view` with `palette`, keeping up to
    /// `cells.len()` cells of a frame.
    #[must_use]
    pub const fn new(view: View, palette: &'p [C], cells: &'p mut [CellSlot]) -> Rig<'p, C> {
        Rig {
            view,
            palette,
            clear: true,
            cells,
            cell_count: 0,
            run: None,
            curves: [None; SERIES],
        }
    }

    /// Draws each frame over the previous one instead of clearing.
    #[must_use]
    pub const fn keep_frames(mut self) -> Rig<'p, C> {
        self.clear = false;
        self
    }

    /// The view.
    #[must_use]
    pub const fn view(&self) -> &View {
        &self.view
    }

    fn colour(&self, index: usize) -> Option<C> {
        match self.palette.len() {
            0 => None,
            len => self.palette.get(index % len).copied(),
        }
    }

    /// Draws one record (some records take effect later: cells when the
    /// frame's cells end, ring points when the ring is complete).
    ///
    /// # Errors
    /// [`RigError::Capacity`] when a frame has more cells than slots;
    /// [`RigError::Draw`] when the target fails.
    pub fn draw<D>(&mut self, record: &Record, target: &mut D) -> Result<(), RigError<D::Error>>
    where
        D: DrawTarget<Color = C>,
    {
        if !matches!(record, Record::Cell { .. }) {
            self.fill_cells(target)?;
        }
        match record {
            Record::FrameStart { .. } => {
                self.run = None;
                self.curves = [None; SERIES];
                if let (true, Some(background)) = (self.clear, self.colour(0)) {
                    target.clear(background).map_err(RigError::Draw)?;
                }
            }
            Record::FrameEnd { .. } => {
                self.run = None;
            }
            Record::Segment {
                a,
                b,
                width,
                colour,
            } => {
                if let Some(c) = self.colour(usize::from(*colour)) {
                    let (a, b) = (self.view.pixel(project(*a)), self.view.pixel(project(*b)));
                    let w = self.view.width_px(*width);
                    line(target, a, b, c, w)?;
                }
            }
            Record::Cell { kind, p, .. } => {
                let at = self.view.subpixel(project([p[0], p[1], Fx::ZERO]));
                let Some(slot) = self.cells.get_mut(self.cell_count) else {
                    return Err(RigError::Capacity {
                        limit: "cell slots",
                        capacity: u32::try_from(self.cells.len()).unwrap_or(u32::MAX),
                    });
                };
                *slot = CellSlot { at, kind: *kind };
                self.cell_count += 1;
            }
            Record::Sample { series, x, y } => {
                let here = self.view.pixel(project([*x, *y, Fx::ZERO]));
                let colour = self.colour(usize::from(*series) + 1);
                let slot = self.curves.get_mut(usize::from(*series));
                let previous = match slot {
                    Some(slot) => slot.replace(here),
                    None => None,
                };
                if let Some(c) = colour {
                    line(target, previous.unwrap_or(here), here, c, 1)?;
                }
            }
            Record::Ring { module, points, .. } => self.open_run(*points, usize::from(*module) + 1),
            Record::Polygon { vertices, colour } => {
                self.open_run(*vertices, usize::from(*colour));
            }
            Record::Point { p } => {
                let here = self.view.pixel(project(*p));
                match self.run.as_mut() {
                    Some(run) => {
                        let from = run.last.unwrap_or(here);
                        run.first.get_or_insert(here);
                        run.last = Some(here);
                        run.remaining = run.remaining.saturating_sub(1);
                        let (colour, done, first) = (run.colour, run.remaining == 0, run.first);
                        line(target, from, here, colour, 1)?;
                        if done {
                            self.run = None;
                            line(target, here, first.unwrap_or(here), colour, 1)?;
                        }
                    }
                    None => self.dot(target, here, 1)?,
                }
            }
            Record::MeshVertex { p, .. } => {
                let here = self.view.pixel(project(*p));
                self.dot(target, here, 1)?;
            }
            _ => {}
        }
        Ok(())
    }

    /// A sink that draws every record onto `target`; a drawing failure
    /// becomes [`SinkError::Write`] (and a full cell buffer too).
    pub fn sink<'a, D>(&'a mut self, target: &'a mut D) -> RigSink<'a, 'p, C, D>
    where
        D: DrawTarget<Color = C>,
    {
        RigSink { rig: self, target }
    }

    fn open_run(&mut self, points: u16, colour: usize) {
        self.run = match (points, self.colour(colour)) {
            (1.., Some(colour)) => Some(OpenRun {
                remaining: points,
                colour,
                first: None,
                last: None,
            }),
            _ => None,
        };
    }

    fn dot<D>(&self, target: &mut D, at: PixelPos, colour: usize) -> Result<(), RigError<D::Error>>
    where
        D: DrawTarget<Color = C>,
    {
        if let (Some(c), Some(p)) = (self.colour(colour), at.inside(&target.bounding_box())) {
            Pixel(p, c).draw(target).map_err(RigError::Draw)?;
        }
        Ok(())
    }

    /// Paints the Voronoi regions of the cells kept so far, then forgets
    /// them. O(pixels · cells): 64×64 px and 1 000 cells is 4 M distance
    /// evaluations.
    fn fill_cells<D>(&mut self, target: &mut D) -> Result<(), RigError<D::Error>>
    where
        D: DrawTarget<Color = C>,
    {
        if self.cell_count == 0 {
            return Ok(());
        }
        let area = target.bounding_box();
        let cells = self.cells.get(..self.cell_count).unwrap_or(&[]);
        let palette = self.palette;
        let colours = area.points().map(|p| {
            let centre = [p.x, p.y].map(|c| (i64::from(c) << SUBPIXEL_SHIFT) + 8);
            let mut best = (i64::MAX, 0u8);
            for cell in cells {
                let dx = cell.at[0].saturating_sub(centre[0]);
                let dy = cell.at[1].saturating_sub(centre[1]);
                let d2 = dx.saturating_mul(dx).saturating_add(dy.saturating_mul(dy));
                // Strictly closer: ties go to the cell that came first.
                if d2 < best.0 {
                    best = (d2, cell.kind);
                }
            }
            match palette.len() {
                0 => None,
                len => palette.get(usize::from(best.1) % len).copied(),
            }
        });
        let result = match self.colour(0) {
            Some(background) => {
                target.fill_contiguous(&area, colours.map(|c| c.unwrap_or(background)))
            }
            None => Ok(()),
        };
        self.cell_count = 0;
        result.map_err(RigError::Draw)
    }
}

/// Draws a line of width `w` from `a` to `b`, clipped to the target first
/// so that far-away endpoints cost no more than visible ones.
fn line<D: DrawTarget>(
    target: &mut D,
    a: PixelPos,
    b: PixelPos,
    colour: D::Color,
    w: u32,
) -> Result<(), RigError<D::Error>> {
    let area = target.bounding_box();
    // Wide lines may start just outside and still reach in.
    let pad = i64::from(w / 2);
    let lo = [
        i64::from(area.top_left.x) - pad,
        i64::from(area.top_left.y) - pad,
    ];
    // Inclusive: the last pixel is at `top_left + size − 1`.
    let hi = [
        lo[0] + i64::from(area.size.width) - 1 + 2 * pad,
        lo[1] + i64::from(area.size.height) - 1 + 2 * pad,
    ];
    let Some((a, b)) = clip(a.0, b.0, lo, hi) else {
        return Ok(());
    };
    Line::new(PixelPos(a).to_point(), PixelPos(b).to_point())
        .into_styled(PrimitiveStyle::with_stroke(colour, w))
        .draw(target)
        .map_err(RigError::Draw)
}

/// Cohen–Sutherland clipping of segment `a`–`b` to the box `lo..=hi`, in
/// integers (intersections rounded towards zero; the box is a guard band,
/// so rounding never shows). `None` when the segment misses the box.
fn clip(
    mut a: [i64; 2],
    mut b: [i64; 2],
    lo: [i64; 2],
    hi: [i64; 2],
) -> Option<([i64; 2], [i64; 2])> {
    let code = |p: [i64; 2]| -> u8 {
        u8::from(p[0] < lo[0])
            | u8::from(p[0] > hi[0]) << 1
            | u8::from(p[1] < lo[1]) << 2
            | u8::from(p[1] > hi[1]) << 3
    };
    // Each pass moves one endpoint onto a box edge: at most 4 per endpoint.
    for _ in 0..8 {
        let (ca, cb) = (code(a), code(b));
        if ca | cb == 0 {
            return Some((a, b));
        }
        if ca & cb != 0 {
            return None;
        }
        let (out, from, to) = if ca != 0 { (ca, a, b) } else { (cb, b, a) };
        // Intersect with the first violated edge; i128 keeps products exact.
        let (axis, edge) = match out {
            o if o & 1 != 0 => (0, lo[0]),
            o if o & 2 != 0 => (0, hi[0]),
            o if o & 4 != 0 => (1, lo[1]),
            _ => (1, hi[1]),
        };
        let other = 1 - axis;
        let t_num = i128::from(edge - from[axis]);
        let t_den = i128::from(to[axis] - from[axis]);
        if t_den == 0 {
            return None;
        }
        let moved = i128::from(from[other]) + i128::from(to[other] - from[other]) * t_num / t_den;
        let mut q = [0; 2];
        q[axis] = edge;
        q[other] = i64::try_from(moved).unwrap_or(if moved < 0 { i64::MIN } else { i64::MAX });
        if ca != 0 {
            a = q;
        } else {
            b = q;
        }
    }
    None
}

/// A [`Sink`] that draws onto a target (see [`Rig::sink`]).
#[derive(Debug)]
pub struct RigSink<'a, 'p, C, D> {
    rig: &'a mut Rig<'p, C>,
    target: &'a mut D,
}

impl<C: PixelColor, D: DrawTarget<Color = C>> Sink for RigSink<'_, '_, C, D> {
    fn record(&mut self, record: &Record) -> Result<(), SinkError> {
        self.rig
            .draw(record, self.target)
            .map_err(|_| SinkError::Write)
    }
}

/// An 8-colour palette for RGB rigs: black background, then white, red,
/// green, blue, yellow, magenta, cyan.
pub const PALETTE_RGB888: [embedded_graphics::pixelcolor::Rgb888; 8] = {
    use embedded_graphics::pixelcolor::Rgb888;
    [
        Rgb888::BLACK,
        Rgb888::WHITE,
        Rgb888::RED,
        Rgb888::GREEN,
        Rgb888::BLUE,
        Rgb888::YELLOW,
        Rgb888::MAGENTA,
        Rgb888::CYAN,
    ]
};

#[cfg(test)]
mod tests {
    use embedded_graphics::mock_display::MockDisplay;
    use embedded_graphics::pixelcolor::Rgb888;

    use super::*;

    fn fx(n: i32) -> Fx {
        Fx::from_int(n)
    }

    /// Draws `records` on a `w`×`h` crop of a mock display with a view fitted
    /// to them and `palette`.
    fn render(records: &[Record], w: u32, h: u32, palette: &[Rgb888]) -> MockDisplay<Rgb888> {
        let mut bounds = Bounds::new();
        records.iter().for_each(|r| bounds.include(r));
        let mut display = MockDisplay::new();
        display.set_allow_overdraw(true);
        let mut screen = display.cropped(&Rectangle::new(Px::zero(), Size::new(w, h)));
        let mut cells = [CellSlot::EMPTY; 8];
        let mut rig = Rig::new(View::fit(&bounds, Size::new(w, h), 0), palette, &mut cells);
        for r in records {
            rig.draw(r, &mut screen).unwrap();
        }
        display
    }

    const RGB: [Rgb888; 4] = [Rgb888::BLACK, Rgb888::RED, Rgb888::GREEN, Rgb888::BLUE];

    #[test]
    fn cells_fill_their_voronoi_regions() {
        // Three cells on an 8×6 screen: red (kind 1) top-left, green (2)
        // top-right, blue (3) bottom-centre; y is up in the model.
        let records = [
            Record::FrameStart {
                frame: 0,
                time: Fx::ZERO,
            },
            Record::Cell {
                id: 0,
                kind: 1,
                p: [fx(0), fx(10)],
            },
            Record::Cell {
                id: 1,
                kind: 2,
                p: [fx(14), fx(10)],
            },
            Record::Cell {
                id: 2,
                kind: 3,
                p: [fx(7), fx(0)],
            },
            Record::FrameEnd { frame: 0 },
        ];
        render(&records, 8, 6, &RGB).assert_pattern(&[
            "RRRRGGGG", //
            "RRRRGGGG", //
            "RRRBBGGG", //
            "RRBBBBGG", //
            "BBBBBBBB", //
            "BBBBBBBB", //
        ]);
    }

    #[test]
    fn segments_rings_and_points_are_lines_and_pixels() {
        let p = |x, y| Record::Point {
            p: [fx(x), fx(y), Fx::ZERO],
        };
        let records = [
            Record::FrameStart {
                frame: 0,
                time: Fx::ZERO,
            },
            // A red diagonal, a green square ring (module 1 → colour 2).
            Record::Segment {
                a: [fx(0), fx(0), Fx::ZERO],
                b: [fx(7), fx(7), Fx::ZERO],
                width: Fx::DELTA,
                colour: 1,
            },
            Record::Ring {
                module: 1,
                ring: 0,
                points: 4,
            },
            p(4, 1),
            p(6, 1),
            p(6, 3),
            p(4, 3),
            // A lone point: colour 1.
            p(1, 6),
            Record::FrameEnd { frame: 0 },
        ];
        render(&records, 8, 8, &RGB).assert_pattern(&[
            "KKKKKKKR", //
            "KRKKKKRK", //
            "KKKKKRKK", //
            "KKKKRKKK", //
            "KKKRGGGK", //
            "KKRKGKGK", //
            "KRKKGGGK", //
            "RKKKKKKK", //
        ]);
    }

    #[test]
    fn depth_is_drawn_down_and_left_at_half_scale() {
        // z = 4 moves a point by −k·4 = −1.41 on both axes.
        assert_eq!(
            project([fx(2), fx(2), fx(4)]),
            [(2 << 16) - 92_680, (2 << 16) - 92_680]
        );
        assert_eq!(project([fx(2), fx(-3), Fx::ZERO]), [2 << 16, -3 << 16]);
    }

    #[test]
    fn samples_are_stretched_into_curves() {
        // Series 0 rises over x = 0..=30 while y goes 0..=1: a chart fills
        // the screen on both axes despite the 30:1 aspect.
        let mut records = std::vec![Record::FrameStart {
            frame: 0,
            time: Fx::ZERO
        }];
        for x in 0..=30 {
            records.push(Record::Sample {
                series: 0,
                x: fx(x),
                y: Fx::from_ratio(x, 30),
            });
        }
        render(&records, 4, 4, &RGB).assert_pattern(&[
            "KKKR", //
            "KKRR", //
            "KRRK", //
            "RKKK", //
        ]);
    }

    #[test]
    fn too_many_cells_is_an_error_naming_the_limit() {
        let mut display = MockDisplay::<Rgb888>::new();
        let mut cells = [CellSlot::EMPTY; 2];
        let mut rig = Rig::new(View::unit(), &RGB, &mut cells);
        for id in 0..2 {
            let cell = Record::Cell {
                id,
                kind: 0,
                p: [Fx::ZERO; 2],
            };
            rig.draw(&cell, &mut display).unwrap();
        }
        let third = Record::Cell {
            id: 2,
            kind: 0,
            p: [Fx::ZERO; 2],
        };
        assert_eq!(
            rig.draw(&third, &mut display),
            Err(RigError::Capacity {
                limit: "cell slots",
                capacity: 2
            })
        );
    }

    #[test]
    fn far_away_lines_are_clipped_not_walked() {
        assert_eq!(
            clip([-1_000_000_000, 5], [1_000_000_000, 5], [0, 0], [9, 9]),
            Some(([0, 5], [9, 5]))
        );
        assert_eq!(clip([-50, -50], [-10, -40], [0, 0], [9, 9]), None);
        let mut display = MockDisplay::<Rgb888>::new();
        let mut screen = display.cropped(&Rectangle::new(Px::zero(), Size::new(3, 1)));
        line(
            &mut screen,
            PixelPos([i64::MIN / 2, 0]),
            PixelPos([i64::MAX / 2, 0]),
            Rgb888::RED,
            1,
        )
        .unwrap();
        display.assert_pattern(&["RRR"]);
    }
}
