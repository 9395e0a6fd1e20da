// The loadable segments of a 32-bit little-endian ARM ELF, copied into the
// emulated Pico's flash at their load addresses, and its symbols' values.

const FLASH = 0x10000000;
const PT_LOAD = 1;
const SHT_SYMTAB = 2;

/** Loads `elf` (a Buffer) into `mcu.flash`; returns `{ symbols }`, a Map of name → address. */
export function loadElf(elf, mcu) {
  const view = new DataView(elf.buffer, elf.byteOffset, elf.byteLength);
  if (view.getUint32(0) !== 0x7f454c46 || elf[4] !== 1 || elf[5] !== 1) {
    throw new Error('not a 32-bit little-endian ELF');
  }
  const u16 = (at) => view.getUint16(at, true);
  const u32 = (at) => view.getUint32(at, true);

  const [phoff, phentsize, phnum] = [u32(28), u16(42), u16(44)];
  for (let i = 0; i < phnum; i++) {
    const ph = phoff + i * phentsize;
    const [type, offset, paddr, filesz] = [u32(ph), u32(ph + 4), u32(ph + 12), u32(ph + 16)];
    if (type !== PT_LOAD || filesz === 0) continue;
    if (paddr < FLASH || paddr + filesz > FLASH + mcu.flash.length) {
      throw new Error(`segment at 0x${paddr.toString(16)} is not in flash`);
    }
    mcu.flash.set(elf.subarray(offset, offset + filesz), paddr - FLASH);
  }

  const [shoff, shentsize, shnum] = [u32(32), u16(46), u16(48)];
  const section = (i) => {
    const sh = shoff + i * shentsize;
    return { type: u32(sh + 4), offset: u32(sh + 16), size: u32(sh + 20), link: u32(sh + 24) };
  };
  const symbols = new Map();
  for (let i = 0; i < shnum; i++) {
    const symtab = section(i);
    if (symtab.type !== SHT_SYMTAB) continue;
    const strtab = section(symtab.link);
    for (let at = symtab.offset; at < symtab.offset + symtab.size; at += 16) {
      const nameAt = strtab.offset + u32(at);
      const name = elf.toString('latin1', nameAt, elf.indexOf(0, nameAt));
      if (name) symbols.set(name, u32(at + 4));
    }
  }
  return { symbols };
}
