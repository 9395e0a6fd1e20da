//! The LM3S6965 board support this program needs: the system clock, UART0
//! and UART1, the instruction clock (SysTick), how a run stops, and the
//! register access the OLED driver (`oled.rs`) shares
//! (register addresses and values from the LM3S6965 data sheet, rev. 2008,
//! chapters 6 "System Control", 9 "GPIO" and 13 "UART").
//!
//! Raw volatile register accesses keep the firmware free of a PAC; each
//! `unsafe` block writes a documented, always-mapped peripheral register.

#![allow(
    unsafe_code,
    reason = "raw volatile register accesses and the device vector table, without a PAC"
)]

use core::ptr::{read_volatile, write_volatile};
use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::peripheral::SYST;
use cortex_m::peripheral::syst::SystClkSource;

use morphogen::embedded_io::{ErrorType, Write};

/// The LM3S6965's device interrupts (IRQ 0 to 43, data sheet table 2-9);
/// an ARMv6-M core (the thumbv6m build) takes at most 32.
const INTERRUPTS: usize = if cfg!(armv6m) { 32 } else { 44 };

unsafe extern "C" {
    /// cortex-m-rt's handler for every vector nobody claims.
    fn DefaultHandler();
}

/// The device part of the vector table, every interrupt to the default
/// handler: the firmware enables none (UART0 is polled). Sized for this
/// chip, where cortex-m-rt without its `device` feature reserves the 240
/// vectors of any Cortex-M3 (800 B more of flash).
#[unsafe(link_section = ".vector_table.interrupts")]
#[unsafe(no_mangle)]
static __INTERRUPTS: [unsafe extern "C" fn(); INTERRUPTS] = [DefaultHandler; INTERRUPTS];

/// System control: run-mode clock configuration (RCC).
const SYSCTL_RCC: usize = 0x400F_E060;
/// System control: run-mode clock gating 1 (bit 0 = UART0, 1 = UART1,
/// 4 = SSI0).
pub const SYSCTL_RCGC1: usize = 0x400F_E104;
/// System control: run-mode clock gating 2 (bit n = GPIO port A + n).
pub const SYSCTL_RCGC2: usize = 0x400F_E108;
/// GPIO port A base address; ports B to D follow every 0x1000.
pub const GPIOA: usize = 0x4000_4000;
/// GPIO port C base address.
pub const GPIOC: usize = 0x4000_6000;
/// GPIO port D base address.
pub const GPIOD: usize = 0x4000_7000;
/// GPIO direction (offset; 1 = output). Data is read and written at
/// `base + (mask << 2)`: only the pins in `mask` change.
pub const GPIO_DIR: usize = 0x400;
/// GPIO alternate function select (offset; 1 = the pin's peripheral).
pub const GPIO_AFSEL: usize = 0x420;
/// GPIO digital enable (offset).
pub const GPIO_DEN: usize = 0x51C;

/// UART registers (offsets from the base): data, flags, integer and
/// fractional baud-rate divisors, line control, control.
const UART_DR: usize = 0x00;
const UART_FR: usize = 0x18;
const UART_IBRD: usize = 0x24;
const UART_FBRD: usize = 0x28;
const UART_LCRH: usize = 0x2C;
const UART_CTL: usize = 0x30;
/// Flags: BUSY, RXFE (receive FIFO empty), TXFF (transmit FIFO full).
const FR_BUSY: u32 = 1 << 3;
const FR_RXFE: u32 = 1 << 4;
const FR_TXFF: u32 = 1 << 5;
/// LCRH: 8 data bits (WLEN = 3), FIFOs on; no parity, 1 stop bit.
const LCRH_8N1_FIFO: u32 = (0b11 << 5) | (1 << 4);
/// CTL: UARTEN | TXE | RXE.
const CTL_ENABLE: u32 = (1 << 0) | (1 << 8) | (1 << 9);

/// The system clock on real hardware: the LM3S6965 EVB's 8 MHz crystal,
/// PLL bypassed and powered down, no divider.
pub const SYSCLK_HZ: u32 = 8_000_000;
/// UART0 line rate.
pub const BAUD: u32 = 115_200;
/// Baud divisor = SYSCLK / (16 · BAUD) = 4.3403: integer part…
const IBRD: u32 = SYSCLK_HZ / (16 * BAUD);
/// …and the fraction in 64ths, rounded to nearest: 0.3403 · 64 → 22
/// (115 107 baud, −0.08 %).
const FBRD: u32 = ((SYSCLK_HZ % (16 * BAUD)) * 64 + 8 * BAUD) / (16 * BAUD);
const _: () = assert!(IBRD == 4 && FBRD == 22);

