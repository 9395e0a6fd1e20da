//! The host-only presets: the big clonal mosaics, whose cell stores (tens of
//! thousands of cells, megabytes) exceed any MCU. The core has no heap, so
//! they live here, on a [`VecStore`]; their parameters are the core's
//! (`morphogen::mosaic::presets`), and their streams are written exactly as
//! a core preset's would be (header by [`morphogen::preset::header`]).
//! `croton-mcu` is the firmware-sized croton, in the core registry.

use morphogen::mosaic::presets as mosaics;
use morphogen::mosaic::store::{CELL_BYTES, CellSlices, CellStore};
use morphogen::mosaic::{Mosaic, Params};
use morphogen::preset;
use morphogen::sim::{Progress, Simulation};
use morphogen::stream::{Sink, params_digest};

/// A cell store on the heap, its capacity chosen at run time.
#[derive(Debug, Default)]
pub struct VecStore {
    pos: Vec<[i32; 2]>,
    kind: Vec<u8>,
    next_division: Vec<u16>,
    order: Vec<u32>,
    push: Vec<[i32; 2]>,
    bins: Vec<u32>,
}

impl VecStore {
    /// A store of `cells` cells and `bins` grid bin offsets (`bins − 1`
    /// bins).
    #[must_use]
    pub fn new(cells: usize, bins: usize) -> VecStore {
        VecStore {
            pos: vec![[0; 2]; cells],
            kind: vec![0; cells],
            next_division: vec![0; cells],
            order: vec![0; cells],
            push: vec![[0; 2]; cells],
            bins: vec![0; bins],
        }
    }

    /// A store sized for a run of `params`:
    /// [`host_capacity`](mosaics::host_capacity) cells and a quarter as many
    /// bins.
    #[must_use]
    pub fn for_params(params: &Params) -> VecStore {
        let cells = mosaics::host_capacity(params);
        VecStore::new(cells, cells / 4 + 1)
    }
}

impl CellStore for VecStore {
    fn capacity(&self) -> usize {
        self.pos.len()
    }

    fn slices(&mut self) -> CellSlices<'_> {
        CellSlices {
            pos: &mut self.pos,
            kind: &mut self.kind,
            next_division: &mut self.next_division,
            order: &mut self.order,
            push: &mut self.push,
            bins: &mut self.bins,
        }
    }

    fn positions(&self) -> &[[i32; 2]] {
        &self.pos
    }

    fn kinds(&self) -> &[u8] {
        &self.kind
    }
}

/// A mosaic run on the host: a big one, or any with a user's mask
/// ([`crate::exec::with_mask`]).
#[derive(Debug)]
pub struct HostPreset {
    /// The name used on the command line and in stream headers.
    pub name: &'static str,
    /// One line for `morphogen list`.
    pub summary: &'static str,
    /// The seed used when none is given.
    pub default_seed: u64,
    /// The mosaic's parameters (the core's).
    pub params: &'static Params,
}

impl HostPreset {
    /// The cells its store holds ([`mosaics::host_capacity`]).
    #[must_use]
    pub fn capacity(&self) -> usize {
        mosaics::host_capacity(self.params)
    }

    /// Why it is host only, for `morphogen list` (the firmware report reads
    /// it there).
    #[must_use]
    pub fn host_only_note(&self) -> String {
        let cells = self.capacity();
        let bytes = cells * CELL_BYTES + (cells / 4 + 1) * 4;
        format!(
            "host only: a {cells}-cell store ({:.1} MB) exceeds an MCU; croton-mcu is the firmware size",
            bytes as f64 / 1e6
        )
    }

    /// A fresh, unstarted mosaic on a heap store sized for this preset.
    #[must_use]
    pub fn mosaic(&self) -> Mosaic<VecStore> {
        Mosaic::new(VecStore::for_params(self.params))
    }
}

