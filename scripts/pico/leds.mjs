// The WS2812 chain on the emulated Pico's PIO0 state machine 0, as
// firmware-rp2040 drives it (src/leds.rs): each word the firmware writes
// to the state machine's TX FIFO is one LED, its top 24 bits green, red,
// blue, which the program shifts out to the chain most significant bit
// first. The chain takes each word as it is written (rp2040js runs PIO
// programs on Node's event loop, which this harness's run never yields
// to), so the bytes the LEDs receive are those words' bytes, in the order
// written: the layout of `morphogen run … --rig WxH:ws2812`'s
// rig-WxH-ws2812.bin.

import { writeFileSync } from 'node:fs';

export class LedChain {
  constructor(mcu, file, progress) {
    this.file = file;
    this.pio = mcu.pio[0];
    this.bytes = [];
    this.pio.machines[0].writeFIFO = (word) => {
      this.bytes.push((word >>> 24) & 0xff, (word >>> 16) & 0xff, (word >>> 8) & 0xff);
      progress();
    };
  }

  /** The number of LED colours received. */
  get leds() {
    return this.bytes.length / 3;
  }

  /** Stops PIO0's program (its timer would keep Node running) and writes the bytes, when a file was given. */
  finish() {
    this.pio.stop();
    if (this.file) writeFileSync(this.file, Uint8Array.from(this.bytes));
  }
}
