//! Growth tables: feature lengths measured at a few ages, interpolated in
//! between (growth paper, Sec. 4 and Tables 1–2; docs/body.md has the values).
//!
//! Ages are months. Between two ages a column is interpolated linearly or by
//! a monotone cubic (Fritsch–Butland tangents, so the curve never overshoots
//! the data: a segment between two rising values rises, a flat or turning
//! point gets a zero slope). Outside the table the first or last value holds.

use serde::Serialize;

use super::{BodyError, Label};
use crate::fx::{Fx, Real};

/// How a column is interpolated between ages.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Interpolation {
    /// Straight lines between the measurements.
    Linear,
    /// A C¹ cubic through the measurements that keeps each segment monotone.
    MonotoneCubic,
}

/// One measured feature: its name and a value per age of the table.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Column<'a> {
    /// The measurement's name (e.g. `elbow-to-ground`).
    pub name: Label,
    /// One value per age, in the table's unit.
    pub values: &'a [Fx],
}

/// Feature lengths at several ages.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GrowthTable<'a> {
    /// The length unit of every value (`"in"`, `"cm"`), for documents.
    pub unit: &'a str,
    /// Ages in months, strictly increasing.
    pub ages: &'a [Fx],
    /// The measured features.
    pub columns: &'a [Column<'a>],
    /// How values between ages are found.
    pub interpolation: Interpolation,
}

/// A tenth of a unit, exactly rounded (`const`, for the tables below).
const fn tenths(v: i32) -> Fx {
    Fx::from_ratio(v, 10)
}

/// A hundredth of a unit, exactly rounded.
const fn hundredths(v: i32) -> Fx {
    Fx::from_ratio(v, 100)
}

/// Ages of the quarter-horse table, months (growth paper, Table 1).
const HORSE_AGES: [Fx; 6] = [
    Fx::from_int(0),
    Fx::from_int(12),
    Fx::from_int(24),
    Fx::from_int(36),
    Fx::from_int(48),
    Fx::from_int(60),
];

/// Quarter horse, length from elbow to ground, inches (Table 1).
const HORSE_ELBOW_TO_GROUND: [Fx; 6] = [
    tenths(250),
    tenths(331),
    tenths(359),
    tenths(351),
    tenths(349),
    tenths(358),
];
/// Quarter horse, diameter of the cannon bone, inches (Table 1).
const HORSE_CANNON_DIAMETER: [Fx; 6] = [
    hundredths(143),
    hundredths(219),
    hundredths(239),
    hundredths(239),
    hundredths(242),
    hundredths(251),
];
/// Quarter horse, length of the hind leg, inches (Table 1).
const HORSE_HIND_LEG: [Fx; 6] = [
    tenths(181),
    tenths(228),
    tenths(230),
    tenths(232),
    tenths(231),
    tenths(233),
];
/// Quarter horse, width of the head, inches (Table 1).
const HORSE_HEAD_WIDTH: [Fx; 6] = [
    tenths(56),
    tenths(78),
    tenths(86),
    tenths(89),
    tenths(91),
    tenths(88),
];

/// Column indices of [`QUARTER_HORSE`].
pub mod horse {
    /// Length from elbow to ground.
    pub const ELBOW_TO_GROUND: u8 = 0;
    /// Diameter of the cannon bone.
    pub const CANNON_DIAMETER: u8 = 1;
    /// Length of the hind leg (hock to ground).
    pub const HIND_LEG: u8 = 2;
    /// Width of the head.
    pub const HEAD_WIDTH: u8 = 3;
}

/// The male quarter horse of Cunningham and Fowler, birth to 60 months,
/// inches (growth paper, Table 1).
pub const QUARTER_HORSE: GrowthTable<'static> = GrowthTable {
    unit: "in",
    ages: &HORSE_AGES,
    columns: &[
        Column {
            name: Label::new("elbow-to-ground"),
            values: &HORSE_ELBOW_TO_GROUND,
        },
        Column {
            name: Label::new("cannon-diameter"),
            values: &HORSE_CANNON_DIAMETER,
        },
        Column {
            name: Label::new("hind-leg"),
            values: &HORSE_HIND_LEG,
        },
        Column {
            name: Label::new("head-width"),
            values: &HORSE_HEAD_WIDTH,
        },
    ],
    interpolation: Interpolation::MonotoneCubic,
};

/// Ages of the Holstein table, months (growth paper, Table 2).
#[cfg(test)]
const COW_AGES: [Fx; 4] = [
    Fx::from_int(0),
    Fx::from_int(12),
    Fx::from_int(24),
    Fx::from_int(36),
];
/// Holstein, height at withers, cm (Table 2).
#[cfg(test)]
const COW_WITHERS: [Fx; 4] = [tenths(704), tenths(1126), tenths(1267), tenths(1316)];
/// Holstein, height at croup, cm (Table 2).
#[cfg(test)]
const COW_CROUP: [Fx; 4] = [tenths(741), tenths(1168), tenths(1295), tenths(1337)];
/// Holstein, depth of chest, cm (Table 2).
#[cfg(test)]
const COW_CHEST_DEPTH: [Fx; 4] = [tenths(284), tenths(545), tenths(642), tenths(684)];
/// Holstein, from poll to muzzle, cm (Table 2).
#[cfg(test)]
const COW_POLL_TO_MUZZLE: [Fx; 4] = [tenths(232), tenths(443), tenths(520), tenths(521)];
/// Holstein, width of forehead, cm (Table 2).
#[cfg(test)]
const COW_FOREHEAD_WIDTH: [Fx; 4] = [tenths(118), tenths(181), tenths(201), tenths(197)];

