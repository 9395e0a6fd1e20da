//! The surface a mosaic's cells live on (MClone thesis Sec. 3.2: the
//! cells grow on the object itself, so the pattern needs no texture
//! mapping): the domain's rectangle, or, when exactly one axis wraps, the
//! cylinder whose side the domain is unrolled from (a cactus stem, a
//! watermelon, Figs. 4.8, 4.16). It gives the cells' 3D positions
//! (`cells_dayNN.csv`), the bare mesh (`surface.obj`), the mosaic
//! coloured on it (`mosaic.obj`, a colour per vertex) and, for a cylinder,
//! a shaded picture of the object (`surface_dayNN.png`, `surface.png`).

use std::f64::consts::TAU;

use anyhow::Result;
use morphogen::fx::Real as _;
use morphogen::mosaic::Domain;
use tiny_skia::{Pixmap, PremultipliedColorU8};

use crate::outputs::mesh::{Mesh, Rgb};
use crate::outputs::picture;
use nalgebra::Vector3;

use crate::outputs::normals::unit;

/// The colour of the mosaic at the fractions (u, v) of the domain's
/// width and height (its Voronoi picture).
pub type Pattern<'a> = &'a dyn Fn(f64, f64) -> Rgb;

/// Quads along the longer side of the coloured mesh: fine enough to show
/// the clones, small enough for an OBJ a viewer opens at once.
const MOSAIC_SIDE: usize = 256;
/// Quads along the longer side of the bare surface.
const SURFACE_SIDE: usize = 64;
/// The picture's height in pixels (drawn at twice the size and halved).
const PICTURE_HEIGHT: f64 = 600.0;
/// The view's elevation above the cylinder's equator, radians.
const ELEVATION: f64 = 0.35;
/// The light's direction (towards the light), normalised when used.
const LIGHT: [f64; 3] = [-0.45, -0.55, 0.7];
/// The picture's background.
const BACKGROUND: Rgb = [246, 244, 238];

/// A mosaic's surface in its domain's units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    size: [f64; 2],
    /// The axis that wraps around a cylinder, if exactly one does.
    wrap: Option<usize>,
}

impl Surface {
    /// The surface of `domain`: a cylinder when one axis is periodic, else
    /// the rectangle (a domain periodic both ways is a flat torus, drawn
    /// flat).
    #[must_use]
    pub fn of(domain: &Domain) -> Surface {
        let size = domain.size.map(f64::from_fx);
        let wrap = match domain.periodic {
            [true, false] => Some(0),
            [false, true] => Some(1),
            _ => None,
        };
        Surface { size, wrap }
    }

    /// The 3D point of the domain position (u, v): (u, v, 0) on the plane;
    /// on a cylinder of circumference `size[a]` around the other axis
    /// (y when u wraps, x when v does), the angle u·2π/size (0 facing +z).
    #[must_use]
    pub fn point(&self, u: f64, v: f64) -> [f64; 3] {
        match self.wrap {
            None => [u, v, 0.0],
            Some(a) => {
                let (around, along) = if a == 0 { (u, v) } else { (v, u) };
                let radius = self.size[a] / TAU;
                let (s, c) = (around / radius).sin_cos();
                if a == 0 {
                    [radius * s, along, radius * c]
                } else {
                    [along, radius * s, radius * c]
                }
            }
        }
    }

