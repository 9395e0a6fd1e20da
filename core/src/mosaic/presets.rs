//! The parameter sets of the built-in mosaic presets (thesis Table 4.1).
//!
//! Choices the thesis leaves open, made here once for all presets:
//! - Table 4.1's "cells" is C_i, the number of **initial** cells (the
//!   thesis's symbol list: "Número de células iniciais"); cells then divide,
//!   so a run ends with several times more (croton: 2 000 → about 19 000).
//! - The domain has an area of C_i (initial spacing 1).
//! - ρ_i = 40 and ρ_s = 8 (the thesis gives no values; ρ_i = 40 makes
//!   the initial pattern regular, Clark–Evans index ≈ 1.8).
//! - α between unlike types is 0 (full repulsion); no mutation unless said.
//! - w_d = 0.066 (the original code), w_a = 0.5 where a field is used.

use super::control::{Anisotropy, ControlVector, Mask};
use super::domain::Domain;
use super::params::{
    CellType, Frames, MAX_TYPES, NO_MUTATION, ORIGINAL_PUSH_WEIGHT, Params, pair_table,
};
use crate::fx::Fx;

/// ρ_i of every preset.
pub const INITIAL_RELAXATIONS: u16 = 40;
/// ρ_s of every preset.
pub const DAILY_RELAXATIONS: u16 = 8;

const fn fx(n: i32) -> Fx {
    Fx::from_int(n)
}

const fn ratio(n: i32, d: i32) -> Fx {
    Fx::from_ratio(n, d)
}

const fn two_types(background: CellType, foreground: CellType) -> [CellType; 2] {
    [background, foreground]
}

const fn cell(colour: [u8; 3], division_days: u16, initial_probability: Fx) -> CellType {
    CellType {
        colour,
        division_days,
        initial_probability,
    }
}

/// Adhesion with α_BB (type 0), α_FF (type 1), α_FB = 0.
const fn adhesion(bb: Fx, ff: Fx) -> [[Fx; MAX_TYPES]; MAX_TYPES] {
    pair_table([bb, ff, Fx::ZERO, Fx::ZERO], Fx::ZERO)
}

const fn base(domain: Domain, initial_cells: u32, types: &'static [CellType], days: u16) -> Params {
    Params {
        domain,
        initial_cells,
        types,
        adhesion: adhesion(ratio(8, 10), ratio(5, 10)),
        mutation: NO_MUTATION,
        radius_weight: Fx::ONE,
        push_weight: ORIGINAL_PUSH_WEIGHT,
        initial_relaxations: INITIAL_RELAXATIONS,
        daily_relaxations: DAILY_RELAXATIONS,
        days,
        mask: None,
        anisotropy: None,
        frames: Frames::EveryDay,
    }
}

// ---------------------------------------------------------------- masks

/// A one-row mask of `W` pixels (`B = ⌈W/8⌉` bytes) allowing `on` pixels of
/// every `period` (stripes along v on a cylinder).
const fn stripes<const B: usize>(width: u32, period: u32, on: u32) -> [u8; B] {
    let mut bits = [0u8; B];
    let mut x = 0;
    while x < width {
        if x % period < on {
            bits[(x / 8) as usize] |= 0x80 >> (x % 8);
        }
        x += 1;
    }
    bits
}

/// A `w × h` mask of transverse zig-zag bands: row `y` at column `x` is
/// allowed when `(y + zig(x)) mod period < on`, zig a triangle wave of
/// amplitude `amp` over the width.
const fn bands<const B: usize>(w: u32, h: u32, period: u32, on: u32, amp: u32) -> [u8; B] {
    let mut bits = [0u8; B];
    let stride = w.div_ceil(8);
    let mut y = 0;
    while y < h {
        let mut x = 0;
        while x < w {
            let t = x * 2 * amp / w; // 0 .. 2·amp
            let zig = if t > amp { 2 * amp - t } else { t };
            if (y + zig) % period < on {
                bits[(y * stride + x / 8) as usize] |= 0x80 >> (x % 8);
            }
            x += 1;
        }
        y += 1;
    }
    bits
}

