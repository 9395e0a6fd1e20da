//! The polygonal body the cylinders deform (growth paper, Sec. 2): either a procedural mesh of
//! tubes generated vertex by vertex on the fly (the built-in quadrupeds, no
//! RAM beyond a few scalars), or an indexed triangle mesh borrowed from the
//! caller (an OBJ file on the host).
//!
//! A tube is a sequence of elliptic rings along a polyline of stations in a
//! side plane (z constant): ring k of a station is centre + h·cos φ·up +
//! w·sin φ·ẑ with φ = k/sides of a turn, `up = ẑ × tangent`. Its layout is
//! `[start cap, ring 0, …, ring S−1, end cap]`, triangles counter-clockwise
//! seen from outside: a fan at each end and two per quad.

use nalgebra::Vector3;
use serde::Serialize;
use serde::ser::{SerializeStruct, Serializer};

use super::BodyError;
use super::cylinder::{norm, point};
use crate::fx::{Angle, Fx, Real};

/// One ring of a tube.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Station {
    /// Centre, model space.
    pub centre: [Fx; 3],
    /// Half size in the side plane, across the tube (its "up" direction).
    pub height: Fx,
    /// Half size along z.
    pub width: Fx,
}

/// A closed generalised cylinder.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Tube<'a> {
    /// Rings from one end to the other (at least 2).
    pub stations: &'a [Station],
    /// Added to every station's z: one list of rings makes a leg or an
    /// ear on either side.
    pub z: Fx,
    /// Vertices per ring (at least 3).
    pub sides: u8,
    /// Whether the end caps bulge out by half the smaller half-size (a
    /// muzzle, a rump) or stay flat (a hoof on the ground).
    pub rounded: bool,
}

/// Serialised as the rings it makes, `z` added: a tube's parameters are
/// its shape, however its rings are shared.
impl Serialize for Tube<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        struct Placed<'t>(&'t Tube<'t>);
        impl Serialize for Placed<'_> {
            fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
                serializer.collect_seq(self.0.stations.iter().map(|s| self.0.placed(s)))
            }
        }
        let mut tube = serializer.serialize_struct("Tube", 3)?;
        tube.serialize_field("stations", &Placed(self))?;
        tube.serialize_field("sides", &self.sides)?;
        tube.serialize_field("rounded", &self.rounded)?;
        tube.end()
    }
}

impl Tube<'_> {
    /// `station` in model space: its centre moved by [`Tube::z`].
    fn placed(&self, station: &Station) -> Station {
        let [x, y, z] = station.centre;
        Station {
            centre: [x, y, z + self.z],
            ..*station
        }
    }

    fn vertex_count(&self) -> u32 {
        self.stations.len() as u32 * u32::from(self.sides) + 2
    }

    fn triangle_count(&self) -> u32 {
        2 * self.stations.len() as u32 * u32::from(self.sides)
    }

    /// The unit tangent of station `s` in the side plane (central difference).
    fn tangent<R: Real>(&self, s: usize) -> Vector3<R> {
        let last = self.stations.len().saturating_sub(1);
        let a = point::<R>(self.stations[s.saturating_sub(1)].centre);
        let b = point::<R>(self.stations[(s + 1).min(last)].centre);
        let d = Vector3::new(b.x - a.x, b.y - a.y, R::zero());
        let n = norm(&d);
        if n <= R::zero() {
            Vector3::x()
        } else {
            d.map(|v| v.div(n))
        }
    }

    fn vertex<R: Real>(&self, j: u32) -> Vector3<R> {
        let sides = u32::from(self.sides);
        let last_station = self.stations.len().saturating_sub(1);
        if j == 0 || j == self.vertex_count() - 1 {
            let (s, sign) = if j == 0 {
                (0, -R::one())
            } else {
                (last_station, R::one())
            };
            let st = self.placed(&self.stations[s]);
            let c = point::<R>(st.centre);
            if !self.rounded {
                return c;
            }
            let bulge = R::from_fx(st.height.min(st.width)) * R::from_fx(Fx::HALF);
            return c + self.tangent::<R>(s) * (bulge * sign);
        }
        let (s, k) = (((j - 1) / sides) as usize, (j - 1) % sides);
        let st = self.placed(&self.stations[s.min(last_station)]);
        let t = self.tangent::<R>(s);
        let up = Vector3::new(-t.y, t.x, R::zero());
        let phi = Angle::from_turn_ratio(i64::from(k), i64::from(sides));
        let (h, w) = (R::from_fx(st.height), R::from_fx(st.width));
        point::<R>(st.centre) + up * (h * R::cos(phi)) + Vector3::z() * (w * R::sin(phi))
    }

    fn triangle(&self, i: u32) -> [u32; 3] {
        let k_count = u32::from(self.sides);
        let rings = self.stations.len() as u32;
        let ring = |r: u32, k: u32| 1 + r * k_count + k % k_count;
        let end_cap = self.vertex_count() - 1;
        if i < k_count {
            return [0, ring(0, i + 1), ring(0, i)];
        }
        let band = i - k_count;
        if band < 2 * k_count * (rings - 1) {
            let (r, m) = (band / (2 * k_count), band % (2 * k_count));
            let k = m / 2;
            return if m % 2 == 0 {
                [ring(r, k), ring(r, k + 1), ring(r + 1, k)]
            } else {
                [ring(r, k + 1), ring(r + 1, k + 1), ring(r + 1, k)]
            };
        }
        let k = band - 2 * k_count * (rings - 1);
        [end_cap, ring(rings - 1, k), ring(rings - 1, k + 1)]
    }
}

