//! What a run's stack costs: the peak depth from stack painting, on a
//! Cortex-M (`cortex-m-rt` paints the stack). The time a run costs is the
//! board's [`InstructionClock`](crate::board::InstructionClock).

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
    #[allow(
        unsafe_code,
        reason = "reads the painted stack region the linker script places"
    )]
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
