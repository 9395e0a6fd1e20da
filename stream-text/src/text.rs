//! The text of numbers in the output files (`records.jsonl`, CSV, OBJ),
//! appended to a line buffer: integers by `itoa`, fixed-point values
//! (`Fx`, I16F16) as their exact decimal expansion read off the bits, and
//! computed `f64` values in Rust's shortest form or rounded to 5 decimals
//! (from the float's bits, as the formatter would, at a tenth the cost).
//!
//! An `Fx` is `bits / 65536`, whose decimal expansion ends after at most
//! 16 fractional digits; [`fx`] prints every one of them, with no `f64` in
//! between. For values of up to 15 significant digits this is the same
//! text as the shortest round-trip `f64` form; longer values (e.g.
//! `1.0000152587890625`) show all their digits, which that form rounds.

use std::fmt::Write as _;

use morphogen::fx::Fx;

/// How an `Fx` with no fractional part is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Whole {
    /// `1` (CSV, OBJ: as Rust prints a whole `f64`).
    Bare,
    /// `1.0` (JSON: a number that reads back as a float).
    PointZero,
}

/// Appends the integer `n`.
pub fn int(out: &mut Vec<u8>, n: impl itoa::Integer) {
    out.extend_from_slice(itoa::Buffer::new().format(n).as_bytes());
}

/// Appends the exact decimal value of `v`, whole numbers written as
/// `whole` says.
///
/// The fraction is 16 bits `f`, worth `f / 2¹⁶ = f · 5¹⁶ / 10¹⁶`: its 16
/// decimals are those of the integer `f · 5¹⁶` (below 2¹⁶ · 5¹⁶ < 10¹⁶,
/// so a `u64`), zero-padded to 16 digits, trailing zeros cut. Hand-written:
/// fixed-point crates print the shortest text that reads back (not every
/// digit), and float printers would need the `f64` round trip.
pub fn fx(out: &mut Vec<u8>, v: Fx, whole: Whole) {
    /// 5¹⁶: one 2⁻¹⁶ in units of 10⁻¹⁶.
    const UNIT: u64 = 152_587_890_625;
    let bits = v.to_bits();
    if bits < 0 {
        out.push(b'-');
    }
    let magnitude = bits.unsigned_abs();
    int(out, magnitude >> 16);
    let fraction = u64::from(magnitude & 0xffff);
    if fraction == 0 {
        if whole == Whole::PointZero {
            out.extend_from_slice(b".0");
        }
        return;
    }
    let mut digits = [b'.'; 17];
    // Below 10¹⁶: the 16 digits after the point.
    let decimals = fraction * UNIT;
    let (high, low) = (decimals / 100_000_000, decimals % 100_000_000);
    eight_digits(&mut digits[1..9], high);
    eight_digits(&mut digits[9..17], low);
    // `fraction / 2¹⁶` with `fraction = odd · 2ᵏ` (k < 16) has exactly
    // 16 − k decimals, the last one not 0.
    let end = 16 - fraction.trailing_zeros() as usize;
    out.extend_from_slice(&digits[..=end]);
}

/// The two digits of each number below 100, `00` to `99`.
const PAIRS: &[u8; 200] = b"0001020304050607080910111213141516171819\
        2021222324252627282930313233343536373839\
        4041424344454647484950515253545556575859\
        6061626364656667686970717273747576777879\
        8081828384858687888990919293949596979899";

/// Writes `n` (below 10⁸) as exactly 8 digits, zero-padded, into `out`.
fn eight_digits(out: &mut [u8], n: u64) {
    // Each quotient is below 100.
    let n = n as u32;
    let (upper, lower) = (n / 10_000, n % 10_000);
    for (k, pair) in [upper / 100, upper % 100, lower / 100, lower % 100]
        .into_iter()
        .enumerate()
    {
        let at = 2 * pair as usize;
        out[2 * k..2 * k + 2].copy_from_slice(&PAIRS[at..at + 2]);
    }
}

