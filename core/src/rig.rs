//! Display rigs: draws a stream's frames onto any `embedded-graphics`
//! [`DrawTarget`] — a 64×64 RGB LED matrix, a 128×64 OLED, or the host's
//! in-memory framebuffer behind `morphogen run … --rig WxH` — so that the
//! picture on the device and the PNG on the host come from the same code.
//!
//! What is drawn (DESIGN.md, "How data flows"):
//! - [`Record::Segment`]: a line, its width scaled like the model (≥ 1 px),
//!   in ink `colour`;
//! - [`Record::Cell`]: a Voronoi region, as MClone displays its mosaics —
//!   a pixel takes the type colour of the nearest cell of the frame within
//!   [`CELL_REACH_PX`] + ½ px (distances compared in ½ px steps, ties to the cell
//!   that came first; see "Bounded memory");
//! - [`Record::Ring`] and [`Record::Polygon`]: the closed polyline through
//!   the [`Record::Point`]s that follow (rings in the ink of their module);
//! - [`Record::Sample`]: a curve per series, joining successive samples;
//! - a [`Record::Triangle`]: filled in ink 0 when it faces the viewer
//!   (counter-clockwise on the screen as seen from outside), skipped when it
//!   faces away — so a mesh shows as its silhouette, the nearest surfaces
//!   over the farther ones in stream order;
//! - a lone [`Record::Point`] or a [`Record::MeshVertex`]: one pixel;
//! - a [`Record::SurfaceCell`]: one pixel in the ink of its type.
//!
//! Headers are not drawn.
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
//! **Bounded memory.** A [`Rig`] keeps no cells: each cell paints, as it
//! arrives, the pixels within 7½ px ([`CELL_REACH_PX`]) that are nearer to it than
//! to any earlier cell of the frame. What "nearer" needs is kept per pixel
//! in a *cell plane* its owner lends it (½ byte per pixel, [`plane_bytes`]:
//! 4 KiB for a 128×64 OLED, whatever the number of cells): the distance to
//! the nearest cell so far, in ½ px steps. A plane smaller than the target
//! is [`RigError::Capacity`]. The picture is the Voronoi diagram of the
//! cells wherever cells are at most 7 px apart, as on any rig-sized mosaic,
//! and drawing costs O(cells), not O(pixels · cells). In a frame of mesh
//! records the same bytes hold the vertices' pixels (4 bytes each: 1,024
//! vertices for a 128×64 OLED); a triangle naming a vertex that did not
//! fit, or one that has not come, is not filled. Since runs are
//! deterministic, a device can run a preset once into [`Bounds`] to fit the
//! view, and again into the rig (see [`Rig::sink`]).
//!
//! ```
//! use embedded_graphics::mock_display::MockDisplay;
//! use embedded_graphics::pixelcolor::Rgb888;
//! use embedded_graphics::prelude::*;
//! use morphogen::fx::Fx;
//! use morphogen::rig::{Bounds, Rig, View, plane_bytes};
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
//! let mut plane = [0u8; plane_bytes(Size::new(4, 1))];
//! let mut rig = Rig::new(View::fit(&bounds, Size::new(4, 1), 0), &palette, &mut plane);
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
/// How far a cell's colour reaches: to pixel centres less than
/// `CELL_REACH_PX + ½` px away. The cell plane holds distances in ½ px
/// steps, 0 to 14, and 15 for "no cell yet".
pub const CELL_REACH_PX: u32 = 7;
/// The cell plane's distance steps per pixel.
const STEPS_PER_PX: i64 = 2;
const _: () = assert!(NO_CELL as i64 == (2 * CELL_REACH_PX as i64 + 1) * STEPS_PER_PX / 2);
// `step_of` divides d² by 64 = (16 / STEPS_PER_PX)²: 1/16 px positions.
const _: () = assert!(SUBPIXEL_SHIFT == 4 && STEPS_PER_PX == 2);
/// The plane's "no cell within reach" (and the cap of every step).
const NO_CELL: u8 = 15;
/// Bytes of a vertex kept in the plane: its pixel `x`, `y` as `i16`.
const VERTEX_BYTES: usize = 4;

