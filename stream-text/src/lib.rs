//! A Morphogen stream read on a host, as text and as streams: its records
//! as JSON Lines ([`jsonl`], the fields in docs/stream-format.md), two
//! streams compared record by record ([`verify`]: the first difference and
//! a tally), a device capture split into the streams it holds
//! ([`capture`]), and the text of numbers that every output file shares
//! ([`text`]).
//!
//! These are the readers the command line (`morphogen decode`, `verify`,
//! `listen`), the Python package and the fuzz targets share; they need
//! nothing but the core.

#![forbid(unsafe_code)]

pub mod capture;
pub mod jsonl;
pub mod text;
pub mod verify;