/// A `w × h` mask allowing the inside of the centred ellipse with radii
/// `a` (columns) and `b` (rows).
const fn ellipse<const B: usize>(w: u32, h: u32, a: i64, b: i64) -> [u8; B] {
    let mut bits = [0u8; B];
    let stride = w.div_ceil(8);
    let (cx2, cy2) = (w as i64, h as i64); // doubled centre
    let mut y = 0;
    while y < h {
        let mut x = 0;
        while x < w {
            let dx = 2 * x as i64 + 1 - cx2;
            let dy = 2 * y as i64 + 1 - cy2;
            // (dx/2a)² + (dy/2b)² ≤ 1
            if dx * dx * b * b + dy * dy * a * a <= 4 * a * a * b * b {
                bits[(y * stride + x / 8) as usize] |= 0x80 >> (x % 8);
            }
            x += 1;
        }
        y += 1;
    }
    bits
}

static WATERMELON_STRIPES: [u8; 8] = stripes::<8>(64, 4, 1);
static SANSEVIERIA_BANDS: [u8; 4 * 128] = bands::<{ 4 * 128 }>(32, 128, 16, 6, 3);
static PHILODENDRON_CENTRE: [u8; 4 * 32] = ellipse::<{ 4 * 32 }>(32, 32, 6, 11);
/// The top 3 of 8 rows of the cap.
static AMANITA_CAP: [u8; 8] = [0x80, 0x80, 0x80, 0, 0, 0, 0, 0];

// --------------------------------------------------------------- presets

static CROTON_TYPES: [CellType; 2] = two_types(
    cell([40, 105, 45], 10, ratio(7, 10)),
    cell([236, 200, 48], 10, ratio(3, 10)),
);

/// `croton`: *Codiaeum variegatum* (Fig. 4.1): 35 days, w_r 1, 2 000
/// initial cells, α_FF .5, α_BB .8, D_F = D_B = 10; F (yellow) 30 %.
/// Periodic 50 × 40. Frames: days 0, 10, 20, 35.
pub static CROTON: Params = Params {
    frames: Frames::Days(&[0, 10, 20, 35]),
    ..base(Domain::periodic(fx(50), fx(40)), 2_000, &CROTON_TYPES, 35)
};

/// `croton-mcu`: `croton` scaled to a 64 KB microcontroller: 180 initial
/// cells on a periodic 15 × 12, ending with about 1 800 (the store holds
/// 2 048). Every day is a frame.
pub static CROTON_MCU: Params = Params {
    frames: Frames::EveryDay,
    ..base(Domain::periodic(fx(15), fx(12)), 180, &CROTON_TYPES, 35)
};

static AGEING_TYPES: [CellType; 2] = two_types(
    cell([40, 105, 45], 10, ratio(9, 10)),
    cell([236, 200, 48], 5, ratio(1, 10)),
);

/// `croton-ageing` (Fig. 4.3): 5–15–20–30 days of one run, w_r 1, 10 000
/// initial cells, α .5/.8, D_F 5, D_B 10; F 10 %. Periodic 100 × 100.
pub static CROTON_AGEING: Params = Params {
    frames: Frames::Days(&[5, 15, 20, 30]),
    ..base(
        Domain::periodic(fx(100), fx(100)),
        10_000,
        &AGEING_TYPES,
        30,
    )
};

static CACTUS_TYPES: [CellType; 2] = two_types(
    cell([58, 122, 60], 60, ratio(998, 1000)),
    cell([226, 214, 86], 3, ratio(2, 1000)),
);

