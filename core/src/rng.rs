//! Deterministic randomness: keyed Xoshiro128++ streams (README.md,
//! "How it is built"). Each consumer (a cell, a production occurrence)
//! draws from its own stream, named by a 64-bit stream id, so results do
//! not depend on traversal order or on how many other consumers exist.

use rand_core::{RngCore, SeedableRng};
use rand_xoshiro::{SplitMix64, Xoshiro128PlusPlus};

use crate::fx::{Fx, func};

/// The largest Poisson mean [`KeyedRng::poisson`] accepts; the variate
/// costs one draw per unit of mean.
pub const POISSON_MAX_MEAN: Fx = Fx::from_int(1024);

/// An error from a variate generator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum RngError {
    /// A Poisson mean above [`POISSON_MAX_MEAN`].
    PoissonMeanTooLarge {
        /// The mean asked for, as Fx bits.
        mean_bits: i32,
    },
}

impl core::fmt::Display for RngError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            RngError::PoissonMeanTooLarge { mean_bits } => write!(
                f,
                "Poisson mean {} exceeds the limit POISSON_MAX_MEAN = {}",
                Fx::from_bits(*mean_bits),
                POISSON_MAX_MEAN
            ),
        }
    }
}

impl core::error::Error for RngError {}

/// One keyed random stream.
///
/// Seeding: `key = SplitMix64(seed).next_u64()`; the generator's 16-byte
/// state is the first two outputs of `SplitMix64(key ^ stream)`, little
/// endian. Distinct stream ids of one seed get distinct keys.
///
/// ```
/// use morphogen::rng::KeyedRng;
/// let mut a = KeyedRng::new(7, 1);
/// let mut b = KeyedRng::new(7, 1);
/// assert_eq!(a.next_u32(), b.next_u32());
/// assert!(a.below(6) < 6);
/// ```
#[derive(Clone, Debug)]
pub struct KeyedRng(Xoshiro128PlusPlus);

impl KeyedRng {
    /// The stream `stream` of the run seeded with `seed`.
    #[must_use]
    pub fn new(seed: u64, stream: u64) -> KeyedRng {
        let key = SplitMix64::seed_from_u64(seed).next_u64();
        let mut state = [0u8; 16];
        SplitMix64::seed_from_u64(key ^ stream).fill_bytes(&mut state);
        KeyedRng(Xoshiro128PlusPlus::from_seed(state))
    }

    /// The next 32 uniformly random bits.
    pub fn next_u32(&mut self) -> u32 {
        self.0.next_u32()
    }

    /// A uniform integer in `[0, n)`, without bias (Lemire's multiply and
    /// reject); `below(0)` is 0.
    pub fn below(&mut self, n: u32) -> u32 {
        if n == 0 {
            return 0;
        }
        let threshold = n.wrapping_neg() % n; // 2³² mod n
        loop {
            let m = self.next_u32() as u64 * n as u64;
            if (m as u32) >= threshold {
                return (m >> 32) as u32;
            }
        }
    }

    /// A uniform integer in `[lo, hi]`; an empty range gives `lo`.
    pub fn between(&mut self, lo: i32, hi: i32) -> i32 {
        if hi <= lo {
            return lo;
        }
        let span = (hi as i64 - lo as i64 + 1) as u64;
        if span > u32::MAX as u64 {
            return self.next_u32() as i32;
        }
        (lo as i64 + self.below(span as u32) as i64) as i32
    }

    /// A uniform fixed-point number in `[0, 1)` (16 random bits).
    pub fn unit(&mut self) -> Fx {
        Fx::from_bits((self.next_u32() >> 16) as i32)
    }

    /// `true` with probability `p` (clamped to `[0, 1]`), from 32 bits.
    pub fn chance(&mut self, p: Fx) -> bool {
        let threshold = (p.clamp(Fx::ZERO, Fx::ONE).to_bits() as u64) << 16; // Q32
        (self.next_u32() as u64) < threshold
    }

    /// An exponential variate with the given mean: `−mean·ln U`, with `U`
    /// uniform in `(0, 1]` at 32-bit resolution (so the largest variate is
    /// `22.18·mean`). A non-positive mean gives zero.
    pub fn exponential(&mut self, mean: Fx) -> Fx {
        if mean <= Fx::ZERO {
            return Fx::ZERO;
        }
        -Fx::from_bits(self.standard_exponential_q16() as i32) * mean
    }

    /// −ln U as Q16 bits, U = (k + 1) / 2³² with k uniform.
    fn standard_exponential_q16(&mut self) -> i64 {
        func::ln_q16(self.next_u32() as u64 + 1, 32)
    }

