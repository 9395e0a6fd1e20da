//! How the program ends: through semihosting under QEMU (the exit code
//! becomes QEMU's), or as the board halts without it (on a Cortex-M, a
//! breakpoint / undefined instruction that `probe-rs run` reports on real
//! hardware).

/// Ends the program successfully.
pub fn success() -> ! {
    #[cfg(feature = "semihosting")]
    semihosting::process::exit(0);
    #[cfg(not(feature = "semihosting"))]
    crate::board::halt_success()
}

/// Ends the program with a failure code.
pub fn failure() -> ! {
    #[cfg(feature = "semihosting")]
    semihosting::process::exit(1);
    #[cfg(not(feature = "semihosting"))]
    crate::board::halt_failure()
}
