//! Procedural meshes of the thesis's objects (Figs. 4.8–4.19): a
//! watermelon's ellipsoid, a ribbed cactus stem, an amanita cap, a
//! philodendron leaf and a sansevieria leaf, each a grid of `rings` rows
//! by `segments` columns of a parametric surface, in fixed point so that
//! every machine builds the same vertices. z is the axis of the control
//! cylinder (Sec. 3.2.2); leaves lie along y.

use serde::Serialize;

use crate::fx::{Angle, Fx, Real};

/// An object's shape and size (units as the mosaic's domain).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Shape {
    /// An ellipsoid with semi-axes `radii` (x, y, z): a watermelon;
    /// `square` blends it towards the box of the same half sizes (0 to
    /// 0.9: a watermelon grown in a glass box, Fig. 4.18).
    Ellipsoid {
        /// Semi-axes.
        radii: [Fx; 3],
        /// The blend towards the box.
        square: Fx,
    },
    /// A cactus stem: a cylinder of `radius` and `length` along z with
    /// `ribs` ribs of relative `depth`, closed by a dome on top, open below.
    Stem {
        /// Mean radius.
        radius: Fx,
        /// Length of the cylindrical part.
        length: Fx,
        /// Number of ribs.
        ribs: u8,
        /// Rib depth as a share of the radius (0 to 0.5).
        depth: Fx,
    },
    /// A mushroom cap: the top of an ellipsoid of `radius` and `height`,
    /// down to `rim` degrees from the top (open at the rim).
    Cap {
        /// Radius.
        radius: Fx,
        /// Height (semi-axis along z).
        height: Fx,
        /// Angle of the rim from the top, degrees (10 to 170).
        rim: u16,
    },
    /// A leaf of `length` along y and `width`: heart-shaped (philodendron,
    /// `heart`) or a narrow strap (sansevieria), cupped by `cup` (the rise
    /// of its edges as a share of the width).
    Leaf {
        /// Length.
        length: Fx,
        /// Greatest width.
        width: Fx,
        /// Heart-shaped (else a strap).
        heart: bool,
        /// Rise of the edges as a share of the width.
        cup: Fx,
    },
}

/// A shape at a resolution: `rings` rows (along the axis) of `segments`
/// columns (around it, or across a leaf).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Tessellation {
    /// The shape.
    pub shape: Shape,
    /// Rows (2 to 1024).
    pub rings: u16,
    /// Columns (3 to 1024).
    pub segments: u16,
}

/// How a grid's rows close: around (columns wrap) and at its ends.
#[derive(Clone, Copy, Debug)]
struct Topology {
    wrap: bool,
    /// Whether the first and the last row are a single vertex.
    poles: [bool; 2],
}

/// `a·b` of Q16 numbers as Q16 bits (i64).
fn mul(a: i64, b: i64) -> i64 {
    (a * b) >> 16
}

fn sin(a: Angle) -> i64 {
    i64::from(<Fx as Real>::sin(a).to_bits())
}

fn cos(a: Angle) -> i64 {
    i64::from(<Fx as Real>::cos(a).to_bits())
}

/// The angle `num/den` of a half turn.
fn half_turn(num: u32, den: u32) -> Angle {
    Angle::from_turn_ratio(i64::from(num), 2 * i64::from(den.max(1)))
}

impl Tessellation {
    /// Whether the resolution and the sizes are usable.
    #[must_use]
    pub fn is_valid(&self) -> bool {
        let size = |x: Fx| x > Fx::ZERO && x <= Fx::from_int(256);
        let grid = (2..=1024).contains(&self.rings) && (3..=1024).contains(&self.segments);
        grid && match self.shape {
            Shape::Ellipsoid { radii, square } => {
                radii.iter().all(|r| size(*r))
                    && (Fx::ZERO..=Fx::from_ratio(9, 10)).contains(&square)
            }
            Shape::Stem {
                radius,
                length,
                ribs,
                depth,
            } => {
                size(radius)
                    && size(length)
                    && u16::from(ribs) * 4 <= self.segments
                    && (Fx::ZERO..=Fx::from_ratio(1, 2)).contains(&depth)
            }
            Shape::Cap {
                radius,
                height,
                rim,
            } => size(radius) && size(height) && (10..=170).contains(&rim),
            Shape::Leaf {
                length, width, cup, ..
            } => size(length) && size(width) && (Fx::ZERO..=Fx::ONE).contains(&cup),
        }
    }

