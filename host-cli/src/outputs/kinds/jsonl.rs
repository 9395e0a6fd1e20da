//! `jsonl`: every record of the stream as a line of JSON
//! (`records.jsonl`), written as the run streams.

use super::{Format, Kind, Product};

/// The kind.
pub(super) const KIND: Kind = Kind {
    name: "jsonl",
    about: "records.jsonl",
    by_default: true,
    format: &Jsonl,
};

struct Jsonl;

impl Format for Jsonl {
    fn takes(&self, product: Product) -> bool {
        product == Product::Records
    }
}
