//! Control of a mosaic through its control cylinder (thesis Secs. 3.2.2 to
//! 3.2.4): a binary mask decides where foreground cells may start, and an
//! anisotropy field — a few control vectors interpolated with
//! inverse-multiquadric radial basis functions — gives cells a preferred
//! direction of motion.

use serde::Serialize;

use super::domain::Domain;
use crate::fx::{Fx, Real};

/// A binary image mapped onto the whole domain (u → columns, v → rows, row
/// 0 at v = 0). Rows are packed MSB first and padded to whole bytes (the
/// layout of a raw PBM, but here **1 = white = allowed**).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Mask<'a> {
    /// Pixels per row.
    pub width: u16,
    /// Rows.
    pub height: u16,
    /// `height × ⌈width/8⌉` bytes.
    pub bits: &'a [u8],
}

impl Mask<'_> {
    /// Bytes per packed row.
    #[must_use]
    pub const fn stride(width: u16) -> usize {
        (width as usize).div_ceil(8)
    }

    /// Whether the sizes agree with the bytes.
    #[must_use]
    pub const fn is_valid(&self) -> bool {
        self.width > 0
            && self.height > 0
            && self.bits.len() == Mask::stride(self.width) * self.height as usize
    }

    /// The pixel at column `x`, row `y` (out of range: not allowed).
    #[must_use]
    pub fn pixel(&self, x: u32, y: u32) -> bool {
        let i = y as usize * Mask::stride(self.width) + (x / 8) as usize;
        self.bits
            .get(i)
            .is_some_and(|b| (b >> (7 - (x % 8))) & 1 == 1)
    }

    /// Whether the mask allows foreground at position `p` of `domain`.
    #[must_use]
    pub fn allows(&self, domain: &Domain, p: [i32; 2]) -> bool {
        let at = |axis: usize, n: u16| {
            let size = i64::from(domain.size[axis].to_bits()).max(1);
            // p ∈ [0, size): the quotient is in [0, n).
            ((i64::from(p[axis]) * i64::from(n)) / size) as u32
        };
        self.pixel(at(0, self.width), at(1, self.height))
    }
}

/// Maximum number of anisotropy control vectors.
pub const MAX_CONTROL_VECTORS: usize = 8;
/// Side of the lattice on which the anisotropy field is tabulated (the
/// thesis evaluates the field once per mesh face; here per lattice cell).
pub const FIELD_LATTICE: usize = 16;

/// A control vector: a preferred direction at a point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ControlVector {
    /// Where, in domain coordinates.
    pub at: [Fx; 2],
    /// The direction (|v| ≤ 1).
    pub v: [Fx; 2],
}

/// Anisotropy: control vectors, the RBF width and the weight `w_a`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Anisotropy<'a> {
    /// The control vectors (at most [`MAX_CONTROL_VECTORS`]).
    pub vectors: &'a [ControlVector],
    /// Width σ of the inverse multiquadric φ(d) = 1/√(1 + (d/σ)²).
    pub width: Fx,
    /// The blend weight w_a ∈ [0, 1].
    pub weight: Fx,
}

/// An error in the control inputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum ControlError {
    /// More control vectors than [`MAX_CONTROL_VECTORS`].
    TooManyVectors,
    /// The RBF system is singular (two control points coincide, or σ ≤ 0).
    Singular,
    /// A mask whose bytes do not match its size.
    BadMask,
}

impl core::fmt::Display for ControlError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ControlError::TooManyVectors => write!(
                f,
                "more than MAX_CONTROL_VECTORS = {MAX_CONTROL_VECTORS} anisotropy control vectors"
            ),
            ControlError::Singular => {
                f.write_str("singular anisotropy RBF system (coincident control points?)")
            }
            ControlError::BadMask => f.write_str("mask size does not match its bytes"),
        }
    }
}

impl core::error::Error for ControlError {}

/// The inverse multiquadric φ(d²) = 1/√(1 + d²/σ²), `d2` and `width2` in Q32.
fn imq<R: Real>(d2: R, width2: R) -> R {
    R::one().div((R::one() + d2.div(width2)).sqrt())
}

