//! The program's arguments: semihosting's command line (QEMU's
//! `-semihosting-config arg=…`). An RTT build has none.

/// Bytes of the command line read (the longest of
/// `scripts/firmware-check.sh`, `morphogen-receiver --screen-sync --streams
/// 14`, has 45).
#[cfg(feature = "semihosting")]
const LINE: usize = 64;

/// Whether `visit` accepts one of the command line's words (the program's
/// name first), visited in order until it does. Words are compared as
/// bytes: semihosting's `Args` would check each for UTF-8 first, in 0.5 KB
/// of flash, for words only ever compared with ASCII.
fn any_word(mut visit: impl FnMut(&[u8]) -> bool) -> bool {
    #[cfg(feature = "semihosting")]
    {
        let mut line = [core::mem::MaybeUninit::uninit(); LINE];
        if let Ok(line) = semihosting::sys::arm_compat::sys_get_cmdline_uninit(&mut line) {
            return line.split(|&b| b == b' ').any(&mut visit);
        }
    }
    let _ = &mut visit;
    false
}

/// Whether `flag` is an argument. (Never inlined: the command line's
/// buffer would stay in the caller's stack frame, `main`'s.)
#[inline(never)]
pub fn flag(flag: &str) -> bool {
    any_word(|word| word == flag.as_bytes())
}

/// The number that follows `name` (`--streams 14`), if it does and is a
/// whole number below 2³². (Never inlined, as [`flag`].)
#[inline(never)]
pub fn number(name: &str) -> Option<u32> {
    let (mut follows, mut number) = (false, None);
    any_word(|word| {
        if follows {
            number = word.iter().try_fold(0u32, |n, &b| {
                let digit = char::from(b).to_digit(10)?;
                n.checked_mul(10)?.checked_add(digit)
            });
            number = number.filter(|_| !word.is_empty());
            return true;
        }
        follows = word == name.as_bytes();
        false
    });
    number
}
