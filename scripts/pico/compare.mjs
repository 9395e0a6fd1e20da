#!/usr/bin/env node
// Compares what a device showed, frame after frame, with the host's frames
// of each preset it ran, in order:
//
//   node compare.mjs --frame-bytes N --label WHAT DEVICE NAME=HOST [NAME=HOST...]
//
// DEVICE holds every frame the emulated device showed (run.mjs --oled);
// each HOST the frames of one preset as `morphogen run NAME --rig …`
// writes them (rig-128x64-ssd1306.bin). The device's frames must be the
// host files' frames one after the other, byte for byte. Prints a line per
// preset; exit status 1 at the first difference, naming the frame and the
// byte, 2 on a usage error.

import { readFileSync } from 'node:fs';
import { parseArgs } from 'node:util';

const { values: args, positionals } = parseArgs({
  allowPositionals: true,
  options: { 'frame-bytes': { type: 'string' }, label: { type: 'string', default: 'frames' } },
});
const frameBytes = Number(args['frame-bytes']);
if (!(frameBytes > 0) || positionals.length < 2) {
  console.error('usage: node compare.mjs --frame-bytes N [--label WHAT] DEVICE NAME=HOST [NAME=HOST...]');
  process.exit(2);
}
const [devicePath, ...presets] = positionals;
const device = readFileSync(devicePath);
if (device.length % frameBytes !== 0) {
  console.error(`${devicePath}: ${device.length} bytes, not whole frames of ${frameBytes}`);
  process.exit(1);
}

let at = 0;
for (const preset of presets) {
  const [name, hostPath] = preset.split('=');
  const host = readFileSync(hostPath);
  const frames = host.length / frameBytes;
  if (!Number.isInteger(frames)) {
    console.error(`${hostPath}: ${host.length} bytes, not whole frames of ${frameBytes}`);
    process.exit(1);
  }
  const shown = device.subarray(at, at + host.length);
  const differs = shown.findIndex((byte, i) => byte !== host[i]);
  if (shown.length < host.length || differs >= 0) {
    const byte = differs >= 0 ? differs : shown.length;
    console.error(
      `${name}: the device's ${args.label} differ from the host's at frame ${Math.floor(byte / frameBytes)} of ${frames}, ` +
        `byte ${byte % frameBytes} (${shown.length < host.length ? 'the device showed fewer frames' : `device 0x${shown[byte].toString(16)}, host 0x${host[byte].toString(16)}`})`,
    );
    process.exit(1);
  }
  console.log(`${name}: ${frames} ${args.label} equal`);
  at += host.length;
}
if (at !== device.length) {
  console.error(`the device showed ${(device.length - at) / frameBytes} ${args.label} more than the host's presets have`);
  process.exit(1);
}