    /// A Poisson variate with the given mean: the number of arrivals of a
    /// unit-rate Poisson process in time `mean` (a sum of exponential
    /// inter-arrival times, so it costs about `mean + 1` draws). A
    /// non-positive mean gives zero.
    ///
    /// # Errors
    /// [`RngError::PoissonMeanTooLarge`] above [`POISSON_MAX_MEAN`].
    pub fn poisson(&mut self, mean: Fx) -> Result<u32, RngError> {
        if mean > POISSON_MAX_MEAN {
            return Err(RngError::PoissonMeanTooLarge {
                mean_bits: mean.to_bits(),
            });
        }
        let horizon = mean.to_bits() as i64;
        let mut elapsed = 0i64;
        let mut count = 0u32;
        loop {
            elapsed -= self.standard_exponential_q16(); // ln U ≤ 0
            if elapsed > horizon {
                return Ok(count);
            }
            count += 1;
        }
    }
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;
    use crate::fx::Real;

    #[test]
    fn keyed_stream_reference_values() {
        let mut rng = KeyedRng::new(2026, 42);
        let first: [u32; 4] = core::array::from_fn(|_| rng.next_u32());
        assert_eq!(first, REFERENCE_2026_42);
        let mut other = KeyedRng::new(2026, 43);
        assert_ne!(other.next_u32(), REFERENCE_2026_42[0]);
    }

    /// The first outputs of `KeyedRng::new(2026, 42)`, computed independently
    /// from the published SplitMix64 and xoshiro128++ algorithms (a short
    /// Python transcription, not this crate). A change here changes every
    /// fixture.
    const REFERENCE_2026_42: [u32; 4] = [7_538_661, 2_474_689_887, 703_520_864, 911_096_205];

    #[test]
    fn below_is_uniform() {
        let mut rng = KeyedRng::new(1, 1);
        let mut counts = [0u32; 6];
        for _ in 0..60_000 {
            counts[rng.below(6) as usize] += 1;
        }
        // χ² with 5 degrees of freedom; 20.5 is the 0.999 quantile.
        let chi2: f64 = counts
            .iter()
            .map(|&c| (c as f64 - 10_000.0).powi(2) / 10_000.0)
            .sum();
        assert!(chi2 < 20.5, "{counts:?}");
        assert_eq!(rng.below(0), 0);
        assert_eq!(rng.between(5, 5), 5);
        assert!((-3..=3).contains(&rng.between(-3, 3)));
    }

    #[test]
    fn unit_is_in_zero_one() {
        let mut rng = KeyedRng::new(3, 9);
        let mean: f64 = (0..10_000)
            .map(|_| rng.unit())
            .inspect(|u| assert!(*u >= Fx::ZERO && *u < Fx::ONE))
            .map(|u| u.to_f64())
            .sum::<f64>()
            / 10_000.0;
        assert!((mean - 0.5).abs() < 0.01, "{mean}");
    }

    #[test]
    fn exponential_has_its_mean() {
        let mut rng = KeyedRng::new(4, 0);
        let n = 20_000;
        let mean: f64 = (0..n)
            .map(|_| rng.exponential(Fx::from_int(10)).to_f64())
            .sum::<f64>()
            / n as f64;
        assert!((mean - 10.0).abs() < 0.3, "{mean}"); // σ/√n = 0.07
    }

    #[test]
    fn poisson_has_its_mean_and_variance() {
        for lambda in [Fx::from_ratio(1, 10), Fx::ONE, Fx::from_int(7)] {
            let mut rng = KeyedRng::new(5, lambda.to_bits() as u64);
            let n = 20_000;
            let draws: heapless::Vec<u32, 20_000> =
                (0..n).map(|_| rng.poisson(lambda).unwrap()).collect();
            let mean = draws.iter().map(|&k| k as f64).sum::<f64>() / n as f64;
            let var = draws
                .iter()
                .map(|&k| (k as f64 - mean).powi(2))
                .sum::<f64>()
                / n as f64;
            let l = lambda.to_f64();
            assert!(
                (mean - l).abs() < 4.0 * (l / n as f64).sqrt() + 1e-3,
                "mean {mean} for {l}"
            );
            assert!((var - l).abs() < 0.06 * l + 0.01, "variance {var} for {l}");
        }
        let mut rng = KeyedRng::new(5, 0);
        assert_eq!(
            rng.poisson(Fx::from_int(2000)),
            Err(RngError::PoissonMeanTooLarge {
                mean_bits: 2000 << 16
            })
        );
        assert_eq!(rng.poisson(-Fx::ONE), Ok(0));
    }

    #[test]
    fn chance_matches_probability() {
        let mut rng = KeyedRng::new(6, 0);
        let hits = (0..100_000)
            .filter(|_| rng.chance(Fx::from_ratio(3, 1000)))
            .count();
        assert!((200..400).contains(&hits), "{hits}");
        assert!(!rng.chance(Fx::ZERO));
        assert!(rng.chance(Fx::ONE));
    }
}
