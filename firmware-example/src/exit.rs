//! How the program ends: through semihosting under QEMU (the exit code
//! becomes QEMU's), or with a breakpoint / undefined instruction that
//! `probe-rs run` reports on real hardware.

/// Ends the program successfully.
pub fn success() -> ! {
    #[cfg(feature = "semihosting")]
    semihosting::process::exit(0);
    #[cfg(not(feature = "semihosting"))]
    loop {
        // probe-rs run stops here and exits 0.
        cortex_m::asm::bkpt();
    }
}

/// Ends the program with a failure code.
pub fn failure() -> ! {
    #[cfg(feature = "semihosting")]
    semihosting::process::exit(1);
    #[cfg(not(feature = "semihosting"))]
    // A HardFault that probe-rs reports as a failed run.
    cortex_m::asm::udf();
}