/// A body's surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Mesh<'a> {
    /// Procedural tubes, generated on the fly.
    Tubes(&'a [Tube<'a>]),
    /// An indexed triangle mesh.
    Indexed {
        /// Vertex positions, model space.
        vertices: &'a [[Fx; 3]],
        /// Triangles by vertex index, counter-clockwise from outside.
        triangles: &'a [[u32; 3]],
    },
}

impl Mesh<'_> {
    /// Checks tubes and triangle indices.
    ///
    /// # Errors
    /// [`BodyError::DegenerateTube`] or [`BodyError::TriangleVertex`].
    pub fn validate(&self) -> Result<(), BodyError> {
        match self {
            Mesh::Tubes(tubes) => {
                for (i, t) in tubes.iter().enumerate() {
                    if t.stations.len() < 2 || t.sides < 3 || t.stations.len() > 1 << 16 {
                        return Err(BodyError::DegenerateTube { tube: i as u16 });
                    }
                }
            }
            Mesh::Indexed {
                vertices,
                triangles,
            } => {
                let n = vertices.len();
                for (i, t) in triangles.iter().enumerate() {
                    if t.iter().any(|&v| v as usize >= n) {
                        return Err(BodyError::TriangleVertex { triangle: i as u32 });
                    }
                }
            }
        }
        Ok(())
    }

    /// Number of vertices.
    #[must_use]
    pub fn vertex_count(&self) -> u32 {
        match self {
            Mesh::Tubes(tubes) => tubes.iter().map(Tube::vertex_count).sum(),
            Mesh::Indexed { vertices, .. } => vertices.len() as u32,
        }
    }

    /// Number of triangles.
    #[must_use]
    pub fn triangle_count(&self) -> u32 {
        match self {
            Mesh::Tubes(tubes) => tubes.iter().map(Tube::triangle_count).sum(),
            Mesh::Indexed { triangles, .. } => triangles.len() as u32,
        }
    }

    /// Vertex `i` in model space.
    #[must_use]
    pub fn vertex<R: Real>(&self, i: u32) -> Option<Vector3<R>> {
        match self {
            Mesh::Tubes(tubes) => {
                let mut j = i;
                for t in *tubes {
                    if j < t.vertex_count() {
                        return Some(t.vertex(j));
                    }
                    j -= t.vertex_count();
                }
                None
            }
            Mesh::Indexed { vertices, .. } => vertices.get(i as usize).map(|p| point(*p)),
        }
    }

    /// Triangle `i` by vertex ids.
    #[must_use]
    pub fn triangle(&self, i: u32) -> Option<[u32; 3]> {
        match self {
            Mesh::Tubes(tubes) => {
                let (mut j, mut first_vertex) = (i, 0);
                for t in *tubes {
                    if j < t.triangle_count() {
                        return Some(t.triangle(j).map(|v| v + first_vertex));
                    }
                    j -= t.triangle_count();
                    first_vertex += t.vertex_count();
                }
                None
            }
            Mesh::Indexed { triangles, .. } => triangles.get(i as usize).copied(),
        }
    }

    /// Calls `edge(a, b)` once per edge of every triangle (shared edges
    /// twice, once per side).
    pub fn for_each_edge(&self, mut edge: impl FnMut(u32, u32)) {
        for i in 0..self.triangle_count() {
            if let Some([a, b, c]) = self.triangle(i) {
                edge(a, b);
                edge(b, c);
                edge(c, a);
            }
        }
    }
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;

    const STATIONS: [Station; 3] = [
        Station {
            centre: [Fx::ZERO, Fx::ZERO, Fx::ZERO],
            height: Fx::ONE,
            width: Fx::ONE,
        },
        Station {
            centre: [Fx::from_int(4), Fx::ZERO, Fx::ZERO],
            height: Fx::from_int(2),
            width: Fx::ONE,
        },
        Station {
            centre: [Fx::from_int(8), Fx::from_int(4), Fx::ZERO],
            height: Fx::ONE,
            width: Fx::ONE,
        },
    ];

    #[test]
    fn a_tube_is_closed_and_its_triangles_face_outwards() {
        let tubes = [Tube {
            stations: &STATIONS,
            z: Fx::ZERO,
            sides: 6,
            rounded: true,
        }];
        let mesh = Mesh::Tubes(&tubes);
        mesh.validate().unwrap();
        assert_eq!(mesh.vertex_count(), 20);
        assert_eq!(mesh.triangle_count(), 36);
        // Closed: every directed edge has its reverse exactly once.
        let mut edges = std::collections::BTreeMap::new();
        mesh.for_each_edge(|a, b| *edges.entry((a, b)).or_insert(0) += 1);
        for (&(a, b), &n) in &edges {
            assert_eq!(n, 1);
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a}-{b} is open");
        }
        // Outward: the signed volume (divergence theorem) is positive.
        let v = |i: u32| mesh.vertex::<f64>(i).unwrap();
        let volume: f64 = (0..mesh.triangle_count())
            .map(|i| {
                let [a, b, c] = mesh.triangle(i).unwrap();
                v(a).dot(&v(b).cross(&v(c))) / 6.0
            })
            .sum();
        assert!(volume > 30.0, "volume {volume}");
    }

    #[test]
    fn bad_meshes_are_refused() {
        let tubes = [Tube {
            stations: &STATIONS[..1],
            z: Fx::ZERO,
            sides: 6,
            rounded: false,
        }];
        assert_eq!(
            Mesh::Tubes(&tubes).validate(),
            Err(BodyError::DegenerateTube { tube: 0 })
        );
        let vertices = [[Fx::ZERO; 3]; 3];
        let triangles = [[0, 1, 2], [0, 1, 3]];
        let mesh = Mesh::Indexed {
            vertices: &vertices,
            triangles: &triangles,
        };
        assert_eq!(
            mesh.validate(),
            Err(BodyError::TriangleVertex { triangle: 1 })
        );
    }
}