/// RCC fields.
const RCC_MOSCDIS: u32 = 1 << 0;
const RCC_OSCSRC_MASK: u32 = 0b11 << 4;
const RCC_XTAL_MASK: u32 = 0xF << 6;
/// XTAL = 0xB: an 8 MHz crystal.
const RCC_XTAL_8MHZ: u32 = 0xB << 6;
const RCC_BYPASS: u32 = 1 << 11;
const RCC_USESYSDIV: u32 = 1 << 22;
const RCC_SYSDIV_MASK: u32 = 0xF << 23;
/// SYSDIV = 3. Unused on hardware (USESYSDIV = 0 keeps 8 MHz), but QEMU
/// derives its CPU clock from SYSDIV alone (200 MHz / (SYSDIV + 1) =
/// 50 MHz), which makes one SysTick tick 20 instructions under
/// `-icount shift=0` (1 ns per instruction) instead of 80 at reset.
const RCC_SYSDIV_3: u32 = 3 << 23;
/// CPU clock QEMU models with this RCC value.
pub const QEMU_CPU_HZ: u32 = 50_000_000;

/// Reads a peripheral register.
pub fn read(addr: usize) -> u32 {
    // SAFETY: `addr` is one of the peripheral registers above: aligned,
    // always mapped on the LM3S6965, reads have no side effects.
    unsafe { read_volatile(addr as *const u32) }
}

/// Writes a peripheral register.
pub fn write(addr: usize, value: u32) {
    // SAFETY: as in `read`; the written values follow the data sheet.
    unsafe { write_volatile(addr as *mut u32, value) }
}

/// Read-modify-writes a peripheral register.
pub fn modify(addr: usize, f: impl FnOnce(u32) -> u32) {
    write(addr, f(read(addr)));
}

/// Switches the system clock from the ±30 % internal oscillator (reset
/// state) to the 8 MHz crystal, so that UART timing is exact.
pub fn init_clock() {
    // Start the main oscillator, let it settle, then select it.
    modify(SYSCTL_RCC, |rcc| rcc & !RCC_MOSCDIS);
    cortex_m::asm::delay(50_000); // ≥ 4 ms at 12 MHz
    modify(SYSCTL_RCC, |rcc| {
        (rcc & !(RCC_OSCSRC_MASK | RCC_XTAL_MASK | RCC_USESYSDIV | RCC_SYSDIV_MASK))
            | RCC_XTAL_8MHZ
            | RCC_BYPASS
            | RCC_SYSDIV_3
    });
}

/// UART0 carries the streams (PA0 = U0Rx, PA1 = U0Tx).
pub type Uart0 = Uart<0>;
/// UART1 carries the screen handshake of `--screen-sync` (PD2 = U1Rx,
/// PD3 = U1Tx).
pub type Uart1 = Uart<1>;

/// UART `N` as an [`embedded_io::Write`](Write): 115 200 baud, 8N1, no flow
/// control. A zero-sized token; [`Uart::init`] is the only way to get one.
#[derive(Clone, Copy, Debug)]
pub struct Uart<const N: usize> {
    _private: (),
}

impl<const N: usize> Uart<N> {
    /// UART0 at 0x4000_C000, UART1 at 0x4000_D000.
    const BASE: usize = 0x4000_C000 + 0x1000 * N;
    /// Its port (A or D) and pins.
    const PINS: (usize, u32) = if N == 0 {
        (GPIOA, 0b11)
    } else {
        (GPIOD, 0b1100)
    };