/// Column indices of the Holstein table (growth paper, Table 2; the
/// `cow-growth` scenario's columns).
pub mod cow {
    /// Height at withers.
    pub const WITHERS_HEIGHT: u8 = 0;
    /// Height at croup.
    pub const CROUP_HEIGHT: u8 = 1;
    /// Depth of chest.
    pub const CHEST_DEPTH: u8 = 2;
    /// From poll to muzzle.
    pub const POLL_TO_MUZZLE: u8 = 3;
    /// Width of forehead.
    pub const FOREHEAD_WIDTH: u8 = 4;
}

/// Holstein cattle after Brody, birth to 36 months, cm (growth paper,
/// Table 2; the `cow-growth` scenario's table).
#[cfg(test)]
pub const HOLSTEIN: GrowthTable<'static> = GrowthTable {
    unit: "cm",
    ages: &COW_AGES,
    columns: &[
        Column {
            name: Label::new("withers-height"),
            values: &COW_WITHERS,
        },
        Column {
            name: Label::new("croup-height"),
            values: &COW_CROUP,
        },
        Column {
            name: Label::new("chest-depth"),
            values: &COW_CHEST_DEPTH,
        },
        Column {
            name: Label::new("poll-to-muzzle"),
            values: &COW_POLL_TO_MUZZLE,
        },
        Column {
            name: Label::new("forehead-width"),
            values: &COW_FOREHEAD_WIDTH,
        },
    ],
    interpolation: Interpolation::MonotoneCubic,
};

impl<'a> GrowthTable<'a> {
    /// Checks the ages and columns.
    ///
    /// # Errors
    /// [`BodyError::TableAges`] or [`BodyError::TableColumn`].
    pub fn validate(&self) -> Result<(), BodyError> {
        if self.ages.is_empty() || self.ages.windows(2).any(|w| w[0] >= w[1]) {
            return Err(BodyError::TableAges);
        }
        for c in self.columns {
            if c.values.len() != self.ages.len() || c.values.iter().any(|v| *v <= Fx::ZERO) {
                return Err(BodyError::TableColumn { column: c.name });
            }
        }
        Ok(())
    }

    /// The index of the column called `name`.
    #[must_use]
    pub fn column_index(&self, name: &str) -> Option<u8> {
        self.columns
            .iter()
            .position(|c| c.name.as_str() == name)
            .and_then(|i| u8::try_from(i).ok())
    }

    /// The value of `column` at `age` (months), or `None` for a missing
    /// column. The table should have passed [`GrowthTable::validate`];
    /// an empty column reads as zero.
    #[must_use]
    pub fn value<R: Real>(&self, column: u8, age: R) -> Option<R> {
        let values = self.columns.get(usize::from(column))?.values;
        let n = values.len().min(self.ages.len());
        let x = |i: usize| R::from_fx(self.ages[i]);
        let y = |i: usize| R::from_fx(values[i]);
        if n == 0 {
            return Some(R::zero());
        }
        if age <= x(0) {
            return Some(y(0));
        }
        if age >= x(n - 1) {
            return Some(y(n - 1));
        }
        // The segment [x(k), x(k+1)] holding `age` (n ≥ 2 here).
        let k = (0..n - 1).rfind(|&i| x(i) <= age).unwrap_or(0);
        let h = x(k + 1) - x(k);
        let t = (age - x(k)).div(h);
        let (y0, y1) = (y(k), y(k + 1));
        Some(match self.interpolation {
            Interpolation::Linear => y0 + (y1 - y0) * t,
            Interpolation::MonotoneCubic => {
                let slope = |i: usize| (y(i + 1) - y(i)).div(x(i + 1) - x(i));
                // Tangents at both ends, already multiplied by h.
                let tangent = |i: usize| -> R {
                    if i == 0 {
                        slope(0)
                    } else if i == n - 1 {
                        slope(n - 2)
                    } else {
                        let (d0, d1) = (slope(i - 1), slope(i));
                        let same_sign = (d0 > R::zero() && d1 > R::zero())
                            || (d0 < R::zero() && d1 < R::zero());
                        if !same_sign {
                            return R::zero();
                        }
                        // Fritsch–Butland: the weighted harmonic mean
                        // 3(h0+h1) / ((2h1+h0)/d0 + (h1+2h0)/d1), written
                        // without reciprocals of small slopes.
                        let (h0, h1) = (x(i) - x(i - 1), x(i + 1) - x(i));
                        let (w0, w1) = (h1 + h1 + h0, h1 + h0 + h0);
                        ((w0 + w1) * d0 * d1).div(w0 * d1 + w1 * d0)
                    }
                };
                let (m0, m1) = (tangent(k) * h, tangent(k + 1) * h);
                let (t2, two, three) = (t * t, R::from_int(2), R::from_int(3));
                let t3 = t2 * t;
                let h10 = t3 - two * t2 + t;
                let h01 = three * t2 - two * t3;
                let h11 = t3 - t2;
                // h00 = 1 − h01: written on the difference y1 − y0 so the
                // basis' rounding is multiplied by the step, not the value.
                y0 + h01 * (y1 - y0) + h10 * m0 + h11 * m1
            }
        })
    }
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;

