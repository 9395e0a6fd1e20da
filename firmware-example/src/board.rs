//! The board the program runs on, chosen by the target: the LM3S6965
//! evaluation board on a Cortex-M (`lm3s6965`, QEMU's `lm3s6965evb`), or
//! QEMU's RISC-V `virt` machine on riscv32 (`virt`). Each gives the same
//! names: [`init_clock`], [`Uart0`] (the streams), [`InstructionClock`]
//! (what a run costs), [`QEMU_CPU_HZ`], [`halt_success`] and
//! [`halt_failure`]; the OLED and UART1 are the LM3S6965's alone.

#[cfg(target_arch = "arm")]
mod lm3s6965;
#[cfg(target_arch = "arm")]
pub use lm3s6965::*;

#[cfg(target_arch = "riscv32")]
mod virt;
#[cfg(target_arch = "riscv32")]
pub use virt::*;