/// `cactus-spots`: *Cereus hildmannianus* (Fig. 4.8): 25 days, w_r 4, 5 000
/// initial cells, α .5/.9, D_F 3, D_B 60, F 0.2 %. A stem: cylinder
/// 50 around × 100 along. Frames: days 0, 10, 20, 25.
pub static CACTUS_SPOTS: Params = Params {
    adhesion: adhesion(ratio(9, 10), ratio(5, 10)),
    radius_weight: fx(4),
    frames: Frames::Days(&[0, 10, 20, 25]),
    ..base(Domain::cylinder(fx(50), fx(100)), 5_000, &CACTUS_TYPES, 25)
};

static PHILODENDRON_TYPES: [CellType; 2] = two_types(
    cell([44, 112, 40], 120, ratio(2, 10)),
    cell([206, 222, 96], 30, ratio(8, 10)),
);

static OUTWARD: [ControlVector; 4] = [
    ControlVector {
        at: [fx(30), fx(50)],
        v: [fx(-1), Fx::ZERO],
    },
    ControlVector {
        at: [fx(70), fx(50)],
        v: [Fx::ONE, Fx::ZERO],
    },
    ControlVector {
        at: [fx(50), fx(20)],
        v: [Fx::ZERO, fx(-1)],
    },
    ControlVector {
        at: [fx(50), fx(80)],
        v: [Fx::ZERO, Fx::ONE],
    },
];

/// `philodendron`: *P. oxycardium* (Fig. 4.10): 25 days (of 20…32), w_r 2,
/// 10 000 initial cells, α .5/.7, D_F 30, D_B 120; F (light) starts in a
/// central ellipse (mask) and the anisotropy field points out from the
/// centre (4 control vectors, IMQ width 30, w_a 0.5). A walled 100 × 100
/// leaf. Frames: days 0 and 25.
pub static PHILODENDRON: Params = Params {
    adhesion: adhesion(ratio(7, 10), ratio(5, 10)),
    radius_weight: fx(2),
    mask: Some(Mask {
        width: 32,
        height: 32,
        bits: &PHILODENDRON_CENTRE,
    }),
    anisotropy: Some(Anisotropy {
        vectors: &OUTWARD,
        width: fx(30),
        weight: Fx::HALF,
    }),
    frames: Frames::Days(&[0, 25]),
    ..base(
        Domain::walled(fx(100), fx(100)),
        10_000,
        &PHILODENDRON_TYPES,
        25,
    )
};

static WATERMELON_TYPES: [CellType; 2] = two_types(
    cell([150, 196, 96], 10, ratio(4, 10)),
    cell([28, 78, 34], 5, ratio(6, 10)),
);

const fn watermelon(radius_weight: Fx) -> Params {
    Params {
        adhesion: adhesion(ratio(9, 10), ratio(5, 10)),
        radius_weight,
        mask: Some(Mask {
            width: 64,
            height: 1,
            bits: &WATERMELON_STRIPES,
        }),
        frames: Frames::Days(&[0, 20]),
        ..base(
            Domain::cylinder(fx(125), fx(80)),
            10_000,
            &WATERMELON_TYPES,
            20,
        )
    }
}

/// `watermelon`: *Citrullus lanatus* (Fig. 4.16, middle): 20 days, w_r 2,
/// 10 000 initial cells, α .5/.9, D_F 5, D_B 10; dark F only in 16 stripes
/// of the mask (a quarter of the circumference), 60 % there. Cylinder
/// 125 around × 80 along. Frames: days 0 and 20.
pub static WATERMELON: Params = watermelon(fx(2));
/// `watermelon-narrow`: as `watermelon` with w_r 1 (Fig. 4.16, left).
pub static WATERMELON_NARROW: Params = watermelon(fx(1));
/// `watermelon-wide`: as `watermelon` with w_r 3 (Fig. 4.16, right).
pub static WATERMELON_WIDE: Params = watermelon(fx(3));

static AMANITA_TYPES: [CellType; 2] = two_types(
    cell([244, 238, 222], 8, ratio(15, 100)),
    cell([196, 30, 22], 6, ratio(85, 100)),
);

