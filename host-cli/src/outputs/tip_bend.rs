//! The horn paper's Fig. 11 (Sec. 8): the bending angle of module E₁ over
//! (0, 4T]. E₁ is turned by every positioner younger than it, one moving
//! at a time, each by α_i(τ) = α_i(T)·f(τ) — the paper's curve, a staircase
//! of sigmoids — and, beside it, how far the direction of E₁'s tip really
//! turns, from the kernel's chain of positioners on `f64`. The two agree
//! when the positioners do not twist (a test); twisted ones also carry E₁
//! about axes that are not parallel (Table 1: 254.9° at 4T, not 252°).

use anyhow::{Context, Result};
use morphogen::fx::Angle;
use morphogen::horn::{HornKernel, HornParams, Moment};
use nalgebra::Vector3;

use super::chart::{Axis, Chart, Series};

/// Samples per T.
const SAMPLES_PER_MODULE: u32 = 120;

/// The figure's span: 4T, or every module when there are fewer.
const MODULES_SHOWN: usize = 4;

/// One sample of the figure: time in years, the paper's bending angle and
/// the kernel's total turning of E₁'s tip, both in degrees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// t, years (t/T · `delay_days` / 365).
    pub years: f64,
    /// Σ α_i(τ_i) of the positioners that have moved E₁ by t.
    pub paper: f64,
    /// The angle E₁'s tip direction has turned through by t.
    pub kernel: f64,
}

/// Degrees of a binary angle, in (−180, 180].
fn degrees(a: Angle) -> f64 {
    f64::from(a.signed()) * 360.0 / 4_294_967_296.0
}

/// The angle between two directions, radians (robust near 0).
fn between(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    let c = a.cross(b);
    c.dot(&c).sqrt().atan2(a.dot(b))
}

/// Fig. 11 of `params`, sampled at `SAMPLES_PER_MODULE` points per T.
///
/// # Errors
/// Parameters the kernel refuses.
pub fn samples(params: &HornParams<'_>) -> Result<Vec<Sample>> {
    let mut kernel = HornKernel::<f64>::new(params).context("the horn's parameters")?;
    let shown = params.modules.len().min(MODULES_SHOWN) as u32;
    let total = shown * SAMPLES_PER_MODULE;
    let delay = params.delay_days;
    let tip = Vector3::x();
    let mut previous = tip;
    let mut turned = 0.0;
    let mut out = Vec::with_capacity(total as usize);
    for n in 1..=total {
        let local = kernel
            .place(Moment::new(n, SAMPLES_PER_MODULE))
            .context("a time within the horn's life")?;
        let tau = local.tau.days::<f64>(delay);
        let youngest = local.youngest as usize;
        // The positioners older than the youngest are at τ = T.
        let paper: f64 = params.modules[..youngest]
            .iter()
            .enumerate()
            .map(|(i, m)| {
                let f = if i + 1 == youngest {
                    params.growth.fraction(tau)
                } else {
                    1.0
                };
                degrees(m.bend) * f
            })
            .sum();
        // E₁'s upper base: its frame W₁ carrying its positioner P₁(τ₁).
        let tau_1 = if youngest == 1 {
            tau
        } else {
            Moment::new(1, 1).days::<f64>(delay)
        };
        let (Some(frame), Some(own)) = (kernel.placement(1), kernel.positioner(1, tau_1)) else {
            anyhow::bail!("module E1 is not placed at sample {n}");
        };
        let direction = frame.compose(&own).apply_vector(&tip);
        turned += between(&previous, &direction);
        previous = direction;
        out.push(Sample {
            years: f64::from(n) / f64::from(SAMPLES_PER_MODULE) * f64::from(delay) / 365.0,
            paper,
            kernel: turned.to_degrees(),
        });
    }
    Ok(out)
}

/// The chart of [`samples`].
#[must_use]
pub fn chart(samples: &[Sample]) -> Chart {
    Chart::new(
        "Bending angle of module E1 (horn paper Fig. 11)",
        Axis::new("time", "years"),
        Axis::new("angle", "degrees"),
    )
    .with_series(Series::line(
        "Σ α_i(τ): the positioners younger than E1, one moving at a time",
        samples.iter().map(|s| (s.years, s.paper)).collect(),
    ))
    .with_series(Series::line(
        "turning of E1's tip direction (kernel, f64)",
        samples.iter().map(|s| (s.years, s.kernel)).collect(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use morphogen::fx::Fx;
    use morphogen::horn::Module;

    /// Table 1's first four rows (tip first), optionally without twist.
    fn table_1(twist: bool) -> Vec<Module> {
        [
            (30, 100, 75, 30),
            (100, 137, 83, 33),
            (137, 150, 59, 24),
            (150, 155, 35, 14),
        ]
        .iter()
        .map(|&(p, b, bend, t)| Module {
            positioner_scale: Fx::from_ratio(p, 100),
            base_scale: Fx::from_ratio(b, 100),
            bend: Angle::from_degrees(bend),
            twist: Angle::from_degrees(if twist { t } else { 0 }),
            path_radius: Fx::from_int(20),
        })
        .collect()
    }

    fn run(modules: &[Module]) -> Vec<Sample> {
        let scenario = morphogen_scenario::builtin("ram-horn").expect("ram-horn is built in");
        scenario.with_preset(|preset| {
            let morphogen::preset::Model::Horn(p) = preset.model else {
                panic!("ram-horn is a horn")
            };
            let params = HornParams {
                modules,
                years: modules.len() as u16,
                ..*p
            };
            samples(&params).expect("Table 1 runs")
        })
    }

    /// At t = T, 2T, 3T, 4T the paper's angle is the running sum of
    /// Table 1's bends: 75°, 158°, 217°, 252°.
    #[test]
    fn the_paper_curve_sums_table_1s_bends() {
        let s = run(&table_1(true));
        assert_eq!(s.len(), 4 * SAMPLES_PER_MODULE as usize);
        for (year, want) in [(1, 75.0), (2, 158.0), (3, 217.0), (4, 252.0)] {
            let at = s[year * SAMPLES_PER_MODULE as usize - 1];
            assert!((at.years - year as f64).abs() < 1e-12);
            assert!((at.paper - want).abs() < 1e-3, "{year}: {}", at.paper);
        }
        // Monotone, flat in winter (each year ends on a plateau of f).
        assert!(s.windows(2).all(|w| w[1].paper >= w[0].paper - 1e-12));
    }

    /// Without twist every positioner bends E₁ about the same axis, and
    /// the kernel's chain turns its tip by exactly the paper's angle.
    #[test]
    fn untwisted_the_kernel_turns_the_tip_by_the_papers_angle() {
        for s in run(&table_1(false)) {
            assert!((s.kernel - s.paper).abs() < 1e-6, "{s:?}");
        }
    }

    /// Twisted (Table 1 as printed): in the first year E₁'s own twist
    /// rolls it about its tip direction, which turns exactly as the paper
    /// says; from the second year the younger positioners' twists carry
    /// the tip about other axes too (254.9° at 4T against the paper's 252°).
    #[test]
    fn twisted_the_tip_departs_from_the_paper_after_the_first_year() {
        let s = run(&table_1(true));
        for s in s.iter().filter(|s| s.years <= 1.0) {
            assert!((s.kernel - s.paper).abs() < 1e-6, "{s:?}");
        }
        let last = s.last().expect("samples");
        assert!((last.kernel - 254.93).abs() < 0.01, "{last:?}");
    }
}
