//! A 16×16 matrix of WS2812 LEDs, one serpentine chain on GP22 driven by
//! PIO0's state machine 0: each frame the rig's picture in colour, the
//! bytes `morphogen run … --rig 16x16:ws2812` writes for it (chain order,
//! `smart-leds`' gamma, brightness 255, green, red, blue).
//!
//! The PIO program is the `ws2812-pio` crate's (which still builds on
//! rp2040-hal 0.11): 10 PIO cycles a bit at 800 kbit/s, a 1 high for 7 of
//! them, a 0 for 2 (RP2040 datasheet, 3.6.2 "WS2812 LEDs").

use morphogen::preset::Model;
use morphogen::rig::PALETTE_RGB888;
use morphogen::rig::embedded_graphics::Pixel;
use morphogen::rig::embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use morphogen::rig::embedded_graphics::prelude::{DrawTarget, OriginDimensions, Size};
use rp2040_hal::fugit::HertzU32;
use rp2040_hal::gpio::bank0::Gpio22;
use rp2040_hal::gpio::{FunctionPio0, Pin, PullDown};
use rp2040_hal::pac;
use rp2040_hal::pio::{Buffers, PIOBuilder, PIOExt, PinDir, SM0, ShiftDirection, Tx};
use smart_leds::RGB8;

/// LEDs across and down.
pub const SIDE: u32 = 16;

/// The LEDs of the chain.
const LEDS: usize = (SIDE * SIDE) as usize;

/// The chain's bit rate (WS2812 datasheet: 800 kbit/s).
const BIT_HZ: u32 = 800_000;

/// PIO cycles a bit: start 2, data 5, stop 3.
const CYCLES_PER_BIT: u32 = 10;

/// The ink colours of an L-system's plant on the host (a ramp from bark
/// brown through olive to leaf green and yellow-green:
/// `host-cli/src/outputs/plant.rs`, `palette`), which `--rig` takes for
/// plants; inks past the last share its colour.
const PLANT_INKS: [[u8; 3]; 13] = [
    [101, 67, 33],
    [103, 78, 35],
    [106, 89, 37],
    [108, 99, 38],
    [110, 110, 40],
    [95, 115, 41],
    [80, 120, 43],
    [65, 125, 44],
    [50, 130, 45],
    [75, 146, 51],
    [100, 163, 58],
    [125, 179, 64],
    [150, 195, 70],
];

/// The most colours a palette holds: the background and the plant's inks.
const MAX_COLOURS: usize = 1 + PLANT_INKS.len();

/// The rig's colours for `model` on an RGB matrix, as the host's `--rig`
/// takes them: the background black, then a mosaic's type colours or a
/// plant's inks, else the rig's own RGB palette. Returns the colours and
/// how many of them are used.
pub fn palette(model: &Model<'_>) -> ([Rgb888; MAX_COLOURS], usize) {
    let mut colours = [Rgb888::BLACK; MAX_COLOURS];
    let used = match model {
        Model::Mosaic(p) => 1 + inks(&mut colours[1..], p.types.iter().map(|t| t.colour)),
        Model::LSystem(_) => 1 + inks(&mut colours[1..], PLANT_INKS.iter().copied()),
        Model::GrowthCurve(_) | Model::Horn(_) | Model::Body(_) | Model::Bones(_) => {
            colours[..PALETTE_RGB888.len()].copy_from_slice(&PALETTE_RGB888);
            PALETTE_RGB888.len()
        }
    };
    (colours, used)
}

/// Writes the `colours` into `slots`, as many as fit; returns how many.
fn inks(slots: &mut [Rgb888], colours: impl Iterator<Item = [u8; 3]>) -> usize {
    slots
        .iter_mut()
        .zip(colours)
        .map(|(slot, [r, g, b])| *slot = Rgb888::new(r, g, b))
        .count()
}

/// The matrix's picture, the rig's draw target: a colour per LED, row by
/// row from the top left.
pub struct Matrix {
    pixels: [Rgb888; LEDS],
}

impl Matrix {
    /// A dark matrix.
    pub const fn new() -> Matrix {
        Matrix {
            pixels: [Rgb888::BLACK; LEDS],
        }
    }

