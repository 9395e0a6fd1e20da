// rp2040js 1.4.1 sets the overflow flag (V) of ADCS and SBCS from the
// second operand plus the carry as one 32-bit number, which is wrong when
// that sum crosses the sign bit: `SBCS` of 0 and 0x7FFFFFFF with a borrow
// sets V, so the 64-bit compare `0 < i64::MAX` comes out false (and
// `i64::min` keeps i64::MAX). Here V is computed from the operands as the
// ARM ARM defines it (AddWithCarry); every other flag and every other
// instruction is the emulator's.

const ADCS = 0b0100000101;
const SBCS = 0b0100000110;

/** Makes `core` (an rp2040js CortexM0Core) set V of ADCS and SBCS as the processor does. */
export function fixCarryOverflow(core) {
  const opcode = () => core.rp2040.readUint16((core.PC - 2) & ~1) >> 6;
  const add = core.addUpdateFlags;
  core.addUpdateFlags = function (addend1, addend2) {
    if (opcode() !== ADCS) return add.call(this, addend1, addend2);
    const carry = this.C ? 1 : 0;
    const result = add.call(this, addend1, addend2);
    const signed = (addend1 | 0) + ((addend2 - carry) | 0) + carry;
    this.V = signed !== (result | 0);
    return result;
  };
  const subtract = core.substractUpdateFlags;
  core.substractUpdateFlags = function (minuend, subtrahend) {
    if (opcode() !== SBCS) return subtract.call(this, minuend, subtrahend);
    const borrow = this.C ? 0 : 1;
    const result = subtract.call(this, minuend, subtrahend);
    const signed = (minuend | 0) - ((subtrahend - borrow) | 0) - borrow;
    this.V = signed !== (result | 0);
    return result;
  };
}