/// Solves `Φ·w = v` for the RBF weights (two right-hand sides), by Gaussian
/// elimination without pivoting (Φ is symmetric positive definite with a
/// unit diagonal for distinct points). Generic so that the f64 reference
/// runs the same steps.
///
/// # Errors
/// [`ControlError::Singular`] on a vanishing pivot.
pub fn rbf_weights<R: Real>(
    points: &[[R; 2]],
    values: &[[R; 2]],
    width: R,
    delta: impl Fn([R; 2], [R; 2]) -> [R; 2],
    out: &mut [[R; 2]; MAX_CONTROL_VECTORS],
) -> Result<(), ControlError> {
    let k = points.len();
    if k > MAX_CONTROL_VECTORS || values.len() != k {
        return Err(ControlError::TooManyVectors);
    }
    if width <= R::zero() {
        return Err(ControlError::Singular);
    }
    let w2 = width * width;
    let mut m = [[R::zero(); MAX_CONTROL_VECTORS]; MAX_CONTROL_VECTORS];
    for i in 0..k {
        for j in 0..k {
            let d = delta(points[i], points[j]);
            m[i][j] = imq(d[0] * d[0] + d[1] * d[1], w2);
        }
        out[i] = values[i];
    }
    let tiny = R::from_ratio(1, 1000);
    for c in 0..k {
        let pivot = m[c][c];
        if pivot < tiny {
            return Err(ControlError::Singular);
        }
        for r in c + 1..k {
            let f = m[r][c].div(pivot);
            let pivot_row = m[c];
            for (x, mcj) in m[r][c..k].iter_mut().zip(&pivot_row[c..k]) {
                *x -= f * *mcj;
            }
            let oc = out[c];
            out[r] = [out[r][0] - f * oc[0], out[r][1] - f * oc[1]];
        }
    }
    for c in (0..k).rev() {
        let mut acc = out[c];
        for j in c + 1..k {
            acc = [acc[0] - m[c][j] * out[j][0], acc[1] - m[c][j] * out[j][1]];
        }
        out[c] = [acc[0].div(m[c][c]), acc[1].div(m[c][c])];
    }
    Ok(())
}

/// The anisotropy field tabulated on a [`FIELD_LATTICE`]² lattice over the
/// domain, as Q14 unit fractions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Field {
    /// Field vectors, row-major (v rows, u columns).
    pub lattice: [[i16; 2]; FIELD_LATTICE * FIELD_LATTICE],
}

impl Field {
    /// No anisotropy (a function, not a constant: a call fills the field
    /// in place, where a copy of a constant would keep 1 KB of zeros in
    /// flash).
    #[must_use]
    pub const fn zero() -> Field {
        Field {
            lattice: [[0; 2]; FIELD_LATTICE * FIELD_LATTICE],
        }
    }

    /// Interpolates `a`'s control vectors over `domain` and tabulates the
    /// field at the lattice cell centres (clamped to |v| ≤ 1 per
    /// component).
    ///
    /// # Errors
    /// A singular system or too many vectors.
    pub fn interpolate(domain: &Domain, a: &Anisotropy) -> Result<Field, ControlError> {
        let k = a.vectors.len();
        if k > MAX_CONTROL_VECTORS {
            return Err(ControlError::TooManyVectors);
        }
        let delta = |p: [Fx; 2], q: [Fx; 2]| {
            [
                Fx::from_bits(domain.delta(0, p[0].to_bits(), q[0].to_bits())),
                Fx::from_bits(domain.delta(1, p[1].to_bits(), q[1].to_bits())),
            ]
        };
        let mut points = [[Fx::ZERO; 2]; MAX_CONTROL_VECTORS];
        let mut values = [[Fx::ZERO; 2]; MAX_CONTROL_VECTORS];
        for (i, c) in a.vectors.iter().enumerate() {
            points[i] = c.at;
            values[i] = c.v;
        }
        let mut w = [[Fx::ZERO; 2]; MAX_CONTROL_VECTORS];
        rbf_weights(&points[..k], &values[..k], a.width, delta, &mut w)?;
        let w2 = a.width * a.width;
        let mut field = Field::zero();
        let n = FIELD_LATTICE as i32;
        for (cell, out) in field.lattice.iter_mut().enumerate() {
            let (col, row) = (cell as i32 % n, cell as i32 / n);
            let at = [
                domain.size[0].saturating_mul_int(2 * col + 1) / Fx::from_int(2 * n),
                domain.size[1].saturating_mul_int(2 * row + 1) / Fx::from_int(2 * n),
            ];
            let mut v = [Fx::ZERO; 2];
            for i in 0..k {
                let d = delta(at, points[i]);
                let phi = imq(d[0] * d[0] + d[1] * d[1], w2);
                v = [v[0] + w[i][0] * phi, v[1] + w[i][1] * phi];
            }
            // Q16 → Q14, clamped to [−1, 1].
            *out = v.map(|x| (x.clamp(-Fx::ONE, Fx::ONE).to_bits() >> 2) as i16);
        }
        Ok(field)
    }

