//! Benchmarks of Morphogen's models started from the built-in scenarios
//! (presets), in `benches/`: criterion for time, gungraun for instruction
//! counts. They live in this crate, above `morphogen-scenario`, so that the
//! core depends on no crate above it; the core's own benches (`kernels`,
//! `kernels_instructions`) need only the core. The library itself is
//! empty. Run one with `cargo bench -p morphogen-benches --bench horn`.

#![no_std]
#![forbid(unsafe_code)]