    /// Clocks the UART and its port, routes the pins to it and sets
    /// 115 200 8N1.
    pub fn init() -> Uart<N> {
        let (port, pins) = Self::PINS;
        let port_bit = (port - GPIOA) / 0x1000;
        modify(SYSCTL_RCGC1, |v| v | 1 << N);
        modify(SYSCTL_RCGC2, |v| v | 1 << port_bit);
        cortex_m::asm::delay(16); // a few clocks before the gated blocks answer
        modify(port + GPIO_AFSEL, |v| v | pins);
        modify(port + GPIO_DEN, |v| v | pins);
        write(Self::BASE + UART_CTL, 0);
        write(Self::BASE + UART_IBRD, IBRD);
        write(Self::BASE + UART_FBRD, FBRD);
        write(Self::BASE + UART_LCRH, LCRH_8N1_FIFO);
        write(Self::BASE + UART_CTL, CTL_ENABLE);
        Uart { _private: () }
    }

    /// Waits for a byte and returns it.
    pub fn read_byte(&mut self) -> u8 {
        while read(Self::BASE + UART_FR) & FR_RXFE != 0 {}
        // Bits 8..11 are error flags; the data is the low byte.
        (read(Self::BASE + UART_DR) & 0xFF) as u8
    }
}

/// Writing blocks while the transmit FIFO is full, and never fails.
impl<const N: usize> ErrorType for Uart<N> {
    type Error = core::convert::Infallible;
}

impl<const N: usize> Write for Uart<N> {
    fn write(&mut self, bytes: &[u8]) -> Result<usize, Self::Error> {
        self.write_all(bytes)?;
        Ok(bytes.len())
    }

    /// Every byte, without the default's loop (and its panic on `Ok(0)`).
    fn write_all(&mut self, bytes: &[u8]) -> Result<(), Self::Error> {
        for &b in bytes {
            while read(Self::BASE + UART_FR) & FR_TXFF != 0 {}
            write(Self::BASE + UART_DR, u32::from(b));
        }
        Ok(())
    }

    /// Waits until the last byte has left the shift register.
    fn flush(&mut self) -> Result<(), Self::Error> {
        while read(Self::BASE + UART_FR) & FR_BUSY != 0 {}
        Ok(())
    }
}

/// SysTick's largest reload value (24-bit counter).
const RELOAD: u32 = 0x00FF_FFFF;

/// SysTick wrap-arounds; only the SysTick handler writes it (so plain
/// load/store atomics suffice, also on ARMv6-M).
static WRAPS: AtomicU32 = AtomicU32::new(0);

/// Counts one wrap of the 24-bit counter (the program's SysTick handler).
pub fn on_systick_wrap() {
    WRAPS.store(
        WRAPS.load(Ordering::Relaxed).wrapping_add(1),
        Ordering::Relaxed,
    );
}

/// A 64-bit tick counter built on SysTick and its wrap interrupt.
/// (Owns SysTick, which has no `Debug`.)
///
/// Under QEMU's `-icount shift=0` every instruction advances virtual time
/// by 1 ns, and SysTick counts the modelled CPU clock ([`QEMU_CPU_HZ`]),
/// so SysTick deltas are repeatable to the tick: one tick ≈ 20
/// instructions. (DWT CYCCNT reads 0 in QEMU.)
pub struct InstructionClock {
    _syst: SYST,
}

impl core::fmt::Debug for InstructionClock {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("InstructionClock").finish_non_exhaustive()
    }
}

impl InstructionClock {
    /// Takes SysTick (once; `None` after) and starts it on the core clock
    /// with the largest reload.
    pub fn take() -> Option<InstructionClock> {
        let mut syst = cortex_m::Peripherals::take()?.SYST;
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(RELOAD);
        syst.clear_current();
        syst.enable_interrupt();
        syst.enable_counter();
        Some(InstructionClock { _syst: syst })
    }

    /// Ticks since [`InstructionClock::take`].
    pub fn now(&self) -> u64 {
        loop {
            let wraps = WRAPS.load(Ordering::Relaxed);
            let current = SYST::get_current();
            // A wrap between the two reads re-runs the loop. The counter
            // is 24 bits wide, `current <= RELOAD`: the difference never
            // wraps.
            if WRAPS.load(Ordering::Relaxed) == wraps {
                return (u64::from(wraps) << 24) | u64::from(RELOAD.wrapping_sub(current));
            }
        }
    }
}

/// Stops where `probe-rs run` reports success (a breakpoint), for a build
/// without semihosting.
pub fn halt_success() -> ! {
    loop {
        cortex_m::asm::bkpt();
    }
}

/// Stops with a HardFault that `probe-rs run` reports as a failed run.
pub fn halt_failure() -> ! {
    cortex_m::asm::udf()
}
