//! Where model points land on the display: the cabinet projection, the
//! extent of a stream ([`Bounds`]) and the [`View`] that fits it (the
//! module documentation of [`crate::rig`], "The fixed view").

use embedded_graphics::geometry::{Point as Px, Size};
use embedded_graphics::primitives::Rectangle;

use crate::fx::Fx;
use crate::stream::{Record, Sink, SinkError};

/// Sub-pixel resolution of projected points: 1/16 px.
pub(super) const SUBPIXEL_SHIFT: u32 = 4;
/// `k = ½·cos 45° = 0.353553…` of the cabinet projection, as I16F16 bits
/// (0.353553 · 65536 = 23170.5, rounded down).
const CABINET_K_BITS: i64 = 23_170;
/// The widest line drawn, in pixels.
const MAX_LINE_WIDTH: i64 = 64;
/// Beyond any projected coordinate: `|u|, |v| < 2^32` (see [`project`]).
/// A [`Record::Extent`] past it did not come from a projection.
const PROJECTED_LIMIT: i64 = 1 << 33;

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

/// The extent of a stream's projected geometry, for [`View::fit`], and its
/// number of frames. Also a [`Sink`], so a run can be measured without
/// storing it, and sent ahead of the stream as a [`Record::Extent`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bounds {
    min: [i64; 2],
    max: [i64; 2],
    empty: bool,
    only_samples: bool,
    frames: u32,
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
            frames: 0,
        }
    }

    /// The frames seen (their [`Record::FrameEnd`]s).
    #[must_use]
    pub const fn frames(&self) -> u32 {
        self.frames
    }

    /// The [`Record::Extent`] that carries these bounds to a receiver.
    #[must_use]
    pub const fn to_record(&self) -> Record {
        Record::Extent {
            min: self.min,
            max: self.max,
            chart: self.only_samples,
            frames: self.frames,
        }
    }

    /// The bounds a [`Record::Extent`] carries; `None` for another record
    /// or coordinates no projection gives (beyond ±2^33 bits).
    #[must_use]
    pub fn from_record(record: &Record) -> Option<Bounds> {
        let Record::Extent {
            min,
            max,
            chart,
            frames,
        } = *record
        else {
            return None;
        };
        let nothing = min == [i64::MAX; 2] && max == [i64::MIN; 2];
        let projected = |c: &i64| (-PROJECTED_LIMIT..=PROJECTED_LIMIT).contains(c);
        if !nothing && !min.iter().chain(&max).all(projected) {
            return None;
        }
        Some(Bounds {
            min,
            max,
            empty: min[0] > max[0] || min[1] > max[1],
            only_samples: chart,
            frames,
        })
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
            Record::FrameEnd { .. } => self.frames = self.frames.saturating_add(1),
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
    pub(super) fn subpixel(&self, uv: [i64; 2]) -> [i64; 2] {
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
    pub(super) fn pixel(&self, uv: [i64; 2]) -> PixelPos {
        let s = self.subpixel(uv);
        PixelPos(s.map(|c| c >> SUBPIXEL_SHIFT))
    }

    /// `length` model units as whole pixels along x, at least 1.
    pub(super) fn width_px(&self, length: Fx) -> u32 {
        let (num, den) = self.scale[0];
        let px = i64::from(length.to_bits().max(0))
            .saturating_mul(num)
            .div_euclid(den.max(1));
        px.clamp(1, MAX_LINE_WIDTH) as u32
    }
}

/// A pixel position before clipping, in `i64`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct PixelPos(pub(super) [i64; 2]);

impl PixelPos {
    pub(super) fn inside(self, area: &Rectangle) -> Option<Px> {
        let p = self.to_point();
        if area.contains(p) { Some(p) } else { None }
    }

    pub(super) fn to_point(self) -> Px {
        let [x, y] = self
            .0
            .map(|c| c.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32);
        Px::new(x, y)
    }
}