    /// A grid of quads over the surface (64 along the longer side), or,
    /// with a `picture`, 256 with each vertex coloured by the picture at
    /// its position.
    ///
    /// # Errors
    /// When the mesh cannot be built (never for these sizes).
    pub fn mesh(&self, picture: Option<Pattern<'_>>) -> Result<Mesh> {
        let long = self.size[0].max(self.size[1]);
        let side = if picture.is_some() {
            MOSAIC_SIDE
        } else {
            SURFACE_SIDE
        };
        let quads = self
            .size
            .map(|s| ((s / long * side as f64).round() as usize).max(1));
        let mut mesh = Mesh::new();
        mesh.set_object(if picture.is_some() {
            "mosaic"
        } else {
            "surface"
        })?;
        for j in 0..=quads[1] {
            for i in 0..=quads[0] {
                let (fu, fv) = (i as f64 / quads[0] as f64, j as f64 / quads[1] as f64);
                let p = self.point(fu * self.size[0], fv * self.size[1]);
                match picture {
                    // The last row and column sample just inside the edge.
                    Some(colour) => mesh.push_coloured_vertex(p, colour(fu, fv))?,
                    None => mesh.push_vertex(p)?,
                };
            }
        }
        let group = mesh.group(None, None)?;
        let row = quads[0] as u32 + 1;
        for j in 0..quads[1] as u32 {
            for i in 0..quads[0] as u32 {
                let a = j * row + i;
                // Counter-clockwise seen from +z (the plane) or from outside
                // the cylinder.
                mesh.push_face(group, &[a, a + 1, a + row + 1, a + row])?;
            }
        }
        Ok(mesh)
    }

    /// The cylinder seen from a little above its equator, shaded, its side
    /// to be coloured by a picture of the domain `pattern` pixels wide and
    /// high (v = 0 at the top, as in the flat pictures); the inside of the
    /// far wall shows through the open top. `None` for a flat surface,
    /// whose picture is the mosaic itself. The same for every day: found
    /// once, painted a day at a time ([`SurfaceView::paint`]).
    ///
    /// # Errors
    /// When the picture cannot be allocated.
    pub fn view(&self, pattern: [usize; 2]) -> Result<Option<SurfaceView>> {
        let Some(a) = self.wrap else {
            return Ok(None);
        };
        let (circumference, height) = (self.size[a], self.size[1 - a]);
        let radius = circumference / TAU;
        let (sin_e, cos_e) = ELEVATION.sin_cos();
        // Orthographic: a screen point (s, w) sees along the view direction;
        // the side's extent on the screen, w = h·cos e ± r·sin e.
        let (w_lo, w_hi) = (-radius * sin_e, height * cos_e + radius * sin_e);
        let scale = 2.0 * PICTURE_HEIGHT / ((w_hi - w_lo) * 1.1);
        let margin = 0.05 * (w_hi - w_lo);
        let width = (((2.0 * radius + 2.0 * margin) * scale).ceil() as u32).max(1);
        let rows = (((w_hi - w_lo + 2.0 * margin) * scale).ceil() as u32).max(1);
        // Refused here, as painting it would be, before a pixel is found.
        if Pixmap::new(width, rows).is_none() {
            anyhow::bail!("a {width}×{rows} picture is too large");
        }
        let light = unit(Vector3::from(LIGHT));
        // What a column sees depends on its screen coordinate s alone: the
        // side's depth there, and on the near side (z = +depth) and the far
        // wall's inside (z = −depth) the angle round the axis and the shade.
        let columns: Vec<Option<[Side; 2]>> = (0..width)
            .map(|i| {
                let s = (f64::from(i) + 0.5) / scale - radius - margin;
                if s.abs() >= radius {
                    return None;
                }
                let depth = (radius * radius - s * s).sqrt();
                let side = |z: f64| {
                    let angle = s.atan2(z).rem_euclid(TAU);
                    // Outward normal (s, 0, z)/r in view space; the inside
                    // faces the other way and gets less light.
                    let n = [s / radius, 0.0, z / radius];
                    let lit = (n[0] * light[0] + n[2] * light[2]).abs();
                    let shade = if z > 0.0 {
                        0.35 + 0.65 * lit
                    } else {
                        0.25 + 0.35 * lit
                    };
                    Side {
                        z,
                        around: angle / TAU,
                        shade,
                    }
                };
                Some([side(depth), side(-depth)])
            })
            .collect();
        let shades = columns
            .iter()
            .flat_map(|sides| sides.map_or([0.0; 2], |sides| sides.map(|s| s.shade)))
            .collect();
        let mut pixels = Vec::with_capacity(columns.len() * rows as usize);
        for row in 0..rows {
            let screen = (f64::from(row) + 0.5) / scale + w_lo - margin;
            pixels.extend(columns.iter().enumerate().map(|(i, column)| {
                // The near side, then the far wall's inside.
                for (k, side) in column.iter().flatten().enumerate() {
                    // Screen rows go down the axis: w = h·cos e + z·sin e.
                    let h = (screen - side.z * sin_e) / cos_e;
                    if !(0.0..height).contains(&h) {
                        continue;
                    }
                    let (fu, fv) = (side.around, h / height);
                    let at = if a == 0 {
                        pattern_pixel(pattern, fu, fv)
                    } else {
                        pattern_pixel(pattern, fv, fu)
                    };
                    return (at as u32, (2 * i + k) as u32);
                }
                SHOWS_NOTHING
            }));
        }
        Ok(Some(SurfaceView {
            width,
            rows,
            pixels,
            shades,
        }))
    }
}