    fn with(interpolation: Interpolation, table: GrowthTable<'static>) -> GrowthTable<'static> {
        GrowthTable {
            interpolation,
            ..table
        }
    }

    #[test]
    fn built_in_tables_are_valid_and_hit_every_measurement_exactly() {
        for table in [QUARTER_HORSE, HOLSTEIN] {
            table.validate().unwrap();
            for interpolation in [Interpolation::Linear, Interpolation::MonotoneCubic] {
                let t = with(interpolation, table);
                for (c, column) in t.columns.iter().enumerate() {
                    for (age, value) in t.ages.iter().zip(column.values) {
                        assert_eq!(t.value(c as u8, *age), Some(*value));
                    }
                }
            }
        }
        assert_eq!(
            QUARTER_HORSE.column_index("head-width"),
            Some(horse::HEAD_WIDTH)
        );
        assert_eq!(
            HOLSTEIN.column_index("forehead-width"),
            Some(cow::FOREHEAD_WIDTH)
        );
        assert_eq!(HOLSTEIN.value::<Fx>(9, Fx::ONE), None);
    }

    #[test]
    fn linear_interpolates_and_clamps() {
        let t = with(Interpolation::Linear, QUARTER_HORSE);
        // Half way from 25.0 (0 months) to 33.1 (12 months; 33.1 is
        // 33.0999985 in I16F16).
        assert!((t.value(0, 6.0).unwrap() - 29.05).abs() < 1e-5);
        assert_eq!(t.value(0, -5.0), Some(25.0));
        assert_eq!(t.value(0, 99.0), Some(HORSE_ELBOW_TO_GROUND[5].to_f64()));
    }

    #[test]
    fn monotone_cubic_never_overshoots_a_segment() {
        for table in [QUARTER_HORSE, HOLSTEIN] {
            for (c, column) in table.columns.iter().enumerate() {
                for k in 0..table.ages.len() - 1 {
                    let (x0, x1) = (table.ages[k].to_f64(), table.ages[k + 1].to_f64());
                    let (y0, y1) = (column.values[k].to_f64(), column.values[k + 1].to_f64());
                    let mut last = y0;
                    for i in 0..=120 {
                        let age = x0 + (x1 - x0) * f64::from(i) / 120.0;
                        let v = table.value(c as u8, age).unwrap();
                        assert!(v >= y0.min(y1) - 1e-9 && v <= y0.max(y1) + 1e-9);
                        assert!(
                            (v - last) * (y1 - y0) >= -1e-12,
                            "column {c} not monotone in segment {k} at {age}"
                        );
                        last = v;
                    }
                }
            }
        }
        // Smooth, not linear: 6 months is above the chord (growth slows down).
        let six = QUARTER_HORSE.value(0, 6.0).unwrap();
        assert!(six > 29.05 + 0.3, "{six}");
    }

    #[test]
    fn fixed_point_follows_the_f64_reference_within_96_lsb() {
        for table in [QUARTER_HORSE, HOLSTEIN] {
            for interpolation in [Interpolation::Linear, Interpolation::MonotoneCubic] {
                let t = with(interpolation, table);
                for c in 0..t.columns.len() as u8 {
                    for i in 0..=600 {
                        let age = Fx::from_ratio(i, 10);
                        let fx = t.value(c, age).unwrap().to_f64();
                        let reference = t.value(c, age.to_f64()).unwrap();
                        let lsb = (fx - reference).abs() * 65_536.0;
                        // Bound: t = (age − x)/h and the cubic basis are rounded to
                        // about 2 LSB together and multiplied by the segment's
                        // rise (≤ 42.2 cm, Holstein withers 0→12 months): 84
                        // LSB, i.e. 2·10⁻⁵ of the value.
                        assert!(
                            lsb <= 96.0,
                            "{lsb} LSB, column {c}, age {age}, {interpolation:?}: {fx} vs {reference}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn bad_tables_are_refused() {
        let ages = [Fx::ONE, Fx::ONE];
        let bad = GrowthTable {
            ages: &ages,
            ..QUARTER_HORSE
        };
        assert_eq!(bad.validate(), Err(BodyError::TableAges));
        let short = [Fx::ONE];
        let columns = [Column {
            name: Label::new("short"),
            values: &short,
        }];
        let bad = GrowthTable {
            columns: &columns,
            ..QUARTER_HORSE
        };
        assert_eq!(
            bad.validate(),
            Err(BodyError::TableColumn {
                column: Label::new("short")
            })
        );
    }
}
