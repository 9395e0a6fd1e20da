//! The program's arguments: semihosting's command line (QEMU's
//! `-semihosting-config arg=…`). An RTT build has none.

/// Bytes of the command line read (the longest of
/// `scripts/firmware-check.sh`, `morphogen-receiver --screen-sync --streams
/// 14`, has 45).
#[cfg(feature = "semihosting")]
const LINE: usize = 64;

/// Whether `flag` is an argument. (Never inlined: the command line's
/// buffer would stay in the caller's stack frame, `main`'s.)
#[inline(never)]
pub fn flag(flag: &str) -> bool {
    #[cfg(feature = "semihosting")]
    if let Ok(args) = semihosting::experimental::env::args::<LINE>() {
        return (&args).into_iter().any(|arg| arg == Ok(flag));
    }
    let _ = flag;
    false
}

/// The number that follows `name` (`--streams 14`), if it does. (Never
/// inlined, as [`flag`].)
#[inline(never)]
pub fn number(name: &str) -> Option<u32> {
    #[cfg(feature = "semihosting")]
    if let Ok(args) = semihosting::experimental::env::args::<LINE>() {
        let mut args = &args;
        while let Some(arg) = args.next() {
            if arg == Ok(name) {
                return args.next()?.ok()?.parse().ok();
            }
        }
    }
    let _ = name;
    None
}