/// What a column of a [`SurfaceView`] sees of one side of the cylinder.
#[derive(Debug, Clone, Copy)]
struct Side {
    /// The side's depth towards the viewer.
    z: f64,
    /// The fraction of the way round the axis.
    around: f64,
    shade: f64,
}

/// The pixel of a picture `size` pixels wide and high at the fractions
/// (`u`, `v`) of its width and height (clamped into it), row by row.
#[must_use]
pub fn pattern_pixel(size: [usize; 2], u: f64, v: f64) -> usize {
    let pixel = |f: f64, n: usize| ((f * n as f64) as usize).min(n.saturating_sub(1));
    pixel(v, size[1]) * size[0] + pixel(u, size[0])
}

/// A pixel of a [`SurfaceView`] that shows no surface.
const SHOWS_NOTHING: (u32, u32) = (u32::MAX, u32::MAX);

/// A cylinder as [`Surface::view`] sees it.
#[derive(Debug, Clone)]
pub struct SurfaceView {
    /// Width and height in pixels (twice the picture's).
    width: u32,
    rows: u32,
    /// Per pixel, row by row: the pattern's pixel it shows and its shade's
    /// index in `shades` ([`SHOWS_NOTHING`]: the background).
    pixels: Vec<(u32, u32)>,
    /// Per column, the shade of its near side and of its far wall.
    shades: Vec<f64>,
}

impl SurfaceView {
    /// The picture, each pixel in the colour of `palette` that `index`
    /// gives the pattern's pixel it shows (black past the palette),
    /// shaded. Each shade of each colour is worked out once.
    ///
    /// # Errors
    /// When the picture cannot be allocated.
    pub fn paint(&self, palette: &[Rgb], index: &dyn Fn(usize) -> u8) -> Result<Pixmap> {
        let mut pixmap = Pixmap::new(self.width, self.rows).ok_or_else(|| {
            anyhow::anyhow!("a {}×{} picture is too large", self.width, self.rows)
        })?;
        let bg = PremultipliedColorU8::from_rgba(BACKGROUND[0], BACKGROUND[1], BACKGROUND[2], 255)
            .unwrap_or(PremultipliedColorU8::TRANSPARENT);
        // Per shade, the palette's colours and black after them.
        let colours = palette.len() + 1;
        let shaded: Vec<PremultipliedColorU8> = self
            .shades
            .iter()
            .flat_map(|&shade| {
                palette.iter().chain([&[0; 3]]).map(move |rgb| {
                    let c = rgb.map(|x| rounded(f64::from(x) * shade));
                    PremultipliedColorU8::from_rgba(c[0], c[1], c[2], 255)
                        .unwrap_or(PremultipliedColorU8::TRANSPARENT)
                })
            })
            .collect();
        for (px, &(at, shade)) in pixmap.pixels_mut().iter_mut().zip(&self.pixels) {
            *px = if at == u32::MAX {
                bg
            } else {
                let k = usize::from(index(at as usize)).min(palette.len());
                shaded[shade as usize * colours + k]
            };
        }
        picture::half(&pixmap)
    }
}

