//! Every preset's stream, end to end through the core's encoder and the
//! host's decoder and JSONL.

use morphogen::stream::{Decoder, Record, StreamDigest};
use morphogen_cli::{exec, fixture};
use morphogen_stream_text::jsonl;

#[test]
fn every_fixture_decodes_cleanly_starts_with_its_header_and_balances_frames() {
    let fixtures = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
    for scenario in morphogen_scenario::builtins() {
        let name = scenario.name();
        let fx = fixture::load(&fixtures, name).unwrap_or_else(|e| panic!("{e:#}"));
        let records: Vec<Record> = Decoder::new(&fx.stream)
            .map(|d| d.result.unwrap())
            .collect();
        let Some(Record::Header(h)) = records.first() else {
            panic!("{name}: no header")
        };
        assert_eq!(h.preset.as_str(), name);
        assert_eq!(h.seed, fx.summary.seed);
        assert_eq!(
            format!("{:016x}", StreamDigest::of(&fx.stream)),
            fx.summary.stream_digest
        );
        let starts = records
            .iter()
            .filter(|r| matches!(r, Record::FrameStart { .. }))
            .count();
        let ends = records
            .iter()
            .filter(|r| matches!(r, Record::FrameEnd { .. }))
            .count();
        assert_eq!(starts, ends, "{name}: unbalanced frames");
        assert!(starts > 0, "{name}: no frames");
        assert_eq!(jsonl::stream(&fx.stream).lines().count(), records.len());
    }
}

#[test]
fn growth_curve_is_seasonal_end_to_end() {
    let run = exec::run(&exec::find("growth-curve", &[]).unwrap(), 0, false).unwrap();
    let daily: Vec<(i32, i32)> = Decoder::new(&run.stream)
        .filter_map(|d| match d.result {
            Ok(Record::Sample { series: 1, x, y }) => Some((x.floor_int(), y.to_bits())),
            _ => None,
        })
        .collect();
    assert_eq!(daily.len(), 366);
    let (peak_day, peak) = daily.iter().copied().max_by_key(|&(_, y)| y).unwrap();
    assert!(
        (120..181).contains(&peak_day),
        "fastest growth on day {peak_day}, not in May–June"
    );
    // October to February: under 10 % of the peak daily growth.
    for &(day, y) in daily.iter().filter(|(d, _)| *d < 59 || *d >= 273) {
        assert!(y * 10 < peak, "day {day} grows {y} of peak {peak}");
    }
}
