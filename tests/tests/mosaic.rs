//! Cross-module checks of the clonal mosaic: regularity after the
//! initial relaxation, growth and mutation against an independent
//! reference of the division process, and reproducibility.
#![allow(
    clippy::float_arithmetic,
    clippy::unwrap_used,
    clippy::needless_range_loop
)]

use morphogen::Error;
use morphogen::fx::Fx;
use morphogen::mosaic::{
    ArrayStore, CELL_LIMIT, CellType, Domain, Frames, MAX_TYPES, McuStore, Mosaic, NO_MUTATION,
    Params,
};
use morphogen::preset::Model;
use morphogen::sim::{Simulation, Start};
use morphogen::stream::{Record, Sink, SinkError, StreamDigest};
use rayon::prelude::*;

/// Calls `f` with the parameters of the built-in mosaic scenario `name`.
fn with_mosaic<R>(name: &str, f: impl FnOnce(&Params<'_>) -> R) -> R {
    let scenario = morphogen_scenario::builtin(name).unwrap();
    scenario.with_preset(|p| {
        let Model::Mosaic(params) = p.model else {
            unreachable!("{name} is not a mosaic")
        };
        f(params)
    })
}

/// Hashes every record's debug text (enough to compare two runs).
struct Hash(StreamDigest);

impl Sink for Hash {
    fn record(&mut self, r: &Record) -> Result<(), SinkError> {
        self.0.update(format!("{r:?}").as_bytes());
        Ok(())
    }
}

type Big = ArrayStore<8192, 2049>;

fn run<'a>(params: &'a Params<'a>, seed: u64) -> (Box<Mosaic<'a, Big>>, u64) {
    let mut m = Box::new(Mosaic::new(Big::EMPTY));
    m.start(params, seed).unwrap();
    let mut h = Hash(StreamDigest::new());
    while !m.step(&mut h).unwrap().finished() {}
    (m, h.0.value())
}

/// Clark–Evans index on a periodic domain: mean nearest-neighbour distance
/// over 0.5·√(area/N), its expectation for a Poisson pattern.
fn clark_evans(m: &Mosaic<'_, Big>, domain: &Domain) -> f64 {
    let size = domain.size.map(|s| f64::from(s.to_bits()) / 65_536.0);
    let pts: Vec<[f64; 2]> = m
        .positions()
        .iter()
        .map(|p| [f64::from(p[0]) / 65_536.0, f64::from(p[1]) / 65_536.0])
        .collect();
    let wrap = |d: f64, s: f64| d - s * (d / s).round();
    let mut sum = 0.0;
    for (i, p) in pts.iter().enumerate() {
        let mut best = f64::MAX;
        for (j, q) in pts.iter().enumerate() {
            if i != j {
                let dx = wrap(p[0] - q[0], size[0]);
                let dy = wrap(p[1] - q[1], size[1]);
                best = best.min(dx * dx + dy * dy);
            }
        }
        sum += best.sqrt();
    }
    let n = pts.len() as f64;
    (sum / n) / (0.5 * (size[0] * size[1] / n).sqrt())
}

#[test]
fn initial_relaxation_makes_the_pattern_regular() {
    let (ce_random, ce_relaxed, relaxations) = with_mosaic("croton", |croton| {
        let random = Params {
            days: 0,
            initial_relaxations: 0,
            ..*croton
        };
        let relaxed = Params { days: 0, ..*croton };
        let (m, _) = run(&random, 5);
        let ce_random = clark_evans(&m, &random.domain);
        let (m, _) = run(&relaxed, 5);
        let ce_relaxed = clark_evans(&m, &relaxed.domain);
        (ce_random, ce_relaxed, relaxed.initial_relaxations)
    });
    println!(
        "Clark-Evans: random {ce_random:.3}, after rho_i = {relaxations} relaxations {ce_relaxed:.3}"
    );
    assert!((0.95..1.05).contains(&ce_random), "{ce_random}");
    assert!(ce_relaxed >= 1.5, "{ce_relaxed}");
}