impl HostPreset {
    /// Runs this preset to the end, exactly as [`morphogen::preset::run`]
    /// runs a core preset: the header, then every step, reporting progress.
    ///
    /// # Errors
    /// The mosaic's errors (a bad parameter, the capacity), or a full sink.
    pub fn run(
        &self,
        seed: u64,
        sink: &mut dyn Sink,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<(), morphogen::Error> {
        let mut mosaic = self.mosaic();
        mosaic.start(self.params, seed)?;
        sink.record(&preset::header(self.name, seed, params_digest(self.params)))?;
        loop {
            let p = mosaic.step(sink)?;
            progress(p);
            if p.finished() {
                return Ok(());
            }
        }
    }
}

/// Every host-only preset, in `morphogen list` order (after the core's).
pub static HOST_PRESETS: &[HostPreset] = &[
    HostPreset {
        name: "croton",
        summary: "MClone Codiaeum variegatum: 2 000 cells growing ~10x over 35 days, days 0/10/20/35 (thesis Fig. 4.1, Table 4.1; host only)",
        default_seed: 1,
        params: &mosaics::CROTON,
    },
    HostPreset {
        name: "croton-ageing",
        summary: "MClone croton ageing: 10 000 cells, fast yellow F, days 5/15/20/30 of one run (thesis Fig. 4.3; host only)",
        default_seed: 1,
        params: &mosaics::CROTON_AGEING,
    },
    HostPreset {
        name: "cactus-spots",
        summary: "MClone Cereus hildmannianus spots: 5 000 cells on a stem, F 0.2 %, w_r 4, 25 days (thesis Fig. 4.8; host only)",
        default_seed: 1,
        params: &mosaics::CACTUS_SPOTS,
    },
    HostPreset {
        name: "philodendron",
        summary: "MClone Philodendron oxycardium: central F mask, outward IMQ-RBF anisotropy, 25 days (thesis Fig. 4.10; host only)",
        default_seed: 1,
        params: &mosaics::PHILODENDRON,
    },
    HostPreset {
        name: "watermelon",
        summary: "MClone watermelon stripes on a cylinder: stripe mask, w_r 2, 20 days (thesis Fig. 4.16 middle; host only)",
        default_seed: 1,
        params: &mosaics::WATERMELON,
    },
    HostPreset {
        name: "watermelon-narrow",
        summary: "MClone watermelon stripes with w_r 1 (thesis Fig. 4.16 left; host only)",
        default_seed: 1,
        params: &mosaics::WATERMELON_NARROW,
    },
    HostPreset {
        name: "watermelon-wide",
        summary: "MClone watermelon stripes with w_r 3 (thesis Fig. 4.16 right; host only)",
        default_seed: 1,
        params: &mosaics::WATERMELON_WIDE,
    },
    HostPreset {
        name: "amanita",
        summary: "MClone Amanita muscaria cap: red F on the top of a cylinder, w_r 3, D_F 6, 20 days (thesis Fig. 4.15; host only)",
        default_seed: 1,
        params: &mosaics::AMANITA,
    },
    HostPreset {
        name: "sansevieria",
        summary: "MClone Sansevieria trifasciata: 15 000 cells, zig-zag band mask, w_r 0.7, 15 days (thesis Fig. 4.19; host only)",
        default_seed: 1,
        params: &mosaics::SANSEVIERIA,
    },
];

/// The host-only preset called `name`.
#[must_use]
pub fn find(name: &str) -> Option<&'static HostPreset> {
    HOST_PRESETS.iter().find(|p| p.name == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn host_presets_are_not_core_presets_and_use_the_core_params() {
        for p in HOST_PRESETS {
            assert!(morphogen::preset::find(p.name).is_none(), "{}", p.name);
            assert!(std::ptr::eq(
                mosaics::by_name(p.name).expect("core params"),
                p.params
            ));
            let store = VecStore::for_params(p.params);
            assert_eq!(store.capacity(), p.capacity());
        }
    }
}