/// `v` (≥ 0) rounded half away from zero, as `f64::round` but without a
/// call to libm, at most 255: `v`'s integer part is exact, and so is what
/// it leaves of `v`.
fn rounded(v: f64) -> u8 {
    let whole = v as u64;
    let up = v - whole as f64 >= 0.5;
    (whole + u64::from(up)).min(255) as u8
}

#[cfg(test)]
mod tests {
    use super::*;
    use morphogen::fx::Fx;

    #[test]
    fn rounding_without_libm_is_f64_round() {
        let mut v: Vec<f64> = (0..=256 * 64).map(|i| f64::from(i) / 64.0).collect();
        // Halves, and the floats either side of them and of 0.5.
        for i in 0..=256 {
            let half = f64::from(i) + 0.5;
            v.extend([half, half.next_down(), half.next_up()]);
        }
        v.extend([0.5f64.next_down(), 0.0, 254.5, 255.49, 300.0, 1e12]);
        for x in v {
            assert_eq!(rounded(x), x.round().clamp(0.0, 255.0) as u8, "{x:e}");
        }
    }

    #[test]
    fn a_cylinder_is_painted_in_shades_of_its_palette_and_black_past_it() {
        let stem = Surface::of(&Domain {
            size: [Fx::from_int(50), Fx::from_int(100)],
            periodic: [true, false],
        });
        let view = stem.view([90, 180]).unwrap().unwrap();
        let bg = BACKGROUND.map(u32::from);
        let painted = |index: u8| {
            let pixmap = view.paint(&[[200, 0, 0]], &|_| index).unwrap();
            pixmap
                .pixels()
                .iter()
                .map(|p| [p.red(), p.green(), p.blue()])
                .filter(|p| p.map(u32::from) != bg)
                .collect::<Vec<_>>()
        };
        let red = painted(0);
        assert!(red.len() > 10_000, "{} pixels show the stem", red.len());
        // Halving averages neighbours, the background's among them at
        // the outline; inside, shades of red only.
        let shades: std::collections::BTreeSet<u8> = red
            .iter()
            .filter(|p| p[1] == 0 && p[2] == 0)
            .map(|p| p[0])
            .collect();
        assert!(shades.len() > 20 && shades.iter().all(|&r| (50..=200).contains(&r)));
        // An index past the palette: black where red was.
        let inside = |p: &&[u8; 3]| p[1] == 0 && p[2] == 0;
        let black = painted(1);
        assert!(black.iter().filter(inside).all(|p| p[0] == 0));
        assert_eq!(
            black.iter().filter(inside).count(),
            red.iter().filter(inside).count()
        );
    }

    #[test]
    fn a_stem_rolls_up_into_a_cylinder_of_its_circumference() {
        let d = Domain {
            size: [Fx::from_int(50), Fx::from_int(100)],
            periodic: [true, false],
        };
        let s = Surface::of(&d);
        assert!(s.wrap.is_some());
        let r = 50.0 / TAU;
        for (u, v) in [(0.0, 0.0), (12.5, 30.0), (37.0, 99.0)] {
            let p = s.point(u, v);
            assert!(((p[0] * p[0] + p[2] * p[2]).sqrt() - r).abs() < 1e-9);
            assert_eq!(p[1], v);
        }
        // A quarter of the way round is a quarter turn.
        let p = s.point(12.5, 0.0);
        assert!((p[0] - r).abs() < 1e-9 && p[2].abs() < 1e-9);
        let flat = Surface::of(&Domain {
            size: [Fx::from_int(10), Fx::from_int(10)],
            periodic: [true, true],
        });
        assert_eq!(flat.point(3.0, 4.0), [3.0, 4.0, 0.0]);
    }
}
