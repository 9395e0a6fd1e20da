//! What a run costs: an instruction-count proxy from SysTick and the peak
//! stack depth from stack painting.
//!
//! Under QEMU's `-icount shift=0` every instruction advances virtual time
//! by 1 ns, and SysTick counts the modelled CPU clock
//! ([`crate::board::QEMU_CPU_HZ`]), so SysTick deltas are repeatable to the
//! tick: one tick ≈ 20 instructions. (DWT CYCCNT reads 0 in QEMU.)

use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::peripheral::SYST;
use cortex_m::peripheral::syst::SystClkSource;

/// SysTick's largest reload value (24-bit counter).
const RELOAD: u32 = 0x00FF_FFFF;

/// SysTick wrap-arounds; only the SysTick handler writes it (so plain
/// load/store atomics suffice, also on ARMv6-M).
static WRAPS: AtomicU32 = AtomicU32::new(0);

/// Counts one wrap of the 24-bit counter.
pub fn on_systick_wrap() {
    WRAPS.store(
        WRAPS.load(Ordering::Relaxed).wrapping_add(1),
        Ordering::Relaxed,
    );
}

/// A 64-bit tick counter built on SysTick and its wrap interrupt.
/// (Owns SysTick, which has no `Debug`.)
pub struct InstructionClock {
    _syst: SYST,
}

impl InstructionClock {
    /// Starts SysTick on the core clock with the largest reload.
    pub fn start(mut syst: SYST) -> InstructionClock {
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(RELOAD);
        syst.clear_current();
        syst.enable_interrupt();
        syst.enable_counter();
        InstructionClock { _syst: syst }
    }

    /// Ticks since [`InstructionClock::start`].
    pub fn now(&self) -> u64 {
        loop {
            let wraps = WRAPS.load(Ordering::Relaxed);
            let current = SYST::get_current();
            // A wrap between the two reads re-runs the loop.
            if WRAPS.load(Ordering::Relaxed) == wraps {
                return (u64::from(wraps) << 24) | u64::from(RELOAD - current);
            }
        }
    }
}

/// Stack use measured against the paint `cortex-m-rt` (feature
/// `paint-stack`) puts between `_stack_end` (end of `.bss`/`.uninit`) and
/// `_stack_start` (top of RAM) before `main`.
#[derive(Debug)]
pub struct StackPaint {
    /// Deepest stack use since reset, in bytes.
    pub peak_bytes: u32,
    /// The whole stack region, in bytes.
    pub region_bytes: u32,
    /// RAM below the stack region (`.data` + `.bss` + `.uninit`), in bytes.
    pub static_bytes: u32,
}

impl StackPaint {
    /// Scans up from the bottom of the stack region for the first word the
    /// program has overwritten.
    pub fn measure() -> StackPaint {
        unsafe extern "C" {
            static _stack_end: u32;
            static _stack_start: u32;
            static __sdata: u32;
        }
        let bottom = &raw const _stack_end as usize;
        let top = &raw const _stack_start as usize;
        let ram = &raw const __sdata as usize;
        let mut addr = bottom;
        while addr < top {
            // SAFETY: `addr` is word-aligned (the linker script aligns
            // `_stack_end` to 4) and inside RAM; words below the current
            // stack pointer are unused and reading them is harmless.
            let word = unsafe { core::ptr::read_volatile(addr as *const u32) };
            if word != cortex_m_rt::STACK_PAINT_VALUE {
                break;
            }
            addr += 4;
        }
        StackPaint {
            peak_bytes: (top - addr) as u32,
            region_bytes: (top - bottom) as u32,
            static_bytes: (bottom - ram) as u32,
        }
    }
}
