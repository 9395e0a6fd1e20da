//! Joint motion from measured angles (growth paper, Sec. 7 and Fig. 7): a
//! gait is a table of joint bends over one stride, sampled at equal phases
//! and interpolated linearly, each channel driving the cylinder of that
//! name. As in the paper, the measured half stride of one diagonal pair is
//! reused for the other pair half a stride later.

use serde::Serialize;

use super::Label;
use super::chain::Joint;
use crate::fx::{Angle, Fx};

/// The bends of one joint over a stride.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Channel<'a> {
    /// The cylinder it bends (cylinders of other names keep their rest
    /// pose; a body without this name ignores the channel).
    pub cylinder: Label,
    /// Phase offset in samples (half the samples for the other diagonal).
    pub shift: u8,
    /// Bend about the cylinder's local Z in whole degrees, one per sample,
    /// measured from the rest pose.
    pub degrees: &'a [i16],
}

/// The footfall timing of a gait (Hildebrand's gait diagram): each hoof
/// touches down at sample 0 of its channel and stays on the ground for the
/// duty factor's share of the stride. A trot whose duty factor is below
/// 0.5 has two suspensions a stride, when no hoof is on the ground and the
/// body flies; a walk's is above 0.5 and it is never airborne.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Footfall {
    /// The share of the stride a hoof is on the ground, in (0, 1).
    pub duty_factor: Fx,
    /// The stride's duration, seconds: the flight's time, for its
    /// ballistic path.
    pub stride_seconds: Fx,
}

/// A cyclic gait.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Gait<'a> {
    /// The joints it moves.
    pub channels: &'a [Channel<'a>],
    /// When each hoof is on the ground; `None`: the lowest fore and hind
    /// hooves support the body at every phase.
    pub footfall: Option<Footfall>,
}

/// Gravity in a table's length unit per second squared (`"in"`, `"cm"`,
/// `"mm"`, `"m"`), or `None` for another unit.
#[must_use]
pub fn gravity(unit: &str) -> Option<Fx> {
    // Standard gravity, 9.80665 m/s².
    match unit {
        "in" => Some(Fx::from_ratio(3_860_886, 10_000)),
        "cm" => Some(Fx::from_ratio(980_665, 1000)),
        "mm" => Some(Fx::from_ratio(980_665, 100)),
        "m" => Some(Fx::from_ratio(980_665, 100_000)),
        _ => None,
    }
}

/// `x` wrapped into [0, 1).
fn turn(x: Fx) -> Fx {
    Fx::from_bits(x.to_bits() & 0xFFFF)
}