static GROWTH_TYPES: [CellType; 3] = [
    CellType {
        colour: [0, 0, 0],
        division_days: 4,
        initial_probability: Fx::from_ratio(1, 2),
    },
    CellType {
        colour: [0, 0, 0],
        division_days: 6,
        initial_probability: Fx::from_ratio(3, 10),
    },
    CellType {
        colour: [0, 0, 0],
        division_days: 9,
        initial_probability: Fx::from_ratio(2, 10),
    },
];

const fn growth_mutation() -> [[Fx; MAX_TYPES]; MAX_TYPES] {
    let mut m = NO_MUTATION;
    m[0][1] = Fx::from_ratio(1, 10);
    m[0][2] = Fx::from_ratio(5, 100);
    m[1][0] = Fx::from_ratio(2, 10);
    m[2][1] = Fx::from_ratio(15, 100);
    m
}

/// Three types with mutation between them, on the `croton-mcu` surface.
fn growth<'a>(croton_mcu: &Params<'a>) -> Params<'a> {
    Params {
        initial_cells: 300,
        types: &GROWTH_TYPES,
        mutation: growth_mutation(),
        days: 12,
        initial_relaxations: 1,
        daily_relaxations: 1,
        momentum: Fx::ZERO,
        frames: Frames::Days(&[]),
        surface: None,
        ..*croton_mcu
    }
}

/// SplitMix64, the reference's own generator (not the crate's).
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Knuth's multiplication method.
    fn poisson(&mut self, mean: f64) -> u32 {
        let limit = (-mean).exp();
        let mut k = 0;
        let mut p = self.unit();
        while p > limit {
            k += 1;
            p *= self.unit();
        }
        k
    }

    fn pick(&mut self, probs: &[f64], fallback: usize) -> usize {
        let u = self.unit();
        let mut acc = 0.0;
        for (i, p) in probs.iter().enumerate() {
            acc += p;
            if u < acc {
                return i;
            }
        }
        fallback
    }
}

/// The division process alone, in f64 with its own random numbers: counts
/// per type at the end.
fn reference(params: &Params, seed: u64) -> [f64; 3] {
    let mut rng = SplitMix(seed ^ 0xDEAD_BEEF);
    let d: Vec<f64> = params
        .types
        .iter()
        .map(|t| f64::from(t.division_days))
        .collect();
    let p0: Vec<f64> = params
        .types
        .iter()
        .map(|t| t.initial_probability.to_bits() as f64 / 65_536.0)
        .collect();
    let mu = |k: usize, j: usize| params.mutation[k][j].to_bits() as f64 / 65_536.0;
    let mut cells: Vec<(usize, u32)> = (0..params.initial_cells)
        .map(|_| {
            let k = rng.pick(&p0, 0);
            (k, rng.poisson(d[k]).max(1))
        })
        .collect();
    for day in 1..=u32::from(params.days) {
        let n = cells.len();
        for i in 0..n {
            let (k, next) = cells[i];
            if next > day {
                continue;
            }
            let row: Vec<f64> = (0..3)
                .map(|j| if j == k { 0.0 } else { mu(k, j) })
                .collect();
            let child = rng.pick(&row, k);
            let c_next = day + rng.poisson(d[child]).max(1);
            cells.push((child, c_next));
            cells[i].1 = day + rng.poisson(d[k]).max(1);
        }
    }
    let mut counts = [0.0; 3];
    for (k, _) in cells {
        counts[k] += 1.0;
    }
    counts
}