/// `amanita`: *Amanita muscaria* (Fig. 4.15, D_F 6): 20 days, w_r 3, 6 000
/// initial cells, α_FF .7, α_BB .9, D_B 8; red F only on the top 3/8 of the
/// cap (mask), 85 % there. Cylinder 100 around × 60 from the top.
/// Frames: days 0 and 20.
pub static AMANITA: Params = Params {
    adhesion: adhesion(ratio(9, 10), ratio(7, 10)),
    radius_weight: fx(3),
    mask: Some(Mask {
        width: 1,
        height: 8,
        bits: &AMANITA_CAP,
    }),
    frames: Frames::Days(&[0, 20]),
    ..base(Domain::cylinder(fx(100), fx(60)), 6_000, &AMANITA_TYPES, 20)
};

static SANSEVIERIA_TYPES: [CellType; 2] = two_types(
    cell([150, 178, 118], 70, ratio(1, 10)),
    cell([30, 74, 44], 5, ratio(9, 10)),
);

/// `sansevieria`: *S. trifasciata* (Fig. 4.19): 15 days, w_r 0.7, 15 000
/// initial cells, α_FF = α_BB = .7, D_F 5, D_B 70; dark F only in the
/// zig-zag transverse bands of the mask, 90 % there. A walled 50 × 300 leaf.
/// Frames: days 0 and 15.
pub static SANSEVIERIA: Params = Params {
    adhesion: adhesion(ratio(7, 10), ratio(7, 10)),
    radius_weight: ratio(7, 10),
    mask: Some(Mask {
        width: 32,
        height: 128,
        bits: &SANSEVIERIA_BANDS,
    }),
    frames: Frames::Days(&[0, 15]),
    ..base(
        Domain::walled(fx(50), fx(300)),
        15_000,
        &SANSEVIERIA_TYPES,
        15,
    )
};

/// The inline store of the MCU presets: 2 048 cells, 512 grid bins, 24 B
/// per cell (49 156 B).
pub type McuStore = super::store::ArrayStore<2048, 513>;

/// The capacity (cells) of a host preset's store: comfortably above the
/// final count of its runs (checked over seeds by the tests); a run that
/// outgrows it stops with [`Error::Capacity`](crate::Error::Capacity). The
/// core has no heap: the big mosaics are host presets, run by the host CLI
/// (`host-cli/src/host_presets.rs`) on a `Vec`-backed
/// [`CellStore`](super::store::CellStore) of this many cells and
/// `cells / 4 + 1` bin offsets.
#[must_use]
pub fn host_capacity(params: &Params) -> usize {
    // The largest growth of any type over the run, ×1.5 margin: a type
    // with D_T divides about days/D_T times (plus Poisson spread).
    let days = u32::from(params.days);
    let growth = params
        .types
        .iter()
        .map(|t| {
            let generations =
                (days + u32::from(t.division_days) / 2) / u32::from(t.division_days).max(1) + 1;
            1u64 << generations.min(20)
        })
        .max()
        .unwrap_or(1);
    (u64::from(params.initial_cells) * growth).min(1 << 24) as usize
}

/// The parameters of the mosaic preset called `name` (a core preset or a
/// host one).
#[must_use]
pub fn by_name(name: &str) -> Option<&'static Params> {
    Some(match name {
        "croton" => &CROTON,
        "croton-mcu" => &CROTON_MCU,
        "croton-ageing" => &CROTON_AGEING,
        "cactus-spots" => &CACTUS_SPOTS,
        "philodendron" => &PHILODENDRON,
        "watermelon" => &WATERMELON,
        "watermelon-narrow" => &WATERMELON_NARROW,
        "watermelon-wide" => &WATERMELON_WIDE,
        "amanita" => &AMANITA,
        "sansevieria" => &SANSEVIERIA,
        _ => return None,
    })
}