    fn topology(&self) -> Topology {
        match self.shape {
            Shape::Ellipsoid { .. } => Topology {
                wrap: true,
                poles: [true, true],
            },
            Shape::Stem { .. } | Shape::Cap { .. } => Topology {
                wrap: true,
                poles: [false, true],
            },
            Shape::Leaf { .. } => Topology {
                wrap: false,
                poles: [false, true],
            },
        }
    }

    /// Vertices in row `row`.
    fn row_len(&self, t: Topology, row: u32) -> u32 {
        let last = u32::from(self.rings);
        if (row == 0 && t.poles[0]) || (row == last && t.poles[1]) {
            1
        } else {
            u32::from(self.segments) + u32::from(!t.wrap)
        }
    }

    /// The numbers of vertices and faces.
    #[must_use]
    pub fn counts(&self) -> (usize, usize) {
        let t = self.topology();
        let rows = u32::from(self.rings) + 1;
        let vertices = (0..rows).map(|r| self.row_len(t, r) as usize).sum();
        let quads = u32::from(self.segments);
        let band = |r: u32| {
            let (a, b) = (self.row_len(t, r), self.row_len(t, r + 1));
            if a == 1 || b == 1 {
                quads as usize
            } else {
                2 * quads as usize
            }
        };
        (vertices, (0..rows - 1).map(band).sum())
    }

    /// The point of row `row`, column `col` (Q16 bits).
    fn point(&self, row: u32, col: u32) -> [i64; 3] {
        let (rings, segments) = (u32::from(self.rings), u32::from(self.segments));
        let around = Angle::from_turn_ratio(i64::from(col), i64::from(segments));
        match self.shape {
            Shape::Ellipsoid { radii, square } => {
                let polar = half_turn(row, rings);
                let s = sin(polar);
                let d = [mul(s, cos(around)), mul(s, sin(around)), cos(polar)];
                // The direction's point on the unit cube: d / max |d_k|.
                let most = d.iter().map(|x| x.abs()).max().unwrap_or(1 << 16).max(1);
                let q = i64::from(square.to_bits());
                [0, 1, 2].map(|k| {
                    let boxed = (d[k] << 16) / most;
                    let blend = mul((1 << 16) - q, d[k]) + mul(q, boxed);
                    mul(i64::from(radii[k].to_bits()), blend)
                })
            }
            Shape::Stem {
                radius,
                length,
                ribs,
                depth,
            } => {
                // Rows up the cylinder, then a quarter circle over the dome.
                let dome = (rings / 4).max(1);
                let side = rings - dome;
                let rib = cos(Angle(around.0.wrapping_mul(u32::from(ribs))));
                let r = mul(
                    i64::from(radius.to_bits()),
                    (1 << 16) + mul(i64::from(depth.to_bits()), rib),
                );
                let length = i64::from(length.to_bits());
                let (scale, z) = if row <= side {
                    (1 << 16, length * i64::from(row) / i64::from(side.max(1)))
                } else {
                    let a = half_turn(row - side, 2 * dome);
                    (cos(a), length + mul(i64::from(radius.to_bits()), sin(a)))
                };
                [
                    mul(mul(r, scale), cos(around)),
                    mul(mul(r, scale), sin(around)),
                    z,
                ]
            }
            Shape::Cap {
                radius,
                height,
                rim,
            } => {
                // Row 0 at the rim, the last row at the top.
                let rim = Angle::from_degrees(i32::from(rim));
                let polar =
                    Angle(rim.0 - (u64::from(rim.0) * u64::from(row) / u64::from(rings)) as u32);
                let s = mul(i64::from(radius.to_bits()), sin(polar));
                [
                    mul(s, cos(around)),
                    mul(s, sin(around)),
                    mul(i64::from(height.to_bits()), cos(polar)),
                ]
            }
            Shape::Leaf {
                length,
                width,
                heart,
                cup,
            } => {
                // v from the base (0) to the tip (1); u across, −1 to 1.
                let v = (i64::from(row) << 16) / i64::from(rings);
                let u = (i64::from(col) << 17) / i64::from(segments) - (1 << 16);
                let outline = if heart {
                    // sin(π·(0.15 + 0.85 v)): lobes at the base, a point at the tip.
                    sin(Angle::from_turn_ratio((15 << 16) + 85 * v, 200 << 16))
                } else {
                    // A strap narrowing in its last third: 1 − v⁴.
                    (1 << 16) - mul(mul(v, v), mul(v, v))
                };
                let half = mul(i64::from(width.to_bits()) / 2, outline);
                let across = mul(half, u);
                let rise = mul(mul(i64::from(cup.to_bits()), half), mul(u, u));
                [across, mul(i64::from(length.to_bits()), v), rise]
            }
        }
    }