impl Gait<'_> {
    /// The phase of the stride at which the hoof of cylinder `name` touches
    /// down (its channel's sample 0), or `None` without a channel.
    #[must_use]
    pub fn touchdown(&self, name: Label) -> Option<Fx> {
        let ch = self.channels.iter().find(|c| c.cylinder == name)?;
        let n = i32::try_from(ch.degrees.len()).ok().filter(|&n| n > 0)?;
        // Sample `shift` is read at phase 0: sample 0 at −shift/n.
        Some(turn(-Fx::from_ratio(i32::from(ch.shift) % n, n)))
    }

    /// Whether the hoof of cylinder `name` is on the ground at `phase`
    /// (always, without footfall timing or a channel).
    #[must_use]
    pub fn on_ground(&self, name: Label, phase: Fx) -> bool {
        match (self.footfall, self.touchdown(name)) {
            (Some(f), Some(t)) => turn(phase - t) < f.duty_factor,
            _ => true,
        }
    }

    /// The joint of the cylinder `name` at `phase` ∈ [0, 1) of the stride.
    #[must_use]
    pub fn joint(&self, name: Label, phase: Fx) -> Joint {
        let Some(ch) = self.channels.iter().find(|c| c.cylinder == name) else {
            return Joint::REST;
        };
        let n = ch.degrees.len();
        if n == 0 {
            return Joint::REST;
        }
        // Position in samples: phase·n, as Q16 (phase < 1, n ≤ 65535).
        let pos = (i64::from(phase.to_bits().max(0)) * n as i64) as u64;
        let whole = (pos >> 16) as usize + usize::from(ch.shift);
        let frac = Fx::from_bits((pos & 0xFFFF) as i32);
        let (a, b) = (
            Fx::from_int(i32::from(ch.degrees[whole % n])),
            Fx::from_int(i32::from(ch.degrees[(whole + 1) % n])),
        );
        // |b − a| ≤ 65535 and frac < 1: no saturation.
        Joint::bend(Angle::from_degrees_fx(a + (b - a) * frac))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fore forearm swing at the elbow over 12 phases of a trot, degrees
    /// (positive: hoof forward); stance in phases 0–5, swing in 6–11. Drawn
    /// after Muybridge's trotting horse, the paper's source (Fig. 7).
    const FORE_SWING: [i16; 12] = [18, 12, 6, 0, -6, -12, -16, -8, 4, 16, 26, 24];
    /// Knee: the cannon folds back during the swing.
    const FORE_KNEE: [i16; 12] = [0, 0, 0, 0, 0, -5, -25, -60, -75, -50, -15, -2];
    /// Fetlock: over-extended under load, folded in the swing.
    const FETLOCK: [i16; 12] = [0, 8, 14, 18, 20, 10, -20, -45, -40, -20, -5, 0];
    /// Hind gaskin swing at the stifle.
    const HIND_SWING: [i16; 12] = [12, 8, 4, 0, -4, -8, -12, -6, 4, 14, 20, 18];
    /// Hock: the hind cannon swings forward as the hock flexes.
    const HOCK: [i16; 12] = [0, 0, 0, 0, 0, 8, 25, 45, 50, 30, 10, 2];

    const fn channel(name: &str, shift: u8, degrees: &'static [i16]) -> Channel<'static> {
        Channel {
            cylinder: Label::new(name),
            shift,
            degrees,
        }
    }

    /// A trot (the `horse-trot` scenario's gait): left fore with right
    /// hind, then right fore with left hind half a stride (6 samples) later.
    static TROT: Gait<'static> = Gait {
        footfall: Some(Footfall {
            duty_factor: Fx::from_ratio(2, 5),
            stride_seconds: Fx::from_ratio(65, 100),
        }),
        channels: &[
            channel("l-fore-forearm", 0, &FORE_SWING),
            channel("l-fore-cannon", 0, &FORE_KNEE),
            channel("l-fore-pastern", 0, &FETLOCK),
            channel("r-hind-gaskin", 0, &HIND_SWING),
            channel("r-hind-cannon", 0, &HOCK),
            channel("r-hind-pastern", 0, &FETLOCK),
            channel("r-fore-forearm", 6, &FORE_SWING),
            channel("r-fore-cannon", 6, &FORE_KNEE),
            channel("r-fore-pastern", 6, &FETLOCK),
            channel("l-hind-gaskin", 6, &HIND_SWING),
            channel("l-hind-cannon", 6, &HOCK),
            channel("l-hind-pastern", 6, &FETLOCK),
        ],
    };

    #[test]
    fn samples_interpolate_and_diagonals_are_half_a_stride_apart() {
        let lf = Label::new("l-fore-forearm");
        assert_eq!(
            TROT.joint(lf, Fx::ZERO),
            Joint::bend(Angle::from_degrees_fx(Fx::from_int(18)))
        );
        // Half way between samples 0 and 1 (18° and 12°): 15°, up to the
        // rounding of the phase 1/24.
        let half = TROT.joint(lf, Fx::from_ratio(1, 24)).bend.to_degrees_fx();
        assert!(
            (half - Fx::from_int(15)).abs() < Fx::from_ratio(1, 1000),
            "{half}"
        );
        let rf = Label::new("r-fore-forearm");
        assert_eq!(TROT.joint(rf, Fx::ZERO), TROT.joint(lf, Fx::HALF));
        assert_eq!(TROT.joint(Label::new("torso"), Fx::HALF), Joint::REST);
    }

    #[test]
    fn diagonal_hooves_land_together_and_a_short_duty_factor_flies() {
        let on = |name: &str, k: i32| TROT.on_ground(Label::new(name), Fx::from_ratio(k, 12));
        let pairs = [
            ["l-fore-pastern", "r-hind-pastern"],
            ["r-fore-pastern", "l-hind-pastern"],
        ];
        let mut suspensions = 0;
        for k in 0..12 {
            let [a, b] = pairs.map(|[f, h]| {
                assert_eq!(on(f, k), on(h, k), "phase {k}/12");
                on(f, k)
            });
            assert!(!(a && b), "phase {k}/12: both pairs down");
            if !a && !b {
                suspensions += 1;
            }
        }
        // Duty factor 0.4: down for 0–4/12 and 6–10/12, flying at 5 and 11.
        assert_eq!(suspensions, 2);
        assert!(on("l-fore-pastern", 0) && on("l-fore-pastern", 4));
        assert!(!on("l-fore-pastern", 5) && on("r-fore-pastern", 6));
        // A cylinder without a channel is always on the ground.
        assert!(on("torso", 5));
    }
}