    /// The field at position `p` (Q14 per component).
    #[inline]
    #[must_use]
    pub fn at(&self, domain: &Domain, p: [i32; 2]) -> [i16; 2] {
        let cell = |axis: usize| {
            let size = i64::from(domain.size[axis].to_bits()).max(1);
            ((i64::from(p[axis]) * FIELD_LATTICE as i64) / size).clamp(0, FIELD_LATTICE as i64 - 1)
                as usize
        };
        self.lattice[cell(1) * FIELD_LATTICE + cell(0)]
    }
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;

    static BITS: [u8; 4] = [0b1010_0000, 0b0000_0000, 0b0000_0001, 0b1000_0000];

    #[test]
    fn mask_maps_onto_the_domain() {
        let m = Mask {
            width: 9,
            height: 2,
            bits: &BITS,
        };
        assert!(m.is_valid());
        assert!(m.pixel(0, 0) && !m.pixel(1, 0) && m.pixel(2, 0));
        assert!(m.pixel(7, 1) && m.pixel(8, 1) && !m.pixel(0, 1));
        let d = Domain::walled(Fx::from_int(9), Fx::from_int(2));
        assert!(m.allows(&d, [Fx::from_ratio(1, 2).to_bits(), 0]));
        assert!(!m.allows(&d, [Fx::from_ratio(3, 2).to_bits(), 0]));
        assert!(m.allows(
            &d,
            [
                Fx::from_ratio(17, 2).to_bits(),
                Fx::from_ratio(3, 2).to_bits()
            ]
        ));
    }

    static OUTWARD: [ControlVector; 4] = [
        ControlVector {
            at: [Fx::from_int(4), Fx::from_int(8)],
            v: [Fx::from_int(-1), Fx::ZERO],
        },
        ControlVector {
            at: [Fx::from_int(12), Fx::from_int(8)],
            v: [Fx::ONE, Fx::ZERO],
        },
        ControlVector {
            at: [Fx::from_int(8), Fx::from_int(4)],
            v: [Fx::ZERO, Fx::from_int(-1)],
        },
        ControlVector {
            at: [Fx::from_int(8), Fx::from_int(12)],
            v: [Fx::ZERO, Fx::ONE],
        },
    ];

    #[test]
    fn rbf_interpolates_the_control_vectors_like_f64() {
        let d = Domain::walled(Fx::from_int(16), Fx::from_int(16));
        let a = Anisotropy {
            vectors: &OUTWARD,
            width: Fx::from_int(4),
            weight: Fx::HALF,
        };
        let f = Field::interpolate(&d, &a).unwrap();
        // Lattice cell centres are at 0.5, 1.5, ...: cell (12, 8) is centred at
        // (12.5, 8.5), half a unit from the control point (12, 8).
        let right = f.at(&d, [Fx::from_int(12).to_bits(), Fx::from_int(8).to_bits()]);
        assert!(right[0] > 14_000 && right[1].abs() < 2_500, "{right:?}");
        let up = f.at(&d, [Fx::from_int(8).to_bits(), Fx::from_int(3).to_bits()]);
        assert!(up[1] < -12_000, "{up:?}");
        // The weights agree with the f64 reference to a few LSB.
        let pts: Vec<[f64; 2]> = OUTWARD.iter().map(|c| c.at.map(|x| x.to_f64())).collect();
        let vals: Vec<[f64; 2]> = OUTWARD.iter().map(|c| c.v.map(|x| x.to_f64())).collect();
        let mut wf = [[0.0; 2]; MAX_CONTROL_VECTORS];
        rbf_weights(&pts, &vals, 4.0, |p, q| [p[0] - q[0], p[1] - q[1]], &mut wf).unwrap();
        let ptx: Vec<[Fx; 2]> = OUTWARD.iter().map(|c| c.at).collect();
        let vx: Vec<[Fx; 2]> = OUTWARD.iter().map(|c| c.v).collect();
        let mut wx = [[Fx::ZERO; 2]; MAX_CONTROL_VECTORS];
        rbf_weights(
            &ptx,
            &vx,
            Fx::from_int(4),
            |p, q| [p[0] - q[0], p[1] - q[1]],
            &mut wx,
        )
        .unwrap();
        for i in 0..4 {
            for c in 0..2 {
                assert!((wx[i][c].to_f64() - wf[i][c]).abs() < 1e-3, "{i} {c}");
            }
        }
        let dup: &'static [ControlVector] = Box::leak(Box::new([OUTWARD[0], OUTWARD[0]]));
        let bad = Anisotropy { vectors: dup, ..a };
        assert_eq!(Field::interpolate(&d, &bad), Err(ControlError::Singular));
    }
}