#[test]
fn growth_and_mutation_match_an_independent_reference() {
    with_mosaic("croton-mcu", |croton_mcu| {
        let growth = growth(croton_mcu);
        let seeds = 20;
        let mut ours = [0.0; 3];
        let mut theirs = [0.0; 3];
        let mut divisions = [[0u64; MAX_TYPES]; MAX_TYPES];
        for seed in 0..seeds {
            let (m, _) = run(&growth, seed);
            for &k in m.kinds() {
                ours[k as usize] += 1.0;
            }
            for (row, d) in divisions.iter_mut().zip(m.divisions()) {
                for (a, b) in row.iter_mut().zip(d) {
                    *a += u64::from(*b);
                }
            }
            let r = reference(&growth, 1000 + seed);
            for k in 0..3 {
                theirs[k] += r[k];
            }
        }
        println!("final cells per type over {seeds} seeds: mosaic {ours:?}, reference {theirs:?}");
        for k in 0..3 {
            let rel = (ours[k] - theirs[k]).abs() / theirs[k];
            assert!(
                rel < 0.05,
                "type {k}: {} vs {} ({rel:.3})",
                ours[k],
                theirs[k]
            );
        }
        // Mutation: the fraction of children of each parent type that switch.
        for k in 0..3 {
            let total: u64 = divisions[k].iter().sum();
            for j in 0..3 {
                if j == k {
                    continue;
                }
                let p = growth.mutation[k][j].to_bits() as f64 / 65_536.0;
                let observed = divisions[k][j] as f64 / total as f64;
                let sigma = (p * (1.0 - p) / total as f64).sqrt();
                println!("mutation {k}->{j}: expected {p:.3}, observed {observed:.4} of {total}");
                assert!(
                    (observed - p).abs() <= 4.0 * sigma + 1e-9,
                    "{k}->{j}: {observed} vs {p}"
                );
            }
        }
    });
}

#[test]
fn the_same_seed_gives_the_same_stream() {
    with_mosaic("croton-mcu", |croton_mcu| {
        let (a, da) = run(croton_mcu, 9);
        let (b, db) = run(croton_mcu, 9);
        let (_, dc) = run(croton_mcu, 10);
        assert_eq!(da, db);
        assert_eq!(a.positions(), b.positions());
        assert_ne!(da, dc);
    });
}

#[test]
fn croton_mcu_fits_its_store_over_many_seeds() {
    let largest = with_mosaic("croton-mcu", |croton_mcu| {
        (0..40)
            .into_par_iter()
            .map(|seed| run(croton_mcu, seed).0.len())
            .max()
            .unwrap()
    });
    println!("croton-mcu: largest final count over 40 seeds {largest} (store 2048)");
    assert!(largest < 2048);
}

/// Counts records.
#[derive(Default)]
struct Count {
    cells: u32,
    frames: u32,
}

impl Sink for Count {
    fn record(&mut self, r: &Record) -> Result<(), SinkError> {
        match r {
            Record::Cell { .. } => self.cells += 1,
            Record::FrameEnd { .. } => self.frames += 1,
            _ => {}
        }
        Ok(())
    }
}

#[test]
fn croton_mcu_runs_and_streams_every_day() {
    with_mosaic("croton-mcu", |croton_mcu| {
        let mut m = Mosaic::new(McuStore::EMPTY);
        m.start(croton_mcu, 1).unwrap();
        let mut sink = Count::default();
        while !m.step(&mut sink).unwrap().finished() {}
        assert_eq!(sink.frames, 36);
        assert!((1_200..2_048).contains(&m.len()), "{}", m.len());
        // Every division is recorded; no mutation in croton.
        let d = m.divisions();
        assert_eq!(d[0][0] + d[1][1] + 180, m.len() as u32);
        assert_eq!(d[0][1] + d[1][0], 0);
    });
}

#[test]
fn a_full_store_is_an_error_naming_the_limit() {
    with_mosaic("croton-mcu", |croton_mcu| {
        let mut m = Mosaic::new(ArrayStore::<200, 51>::EMPTY);
        m.start(croton_mcu, 1).unwrap();
        let mut sink = Count::default();
        let e = loop {
            match m.step(&mut sink) {
                Ok(p) => assert!(!p.finished(), "should have overflowed"),
                Err(e) => break e,
            }
        };
        assert_eq!(
            e,
            Error::Capacity {
                limit: CELL_LIMIT,
                capacity: 200
            }
        );
        let mut small = Mosaic::new(ArrayStore::<100, 26>::EMPTY);
        assert!(small.start(croton_mcu, 1).is_err());
        assert!(small.step(&mut sink).is_err());
    });
}