/// What the lent plane holds in the current frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum PlaneUse {
    /// Nothing of this frame yet.
    Stale,
    /// The distance of each pixel to its nearest cell.
    Cells,
    /// The pixels of this many vertices, by id.
    Vertices(u32),
}

/// Squared distances (in (1/16 px)²) ÷ 64 → ½ px steps: `⌊√(d²)/8⌋ =
/// ⌊√⌊d²/64⌋⌋`, tabulated up to the first square that is out of reach.
const STEPS: [u8; (NO_CELL as usize).pow(2)] = {
    let mut table = [0; (NO_CELL as usize).pow(2)];
    let mut i = 0;
    while i < table.len() {
        let mut step = 0;
        while (step + 1) * (step + 1) <= i {
            step += 1;
        }
        table[i] = step as u8;
        i += 1;
    }
    table
};

/// The ½ px step of a squared distance `d2` in (1/16 px)², or [`NO_CELL`]
/// when it is out of reach.
fn step_of(d2: i64) -> u8 {
    usize::try_from(d2 >> 6)
        .ok()
        .and_then(|i| STEPS.get(i))
        .copied()
        .unwrap_or(NO_CELL)
}

/// The bytes of cell plane a rig drawing on a target of `size` needs:
/// one nibble per pixel.
#[must_use]
pub const fn plane_bytes(size: Size) -> usize {
    (size.width as usize * size.height as usize).div_ceil(2)
}

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
            Record::Point { p } | Record::MeshVertex { p, .. } | Record::SurfaceCell { p, .. } => {
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
    /// The cell plane is smaller than the target needs ([`plane_bytes`]).
    Capacity {
        /// The limit's name: `cell plane bytes`.
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
                "the target needs more than the rig's {capacity} {limit}; lend it plane_bytes(size)"
            ),
            RigError::Draw(e) => write!(f, "the display failed: {e:?}"),
        }
    }
}

impl<E: core::fmt::Debug> core::error::Error for RigError<E> {}

/// Draws records onto a [`DrawTarget`] through a fixed [`View`], keeping
/// each pixel's distance to the nearest cell of the frame in a borrowed
/// cell plane for the Voronoi fill. Colours come from
/// `palette` by index (modulo its length); an empty palette draws nothing.
///
/// Each [`Record::FrameStart`] clears the target to `palette[0]` (the
/// background) unless [`Rig::keep_frames`] was called. Everything else is
/// drawn in *ink* `n` — a segment's or polygon's colour, a cell's type, a
/// ring's module, a sample's series, 0 for lone points — which is
/// `palette[1 + n mod (len − 1)]`: never the background, so that nothing
/// drawn disappears (a one-colour palette draws in its colour).
#[derive(Debug)]
pub struct Rig<'p, C> {
    view: View,
    palette: &'p [C],
    clear: bool,
    plane: &'p mut [u8],
    plane_use: PlaneUse,
    run: Option<OpenRun<C>>,
    curves: [Option<PixelPos>; SERIES],
}

