//! What a mosaic's Voronoi pictures cost, a part of `run` ÷ `verify`.
//! Run with `cargo bench -p morphogen-cli --bench pictures`.
//!
//! Each bench colours every day of a preset's golden stream
//! (`fixtures/<preset>/stream.bin`) as `run` does for `day_NN.png`, the
//! animation and the areas of `types.csv`, without encoding or writing:
//! croton (2,000 to 19,369 cells on 900 × 720 pixels), croton-ageing
//! (12,022 to 196,739 cells on 900 × 900), watermelon-narrow (10,000
//! and 51,765 cells on 900 × 576, the pattern its cylinder shows) and
//! croton-mcu (36 days of at most 2,048 cells: big tiles, few cells).

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    missing_docs,
    reason = "a benchmark stops on a setup that is not as it expects; its harness macros generate undocumented items"
)]

use std::hint::black_box;
use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use morphogen::mosaic::Params;
use morphogen::preset::Model;
use morphogen::stream::Record;
use morphogen_cli::outputs::mosaic::{self, Day};
use morphogen_cli::records::{Place, Records, StreamFile};

/// The colours of `name`'s types and its days, from its fixture.
fn days(name: &str) -> (Vec<[u8; 3]>, Vec<Day>) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures")
        .join(name)
        .join("stream.bin");
    let mut records: Vec<Record> = Vec::new();
    StreamFile::new(&path)
        .visit(Place::START, |_, r| {
            records.push(r.clone());
            Ok(())
        })
        .expect("a readable fixture");
    let colours = with_params(name, |p| p.types.iter().map(|t| t.colour).collect());
    (colours, mosaic::days(&records))
}

/// Calls `f` with the built-in mosaic `name`'s parameters.
fn with_params<R>(name: &str, f: impl FnOnce(&Params<'_>) -> R) -> R {
    let scenario = morphogen_scenario::builtin(name).expect("a built-in scenario");
    scenario.with_preset(|p| {
        let Model::Mosaic(params) = p.model else {
            unreachable!("{name} is a mosaic")
        };
        f(params)
    })
}

fn voronoi(c: &mut Criterion) {
    let mut group = c.benchmark_group("voronoi");
    group.sample_size(20);
    for name in ["croton", "croton-ageing", "watermelon-narrow", "croton-mcu"] {
        let (colours, days) = days(name);
        with_params(name, |params| {
            group.bench_function(format!("{name}, every day"), |b| {
                b.iter(|| {
                    for day in &days {
                        black_box(mosaic::voronoi(&params.domain, &colours, &day.cells));
                    }
                });
            });
        });
    }
    group.finish();
}

criterion_group!(benches, voronoi);
criterion_main!(benches);
