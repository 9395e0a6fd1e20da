//! The frames of a horn stream: each frame's rings, read from its
//! records (horn paper, Sec. 7).

use anyhow::{Context, Result, bail};
use morphogen::fx::Real as _;
use morphogen::stream::Record;
use nalgebra::Vector3;

/// A point in cm.
pub type P3 = Vector3<f64>;

/// One cross-section of a frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Ring {
    /// Module (1 = the tip).
    pub module: u16,
    /// Ring index within the module.
    pub ring: u16,
    /// Its points, cm.
    pub points: Vec<P3>,
}

/// One frame of the horn.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Frame {
    /// Frame index.
    pub index: u32,
    /// Global time, years.
    pub years: f64,
    /// The rings, module 1 first.
    pub rings: Vec<Ring>,
}

/// Groups a horn stream's records into frames, one record at a time.
#[derive(Debug, Default)]
pub struct Framer {
    current: Option<Frame>,
    /// Points the current ring still announces.
    expected: usize,
}

impl Framer {
    /// Takes the next record; returns the frame it ends, if any.
    ///
    /// # Errors
    /// When points arrive outside a ring, a ring is short of points, or
    /// frames do not balance.
    pub fn push(&mut self, r: &Record) -> Result<Option<Frame>> {
        match r {
            Record::FrameStart { frame, time } => {
                if self.current.is_some() {
                    bail!("frame {frame} starts before the previous one ended");
                }
                self.current = Some(Frame {
                    index: *frame,
                    years: f64::from_fx(*time),
                    rings: Vec::new(),
                });
            }
            Record::Ring {
                module,
                ring,
                points,
            } => {
                let f = self.current.as_mut().context("a ring outside a frame")?;
                if self.expected != 0 {
                    bail!(
                        "frame {}: a ring is short of {} points",
                        f.index,
                        self.expected
                    );
                }
                self.expected = usize::from(*points);
                f.rings.push(Ring {
                    module: *module,
                    ring: *ring,
                    points: Vec::with_capacity(self.expected),
                });
            }
            Record::Point { p } => {
                let f = self.current.as_mut().context("a point outside a frame")?;
                let ring = f.rings.last_mut().context("a point before any ring")?;
                if self.expected == 0 {
                    bail!("frame {}: more points than the ring announced", f.index);
                }
                ring.points.push(P3::new(
                    f64::from_fx(p[0]),
                    f64::from_fx(p[1]),
                    f64::from_fx(p[2]),
                ));
                self.expected -= 1;
            }
            Record::FrameEnd { frame } => {
                let f = self
                    .current
                    .take()
                    .context("a frame ends that never started")?;
                if f.index != *frame || self.expected != 0 {
                    bail!("frame {frame} ends unbalanced");
                }
                return Ok(Some(f));
            }
            _ => {}
        }
        Ok(None)
    }

    /// Checks that the stream did not end inside a frame.
    ///
    /// # Errors
    /// When it did.
    pub fn finish(&self) -> Result<()> {
        if self.current.is_some() {
            bail!("the stream ends inside a frame");
        }
        Ok(())
    }
}

/// Groups a horn stream's records into frames.
///
/// # Errors
/// When points arrive outside a ring, a ring is short of points, or frames
/// do not balance.
pub fn frames(records: &[Record]) -> Result<Vec<Frame>> {
    let mut framer = Framer::default();
    let mut out = Vec::new();
    for r in records {
        out.extend(framer.push(r)?);
    }
    framer.finish()?;
    Ok(out)
}
