//! The Raspberry Pi Pico this firmware drives, through `rp2040-hal`: the
//! clocks, UART0 to a USB-UART adapter, I2C0 to an SSD1306 OLED and PIO0
//! to a WS2812 LED matrix.
//!
//! References: the RP2040 datasheet (sections named where used) and the
//! Raspberry Pi Pico datasheet (its pinout, 2.1 "Raspberry Pi Pico
//! Pinout", and its 12 MHz crystal).

use rp2040_hal::Clock;
use rp2040_hal::clocks::init_clocks_and_plls;
use rp2040_hal::fugit::RateExtU32;
use rp2040_hal::gpio::bank0::{Gpio0, Gpio1, Gpio4, Gpio5};
use rp2040_hal::gpio::{FunctionI2C, FunctionPio0, FunctionUart, Pin, Pins, PullDown, PullUp};
use rp2040_hal::i2c::I2C;
use rp2040_hal::pac;
use rp2040_hal::uart::{DataBits, Enabled, StopBits, UartConfig, UartPeripheral};
use rp2040_hal::{Sio, Watchdog};
use ssd1306::mode::{BufferedGraphicsMode, DisplayConfig};
use ssd1306::prelude::{DisplayRotation, DisplaySize128x64, I2CInterface};
use ssd1306::{I2CDisplayInterface, Ssd1306};

use crate::leds::Chain;

/// Boot stage 2 for the Pico's W25Q080 flash: the 256 bytes (with their
/// CRC32) that the bootrom copies to SRAM and runs first to set up
/// execute-in-place (RP2040 datasheet, 2.8.1 "Processor Controlled Boot
/// Sequence"); `memory.x` puts them at the start of flash.
#[allow(unsafe_code, reason = "the boot stage goes where the bootrom reads it")]
#[unsafe(link_section = ".boot2")]
#[unsafe(no_mangle)]
#[used]
pub static BOOT2_FIRMWARE: [u8; 256] = rp2040_boot2::BOOT_LOADER_W25Q080;

/// The Pico's crystal (Pico datasheet; RP2040 datasheet, 2.16 "Crystal
/// Oscillator (XOSC)"), from which the HAL sets the PLLs up for a 125 MHz
/// system clock and a 125 MHz peripheral clock (RP2040 datasheet, 2.15
/// "Clocks", 2.18 "PLL").
const XTAL_HZ: u32 = 12_000_000;

/// UART0's line rate: 115 200 baud, 8 data bits, no parity, 1 stop bit
/// (what `morphogen listen` expects by default).
pub const BAUD: u32 = 115_200;

/// The OLED's I²C clock: fast mode (RP2040 datasheet, 4.3 "I2C"; the
/// SSD1306 takes up to 400 kHz). A 128×64 frame is 1 KiB: about 25 ms.
const I2C_HZ: u32 = 400_000;

/// UART0 on GP0 (TX, to the adapter's RX) and GP1 (RX, unused): function
/// F2 of these pins (RP2040 datasheet, 2.19.2 "Function Select"; 4.2
/// "UART"). An `embedded_io::Write` of the core's own `embedded-io` 0.7.
pub type Uart = UartPeripheral<
    Enabled,
    pac::UART0,
    (
        Pin<Gpio0, FunctionUart, PullDown>,
        Pin<Gpio1, FunctionUart, PullDown>,
    ),
>;

/// I2C0 on GP4 (SDA) and GP5 (SCL), function F3, with the pads' pull-ups
/// on (RP2040 datasheet, 2.19.2 "Function Select", 4.3 "I2C"; most OLED
/// modules carry their own pull-ups too).
type OledI2c = I2C<
    pac::I2C0,
    (
        Pin<Gpio4, FunctionI2C, PullUp>,
        Pin<Gpio5, FunctionI2C, PullUp>,
    ),
>;

/// A 128×64 SSD1306 on I2C0 at address 0x3C, drawn into a 1 KiB buffer in
/// RAM and sent to the panel by `flush`.
pub type Oled =
    Ssd1306<I2CInterface<OledI2c>, DisplaySize128x64, BufferedGraphicsMode<DisplaySize128x64>>;

/// What the firmware uses of the board.
pub struct Board {
    /// UART0, 115 200 8N1.
    pub uart: Uart,
    /// The OLED, or `None` when none answers on I2C0 (the presets still
    /// stream).
    pub oled: Option<Oled>,
    /// The WS2812 chain on GP22 (PIO0), which has no way to answer: the
    /// firmware always drives it.
    pub leds: Chain,
}

impl Board {
    /// Sets the clocks up from the crystal, then UART0, the OLED and the
    /// LED chain.
    pub fn init() -> Board {
        let Some(mut pac) = pac::Peripherals::take() else {
            defmt::panic!("the peripherals were taken twice")
        };
        let mut watchdog = Watchdog::new(pac.WATCHDOG);
        let Ok(clocks) = init_clocks_and_plls(
            XTAL_HZ,
            pac.XOSC,
            pac.CLOCKS,
            pac.PLL_SYS,
            pac.PLL_USB,
            &mut pac.RESETS,
            &mut watchdog,
        ) else {
            defmt::panic!("the crystal oscillator or a PLL did not start")
        };
        let sio = Sio::new(pac.SIO);
        let pins = Pins::new(
            pac.IO_BANK0,
            pac.PADS_BANK0,
            sio.gpio_bank0,
            &mut pac.RESETS,
        );

        let uart_pins = (
            pins.gpio0.into_function::<FunctionUart>(),
            pins.gpio1.into_function::<FunctionUart>(),
        );
        let config = UartConfig::new(BAUD.Hz(), DataBits::Eight, None, StopBits::One);
        let Ok(uart) = UartPeripheral::new(pac.UART0, uart_pins, &mut pac.RESETS)
            .enable(config, clocks.peripheral_clock.freq())
        else {
            defmt::panic!("UART0 cannot make {=u32} baud", BAUD)
        };

        let leds = Chain::new(
            pac.PIO0,
            pins.gpio22.into_function::<FunctionPio0>(),
            &mut pac.RESETS,
            clocks.system_clock.freq(),
        );

        let i2c: OledI2c = I2C::i2c0(
            pac.I2C0,
            pins.gpio4.reconfigure(),
            pins.gpio5.reconfigure(),
            I2C_HZ.Hz(),
            &mut pac.RESETS,
            clocks.system_clock.freq(),
        );
        let mut oled = Ssd1306::new(
            I2CDisplayInterface::new(i2c),
            DisplaySize128x64,
            DisplayRotation::Rotate0,
        )
        .into_buffered_graphics_mode();
        let oled = match oled.init() {
            Ok(()) => Some(oled),
            Err(_) => {
                defmt::warn!("no SSD1306 answers at 0x3C on I2C0 (GP4/GP5): streaming only");
                None
            }
        };
        Board { uart, oled, leds }
    }
}
