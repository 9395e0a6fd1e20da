//! A small line-plot canvas on tiny-skia, for curves and side views.

use std::path::Path;

use anyhow::{Context, Result};
use tiny_skia::{Color, Paint, PathBuilder, Pixmap, Stroke, Transform};

/// A plot area mapping data coordinates to pixels, y up.
#[derive(Debug)]
pub struct Plot {
    pixmap: Pixmap,
    x: (f64, f64),
    y: (f64, f64),
    margin: f32,
}

/// An RGB colour.
#[must_use]
pub fn rgb(r: u8, g: u8, b: u8) -> Color {
    Color::from_rgba8(r, g, b, 255)
}

impl Plot {
    /// A white `width × height` canvas showing `x` by `y`.
    ///
    /// # Errors
    /// When the size is zero or too large.
    pub fn new(width: u32, height: u32, x: (f64, f64), y: (f64, f64)) -> Result<Plot> {
        let mut pixmap = Pixmap::new(width, height).context("plot size must be positive")?;
        pixmap.fill(Color::WHITE);
        Ok(Plot {
            pixmap,
            x,
            y,
            margin: 24.0,
        })
    }

    fn to_px(&self, (x, y): (f64, f64)) -> (f32, f32) {
        let w = self.pixmap.width() as f32 - 2.0 * self.margin;
        let h = self.pixmap.height() as f32 - 2.0 * self.margin;
        let fx = ((x - self.x.0) / (self.x.1 - self.x.0)) as f32;
        let fy = ((y - self.y.0) / (self.y.1 - self.y.0)) as f32;
        (self.margin + fx * w, self.margin + (1.0 - fy) * h)
    }

    /// A polyline through `points` in data coordinates.
    pub fn line(&mut self, points: &[(f64, f64)], colour: Color, width: f32) {
        let mut pb = PathBuilder::new();
        for (i, &p) in points.iter().enumerate() {
            let (x, y) = self.to_px(p);
            if i == 0 {
                pb.move_to(x, y)
            } else {
                pb.line_to(x, y)
            }
        }
        let Some(path) = pb.finish() else { return };
        let mut paint = Paint::default();
        paint.set_color(colour);
        paint.anti_alias = true;
        let stroke = Stroke {
            width,
            ..Stroke::default()
        };
        self.pixmap
            .stroke_path(&path, &paint, &stroke, Transform::identity(), None);
    }

    /// Vertical grid lines at `xs` and horizontal ones at `ys`, plus the frame.
    pub fn grid(&mut self, xs: &[f64], ys: &[f64]) {
        let grey = rgb(220, 220, 220);
        for &x in xs {
            self.line(&[(x, self.y.0), (x, self.y.1)], grey, 1.0);
        }
        for &y in ys {
            self.line(&[(self.x.0, y), (self.x.1, y)], grey, 1.0);
        }
        let (x0, x1, y0, y1) = (self.x.0, self.x.1, self.y.0, self.y.1);
        self.line(
            &[(x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0)],
            rgb(90, 90, 90),
            1.0,
        );
    }

    /// Writes the PNG atomically.
    ///
    /// # Errors
    /// When encoding or writing fails.
    pub fn save(&self, path: &Path) -> Result<()> {
        super::picture::save(&self.pixmap, path)
    }
}