impl<'p, C: PixelColor> Rig<'p, C> {
    /// A rig drawing through `view` with `palette`, with a cell `plane` of
    /// at least [`plane_bytes`] of the target's size (its content does not
    /// matter; an empty one will do for streams without cells).
    #[must_use]
    pub const fn new(view: View, palette: &'p [C], plane: &'p mut [u8]) -> Rig<'p, C> {
        Rig {
            view,
            palette,
            clear: true,
            plane,
            plane_use: PlaneUse::Stale,
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

    /// Ink `n` (see the type's documentation).
    fn ink(&self, n: usize) -> Option<C> {
        match self.palette.len() {
            0 => None,
            1 => self.colour(0),
            len => self.colour(1 + n % (len - 1)),
        }
    }

    /// Draws one record (the lines of a ring or polygon close when its last
    /// point arrives).
    ///
    /// # Errors
    /// [`RigError::Capacity`] when a cell arrives and the cell plane is
    /// smaller than the target; [`RigError::Draw`] when the target fails.
    pub fn draw<D>(&mut self, record: &Record, target: &mut D) -> Result<(), RigError<D::Error>>
    where
        D: DrawTarget<Color = C>,
    {
        match record {
            Record::FrameStart { .. } => {
                self.plane_use = PlaneUse::Stale;
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
                if let Some(c) = self.ink(usize::from(*colour)) {
                    let (a, b) = (self.view.pixel(project(*a)), self.view.pixel(project(*b)));
                    let w = self.view.width_px(*width);
                    line(target, a, b, c, w)?;
                }
            }
            Record::Cell { kind, p, .. } => {
                let at = self.view.subpixel(project([p[0], p[1], Fx::ZERO]));
                self.cell(target, at, usize::from(*kind))?;
            }
            Record::Sample { series, x, y } => {
                let here = self.view.pixel(project([*x, *y, Fx::ZERO]));
                let colour = self.ink(usize::from(*series));
                let slot = self.curves.get_mut(usize::from(*series));
                let previous = match slot {
                    Some(slot) => slot.replace(here),
                    None => None,
                };
                if let Some(c) = colour {
                    line(target, previous.unwrap_or(here), here, c, 1)?;
                }
            }
            Record::Ring { module, points, .. } => self.open_run(*points, usize::from(*module)),
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
                    None => self.dot(target, here, 0)?,
                }
            }
            Record::MeshVertex { id, p } => {
                let here = self.view.pixel(project(*p));
                self.keep_vertex(*id, here);
                self.dot(target, here, 0)?;
            }
            Record::Triangle { v } => self.triangle(target, *v)?,
            Record::SurfaceCell { kind, p, .. } => {
                let here = self.view.pixel(project(*p));
                self.dot(target, here, usize::from(*kind))?;
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
        self.run = match (points, self.ink(colour)) {
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
        if let (Some(c), Some(p)) = (self.ink(colour), at.inside(&target.bounding_box())) {
            Pixel(p, c).draw(target).map_err(RigError::Draw)?;
        }
        Ok(())
    }

    /// Keeps vertex `id`'s pixel in the plane when it is the next vertex of
    /// the frame (ids count from 0) and there is room.
    fn keep_vertex(&mut self, id: u32, at: PixelPos) {
        let count = match self.plane_use {
            PlaneUse::Vertices(count) => count,
            _ => 0,
        };
        self.plane_use = PlaneUse::Vertices(count);
        let start = VERTEX_BYTES * count as usize;
        let Some(slot) = self.plane.get_mut(start..start + VERTEX_BYTES) else {
            return;
        };
        if id != count {
            return;
        }
        let [x, y] =
            at.0.map(|c| c.clamp(i64::from(i16::MIN), i64::from(i16::MAX)) as i16);
        slot[..2].copy_from_slice(&x.to_le_bytes());
        slot[2..].copy_from_slice(&y.to_le_bytes());
        self.plane_use = PlaneUse::Vertices(count + 1);
    }

    /// The pixel kept for vertex `id`, if it was.
    fn vertex(&self, id: u32) -> Option<Px> {
        let PlaneUse::Vertices(count) = self.plane_use else {
            return None;
        };
        if id >= count {
            return None;
        }
        let start = VERTEX_BYTES * id as usize;
        let slot = self.plane.get(start..start + VERTEX_BYTES)?;
        let x = i16::from_le_bytes([slot[0], slot[1]]);
        let y = i16::from_le_bytes([slot[2], slot[3]]);
        Some(Px::new(i32::from(x), i32::from(y)))
    }

    /// Fills the triangle of vertices `v` in ink 0 if it faces the viewer.
    fn triangle<D>(&mut self, target: &mut D, v: [u32; 3]) -> Result<(), RigError<D::Error>>
    where
        D: DrawTarget<Color = C>,
    {
        let (Some(a), Some(b), Some(c), Some(ink)) = (
            self.vertex(v[0]),
            self.vertex(v[1]),
            self.vertex(v[2]),
            self.ink(0),
        ) else {
            return Ok(());
        };
        // Counter-clockwise from outside in model space (y up) is clockwise
        // on the screen (y down): a negative cross product. |coordinates|
        // ≤ 2^15, so the products fit in i64.
        let (ab, ac) = (b - a, c - a);
        let cross = i64::from(ab.x) * i64::from(ac.y) - i64::from(ab.y) * i64::from(ac.x);
        if cross >= 0 {
            return Ok(());
        }
        fill_triangle(target, [a, b, c], ink).map_err(RigError::Draw)
    }

    /// Paints the pixels within reach of the cell at `at` (1/16 px) that
    /// are nearer to it than to every earlier cell of the frame, recording
    /// their distance in the plane (the "Bounded memory" of the module).
    fn cell<D>(
        &mut self,
        target: &mut D,
        at: [i64; 2],
        kind: usize,
    ) -> Result<(), RigError<D::Error>>
    where
        D: DrawTarget<Color = C>,
    {
        let area = target.bounding_box();
        let (width, height) = (area.size.width as usize, area.size.height as usize);
        if self.plane.len() < plane_bytes(area.size) {
            return Err(RigError::Capacity {
                limit: "cell plane bytes",
                capacity: u32::try_from(self.plane.len()).unwrap_or(u32::MAX),
            });
        }
        if self.plane_use != PlaneUse::Cells {
            self.plane.fill(NO_CELL << 4 | NO_CELL);
            self.plane_use = PlaneUse::Cells;
        }
        let Some(colour) = self.ink(kind) else {
            return Ok(());
        };
        // Pixel centres are at `16·i + 8` (1/16 px); reach is 15 steps of 8
        // (= (CELL_REACH_PX + ½) · 16).
        let one = 1 << SUBPIXEL_SHIFT;
        let reach = i64::from(NO_CELL) * one / STEPS_PER_PX;
        let origin = [i64::from(area.top_left.x), i64::from(area.top_left.y)];
        let span = |axis: usize, len: usize| {
            let lo = (at[axis] - reach - one / 2).div_euclid(one) + 1;
            let hi = (at[axis] + reach - one / 2).div_euclid(one);
            let first = lo.max(origin[axis]);
            let last = hi.min(origin[axis] + len as i64 - 1);
            first..=last
        };
        let (xs, ys) = (span(0, width), span(1, height));
        let plane = &mut *self.plane;
        let pixels = ys
            .flat_map(|y| xs.clone().map(move |x| (x, y)))
            .filter_map(|(x, y)| {
                let d = [x * one + one / 2 - at[0], y * one + one / 2 - at[1]];
                // |d| < 2^8 inside the spans: the square fits easily.
                let step = step_of(d[0] * d[0] + d[1] * d[1]);
                // Inside the target: 0 ≤ x − origin < width, likewise y.
                let index = (y - origin[1]) as usize * width + (x - origin[0]) as usize;
                let byte = plane.get_mut(index / 2)?;
                let shift = if index.is_multiple_of(2) { 4 } else { 0 };
                // Strictly nearer: ties stay with the earlier cell.
                if step < (*byte >> shift) & 0xF {
                    *byte = (*byte & !(0xF << shift)) | step << shift;
                    Some(Pixel(Px::new(x as i32, y as i32), colour))
                } else {
                    None
                }
            });
        target.draw_iter(pixels).map_err(RigError::Draw)
    }
}

/// Fills the pixels whose centres lie inside triangle `t` (or on a left or
/// top edge: each row's span is half-open), one row at a time, clipped to
/// the target. Hand-written rather than `embedded-graphics`' `Triangle`,
/// whose general scanline code costs 7 KB of flash on a Cortex-M3 for the
/// same picture's worth of work.
fn fill_triangle<D: DrawTarget>(
    target: &mut D,
    t: [Px; 3],
    colour: D::Color,
) -> Result<(), D::Error> {
    let area = target.bounding_box();
    let Some(bottom_right) = area.bottom_right() else {
        return Ok(());
    };
    // Doubled coordinates: pixel (x, y) has its centre at (2x + 1, 2y + 1).
    // The vertices are pixels too: their centres.
    let p = t.map(|q| [2 * i64::from(q.x) + 1, 2 * i64::from(q.y) + 1]);
    let rows = |lo: i64, hi: i64| {
        (
            lo.max(i64::from(area.top_left.y)),
            hi.min(i64::from(bottom_right.y)),
        )
    };
    let (ys, ye) = rows(
        (p.iter().map(|q| q[1]).min().unwrap_or(0) - 1).div_euclid(2),
        (p.iter().map(|q| q[1]).max().unwrap_or(0) - 1).div_euclid(2),
    );
    for y in ys..=ye {
        let centre = 2 * y + 1;
        // Where the row's centre line crosses the edges that span it
        // (each edge half-open in y, so a vertex is counted once).
        let mut span = [i64::MAX, i64::MIN];
        for (a, b) in [(p[0], p[1]), (p[1], p[2]), (p[2], p[0])] {
            let (top, bottom) = if a[1] <= b[1] { (a, b) } else { (b, a) };
            if !(top[1] <= centre && centre < bottom[1]) {
                continue;
            }
            let x =
                top[0] + ((centre - top[1]) * (bottom[0] - top[0])).div_euclid(bottom[1] - top[1]);
            span = [span[0].min(x), span[1].max(x)];
        }
        if span[0] >= span[1] {
            continue;
        }
        // Pixels with centres in [span₀, span₁): 2x + 1 ≥ span₀, < span₁.
        let first = span[0].div_euclid(2).max(i64::from(area.top_left.x));
        let last = (span[1] - 2).div_euclid(2).min(i64::from(bottom_right.x));
        if first > last {
            continue;
        }
        // Inside the target: the casts cannot truncate.
        let row = Rectangle::new(
            Px::new(first as i32, y as i32),
            Size::new((last - first + 1) as u32, 1),
        );
        target.fill_solid(&row, colour)?;
    }
    Ok(())
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

/// An 8-grey palette for 4-bit grey OLEDs (SSD0323, SSD1327): black
/// background, then white and greys spaced so that neighbouring indices
/// (a mosaic's cell types, a body's parts) differ by at least 3 levels.
pub const PALETTE_GRAY4: [embedded_graphics::pixelcolor::Gray4; 8] = {
    use embedded_graphics::pixelcolor::Gray4;
    [
        Gray4::new(0),
        Gray4::new(15),
        Gray4::new(9),
        Gray4::new(5),
        Gray4::new(12),
        Gray4::new(7),
        Gray4::new(3),
        Gray4::new(10),
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
        let mut plane = std::vec![0; plane_bytes(Size::new(w, h))];
        let mut rig = Rig::new(View::fit(&bounds, Size::new(w, h), 0), palette, &mut plane);
        for r in records {
            rig.draw(r, &mut screen).unwrap();
        }
        display
    }

    const RGB: [Rgb888; 4] = [Rgb888::BLACK, Rgb888::RED, Rgb888::GREEN, Rgb888::BLUE];

    #[test]
    fn cells_fill_their_voronoi_regions() {
        // Three cells on an 8×6 screen: red (kind 0: ink 0 is palette[1])
        // top-left, green (1) top-right, blue (2) bottom-centre; y is up in
        // the model.
        let records = [
            Record::FrameStart {
                frame: 0,
                time: Fx::ZERO,
            },
            Record::Cell {
                id: 0,
                kind: 0,
                p: [fx(0), fx(10)],
            },
            Record::Cell {
                id: 1,
                kind: 1,
                p: [fx(14), fx(10)],
            },
            Record::Cell {
                id: 2,
                kind: 2,
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
            // A red diagonal (ink 0), a green square ring (module 1 → ink 1).
            Record::Segment {
                a: [fx(0), fx(0), Fx::ZERO],
                b: [fx(7), fx(7), Fx::ZERO],
                width: Fx::DELTA,
                colour: 0,
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
            // A lone point: ink 0.
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
    fn a_small_cell_plane_is_an_error_naming_the_limit() {
        let mut display = MockDisplay::<Rgb888>::new();
        let mut screen = display.cropped(&Rectangle::new(Px::zero(), Size::new(4, 4)));
        let mut plane = [0; 7];
        let mut rig = Rig::new(View::unit(), &RGB, &mut plane);
        let cell = Record::Cell {
            id: 0,
            kind: 0,
            p: [Fx::ZERO; 2],
        };
        assert_eq!(
            rig.draw(&cell, &mut screen),
            Err(RigError::Capacity {
                limit: "cell plane bytes",
                capacity: 7
            })
        );
    }

    #[test]
    fn cells_reach_seven_pixels_and_no_further() {
        // One cell at the centre of pixel (0, 0) of a 10×1 screen: pixel 7
        // is 7 px away, pixel 8 is 8.
        let records = [
            Record::FrameStart {
                frame: 0,
                time: Fx::ZERO,
            },
            Record::Cell {
                id: 0,
                kind: 0,
                p: [Fx::ZERO; 2],
            },
            Record::FrameEnd { frame: 0 },
        ];
        let mut display = MockDisplay::<Rgb888>::new();
        display.set_allow_overdraw(true);
        let mut screen = display.cropped(&Rectangle::new(Px::zero(), Size::new(10, 1)));
        let mut plane = [0; 5];
        let view = View {
            origin: [-(1 << 15), 1 << 15],
            ..View::unit()
        };
        let mut rig = Rig::new(view, &RGB, &mut plane);
        for r in &records {
            rig.draw(r, &mut screen).unwrap();
        }
        display.assert_pattern(&["RRRRRRRRKK"]);
    }

    #[test]
    fn triangles_facing_the_viewer_are_filled_and_the_others_skipped() {
        let vertex = |id, x, y| Record::MeshVertex {
            id,
            p: [fx(x), fx(y), Fx::ZERO],
        };
        let frame = |v| {
            [
                Record::FrameStart {
                    frame: 0,
                    time: Fx::ZERO,
                },
                vertex(0, 0, 0),
                vertex(1, 5, 0),
                vertex(2, 0, 5),
                Record::Triangle { v },
                Record::FrameEnd { frame: 0 },
            ]
        };
        // Counter-clockwise seen from +z (the viewer): filled in ink 0. (A
        // 6×6 rig's plane holds 18 bytes: 4 vertices.) Pixel centres on the
        // bottom edge and the hypotenuse (a right edge) belong to the
        // neighbours a mesh has there: only the vertices' own pixels show.
        render(&frame([0, 1, 2]), 6, 6, &RGB).assert_pattern(&[
            "RKKKKK", //
            "RKKKKK", //
            "RRKKKK", //
            "RRRKKK", //
            "RRRRKK", //
            "RKKKKR", //
        ]);
        // Clockwise: its back; only the vertices' pixels show.
        render(&frame([0, 2, 1]), 6, 6, &RGB).assert_pattern(&[
            "RKKKKK", //
            "KKKKKK", //
            "KKKKKK", //
            "KKKKKK", //
            "KKKKKK", //
            "RKKKKR", //
        ]);
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
