#!/usr/bin/env node
// Runs firmware-rp2040's ELF on an emulated Raspberry Pi Pico (rp2040js)
// and writes what the board sends:
//
//   --uart FILE   every byte of UART0 (the framed streams)
//   --rtt FILE    the defmt log's raw bytes from RTT up-channel 0 (decode
//                 them with `defmt-print -e ELF < FILE`)
//   --oled FILE   every frame the SSD1306 on I2C0 shows (oled.mjs)
//   --leds FILE   every byte the WS2812 chain on PIO0 receives (leds.mjs)
//
// The run ends when the firmware sleeps for good (WFI with no timer
// armed: its end, after the last preset) or when it has run --stall
// emulated seconds (default 120) without a byte on UART0, RTT, I2C0 or
// the LED chain.
// Both are counted in emulated time, so a slow machine only takes longer.
// Exit status 0 at the firmware's end, 1 on a stall, a stray access or
// a command the SSD1306 model refuses.
//
// The emulator starts the image the way the boot ROM would after its own
// checks: at boot stage 2, the first 256 bytes of flash, which sets the
// flash up and jumps to the vector table after it. rp2040js ships no boot
// ROM, and none is loaded: the firmware is built with rp2040-hal's
// `disable-intrinsics`, so it never calls into the ROM.

import { readFileSync, writeFileSync } from 'node:fs';
import { parseArgs } from 'node:util';
import { Simulator } from 'rp2040js';
import { loadElf } from './elf.mjs';
import { fixCarryOverflow } from './flags.mjs';
import { LedChain } from './leds.mjs';
import { Ssd1306 } from './oled.mjs';

const { values: args, positionals } = parseArgs({
  allowPositionals: true,
  options: {
    uart: { type: 'string' },
    rtt: { type: 'string' },
    oled: { type: 'string' },
    leds: { type: 'string' },
    stall: { type: 'string', default: '120' },
  },
});
if (positionals.length !== 1 || !args.uart) {
  console.error(
    'usage: node run.mjs ELF --uart FILE [--rtt FILE] [--oled FILE] [--leds FILE] [--stall SECONDS]',
  );
  process.exit(2);
}
const stallNanos = Number(args.stall) * 1e9;
if (!(stallNanos > 0)) {
  console.error(`--stall ${args.stall}: not a positive number of seconds`);
  process.exit(2);
}

const simulator = new Simulator();
const mcu = simulator.rp2040;
// A stray access (outside memory and peripherals, or an instruction the
// core lacks) ends the run. A peripheral's register that rp2040js does not
// model (UART0's DMA control, I2C0's SDA hold time) is said once and the
// run goes on.
const unmodelled = new Set();
const strayAccess = (component, message) => {
  if (component !== 'RP2040' && component !== 'CortexM0Core') {
    const register = `${component}: ${message.replace(/: 0x[0-9a-f]+$/, '')}`;
    if (!unmodelled.has(register)) console.error(`pico: ${register} (not modelled)`);
    unmodelled.add(register);
    return;
  }
  throw new Error(`${component}: ${message}`);
};
mcu.logger = { debug() {}, info() {}, warn: strayAccess, error: strayAccess };
const { symbols } = loadElf(readFileSync(positionals[0]), mcu);
fixCarryOverflow(mcu.core);
const clock = simulator.clock;
let lastProgress = 0;
const progress = () => {
  lastProgress = clock.nanos;
};

const uart = [];
mcu.uart[0].onByte = (byte) => {
  uart.push(byte);
  progress();
};

const oled = args.oled ? new Ssd1306(mcu.i2c[0], args.oled, progress) : null;
// The firmware always drives its LED chain: without a chain taking the
// words, PIO0's TX FIFO would stay full.
const leds = new LedChain(mcu, args.leds, progress);

// defmt-rtt's control block: "SEGGER RTT" (16 bytes), the numbers of up
// and down channels (2 × u32), then each up channel: name, buffer, size,
// write offset, read offset, flags (6 × u32). The harness is the probe:
// it takes what lies between read and write and moves read on.
const rttBlock = symbols.get('_SEGGER_RTT');
const rtt = [];
function drainRtt() {
  if (rttBlock === undefined) return;
  const channel = rttBlock + 24;
  const buffer = mcu.readUint32(channel + 4);
  const size = mcu.readUint32(channel + 8);
  const write = mcu.readUint32(channel + 12);
  let read = mcu.readUint32(channel + 16);
  if (size === 0 || read === write) return;
  while (read !== write) {
    rtt.push(mcu.readUint8(buffer + read));
    read = (read + 1) % size;
  }
  mcu.writeUint32(channel + 16, read);
  progress();
}

// Boot stage 2 at the start of flash, entered as the boot ROM enters it:
// the stack at the top of SRAM and a zero return address, which makes it
// jump to the vector table after it (RP2040 datasheet, 2.8.1).
mcu.core.SP = 0x20042000;
mcu.core.LR = 0;
mcu.core.PC = 0x10000000;

const cycleNanos = 1e9 / 125e6;
const core = mcu.core;
let ended = false;
let stalled = false;
let failure = null;
const started = Date.now();
try {
  while (!ended && !stalled) {
    for (let i = 0; i < 100_000; i++) {
      if (core.waiting) {
        const next = clock.nanosToNextAlarm;
        if (next <= 0) {
          ended = true;
          break;
        }
        clock.tick(next);
      } else {
        clock.tick(core.executeInstruction() * cycleNanos);
      }
    }
    drainRtt();
    if (clock.nanos - lastProgress > stallNanos) stalled = true;
  }
} catch (error) {
  failure = error;
}
drainRtt();

// What came out until the end, a stall or a failure (a stray access, a
// command the SSD1306 model refuses): the log then says where the
// firmware was.
writeFileSync(args.uart, Uint8Array.from(uart));
if (args.rtt) writeFileSync(args.rtt, Uint8Array.from(rtt));
oled?.finish();
leds.finish();
const seconds = (clock.nanos / 1e9).toFixed(2);
const wall = ((Date.now() - started) / 1000).toFixed(0);
if (failure) {
  console.error(`pico: stopped at ${seconds} emulated s (PC ${core.PC.toString(16)}): ${failure.message}`);
  process.exit(1);
}
if (stalled) {
  console.error(
    `pico: no byte on UART0, RTT, I2C0 or the LED chain for ${args.stall} emulated s: stopped at ${seconds} s (PC ${core.PC.toString(16)})`,
  );
  process.exit(1);
}
console.error(
  `pico: the firmware sleeps after ${seconds} emulated s (${wall} s here); UART0 ${uart.length} B` +
    (oled ? `, ${oled.frames} OLED frames` : '') +
    `, ${leds.leds} LED colours`,
);
