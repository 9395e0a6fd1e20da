//! The board's OLED: an OSRAM Pictiva 128×64 panel with 16 grey levels,
//! driven by a Solomon SSD0323 over SSI0, as QEMU's `lm3s6965evb` wires it
//! (`hw/arm/stellaris.c`): SSI0 clock and data on PA2/PA5, the D/C line
//! (low = command, high = data) on PC7, and PD0 high to select the OLED
//! rather than the SD card that shares the bus. Registers from the LM3S6965
//! data sheet, rev. 2008, chapter 14 "Synchronous Serial Interface";
//! commands from the SSD0323 data sheet, rev. 1.0, section 8.
//!
//! The picture is drawn into a [`Frame`], an `embedded-graphics`
//! framebuffer whose bytes are the controller's: two pixels per byte, the
//! left one in the high nibble, rows top to bottom ([`Oled::show`] sends
//! them as they are). Checked in QEMU, whose model ignores the panel's
//! timing commands; on a real board compare `INIT` with TI's
//! `osram128x64x4` driver first.

use morphogen::rig::embedded_graphics::framebuffer::{Framebuffer, buffer_size};
use morphogen::rig::embedded_graphics::geometry::Size;
use morphogen::rig::embedded_graphics::pixelcolor::Gray4;
use morphogen::rig::embedded_graphics::pixelcolor::raw::BigEndian;
use morphogen::rig::embedded_graphics::pixelcolor::raw::RawU4;

use crate::board::{
    GPIO_AFSEL, GPIO_DEN, GPIO_DIR, GPIOA, GPIOC, GPIOD, SYSCTL_RCGC1, SYSCTL_RCGC2, modify, read,
    write,
};

/// The panel's pixels across and down.
pub const WIDTH: usize = 128;
/// See [`WIDTH`].
pub const HEIGHT: usize = 64;
/// The panel's size for `embedded-graphics`.
pub const SIZE: Size = Size::new(WIDTH as u32, HEIGHT as u32);
/// Bytes of a frame: 4 bits per pixel.
const FRAME_BYTES: usize = buffer_size::<Gray4>(WIDTH, HEIGHT);

/// A picture for the OLED: 4 KiB, in the controller's byte order.
pub type Frame = Framebuffer<Gray4, RawU4, BigEndian, WIDTH, HEIGHT, FRAME_BYTES>;

/// SSI0's registers: control 0 and 1, data, status, clock prescale.
const SSI0: usize = 0x4000_8000;
const SSI_CR0: usize = SSI0;
const SSI_CR1: usize = SSI0 + 0x04;
const SSI_DR: usize = SSI0 + 0x08;
const SSI_SR: usize = SSI0 + 0x0C;
const SSI_CPSR: usize = SSI0 + 0x10;
/// CR0: 8-bit frames (DSS = 7), Freescale SPI mode 3 (SPO = SPH = 1),
/// serial clock rate 0: SSIClk = SysClk / CPSR.
const CR0_8BIT_MODE3: u32 = 0x7 | 1 << 6 | 1 << 7;
/// CR1: SSI enable (master).
const CR1_SSE: u32 = 1 << 1;
/// Prescale 2: 4 MHz from the 8 MHz clock (the SSD0323 takes ≤ 10 MHz).
const CPSR_DIV2: u32 = 2;
/// Status: transmit FIFO not full, receive FIFO not empty, busy.
const SR_TNF: u32 = 1 << 1;
const SR_RNE: u32 = 1 << 2;
const SR_BSY: u32 = 1 << 4;
/// PA2 = SSI0Clk, PA3 = SSI0Fss, PA4 = SSI0Rx, PA5 = SSI0Tx.
const SSI0_PINS: u32 = 0b11_1100;
/// PC7: the controller's D/C input.
const DC_PIN: u32 = 1 << 7;
/// PD0: high selects the OLED (and deselects the SD card).
const SELECT_PIN: u32 = 1 << 0;

/// Start-up commands (SSD0323 data sheet, table 8-1): display off, the
/// whole 64×64-byte window, contrast, remap for this panel (COM split,
/// column address wrap), 64 rows, clock and phase settings, a linear grey
/// table, display on.
const INIT: [u8; 35] = [
    0xAE, // display off
    0x15, 0x00, 0x3F, // columns 0..63 (two pixels each)
    0x75, 0x00, 0x3F, // rows 0..63
    0x81, 0x33, // contrast
    0x85, // full current range
    0xA0, 0x40, // remap: COM split odd/even, horizontal address increment
    0xA1, 0x00, // display start line 0
    0xA2, 0x00, // display offset 0
    0xA4, // normal display
    0xA8, 0x3F, // multiplex ratio: 64 rows
    0xB1, 0x22, // phase length
    0xB2, 0x46, // row period
    0xB3, 0x91, // clock divider
    0xB8, 0x01, 0x11, 0x22, 0x32, 0x43, 0x54, 0x65, 0x76, // grey table
    0xAF, // display on
];
/// Puts the address pointer back at the top-left pixel.
const HOME: [u8; 6] = [0x15, 0x00, 0x3F, 0x75, 0x00, 0x3F];

/// The OLED, ready to show frames. A zero-sized token; [`Oled::init`] is
/// the only way to get one.
#[derive(Debug)]
pub struct Oled {
    _private: (),
}

impl Oled {
    /// Clocks SSI0 and ports A, C and D, selects the OLED, and sends the
    /// start-up commands.
    pub fn init() -> Oled {
        modify(SYSCTL_RCGC1, |v| v | 1 << 4);
        modify(SYSCTL_RCGC2, |v| v | 0b1101);
        cortex_m::asm::delay(16); // a few clocks before the gated blocks answer
        modify(GPIOA + GPIO_AFSEL, |v| v | SSI0_PINS);
        modify(GPIOA + GPIO_DEN, |v| v | SSI0_PINS);
        for (port, pin) in [(GPIOC, DC_PIN), (GPIOD, SELECT_PIN)] {
            modify(port + GPIO_DIR, |v| v | pin);
            modify(port + GPIO_DEN, |v| v | pin);
        }
        write(GPIOD + ((SELECT_PIN as usize) << 2), SELECT_PIN);
        write(SSI_CR1, 0);
        write(SSI_CPSR, CPSR_DIV2);
        write(SSI_CR0, CR0_8BIT_MODE3);
        write(SSI_CR1, CR1_SSE);
        let mut oled = Oled { _private: () };
        oled.send(Mode::Command, &INIT);
        oled
    }

    /// Shows `frame`: 4 KiB over SSI, about 8 ms at 4 MHz.
    pub fn show(&mut self, frame: &Frame) {
        self.send(Mode::Command, &HOME);
        self.send(Mode::Data, frame.data());
    }

    /// Sets D/C for `mode` once the bus is idle, then clocks `bytes` out,
    /// reading back (and dropping) what the receive FIFO collects.
    fn send(&mut self, mode: Mode, bytes: &[u8]) {
        while read(SSI_SR) & SR_BSY != 0 {}
        let level = match mode {
            Mode::Command => 0,
            Mode::Data => DC_PIN,
        };
        write(GPIOC + ((DC_PIN as usize) << 2), level);
        for &b in bytes {
            while read(SSI_SR) & SR_TNF == 0 {}
            write(SSI_DR, u32::from(b));
            while read(SSI_SR) & SR_RNE == 0 {}
            read(SSI_DR);
        }
    }
}

/// What the controller takes the next bytes as.
#[derive(Clone, Copy, Debug)]
enum Mode {
    Command,
    Data,
}
