//! Drawing a stream as it arrives on a wire (docs/stream-format.md,
//! "Drawing what arrives"): the view comes from the [`Record::Extent`]
//! that follows the header, and a frame is shown whole or not at all — a
//! frame with a damaged record, or whose start or end was lost, is
//! skipped, so that the display keeps the last good one.

use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::geometry::Size;
use embedded_graphics::pixelcolor::PixelColor;

use super::{Bounds, Rig, RigError, View};
use crate::stream::{FrameError, Record};

/// A frame that has ended, shown or not.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FrameDone {
    /// Its index.
    pub frame: u32,
    /// Whether the target now holds all of it, to be shown (a skipped
    /// frame leaves the target part-drawn: show the previous one).
    pub shown: bool,
    /// Whether it is the stream's last frame (by its extent).
    pub last: bool,
}

/// Where the receiver is in the stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Place {
    /// Between frames.
    Between,
    /// Right after a header: the extent may come.
    AfterHeader,
    /// Inside frame `frame`; `intact` while every frame of it was read.
    Drawing { frame: u32, intact: bool },
}

/// Draws the frames of received streams through a [`Rig`] fitted to each
/// stream's [`Record::Extent`], one frame at a time, each whole or not at
/// all.
///
/// ```
/// use embedded_graphics::mock_display::MockDisplay;
/// use embedded_graphics::pixelcolor::BinaryColor;
/// use embedded_graphics::prelude::*;
/// use morphogen::fx::Fx;
/// use morphogen::rig::{Bounds, Receiver, plane_bytes};
/// use morphogen::stream::{Encoder, FrameError, Header, Reader, Record, Sink};
///
/// let frame = [
///     Record::FrameStart { frame: 0, time: Fx::ZERO },
///     Record::Point { p: [Fx::ZERO; 3] },
///     Record::FrameEnd { frame: 0 },
/// ];
/// let mut bounds = Bounds::new();
/// frame.iter().for_each(|r| bounds.include(r));
/// let header = Record::Header(Header {
///     version: 1,
///     preset: "dot".try_into().unwrap(),
///     seed: 0,
///     params: 0,
/// });
/// // What a sender writes: the header, the extent, the frames.
/// let mut wire = Encoder::new(Vec::new());
/// for r in [header, bounds.to_record()].iter().chain(&frame) {
///     wire.record(r).unwrap();
/// }
///
/// let palette = [BinaryColor::Off, BinaryColor::On];
/// let mut plane = [0u8; plane_bytes(Size::new(3, 3))];
/// let mut receiver = Receiver::new(Size::new(3, 3), 1, &palette, &mut plane);
/// let mut display = MockDisplay::new();
/// display.set_allow_overdraw(true);
/// let mut reader = Reader::new();
/// let mut done = Vec::new();
/// for &byte in &wire.into_writer() {
///     if let Some(frame) = reader.push(byte) {
///         done.extend(receiver.take(&frame, &mut display).unwrap());
///     }
/// }
/// assert!(done[0].shown && done[0].last);
/// ```
#[derive(Debug)]
pub struct Receiver<'p, C> {
    rig: Rig<'p, C>,
    size: Size,
    margin: u32,
    /// The frames of the stream, once its extent has come.
    frames: Option<u32>,
    place: Place,
}

impl<'p, C: PixelColor> Receiver<'p, C> {
    /// A receiver for a `size` display, fitting each stream's extent with
    /// `margin` pixels each side, drawing with `palette` and a cell `plane`
    /// of at least [`super::plane_bytes`]`(size)` (as [`Rig::new`]).
    #[must_use]
    pub const fn new(size: Size, margin: u32, palette: &'p [C], plane: &'p mut [u8]) -> Self {
        Receiver {
            rig: Rig::new(View::unit(), palette, plane),
            size,
            margin,
            frames: None,
            place: Place::Between,
        }
    }

    /// Whether the stream in progress came with its extent (without it,
    /// every frame is skipped: the view is unknown).
    #[must_use]
    pub const fn fitted(&self) -> bool {
        self.frames.is_some()
    }

    /// Takes what the [`crate::stream::Reader`] made of one frame. Returns
    /// the frame that ended, if one did: at its [`Record::FrameEnd`], or
    /// (not shown) when the next frame or stream starts without it.
    ///
    /// # Errors
    /// As [`Rig::draw`]: a cell plane smaller than the target, or a failed
    /// target.
    pub fn take<D>(
        &mut self,
        frame: &Result<Record, FrameError>,
        target: &mut D,
    ) -> Result<Option<FrameDone>, RigError<D::Error>>
    where
        D: DrawTarget<Color = C>,
    {
        let record = match frame {
            Ok(record) => record,
            Err(e) if e.is_corrupt() => {
                self.place = match self.place {
                    Place::Drawing { frame, .. } => Place::Drawing {
                        frame,
                        intact: false,
                    },
                    Place::Between | Place::AfterHeader => Place::Between,
                };
                return Ok(None);
            }
            // A newer kind of record: nothing this receiver draws.
            Err(_) => return Ok(None),
        };
        let after_header = self.place == Place::AfterHeader;
        if after_header {
            self.place = Place::Between;
        }
        match record {
            Record::Header(_) => {
                let lost = self.abandon();
                self.frames = None;
                self.place = Place::AfterHeader;
                Ok(lost)
            }
            Record::Extent { .. } => {
                // Only right after its header: otherwise whose is it?
                if let (true, Some(bounds)) = (after_header, Bounds::from_record(record)) {
                    self.rig
                        .set_view(View::fit(&bounds, self.size, self.margin));
                    self.frames = Some(bounds.frames());
                }
                Ok(None)
            }
            Record::FrameStart { frame, .. } => {
                let lost = self.abandon();
                let intact = self.fitted();
                if intact {
                    self.rig.draw(record, target)?;
                }
                self.place = Place::Drawing {
                    frame: *frame,
                    intact,
                };
                Ok(lost)
            }
            Record::FrameEnd { frame } => {
                let shown = self.place
                    == Place::Drawing {
                        frame: *frame,
                        intact: true,
                    };
                if shown {
                    self.rig.draw(record, target)?;
                }
                self.place = Place::Between;
                Ok(Some(self.done(*frame, shown)))
            }
            _ => {
                if let Place::Drawing { intact: true, .. } = self.place {
                    self.rig.draw(record, target)?;
                }
                Ok(None)
            }
        }
    }

    /// The frame in progress, lost: its end did not come.
    fn abandon(&mut self) -> Option<FrameDone> {
        match core::mem::replace(&mut self.place, Place::Between) {
            Place::Drawing { frame, .. } => Some(self.done(frame, false)),
            Place::Between | Place::AfterHeader => None,
        }
    }

    fn done(&self, frame: u32, shown: bool) -> FrameDone {
        FrameDone {
            frame,
            shown,
            last: self.frames.is_some_and(|n| frame.checked_add(1) == Some(n)),
        }
    }
}
