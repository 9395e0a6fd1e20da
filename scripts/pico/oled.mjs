// A 128×64 SSD1306 at I²C address 0x3C on the emulated Pico's I2C0, as
// firmware-rp2040 drives it through the `ssd1306` crate: every write is a
// control byte (0x00: commands follow, 0x40: display data follows) and its
// bytes; data fills the display RAM (8 pages of 128 columns, a byte is 8
// pixels down, the lowest bit on top) through the column and page window
// the commands set, in horizontal addressing mode. Each time a write
// reaches the window's last byte the panel shows a new frame. The frames
// go to a file as the panel shows them, in the layout of the display RAM
// (8 pages of 128 bytes a frame, the lowest bit on top, lit 1): the layout
// of `morphogen run … --rig 128x64:mono`'s rig-128x64-ssd1306.bin.

import { writeFileSync } from 'node:fs';
import { I2CMode } from 'rp2040js';

const ADDRESS = 0x3c;
const WIDTH = 128;
const PAGES = 8;

/** The number of argument bytes each command takes (SSD1306 datasheet, 9 "Command Table"). */
function argumentCount(command) {
  switch (command) {
    case 0x81: // contrast
    case 0x8d: // charge pump
    case 0x20: // addressing mode
    case 0xa8: // multiplex ratio
    case 0xd3: // display offset
    case 0xd5: // clock divide
    case 0xd9: // pre-charge period
    case 0xda: // COM pins
    case 0xdb: // VCOMH level
      return 1;
    case 0x21: // column window
    case 0x22: // page window
    case 0xa3: // vertical scroll area
      return 2;
    case 0x29:
    case 0x2a: // vertical and horizontal scroll
      return 5;
    case 0x26:
    case 0x27: // horizontal scroll
      return 6;
    default:
      return 0;
  }
}

export class Ssd1306 {
  constructor(i2c, file, progress) {
    this.file = file;
    this.progress = progress;
    this.ram = new Uint8Array(WIDTH * PAGES);
    this.frames = 0;
    this.out = [];
    // Reset state: page addressing mode, the whole RAM as the window.
    this.mode = 2;
    this.columns = [0, WIDTH - 1];
    this.pages = [0, PAGES - 1];
    this.column = 0;
    this.page = 0;
    this.segmentRemap = false;
    this.comReversed = false;
    this.inverted = false;
    this.addressed = false;
    this.control = null;
    this.command = [];

    i2c.onStart = () => i2c.completeStart();
    i2c.onConnect = (address, mode) => {
      this.addressed = address === ADDRESS && mode === I2CMode.Write;
      this.control = null;
      i2c.completeConnect(this.addressed);
    };
    i2c.onWriteByte = (byte) => {
      this.byte(byte);
      i2c.completeWrite(true);
    };
    i2c.onReadByte = () => {
      throw new Error('SSD1306: the firmware reads from I2C0, which the panel never answers');
    };
    i2c.onStop = () => {
      if (this.command.length > 0) {
        throw new Error(`SSD1306: command 0x${this.command[0].toString(16)} cut short by a stop`);
      }
      i2c.completeStop();
    };
  }

  byte(value) {
    this.progress();
    if (this.control === null) {
      if ((value & 0x3f) !== 0 || value & 0x80) {
        throw new Error(`SSD1306: control byte 0x${value.toString(16)}, not 0x00 or 0x40`);
      }
      this.control = value;
    } else if (this.control === 0x40) {
      this.data(value);
    } else {
      this.command.push(value);
      if (this.command.length === 1 + argumentCount(this.command[0])) {
        this.run(this.command);
        this.command = [];
      }
    }
  }

  run([command, ...args]) {
    switch (command) {
      case 0x20:
        this.mode = args[0] & 3;
        break;
      case 0x21:
        this.columns = [args[0] & 0x7f, args[1] & 0x7f];
        this.column = this.columns[0];
        break;
      case 0x22:
        this.pages = [args[0] & 7, args[1] & 7];
        this.page = this.pages[0];
        break;
      case 0xa0:
      case 0xa1:
        this.segmentRemap = command === 0xa1;
        break;
      case 0xc0:
      case 0xc8:
        this.comReversed = command === 0xc8;
        break;
      case 0xa6:
      case 0xa7:
        this.inverted = command === 0xa7;
        break;
      default:
        if (command >= 0xb0 && command <= 0xb7 && this.mode === 2) this.page = command & 7;
    }
  }

  data(value) {
    if (this.mode !== 0) {
      throw new Error(`SSD1306: display data in addressing mode ${this.mode}; only horizontal (0) is modelled`);
    }
    this.ram[this.page * WIDTH + this.column] = value;
    if (this.column < this.columns[1]) {
      this.column++;
      return;
    }
    this.column = this.columns[0];
    if (this.page < this.pages[1]) {
      this.page++;
      return;
    }
    this.page = this.pages[0];
    this.show();
  }

  /**
   * The panel's picture as display RAM in the upright orientation of the
   * `ssd1306` crate (segment remap on, 0xA1; COM scan reversed, 0xC8:
   * RAM column x shows at x, RAM row y at y); the other settings mirror it.
   */
  show() {
    const frame = new Uint8Array(WIDTH * PAGES);
    for (let y = 0; y < PAGES * 8; y++) {
      const row = this.comReversed ? y : PAGES * 8 - 1 - y;
      for (let x = 0; x < WIDTH; x++) {
        const column = this.segmentRemap ? x : WIDTH - 1 - x;
        const lit = ((this.ram[(row >> 3) * WIDTH + column] >> (row & 7)) & 1) ^ (this.inverted ? 1 : 0);
        frame[(y >> 3) * WIDTH + x] |= lit << (y & 7);
      }
    }
    this.out.push(frame);
    this.frames++;
  }

  finish() {
    const all = new Uint8Array(this.out.length * WIDTH * PAGES);
    this.out.forEach((frame, i) => all.set(frame, i * frame.length));
    writeFileSync(this.file, all);
  }
}
