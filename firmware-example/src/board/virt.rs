//! QEMU's RISC-V `virt` machine (`qemu-system-riscv32 -machine virt`, one
//! riscv32imac hart in machine mode): its NS16550A UART at 0x1000_0000
//! carries the streams, `mcycle` counts what a run costs. QEMU's
//! `hw/riscv/virt.c` maps the UART; the registers are the 16550's (TI
//! PC16550D data sheet, table 2).
//!
//! Raw volatile register accesses keep the firmware free of a PAC; each
//! `unsafe` block reads or writes one of the UART's byte registers, which
//! are always mapped.

#![allow(
    unsafe_code,
    reason = "raw volatile register accesses and the semihosting break, without a PAC"
)]

use core::ptr::{read_volatile, write_volatile};

use morphogen::embedded_io::{ErrorType, Write};

/// The UART's base address (`VIRT_UART0`).
const UART0_BASE: usize = 0x1000_0000;
/// Registers (byte offsets): receive buffer / transmit holding, FIFO
/// control, line control, line status.
const UART_RBR_THR: usize = 0;
const UART_FCR: usize = 2;
const UART_LCR: usize = 3;
const UART_LSR: usize = 5;
/// FCR: FIFOs on, both cleared.
const FCR_FIFO_CLEAR: u8 = 0b111;
/// LCR: 8 data bits, no parity, 1 stop bit.
const LCR_8N1: u8 = 0b11;
/// LSR: data ready, transmit holding register empty, transmitter empty.
const LSR_DR: u8 = 1 << 0;
const LSR_THRE: u8 = 1 << 5;
const LSR_TEMT: u8 = 1 << 6;

/// The rate `mcycle` counts at under QEMU's `-icount shift=0`: one cycle
/// per instruction, 1 ns each, so one tick is one instruction.
pub const QEMU_CPU_HZ: u32 = 1_000_000_000;

/// Reads a UART register.
fn read(offset: usize) -> u8 {
    // SAFETY: `offset` is one of the UART's registers above, always mapped
    // on the virt machine; byte reads of LSR have no side effects, of RBR
    // they take the received byte.
    unsafe { read_volatile((UART0_BASE + offset) as *const u8) }
}

/// Writes a UART register.
fn write(offset: usize, value: u8) {
    // SAFETY: as in `read`; the written values follow the data sheet.
    unsafe { write_volatile((UART0_BASE + offset) as *mut u8, value) }
}

/// Nothing to set: QEMU's virt machine has no clock tree.
pub fn init_clock() {}

/// The 16550 UART as an [`embedded_io::Write`](Write): 8N1 (QEMU ignores
/// the line rate). A zero-sized token; [`Uart0::init`] is the only way to
/// get one.
#[derive(Clone, Copy, Debug)]
pub struct Uart0 {
    _private: (),
}

impl Uart0 {
    /// Sets 8N1 and turns the FIFOs on.
    pub fn init() -> Uart0 {
        write(UART_LCR, LCR_8N1);
        write(UART_FCR, FCR_FIFO_CLEAR);
        Uart0 { _private: () }
    }

    /// Waits for a byte and returns it.
    pub fn read_byte(&mut self) -> u8 {
        while read(UART_LSR) & LSR_DR == 0 {}
        read(UART_RBR_THR)
    }
}

/// Writing blocks while the transmit register is full, and never fails.
impl ErrorType for Uart0 {
    type Error = core::convert::Infallible;
}

impl Write for Uart0 {
    fn write(&mut self, bytes: &[u8]) -> Result<usize, Self::Error> {
        self.write_all(bytes)?;
        Ok(bytes.len())
    }

    /// Every byte, without the default's loop (and its panic on `Ok(0)`).
    fn write_all(&mut self, bytes: &[u8]) -> Result<(), Self::Error> {
        for &b in bytes {
            while read(UART_LSR) & LSR_THRE == 0 {}
            write(UART_RBR_THR, b);
        }
        Ok(())
    }

    /// Waits until the last byte has left the transmitter.
    fn flush(&mut self) -> Result<(), Self::Error> {
        while read(UART_LSR) & LSR_TEMT == 0 {}
        Ok(())
    }
}

/// A 64-bit cycle counter: the hart's `mcycle`, which under QEMU's
/// `-icount shift=0` counts instructions, repeatable to the instruction.
#[derive(Debug)]
pub struct InstructionClock {
    _private: (),
}

impl InstructionClock {
    /// The counter (running since reset; any number of handles read it).
    pub fn take() -> Option<InstructionClock> {
        Some(InstructionClock { _private: () })
    }

    /// Cycles since reset.
    pub fn now(&self) -> u64 {
        riscv::register::mcycle::read64()
    }
}

/// Stops the hart (waiting for interrupts, none enabled), for a build
/// without semihosting.
pub fn halt_success() -> ! {
    loop {
        riscv::asm::wfi();
    }
}

/// Stops at a breakpoint, where a debugger sees the failure.
pub fn halt_failure() -> ! {
    loop {
        // SAFETY: `ebreak` traps to the debugger, or to the trap handler,
        // which ends the program; it touches no memory.
        unsafe { riscv::asm::ebreak() };
    }
}