    /// Writes the vertices (Q16 bits) and faces; the slices must hold
    /// [`Tessellation::counts`] entries (extra ones are left alone).
    /// Returns the numbers written.
    pub fn build(&self, vertices: &mut [[i32; 3]], faces: &mut [[u32; 3]]) -> (usize, usize) {
        let t = self.topology();
        let rows = u32::from(self.rings) + 1;
        let mut nv = 0usize;
        let mut starts = [0u32; 2]; // first vertex of the previous and this row
        let mut nf = 0usize;
        for row in 0..rows {
            let len = self.row_len(t, row);
            starts = [starts[1], nv as u32];
            for col in 0..len {
                if let Some(v) = vertices.get_mut(nv) {
                    *v = self.point(row, col).map(|x| x as i32);
                }
                nv += 1;
            }
            if row == 0 {
                continue;
            }
            let prev = self.row_len(t, row - 1);
            let quads = u32::from(self.segments);
            let (a0, b0) = (starts[0], starts[1]);
            let at = |start: u32, n: u32, c: u32| start + if n == 1 { 0 } else { c % n };
            for c in 0..quads {
                let (a, a1) = (at(a0, prev, c), at(a0, prev, c + 1));
                let (b, b1) = (at(b0, len, c), at(b0, len, c + 1));
                let mut put = |f: [u32; 3]| {
                    if let Some(slot) = faces.get_mut(nf) {
                        *slot = f;
                    }
                    nf += 1;
                };
                if prev == 1 {
                    put([a, b, b1]);
                } else if len == 1 {
                    put([a, b, a1]);
                } else {
                    put([a, b, b1]);
                    put([a, b1, a1]);
                }
            }
        }
        (nv, nf)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mosaic::mesh::{Mesh, MeshParts};

    fn check(t: Tessellation, closed: bool) {
        let (nv, nf) = t.counts();
        let mut v = vec![[0; 3]; nv];
        let mut f = vec![[0; 3]; nf];
        assert_eq!(t.build(&mut v, &mut f), (nv, nf));
        let mut nb = vec![[0; 3]; nf];
        let mut normals = vec![[0; 3]; nf];
        let mut inward = vec![[[0; 3]; 3]; nf];
        let mut edges = vec![0; 3 * nf];
        let parts = MeshParts {
            neighbours: &mut nb,
            normals: &mut normals,
            inward: &mut inward,
            edges: &mut edges,
        };
        let mesh = Mesh::new_checked(&v, &f, parts).expect("a valid mesh");
        assert!(mesh.area_q16() > 0);
        let boundary = nb.iter().flatten().filter(|&&g| g == u32::MAX).count();
        assert_eq!(boundary == 0, closed, "{t:?}: {boundary} boundary edges");
    }

    #[test]
    fn every_shape_is_a_valid_mesh() {
        let f = Fx::from_int;
        check(
            Tessellation {
                shape: Shape::Ellipsoid {
                    radii: [f(10), f(10), f(14)],
                    square: Fx::ZERO,
                },
                rings: 12,
                segments: 16,
            },
            true,
        );
        check(
            Tessellation {
                shape: Shape::Stem {
                    radius: f(5),
                    length: f(30),
                    ribs: 8,
                    depth: Fx::from_ratio(1, 8),
                },
                rings: 20,
                segments: 64,
            },
            false,
        );
        check(
            Tessellation {
                shape: Shape::Cap {
                    radius: f(8),
                    height: f(5),
                    rim: 100,
                },
                rings: 10,
                segments: 32,
            },
            false,
        );
        check(
            Tessellation {
                shape: Shape::Ellipsoid {
                    radii: [f(10); 3],
                    square: Fx::from_ratio(8, 10),
                },
                rings: 16,
                segments: 24,
            },
            true,
        );
        for heart in [true, false] {
            check(
                Tessellation {
                    shape: Shape::Leaf {
                        length: f(20),
                        width: f(12),
                        heart,
                        cup: Fx::from_ratio(1, 5),
                    },
                    rings: 16,
                    segments: 12,
                },
                false,
            );
        }
    }
}