/// Appends `x` rounded to 5 decimals exactly as `format!("{:.5}", x)`
/// prints it (ties to even on the exact binary value, `-` on every
/// negative value, `-0.00000` included), in integers.
///
/// A finite `x` is `m · 2^e` with `m < 2⁵³`; below 2⁴⁰, `e < 0` and
/// `x · 10⁵ = m · 10⁵ / 2^−e`, whose numerator (< 2⁷⁰) fits a `u128`, so
/// the quotient and the rest are exact, and the rounded quotient
/// (< 2⁵⁷) fits a `u64`. Larger or non-finite values (no picture holds
/// one) go through the formatter.
pub fn decimals_5(out: &mut Vec<u8>, x: f64) {
    const LIMIT: f64 = (1u64 << 40) as f64;
    if !x.is_finite() || x.abs() >= LIMIT {
        let mut s = String::new();
        let _ = write!(s, "{x:.5}");
        out.extend_from_slice(s.as_bytes());
        return;
    }
    let bits = x.to_bits();
    let biased = (bits >> 52) & 0x7ff;
    let fraction = bits & ((1 << 52) - 1);
    // Subnormals have exponent −1074 and no hidden bit.
    let (mantissa, shift) = if biased == 0 {
        (fraction, 1074)
    } else {
        (fraction | 1 << 52, 1075 - biased)
    };
    let scaled = u128::from(mantissa) * 100_000;
    // `shift` > 12 below 2⁴⁰; past 127 the value is far below half a unit.
    let rounded = if shift > 127 {
        0
    } else {
        let (quotient, rest) = ((scaled >> shift) as u64, scaled & ((1 << shift) - 1));
        let half = 1u128 << (shift - 1);
        match rest.cmp(&half) {
            std::cmp::Ordering::Greater => quotient + 1,
            std::cmp::Ordering::Equal => quotient + (quotient & 1),
            std::cmp::Ordering::Less => quotient,
        }
    };
    if x.is_sign_negative() {
        out.push(b'-');
    }
    int(out, rounded / 100_000);
    // Below 10⁵: the first digit, then two pairs.
    let rest = (rounded % 100_000) as u32;
    let (first, pairs) = (rest / 10_000, rest % 10_000);
    let pair = |n: u32| {
        let at = 2 * n as usize;
        [PAIRS[at], PAIRS[at + 1]]
    };
    let ([a, b], [c, d]) = (pair(pairs / 100), pair(pairs % 100));
    // `first` is below 10.
    out.extend_from_slice(&[b'.', b'0' + first as u8, a, b, c, d]);
}

/// `x` as a fixed-point value, when it is one exactly (every coordinate
/// read from a stream, before any arithmetic).
fn as_fx(x: f64) -> Option<Fx> {
    let bits = x * 65_536.0;
    // Whole and in range: the conversion is exact.
    (bits.fract() == 0.0 && (f64::from(i32::MIN)..=f64::from(i32::MAX)).contains(&bits))
        .then(|| Fx::from_bits(bits as i32))
}

/// Appends `x` in full: a fixed-point value exactly ([`fx`]), a computed
/// one as the shortest text that reads back to it (as Rust's `{}`, by
/// `ryu`; where two shortest texts are equally near, ryu's may differ
/// from Rust's in the last digit).
pub fn float(out: &mut Vec<u8>, x: f64) {
    if let Some(v) = as_fx(x) {
        return fx(out, v, Whole::Bare);
    }
    let mut buffer = ryu::Buffer::new();
    let text = buffer.format(x);
    // ryu writes whole numbers as `1.0` and very small or large ones with
    // an exponent; Rust's `{}` writes `1` and never uses an exponent.
    if let Some(bare) = text.strip_suffix(".0") {
        out.extend_from_slice(bare.as_bytes());
    } else if text.bytes().any(|b| matches!(b, b'e' | b'N' | b'i')) {
        let mut s = String::new();
        let _ = write!(s, "{x}");
        out.extend_from_slice(s.as_bytes());
    } else {
        out.extend_from_slice(text.as_bytes());
    }
}

