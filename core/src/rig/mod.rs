//! Display rigs: draws a stream's frames onto any `embedded-graphics`
//! [`DrawTarget`] — a 64×64 RGB LED matrix, a 128×64 OLED, or the host's
//! in-memory framebuffer behind `morphogen run … --rig WxH` — so that the
//! picture on the device and the PNG on the host come from the same code.
//!
//! What is drawn (docs/stream-format.md, "What the records mean"):
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
//! view, and again into the rig (see [`Rig::sink`]); it sends the bounds
//! after the header ([`Record::Extent`]) so that a device that only
//! receives the stream can fit the same view: a [`Receiver`].
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
use embedded_graphics::pixelcolor::PixelColor;
use embedded_graphics::prelude::*;

use crate::fx::Fx;
use crate::stream::{Record, Sink, SinkError};

mod plane;
mod raster;
mod receive;
mod view;

pub use plane::{CELL_REACH_PX, plane_bytes};
pub use receive::{FrameDone, Receiver};
pub use view::{Bounds, View, project};

use plane::Plane;
use raster::{fill_triangle, line};
use view::PixelPos;

/// The `embedded-graphics` this renderer draws with (0.8), so that users
/// name the same version.
pub use embedded_graphics;

/// Curves kept per frame ([`Record::Sample`] series `0..SERIES`); samples of
/// higher series are drawn as lone pixels.
pub const SERIES: usize = 8;

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
    plane: Plane<'p>,
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
            plane: Plane::new(plane),
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

    /// Draws through `view` from now on (the next stream's).
    pub const fn set_view(&mut self, view: View) {
        self.view = view;
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
                self.plane.new_frame();
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
                    line(target, a, b, c, w).map_err(RigError::Draw)?;
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
                    line(target, previous.unwrap_or(here), here, c, 1).map_err(RigError::Draw)?;
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
                        line(target, from, here, colour, 1).map_err(RigError::Draw)?;
                        if done {
                            self.run = None;
                            line(target, here, first.unwrap_or(here), colour, 1)
                                .map_err(RigError::Draw)?;
                        }
                    }
                    None => self.dot(target, here, 0)?,
                }
            }
            Record::MeshVertex { id, p } => {
                let here = self.view.pixel(project(*p));
                self.plane.keep_vertex(*id, here);
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

    /// Paints the cell at `at` (1/16 px) of type `kind` through the plane.
    fn cell<D>(
        &mut self,
        target: &mut D,
        at: [i64; 2],
        kind: usize,
    ) -> Result<(), RigError<D::Error>>
    where
        D: DrawTarget<Color = C>,
    {
        if self.plane.len() < plane_bytes(target.bounding_box().size) {
            return Err(RigError::Capacity {
                limit: "cell plane bytes",
                capacity: u32::try_from(self.plane.len()).unwrap_or(u32::MAX),
            });
        }
        match self.ink(kind) {
            Some(colour) => self
                .plane
                .paint_cell(target, at, colour)
                .map_err(RigError::Draw),
            None => Ok(()),
        }
    }

    /// Fills the triangle of vertices `v` in ink 0 if it faces the viewer.
    fn triangle<D>(&mut self, target: &mut D, v: [u32; 3]) -> Result<(), RigError<D::Error>>
    where
        D: DrawTarget<Color = C>,
    {
        let (Some(a), Some(b), Some(c), Some(ink)) = (
            self.plane.vertex(v[0]),
            self.plane.vertex(v[1]),
            self.plane.vertex(v[2]),
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
mod tests;
