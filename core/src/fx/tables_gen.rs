//! Regenerates `tables.rs` from `libm` f64 and checks the committed file
//! matches. Run `MORPHOGEN_REGENERATE_TABLES=1 cargo test -p morphogen
//! tables_are_current` to rewrite it after changing a table's definition.

#![allow(clippy::float_arithmetic)] // generating the tables from f64 is this module's job

extern crate std;

use std::fmt::Write;
use std::string::String;

/// One table: name, doc line, length, and the exact value of entry `i`
/// already scaled to its integer format.
struct Table {
    name: &'static str,
    doc: &'static str,
    len: usize,
    entry: fn(f64) -> f64,
}

fn tables() -> [Table; 5] {
    [
        Table {
            name: "SIN_Q30",
            doc: "sin(i/256 · π/2) in Q2.30, i = 0..=256 (the quarter wave).",
            len: 257,
            entry: |i| libm::sin(i / 256.0 * core::f64::consts::FRAC_PI_2) * (1u64 << 30) as f64,
        },
        Table {
            name: "ATAN_Q32",
            doc: "atan(i/256) in turns as Q0.32 binary-angle units, i = 0..=256.",
            len: 257,
            entry: |i| libm::atan(i / 256.0) / core::f64::consts::TAU * (1u64 << 32) as f64,
        },
        Table {
            name: "EXP2_Q30",
            doc: "2^(i/256) in Q2.30, i = 0..=256.",
            len: 257,
            entry: |i| libm::exp2(i / 256.0) * (1u64 << 30) as f64,
        },
        Table {
            name: "LOG2_Q31",
            doc: "log2(1 + i/256) in Q1.31, i = 0..=256.",
            len: 257,
            entry: |i| libm::log2(1.0 + i / 256.0) * (1u64 << 31) as f64,
        },
        Table {
            name: "SIGMOID_Q32",
            doc: "The logistic 1/(1 + e^(−i/32)) in Q0.32, i = 0..=512 (x from 0 to 16).",
            len: 513,
            entry: |i| 1.0 / (1.0 + libm::exp(-i / 32.0)) * (1u64 << 32) as f64,
        },
    ]
}

fn render() -> String {
    let mut out = String::new();
    out.push_str(
        "//! Lookup tables for the elementary functions, generated from `libm` f64\n\
         //! by `tables_gen.rs`; do not edit by hand. Regenerate with\n\
         //! `MORPHOGEN_REGENERATE_TABLES=1 cargo test -p morphogen tables_are_current`.\n",
    );
    for t in tables() {
        let _ = write!(
            out,
            "\n/// {}\n#[rustfmt::skip]\npub(super) const {}: [u32; {}] = [\n",
            t.doc, t.name, t.len
        );
        for row in (0..t.len).collect::<std::vec::Vec<_>>().chunks(6) {
            out.push_str("   ");
            for &i in row {
                let v = libm::round((t.entry)(i as f64));
                assert!(
                    (0.0..=u32::MAX as f64).contains(&v),
                    "{} entry {i} out of u32",
                    t.name
                );
                let _ = write!(out, " {},", group(v as u64));
            }
            out.push('\n');
        }
        out.push_str("];\n");
    }
    out
}

/// `1234567` → `1_234_567`, as rustfmt-friendly literals.
fn group(v: u64) -> String {
    let digits = std::format!("{v}");
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push('_');
        }
        out.push(c);
    }
    out
}

#[test]
fn tables_are_current() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/src/fx/tables.rs");
    let fresh = render();
    if std::env::var_os("MORPHOGEN_REGENERATE_TABLES").is_some() {
        std::fs::write(path, &fresh).expect("write tables.rs");
    }
    let committed = std::fs::read_to_string(path).expect("read tables.rs");
    assert!(
        committed == fresh,
        "src/fx/tables.rs differs from what libm gives; regenerate it (see tables_gen.rs)"
    );
}