/// `x` with at most `decimals` decimals, trailing zeros cut (`2.5`,
/// `3`, `0.08`): a frame label's number.
#[must_use]
pub fn trimmed(x: f64, decimals: usize) -> String {
    let text = format!("{x:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text(f: impl Fn(&mut Vec<u8>)) -> String {
        let mut out = Vec::new();
        f(&mut out);
        String::from_utf8(out).unwrap()
    }

    fn exact(bits: i32, whole: Whole) -> String {
        text(|o| fx(o, Fx::from_bits(bits), whole))
    }

    #[test]
    fn fixed_point_values_print_every_digit() {
        assert_eq!(exact(0, Whole::PointZero), "0.0");
        assert_eq!(exact(0, Whole::Bare), "0");
        assert_eq!(exact(65_536, Whole::PointZero), "1.0");
        assert_eq!(exact(-65_536 * 3, Whole::Bare), "-3");
        assert_eq!(exact(1, Whole::Bare), "0.0000152587890625");
        assert_eq!(exact(-1, Whole::Bare), "-0.0000152587890625");
        assert_eq!(exact(65_537, Whole::Bare), "1.0000152587890625");
        assert_eq!(exact(i32::MAX, Whole::Bare), "32767.9999847412109375");
        assert_eq!(exact(i32::MIN, Whole::PointZero), "-32768.0");
        assert_eq!(exact(98_304, Whole::PointZero), "1.5");
    }

    #[test]
    fn short_values_match_the_shortest_f64_text() {
        // Up to 15 significant digits the exact text is the shortest one
        // (f64 keeps 15 digits apart), so earlier files read the same.
        for bits in (-3_000_000..3_000_000).step_by(7) {
            let e = exact(bits, Whole::Bare);
            let shortest = format!("{}", f64::from(bits) / 65_536.0);
            let significant = e
                .trim_start_matches('-')
                .trim_start_matches(['0', '.'])
                .bytes()
                .filter(u8::is_ascii_digit)
                .count();
            if significant <= 15 {
                assert_eq!(e, shortest, "bits {bits}");
            }
            let back: f64 = e.parse().unwrap();
            assert_eq!(back, f64::from(bits) / 65_536.0, "bits {bits}");
            let json: f64 = exact(bits, Whole::PointZero).parse().unwrap();
            assert_eq!(json, back, "bits {bits}");
        }
    }

    #[test]
    fn five_decimals_match_rust_formatting() {
        let samples = (-70_000..70_000)
            .chain((0..4_000).map(|k| k * 524_287 - 1_000_000_000))
            .chain([i32::MIN, i32::MAX, i32::MIN + 1]);
        for bits in samples {
            let x = f64::from(bits) / 65_536.0;
            let ours = text(|o| decimals_5(o, x));
            let rust = format!("{x:.5}");
            assert_eq!(ours, rust, "bits {bits}");
        }
    }

    #[test]
    fn five_decimals_of_any_f64_match_rust_formatting() {
        let named = [
            0.1,
            -2.5e-6,
            1.0 / 3.0,
            7.0,
            65_537.0 / 65_536.0,
            1e12,
            0.000_005,
            0.000_015,
            -0.000_025,
            2.675,
            -0.0,
            f64::MIN_POSITIVE,
            5e-324,
            4.5e15,
            1_099_511_627_775.999_9,
            -1_099_511_627_776.0,
            1e300,
            f64::NAN,
            f64::NEG_INFINITY,
        ];
        // Quotients like the computed points' and colours' (k / 255),
        // and ties (n + ½) · 10⁻⁵ near exact.
        let computed = (0..200_000).map(|k| f64::from(k - 100_000) * 0.731 / 255.0);
        let ties = (0..20_000).map(|n| (f64::from(n) + 0.5) / 100_000.0);
        for x in named.into_iter().chain(computed).chain(ties) {
            assert_eq!(text(|o| decimals_5(o, x)), format!("{x:.5}"), "{x:e}");
        }
    }

    #[test]
    fn floats_print_as_rust_does() {
        for x in [
            0.0,
            1.0,
            -2.0,
            0.1,
            1e-7,
            -3.5e-12,
            123_456.789,
            1e21,
            0.3333333333333333,
        ] {
            assert_eq!(text(|o| float(o, x)), format!("{x}"));
        }
        // A fixed-point value prints exactly, not as the shortest f64.
        assert_eq!(
            text(|o| float(o, 576_357.0 / 65_536.0)),
            "8.7945098876953125"
        );
    }
}