    /// The colours in chain order: the first LED at the top left, even
    /// rows left to right, odd rows right to left.
    fn chain(&self) -> impl Iterator<Item = RGB8> + '_ {
        (0..SIDE * SIDE).map(|i| {
            let (row, along) = (i / SIDE, i % SIDE);
            let x = if row % 2 == 1 {
                SIDE - 1 - along
            } else {
                along
            };
            let c = self.pixels[(row * SIDE + x) as usize];
            RGB8::new(c.r(), c.g(), c.b())
        })
    }
}

impl OriginDimensions for Matrix {
    fn size(&self) -> Size {
        Size::new(SIDE, SIDE)
    }
}

impl DrawTarget for Matrix {
    type Color = Rgb888;
    type Error = core::convert::Infallible;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Self::Error>
    where
        I: IntoIterator<Item = Pixel<Rgb888>>,
    {
        for Pixel(p, c) in pixels {
            if let (Ok(x @ 0..SIDE), Ok(y @ 0..SIDE)) = (u32::try_from(p.x), u32::try_from(p.y)) {
                self.pixels[(y * SIDE + x) as usize] = c;
            }
        }
        Ok(())
    }
}

/// The chain's data line: GP22 as PIO0's side-set pin, state machine 0
/// sending each word of its TX FIFO as 24 bits, most significant first.
pub struct Chain {
    tx: Tx<(pac::PIO0, SM0)>,
    _pin: Pin<Gpio22, FunctionPio0, PullDown>,
}

impl Chain {
    /// Loads the WS2812 program into PIO0 and starts state machine 0 on
    /// `pin`, its clock divided from `system_clock` to 10 cycles a bit.
    pub fn new(
        pio0: pac::PIO0,
        pin: Pin<Gpio22, FunctionPio0, PullDown>,
        resets: &mut pac::RESETS,
        system_clock: HertzU32,
    ) -> Chain {
        let (mut pio, sm0, _, _, _) = pio0.split(resets);
        let mut a = pio::Assembler::<{ pio::RP2040_MAX_PROGRAM_SIZE }>::new_with_side_set(
            pio::SideSet::new(false, 1, false),
        );
        let (mut wrap_target, mut wrap_source, mut do_zero) = (a.label(), a.label(), a.label());
        a.bind(&mut wrap_target);
        a.out_with_delay_and_side_set(pio::OutDestination::X, 1, 2, 0);
        a.jmp_with_delay_and_side_set(pio::JmpCondition::XIsZero, &mut do_zero, 1, 1);
        a.jmp_with_delay_and_side_set(pio::JmpCondition::Always, &mut wrap_target, 4, 1);
        a.bind(&mut do_zero);
        a.nop_with_delay_and_side_set(4, 0);
        a.bind(&mut wrap_source);
        let program = a.assemble_with_wrap(wrap_source, wrap_target);
        let Ok(installed) = pio.install(&program) else {
            defmt::panic!("PIO0 has no room for the WS2812 program")
        };
        // In 1/256 of a cycle: 125 MHz / 8 MHz = 15 + 160/256.
        let cycles = u64::from(BIT_HZ * CYCLES_PER_BIT);
        let divisor = u64::from(system_clock.to_Hz()) * 256 / cycles;
        let (int, frac) = ((divisor >> 8) as u16, (divisor & 0xff) as u8);
        let (mut sm, _, tx) = PIOBuilder::from_installed_program(installed)
            .buffers(Buffers::OnlyTx)
            .side_set_pin_base(pin.id().num)
            .out_shift_direction(ShiftDirection::Left)
            .autopull(true)
            .pull_threshold(24)
            .clock_divisor_fixed_point(int, frac)
            .build(sm0);
        sm.set_pindirs([(pin.id().num, PinDir::Output)]);
        sm.start();
        Chain { tx, _pin: pin }
    }

    /// Sends `matrix` down the chain: each LED's colour gamma-corrected as
    /// `smart-leds` does it (brightness 255 leaves it so), green, red,
    /// blue; waits while the TX FIFO is full.
    pub fn show(&mut self, matrix: &Matrix) {
        for c in smart_leds::brightness(smart_leds::gamma(matrix.chain()), u8::MAX) {
            let word = (u32::from(c.g) << 24) | (u32::from(c.r) << 16) | (u32::from(c.b) << 8);
            while !self.tx.write(word) {
                core::hint::spin_loop();
            }
        }
    }
}
