//! Cross-module tests of the L-system engine: reference counts, streaming
//! vs buffered, ABOP figures, located errors.
#![allow(clippy::float_arithmetic)]

use std::string::String;
use std::vec;
use std::vec::Vec;

use super::*;
use crate::fx::{Fx, Real};
use crate::sim::{Simulation, Start};
use crate::stream::{Record, Sink, SinkError};
use crate::turtle::{Drawn, Params, Turtle};

/// ABOP Fig. 1.25, the three-dimensional shrub (n = 7, δ = 22.5°).
const SHRUB: &str = include_str!("../../../grammars/abop-shrub.lsys");
/// ABOP Fig. 1.24a, a 2D bracketed plant (n = 5, δ = 25.7°).
const PLANT_2D: &str = include_str!("../../../grammars/abop-2d-plant.lsys");
/// ABOP Fig. 1.27, three stochastic plants from three seeds.
const STOCHASTIC: &str = include_str!("../../../grammars/abop-stochastic.lsys");
/// ABOP Fig. 2.6a, the parametric monopodial tree (n = 10).
const MONOPODIAL: &str = include_str!("../../../grammars/abop-monopodial.lsys");

/// ABOP Fig. 2.8a, a tree bent by tropism (n = 6).
const TROPISM: &str = include_str!("../../../grammars/abop-tropism.lsys");

/// Predefined surfaces drawn by interpretation rules.
const FLOWER: &str = include_str!("../../../grammars/lsys-flower.lsys");

/// The grammars of the built-in L-system scenarios (`scenarios/abop-*.toml`
/// read these files), with their scenario names.
pub(super) const ALL: [(&str, &str); 6] = [
    ("abop-shrub", SHRUB),
    ("abop-2d-plant", PLANT_2D),
    ("abop-stochastic", STOCHASTIC),
    ("abop-monopodial", MONOPODIAL),
    ("abop-tropism", TROPISM),
    ("lsys-flower", FLOWER),
];

fn grammar(text: &str) -> Grammar {
    let mut g = Grammar::new();
    g.parse(text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    g
}

/// Feeds every module `d` derives to `f`, asking again while it is
/// pending.
fn each_module<D: Derivation>(d: &mut D, g: &Grammar, mut f: impl FnMut(Module)) {
    loop {
        match d.next_module(g).unwrap() {
            Next::Module(m) => f(m),
            Next::Pending => {}
            Next::End => break,
        }
    }
}

fn streamed(g: &Grammar, steps: u8, seed: u64) -> Vec<Module> {
    let mut d = Streaming::new();
    d.restart(g, steps, seed).unwrap();
    let mut out = Vec::new();
    each_module(&mut d, g, |m| out.push(m));
    out
}

fn buffered(g: &Grammar, steps: u8, seed: u64) -> Vec<Module> {
    let mut a = vec![Module::default(); 200_000];
    let mut b = vec![Module::default(); 200_000];
    let mut links = vec![Neighbours::default(); 200_000];
    let mut d = Buffered::new(&mut a, &mut b, &mut links);
    d.restart(g, steps, seed).unwrap();
    let mut out = Vec::new();
    each_module(&mut d, g, |m| out.push(m));
    assert_eq!(d.string(), out);
    out
}

fn text(modules: &[Module]) -> String {
    modules.iter().map(|m| m.symbol as char).collect()
}

/// The shrub's string lengths after 0..=7 steps, by hand: with
/// `a, f, s` the lengths derived from A, F, S after k steps and L's
/// successor of 23 terminals, `a' = 26 + 3a + 3f + 3l`, `f' = 5 + s + f`,
/// `s' = f + l` (l = 1 at k = 0, 23 after), from a = f = s = 1.
const SHRUB_LENGTHS: [u64; 8] = [1, 35, 221, 800, 2642, 8294, 25481, 77399];

#[test]
fn shrub_symbol_counts_match_the_hand_computed_reference() {
    let g = grammar(SHRUB);
    assert_eq!(g.settings().steps, 7);
    assert_eq!(g.settings().delta, Fx::from_ratio(45, 2));
    // Streaming: the per-level position counters are the lengths.
    let mut d = Streaming::new();
    d.restart(&g, 7, 0).unwrap();
    let mut count = 0u64;
    each_module(&mut d, &g, |_| count += 1);
    assert_eq!(count, SHRUB_LENGTHS[7]);
    assert!(d.positions().eq(SHRUB_LENGTHS));
    for k in 0..=7u8 {
        assert_eq!(buffered(&g, k, 0).len() as u64, SHRUB_LENGTHS[k as usize]);
    }
    assert_eq!(
        text(&streamed(&g, 1, 0)),
        "[&FL!A]/////'[&FL!A]///////'[&FL!A]"
    );
}

#[test]
fn only_predecessor_symbols_are_rewritten() {
    let g = grammar(SHRUB);
    let rewritten: String = (0..=u8::MAX)
        .filter(|&s| s.is_ascii_graphic() && g.is_rewritten(s))
        .map(char::from)
        .collect();
    assert_eq!(rewritten, "AFLS");
    assert!(g.is_rewritten(200), "past the set: conservatively true");
}

#[test]
fn streaming_and_buffered_derivations_agree() {
    for (name, source) in ALL {
        let g = grammar(source);
        for seed in [0, 1, 2, 77] {
            let steps = g.settings().steps.min(6);
            let s = streamed(&g, steps, seed);
            let b = buffered(&g, steps, seed);
            assert_eq!(s.len(), b.len(), "{name} seed {seed}");
            assert!(s == b, "{name} seed {seed}: strings differ");
        }
    }
}

/// Collects records.
#[derive(Default)]
struct Records(Vec<Record>);

impl Sink for Records {
    fn record(&mut self, r: &Record) -> Result<(), SinkError> {
        self.0.push(r.clone());
        Ok(())
    }
}

fn run_sim(sim: &mut impl Simulation) -> Vec<Record> {
    let mut sink = Records::default();
    loop {
        let p = sim.step(&mut sink).unwrap();
        if p.finished() {
            return sink.0;
        }
    }
}

/// How many segments `records` holds.
fn segments_in(records: &[Record]) -> usize {
    records
        .iter()
        .filter(|r| matches!(r, Record::Segment { .. }))
        .count()
}

#[test]
fn streaming_and_buffered_simulations_emit_identical_streams() {
    for (name, source) in ALL {
        for seed in [0, 5] {
            let mut streaming = LSystem::new();
            streaming.start(source, seed).unwrap();
            let s = run_sim(&mut streaming);
            let mut a = vec![Module::default(); 100_000];
            let mut b = vec![Module::default(); 100_000];
            let mut links = vec![Neighbours::default(); 100_000];
            let mut buffered =
                LSystem::<_>::with_derivation(Buffered::new(&mut a, &mut b, &mut links));
            buffered.start(source, seed).unwrap();
            let b = run_sim(&mut buffered);
            assert!(s.len() > 100, "{name}");
            assert!(s == b, "{name} seed {seed}: streams differ");
        }
    }
}

#[test]
fn stochastic_choices_depend_on_the_seed_with_the_right_odds() {
    let g = grammar(STOCHASTIC);
    let plants: Vec<String> = (1..=3).map(|s| text(&streamed(&g, 5, s))).collect();
    assert_ne!(plants[0], plants[1]);
    assert_ne!(plants[1], plants[2]);
    assert_eq!(
        text(&streamed(&g, 5, 2)),
        plants[1],
        "same seed, same plant"
    );
    // 3000 F in three steps (A -> 20 B, B -> 150 C, C -> F), then one
    // stochastic step: the three successors' frequencies.
    let rules = STOCHASTIC.split("axiom: '(8)F\n").nth(1).unwrap();
    let g = grammar(&format!(
        "n = 4\naxiom: A\nA -> {}\nB -> {}\nC -> F\n{rules}",
        "B".repeat(20),
        "C".repeat(150)
    ));
    let one = text(&streamed(&g, 4, 9));
    let both = one.matches("F[+F]F[-F]F").count();
    let plus = one.matches("F[+F]F").count() - both;
    let minus = one.matches("F[-F]F").count() - both;
    assert_eq!(both + plus + minus, 3000);
    for (k, p) in [(both, 0.33), (plus, 0.33), (minus, 0.34)] {
        let expected = 3000.0 * p;
        // 4 standard deviations of a binomial(3000, p).
        assert!(
            (k as f64 - expected).abs() < 4.0 * (expected * (1.0 - p)).sqrt(),
            "{k} vs {expected}"
        );
    }
}

#[test]
fn parametric_monopodial_tree_derives_as_in_abop() {
    let g = grammar(MONOPODIAL);
    let s = streamed(&g, 1, 0);
    assert_eq!(text(&s), "!F[&B]/A");
    let f = |x: f64| Fx::from_fixed(fixed::types::I16F16::from_num(x));
    assert_eq!(s[0].args(), [Fx::from_int(10)]);
    assert_eq!(s[1].args(), [Fx::from_int(100)]);
    assert_eq!(s[3].args(), [Fx::from_int(45)]);
    assert_eq!(
        s[4].args(),
        [
            Fx::from_int(100).saturating_mul(f(0.6)),
            Fx::from_int(10).saturating_mul(f(0.707))
        ]
    );
    assert_eq!(s[6].args(), [f(137.5)]);
    assert_eq!(
        s[7].args(),
        [
            Fx::from_int(100).saturating_mul(f(0.9)),
            Fx::from_int(10).saturating_mul(f(0.707))
        ]
    );
    // Two apices per apex per step: 2^10 apices after 10 steps.
    let last = streamed(&g, 10, 0);
    let apices = last.iter().filter(|m| b"ABC".contains(&m.symbol)).count();
    assert_eq!(apices, 1024);
}

#[test]
fn context_sensitive_signal_propagation() {
    // ABOP Sec. 1.8: a signal b travels right through a string of a's.
    let g = grammar("n = 3\naxiom: baaaaaaaa\nb < a -> b\nb -> a");
    assert_eq!(text(&buffered(&g, 1, 0)), "abaaaaaaa");
    assert_eq!(text(&buffered(&g, 3, 0)), "aaabaaaaa");
    let mut d = Streaming::new();
    assert_eq!(d.restart(&g, 1, 0), Err(LsysError::NeedsBuffer));
    // ABOP p. 32: contexts skip branches and ignored symbols, climb out at `[`.
    let g = grammar(
        "n = 1\nignore: +-\naxiom: A+[B]C[-D]E\nA < C > E -> X\nA < B -> Y\nB > C -> Z\nC < D -> W\nA < D -> V",
    );
    assert_eq!(text(&buffered(&g, 1, 0)), "A+[Y]X[-W]E");
    // Parametric contexts bind in text order.
    let g = grammar(
        "n = 1\naxiom: A(1)B(2)C(3)\nA(x) < B(y) > C(z) : x + z == 4 -> B(x * 100 + y * 10 + z)",
    );
    let s = buffered(&g, 1, 0);
    assert_eq!(s[1].args(), [Fx::from_int(123)]);
}

#[test]
fn buffer_capacity_is_an_error_naming_the_limit() {
    let g = grammar(SHRUB);
    let mut a = vec![Module::default(); 1000];
    let mut b = vec![Module::default(); 1000];
    let mut links = vec![Neighbours::default(); 1000];
    let mut d = Buffered::new(&mut a, &mut b, &mut links);
    d.restart(&g, 4, 0).unwrap();
    // Step 4 writes 2,642 modules: the error comes while deriving, before
    // any module is given.
    let error = loop {
        match d.next_module(&g) {
            Ok(Next::Pending) => {}
            other => break other,
        }
    };
    assert_eq!(
        error,
        Err(LsysError::Capacity {
            limit: "BUFFER_MODULES",
            capacity: 1000
        })
    );
}

fn segments(source: &str, seed: u64) -> Vec<([Fx; 3], [Fx; 3])> {
    let mut sim = LSystem::new();
    sim.start(source, seed).unwrap();
    run_sim(&mut sim)
        .into_iter()
        .filter_map(|r| match r {
            Record::Segment { a, b, .. } => Some((a, b)),
            _ => None,
        })
        .collect()
}

#[test]
fn abop_fig_1_24a_main_axis_is_3_to_the_n_steps_straight_up() {
    let segs = segments(PLANT_2D, 0);
    assert_eq!(segs.len(), 5usize.pow(5));
    let tip = segs.last().unwrap().1;
    assert_eq!(tip, [Fx::ZERO, Fx::from_int(243), Fx::ZERO]);
    let top = segs.iter().map(|s| s.1[1]).max().unwrap();
    assert_eq!(top, Fx::from_int(243));
    assert!(
        segs.iter().all(|s| s.1[2] == Fx::ZERO),
        "a 2D figure stays in z = 0"
    );
    // Width 1 throughout, colour 0.
}

#[test]
fn abop_quadratic_koch_island_closes() {
    // ABOP Fig. 1.7a: F-F-F-F, F -> F-F+F+FF-F-F+F, δ = 90°. The generator
    // moves (0,1) (1,1) (1,2) (0,2) (-1,2) (-1,3) (0,3) (0,4): a net 4 along
    // the segment it replaces, so after n = 2 each side of the initial
    // square (drawn clockwise, `-` turns right) is 64 segments spanning 16.
    let g = "n = 2\ndelta = 90\naxiom: F-F-F-F\nF -> F-F+F+FF-F-F+F";
    let segs = segments(g, 0);
    assert_eq!(segs.len(), 4 * 64);
    let corner = |k: usize| segs[64 * k - 1].1;
    let p = |x: i32, y: i32| [Fx::from_int(x), Fx::from_int(y), Fx::ZERO];
    assert_eq!(
        [corner(1), corner(2), corner(3), corner(4)],
        [p(0, 16), p(16, 16), p(16, 0), p(0, 0)]
    );
    assert_eq!(
        segs[..8].iter().map(|s| s.1).collect::<Vec<_>>(),
        [
            p(0, 1),
            p(1, 1),
            p(1, 2),
            p(0, 2),
            p(-1, 2),
            p(-1, 3),
            p(0, 3),
            p(0, 4)
        ]
    );
}

#[test]
fn fixed_point_shrub_tracks_the_f64_reference() {
    let g = grammar(SHRUB);
    let s = g.settings();
    let mut fx = Turtle::<Fx>::new(Params {
        step: s.step,
        delta: crate::fx::Angle::from_degrees_fx(s.delta),
        width: s.width,
        thin: s.thin,
        tropism: nalgebra::Vector3::zeros(),
        elasticity: Fx::ZERO,
    });
    let mut reference = Turtle::<f64>::new(Params {
        step: 1.0,
        delta: crate::fx::Angle::from_degrees_fx(s.delta),
        width: s.width.to_f64(),
        thin: s.thin.to_f64(),
        tropism: nalgebra::Vector3::zeros(),
        elasticity: 0.0,
    });
    let mut d = Streaming::new();
    d.restart(&g, 7, 0).unwrap();
    let (mut worst, mut extent, mut n) = (0.0f64, 0.0f64, 0);
    each_module(&mut d, &g, |m| {
        let (a, b) = (fx.apply(&m).unwrap(), reference.apply(&m).unwrap());
        if let (Drawn::Segment { b: p, .. }, Drawn::Segment { b: q, .. }) = (a, b) {
            for i in 0..3 {
                worst = worst.max((p[i].to_f64() - q[i]).abs());
                extent = extent.max(q[i].abs());
            }
            n += 1;
        }
    });
    assert!(n > 3000, "{n} segments");
    // End to end, within 1/1000 of the shrub's size. The error is the
    // quantised sin/cos of δ (≤ 1·10⁻⁵ rad per turn, systematic), compounded
    // over the ~hundreds of turns along the longest branch.
    std::println!("shrub: fixed vs f64 worst {worst:.6} of extent {extent:.3} over {n} segments");
    assert!(worst < extent / 1000.0, "worst {worst} of extent {extent}");
}

/// The simulation's RAM: what a `static` holds for the shrub on the MCU.
#[test]
fn simulation_state_fits_the_mcu_budget() {
    let size = core::mem::size_of::<LSystem>();
    // 6.5 KB: the cut state per level (140 B), the interpretation stack
    // (200 B) and the rule sections (100 B) took it past 6 KB.
    assert!(size < 6 * 1024 + 512, "LSystem is {size} bytes");
    // Buffered derivation of the same shrub holds two strings at once.
    let g = grammar(SHRUB);
    let mut a = vec![Module::default(); 80_000];
    let mut b = vec![Module::default(); 80_000];
    let mut links = vec![Neighbours::default(); 80_000];
    let mut d = Buffered::new(&mut a, &mut b, &mut links);
    d.restart(&g, 7, 0).unwrap();
    each_module(&mut d, &g, |_| {});
    let peak = d.peak_modules();
    assert_eq!(peak as u64, SHRUB_LENGTHS[6] + SHRUB_LENGTHS[7]);
    std::println!(
        "shrub peak memory: streaming {size} bytes (whole simulation), buffered {} bytes of modules ({peak} × {})",
        peak * core::mem::size_of::<Module>(),
        core::mem::size_of::<Module>()
    );
    std::println!(
        "size_of: LSystem {size}, Grammar {}, Streaming {}, Turtle {}, Module {}",
        core::mem::size_of::<Grammar>(),
        core::mem::size_of::<Streaming>(),
        core::mem::size_of::<Turtle>(),
        core::mem::size_of::<Module>()
    );
}

fn parse_err(text: &str) -> ParseError {
    let mut g = Grammar::new();
    match g.parse(text) {
        Err(e) => e,
        Ok(()) => panic!("parsed: {text}"),
    }
}

#[test]
fn malformed_grammars_get_located_errors() {
    use ParseErrorKind as K;
    let cases: [(&str, u32, u32, K); 21] = [
        ("n = 1\naxiom: F[", 2, 9, K::UnclosedBranch),
        ("n = 1\naxiom: F\nF -> F]F", 3, 7, K::UnmatchedClose),
        ("n = 1\naxiom: F\nF -> F[+F][[-F]", 3, 11, K::UnclosedBranch),
        (
            "n = 1\naxiom: F\nF -> F(",
            3,
            8,
            K::Expected("an expression"),
        ),
        (
            "n = 1\naxiom: F\nF F -> F",
            3,
            1,
            K::Expected("one predecessor module before `->`"),
        ),
        ("n = 1\naxiom: F\nF(x) -> F(y)", 3, 11, K::UnknownName),
        ("n = 1\naxiom: F\nF(x, x) -> F", 3, 6, K::DuplicateName),
        ("n = 1\naxiom: F\naxiom: G", 3, 1, K::DuplicateAxiom),
        ("n = 1\n", 2, 1, K::MissingAxiom),
        ("axiom: F", 1, 1, K::MissingSteps),
        (
            "n = 256\naxiom: F",
            1,
            5,
            K::InvalidValue(
                "`n` must be a whole number from 0 to MAX_BUFFERED_STEPS = 255 (above Streaming<STEPS>, 32 by default, only buffered derivation derives it)",
            ),
        ),
        ("n = 1\naxiom: F(40000)", 2, 10, K::NumberOutOfRange),
        (
            "n = 1\ndelta = 1e9\naxiom: F",
            2,
            10,
            K::Expected("a decimal without exponent (0.001, not 1e-3)"),
        ),
        (
            "n = 1\naxiom: F(2.5E-3)",
            2,
            13,
            K::Expected("a decimal without exponent (0.001, not 1e-3)"),
        ),
        ("n = 1\naxiom: F\nF -> F é", 3, 8, K::NotAscii),
        ("n = 1\naxiom: F\nF : x > -> F", 3, 5, K::UnknownName),
        (
            "n = 1\naxiom: F\nwhat is this",
            3,
            1,
            K::Expected(
                "a production `pred -> successor`, `axiom:`, `ignore:`, `name = value`, a section `production:`, `decomposition:`, `interpretation:` or `maximum depth: n`",
            ),
        ),
        (
            "n = 1\naxiom: F\n[ -> F",
            3,
            1,
            K::Expected(
                "a module other than `[` or `]` (brackets are neither rewritten nor matched)",
            ),
        ),
        (
            "n = 1\naxiom: F\nF -> (0.5 F",
            3,
            11,
            K::Expected("`)` after the probability"),
        ),
        ("n = 1\nn = 2\naxiom: F", 2, 1, K::DuplicateName),
        (
            "n = 1\naxiom: F(((((((((((((((((((1)))))))))))))))))))",
            2,
            26,
            K::Capacity {
                limit: "MAX_NESTING",
                capacity: 16,
            },
        ),
    ];
    for (text, line, column, kind) in cases {
        let e = parse_err(text);
        assert_eq!(
            (e.line, e.column, e.kind),
            (line, column, kind),
            "{text:?}: {e}"
        );
    }
    let many: String = (0..40).map(|i| format!("c{i} = {i}\n")).collect();
    let e = parse_err(&format!("n = 1\n{many}axiom: F"));
    assert_eq!(
        e.kind,
        K::Capacity {
            limit: "MAX_CONSTANTS",
            capacity: 32
        }
    );
    assert_eq!(e.line, 33); // `n` is the first of the 32
}

#[test]
fn expressions_conditions_and_settings() {
    let g = grammar(
        "n = 2   # steps\nk = 2 * 3 + 1\ndelta = k * 10 - 50\naxiom: A(0)\n\
         A(x) : x < 1 && !(x == 5) -> A(x + 1) B(k ^ 2, 7 / 0, -x)\nA(x) : * -> C(sqrt(16), floor(2.5), x)",
    );
    assert_eq!(g.settings().delta, Fx::from_int(20));
    let s = streamed(&g, 2, 0);
    assert_eq!(text(&s), "CB");
    assert_eq!(s[0].args(), [Fx::from_int(4), Fx::from_int(2), Fx::ONE]);
    assert_eq!(s[1].args(), [Fx::from_int(49), Fx::MAX, Fx::ZERO]);
}

#[test]
fn a_negative_width_or_an_out_of_range_colour_is_an_error() {
    use crate::turtle::TurtleError;
    for (text, error) in [
        ("n = 0\naxiom: !(-5)F", TurtleError::NegativeWidth),
        ("n = 0\naxiom: '(-300)F", TurtleError::ColourOutOfRange),
        ("n = 0\naxiom: '(-1)F", TurtleError::ColourOutOfRange),
    ] {
        let mut sim = LSystem::new();
        sim.start(text, 0).unwrap();
        let mut sink = Records::default();
        let e = loop {
            match sim.step(&mut sink) {
                Ok(p) if p.finished() => panic!("{text}: drew without an error"),
                Ok(_) => {}
                Err(e) => break e,
            }
        };
        assert_eq!(e, crate::Error::Lsys(LsysError::Turtle(error)), "{text}");
    }
}

fn segment_count(source: &str) -> usize {
    segments(source, 0).len()
}

#[test]
fn cut_removes_the_rest_of_its_branch() {
    // ABOP p. 28: each step adds a branch [+F%F] and an F to the axis; the
    // cut leaves [+F], so after n steps there are 1 + 2n segments (with no
    // cut, [+FF]: 1 + 3n).
    let cut = "n = 4\naxiom: F A\nA -> [+F%F]F A";
    let uncut = "n = 4\naxiom: F A\nA -> [+F F]F A";
    assert_eq!(segment_count(cut), 1 + 2 * 4);
    assert_eq!(segment_count(uncut), 1 + 3 * 4);
    let g = grammar(cut);
    assert_eq!(text(&buffered(&g, 2, 0)), "F[+F]F[+F]FA");
    assert_eq!(text(&streamed(&g, 2, 0)), "F[+F]F[+F]FA");
    // At the top level a cut runs to the end of the string; in the axiom
    // too.
    let g = grammar("n = 1\naxiom: F%[+F]F\nF -> FF");
    assert_eq!(text(&buffered(&g, 0, 0)), "F");
    assert_eq!(text(&streamed(&g, 1, 0)), "FF");
    // A branch closed by a `]` of an earlier level: A's successor cuts C's
    // expansion too, and the `]` stays.
    let g = grammar("n = 2\naxiom: [A C]B\nA -> F%\nC -> G\nB -> BB");
    assert_eq!(text(&buffered(&g, 1, 0)), "[F]BB");
    assert_eq!(text(&streamed(&g, 1, 0)), "[F]BB");
    assert_eq!(text(&streamed(&g, 2, 0)), "[F]BBBB");
    // `%` cannot be a predecessor.
    assert_eq!(parse_err("n = 1\naxiom: F\n% -> F").column, 1);
}

#[test]
fn cuts_stream_as_they_buffer_with_stochastic_positions() {
    // Cuts at every level, inside and across successors, with stochastic
    // choices keyed by position: streaming must count exactly the modules
    // the buffered derivation keeps.
    let grammars = [
        "n = 6\naxiom: A\nA -> (1) F[+A%B]A\nA -> (1) F[-B]%A\nA -> (1) [A]B\nB -> (1) F%[A]\nB -> (2) B F",
        "n = 5\naxiom: [A]A%B\nA -> (1) A[%A]B\nA -> (2) F[B%]A\nB -> (1) [A%F]\nB -> (1) G B",
        "n = 7\naxiom: X\nX -> (1) F[+X][-X%X]X\nX -> (1) F%\nX -> (1) [X%]F X\nF -> (3) F\nF -> (1) F F",
    ];
    for source in grammars {
        let g = grammar(source);
        for seed in 0..12 {
            for steps in 0..=g.settings().steps {
                let s = streamed(&g, steps, seed);
                let b = buffered(&g, steps, seed);
                assert!(
                    s == b,
                    "{source} seed {seed} n {steps}:\n{}\n{}",
                    text(&s),
                    text(&b)
                );
                assert!(!text(&s).contains('%'));
            }
        }
    }
}

/// A doubling to 2^(n−1) modules that the last step erases, by a cut
/// (`%`, to the end of the branch or the string) or by an empty
/// successor; step 3 puts each of its subtrees in a branch followed by an
/// `F` that stays, between `F` and `G` in the axiom.
fn erasing(n: u8, erase: &str) -> Grammar {
    let last = n - 1;
    grammar(&format!(
        "n = {n}\naxiom: F A(0) G\n\
         A(x) : x == 3 -> [A(x + 1) A(x + 1)] F\n\
         A(x) : x < {last} -> A(x + 1) A(x + 1)\n\
         A(x) : x >= {last} -> {erase}"
    ))
}

#[test]
fn erasing_billions_of_modules_is_pending_not_a_hang() {
    // The fuzz smoke's 20 s timeout: the first call after `F` visited the
    // 2^24 modules erased before the next one. It visits VISITS_PER_CALL.
    for erase in ["%", ""] {
        let g = erasing(28, erase);
        let mut d = Streaming::new();
        d.restart(&g, 28, 0).unwrap();
        let first = [b'F', b'['].map(|s| Next::Module(Module::bare(s)));
        for expected in first {
            assert_eq!(d.next_module(&g).unwrap(), expected);
        }
        for _ in 0..1000 {
            assert_eq!(d.next_module(&g).unwrap(), Next::Pending, "`{erase}`");
        }
        // A simulation step counts each pending call as a module.
        let mut sim = LSystem::new();
        let text = format!(
            "n = 28\naxiom: F A(0)\nA(x) : x < 27 -> A(x + 1) A(x + 1)\nA(x) : x >= 27 -> {erase}"
        );
        sim.start(&text, 0).unwrap();
        let mut sink = Records::default();
        for _ in 0..3 {
            assert!(!sim.step(&mut sink).unwrap().finished());
        }
        // The frame's start and F's segment.
        assert_eq!(sink.0.len(), 2, "{:?}", sink.0);
    }
}

#[test]
fn interpretation_rules_erasing_millions_are_pending_too() {
    // 8^7 J's, each interpreted as nothing, between two F's: each step
    // interprets MODULES_PER_STEP pending calls at most, then the plant
    // ends with both segments.
    let mut rules = String::new();
    for (a, b) in "ABCDEHI".chars().zip("BCDEHIJ".chars()) {
        rules += &format!("{a} -> {}\n", format!("{b} ").repeat(8));
    }
    let text = format!("n = 0\naxiom: F A F\ninterpretation:\nmaximum depth: 8\n{rules}J ->");
    let mut sim = LSystem::new();
    sim.start(&text, 0).unwrap();
    let mut sink = Records::default();
    let mut steps = 0;
    while !sim.step(&mut sink).unwrap().finished() {
        steps += 1;
        assert!(sink.0.len() <= 2, "step {steps}: {:?}", sink.0);
    }
    // 2 · 8^7 visits, VISITS_PER_CALL per call, MODULES_PER_STEP calls.
    let visits = 2 * 8u64.pow(7);
    let calls = (VISITS_PER_CALL as u64) * (MODULES_PER_STEP as u64);
    assert!(steps as u64 >= visits / calls, "{steps} steps");
    assert_eq!(segments_in(&sink.0), 2);
}

#[test]
fn a_pending_derivation_goes_on_where_it_stopped() {
    // Runs of 2^9 erased modules: streaming, asked again after each
    // pending call, derives what buffering does.
    for erase in ["", "%", "% G", "F %"] {
        let g = erasing(13, erase);
        let mut d = Streaming::new();
        d.restart(&g, 13, 0).unwrap();
        let (mut modules, mut pending) = (Vec::new(), 0);
        loop {
            match d.next_module(&g).unwrap() {
                Next::Module(m) => modules.push(m),
                Next::Pending => pending += 1,
                Next::End => break,
            }
        }
        assert_eq!(modules, buffered(&g, 13, 0), "`{erase}`");
        assert!(pending > 0, "`{erase}`: never pending");
    }
}

#[test]
fn symbols_with_a_meaning_elsewhere_are_located_errors() {
    // Each symbol of the table, in the axiom, a successor and a
    // predecessor: an error at its column naming it, never drawn as
    // nothing.
    for symbol in UNSUPPORTED_SYMBOLS {
        let s = char::from(symbol);
        let kind = ParseErrorKind::UnsupportedSymbol { symbol };
        for (text, line, column) in [
            (format!("n = 1\naxiom: F {s}F"), 2, 10),
            (format!("n = 1\naxiom: F\nF -> F[+F]{s}(2)"), 3, 11),
            (format!("n = 1\naxiom: F\n{s} -> F"), 3, 1),
        ] {
            let e = parse_err(&text);
            assert_eq!((e.line, e.column, e.kind), (line, column, kind), "{text}");
            assert!(std::format!("{e}").contains(&std::format!("`{s}`")), "{e}");
        }
    }
}

#[test]
fn every_definition_is_reported_with_whether_it_is_read() {
    let mut defined = Vec::new();
    Grammar::new()
        .parse_with(
            "n = 2\nr = 0.5\n  delta = r * 60\ndetla = 1\naxiom: F(r)",
            |d| defined.push((String::from(d.name), d.value, d.read, d.line, d.column)),
        )
        .unwrap();
    let expected = [
        ("n", Fx::from_int(2), false, 1, 1),
        ("r", Fx::from_ratio(1, 2), true, 2, 1),
        ("delta", Fx::from_int(30), false, 3, 3),
        ("detla", Fx::ONE, false, 4, 1),
    ]
    .map(|(n, v, read, line, column)| (String::from(n), v, read, line, column));
    assert_eq!(defined, expected);
}

#[test]
fn tropism_bends_a_straight_line_towards_t() {
    // H = (sin φ, cos φ, 0) and T = (1, 0, 0): ‖H × T‖ = cos φ, so each F
    // draws along φ_k and then turns by e·cos φ_k towards +x (ABOP Eq.
    // 2.3). The end points, from that recurrence in f64:
    let e = 0.2f64;
    let mut phi = 0.0f64;
    let mut p = [0.0f64; 2];
    let mut expected = Vec::new();
    for _ in 0..40 {
        p[0] += phi.sin();
        p[1] += phi.cos();
        expected.push(p);
        phi += e * phi.cos();
    }
    let source = format!(
        "n = 0\ntropism = 1, 0, 0\nelasticity = {e}\naxiom: {}",
        "F".repeat(40)
    );
    let segs = segments(&source, 0);
    assert_eq!(segs.len(), 40);
    for (k, (s, q)) in segs.iter().zip(&expected).enumerate() {
        let (x, y) = (s.1[0].to_f64(), s.1[1].to_f64());
        assert!(
            (x - q[0]).abs() < 2e-3 && (y - q[1]).abs() < 2e-3,
            "segment {k}: ({x}, {y}) vs {q:?}"
        );
        assert_eq!(s.1[2], Fx::ZERO, "stays in the plane of H and T");
    }
    // By the end the line runs along T.
    let (a, b) = segs[39];
    assert!((b[0] - a[0]).to_f64() > 0.999, "{a:?} -> {b:?}");
    // Without elasticity the line is straight; a negative one bends away.
    let straight = source.replace("elasticity = 0.2", "elasticity = 0");
    assert_eq!(segments(&straight, 0)[39].1[1], Fx::from_int(40));
    let away = source.replace("elasticity = 0.2", "elasticity = -0.2");
    assert!(segments(&away, 0)[10].1[0] < Fx::ZERO);
    // Settings errors are located.
    assert_eq!(
        parse_err("n = 0\ntropism = 1, 0\naxiom: F").kind,
        ParseErrorKind::Expected("`,` (tropism = x, y, z)")
    );
    let e = parse_err("n = 0\ntropism = 0, 1, 0\ntropism = 0, 1, 0\naxiom: F");
    assert_eq!((e.line, e.kind), (3, ParseErrorKind::DuplicateName));
}

#[test]
fn abop_fig_2_8a_tracks_an_f64_turtle_and_droops() {
    // The fixed-point turtle against the generic one in f64 on the whole
    // tree (tropism after each of 1 457 F: 1 + 4·(3⁶ − 1)/2), and the tips
    // bent below the branch points: T = (0, −1, 0) pulls them down.
    let g = grammar(TROPISM);
    let s = g.settings();
    assert_eq!(s.tropism, [Fx::ZERO, -Fx::ONE, Fx::ZERO]);
    let mut fx = Turtle::<Fx>::new(crate::lsys::turtle_params(&g));
    let mut reference = Turtle::<f64>::new(Params {
        step: 1.0,
        delta: crate::fx::Angle::from_degrees_fx(s.delta),
        width: 1.0,
        thin: 0.7,
        tropism: nalgebra::Vector3::new(0.0, -1.0, 0.0),
        elasticity: s.elasticity.to_f64(),
    });
    let (mut worst, mut extent, mut n) = (0.0f64, 0.0f64, 0);
    for m in streamed(&g, 6, 0) {
        let (a, b) = (fx.apply(&m).unwrap(), reference.apply(&m).unwrap());
        if let (Drawn::Segment { b: p, .. }, Drawn::Segment { b: q, .. }) = (a, b) {
            for i in 0..3 {
                worst = worst.max((p[i].to_f64() - q[i]).abs());
                extent = extent.max(q[i].abs());
            }
            n += 1;
        }
    }
    assert_eq!(n, 1457);
    std::println!("Fig. 2.8a: fixed vs f64 worst {worst:.5} of extent {extent:.1}");
    assert!(worst < extent / 1000.0, "worst {worst} of extent {extent}");
    // Without tropism the same tree's segments end far higher on average.
    let mean_height = |source: &str| {
        let segs = segments(source, 0);
        segs.iter().map(|s| s.1[1].to_f64()).sum::<f64>() / segs.len() as f64
    };
    let bent = mean_height(TROPISM);
    let upright = mean_height(&TROPISM.replace("elasticity = 0.22", "elasticity = 0"));
    std::println!("Fig. 2.8a: mean height {bent:.1}, without tropism {upright:.1}");
    assert!(bent < upright - 100.0, "{bent} vs {upright}");
}

fn sim_error(source: &str) -> crate::Error {
    let mut sim = LSystem::new();
    sim.start(source, 0).unwrap();
    let mut sink = Records::default();
    loop {
        match sim.step(&mut sink) {
            Ok(p) if p.finished() => panic!("{source}: ran without an error"),
            Ok(_) => {}
            Err(e) => return e,
        }
    }
}

#[test]
fn a_plant_that_draws_nothing_while_its_string_grows_stops_at_its_limit() {
    // 2^32 modules, none drawn, no stream to cap: the plant's module
    // count bounds it.
    assert_eq!(
        sim_error("n = 32\naxiom: A\nA -> A A"),
        crate::Error::Lsys(LsysError::Capacity {
            limit: "MAX_PLANT_MODULES",
            capacity: super::MAX_PLANT_MODULES
        })
    );
}

#[test]
fn interpretation_rules_draw_without_changing_the_derivation() {
    // L-Py's `interpretation:` (a homomorphism): A grows B's, the turtle
    // sees A as F and B as [+F]; the derived string keeps A and B.
    let source = "n = 3\naxiom: A\nA -> A B\ninterpretation:\nA -> F\nB -> [+F]";
    let g = grammar(source);
    assert_eq!(text(&streamed(&g, 3, 0)), "ABBB");
    assert_eq!(text(&buffered(&g, 3, 0)), "ABBB");
    let segs = segments(source, 0);
    assert_eq!(segs.len(), 4, "A's F and three B's [+F]");
    let p = |x: i32, y: i32| [Fx::from_int(x), Fx::from_int(y), Fx::ZERO];
    assert_eq!(segs[0], (p(0, 0), p(0, 1)));
    // [+F] turns left by δ = 90° from the end of A's F.
    assert_eq!(segs[1], (p(0, 1), p(-1, 1)));
    // Nested rules, within `maximum depth`.
    let nested = "n = 0\naxiom: A\ninterpretation:\nmaximum depth: 2\nA -> B B\nB -> F";
    assert_eq!(segments(nested, 0).len(), 2);
    // At it, the deepest rule's modules are drawn as they are (L-Py): with
    // depth 1 the turtle sees B B and draws nothing; `A -> F A` draws one
    // F, at the default depth 1 and at the largest a default `LSystem`
    // draws (`INTERPRETATION` = 8).
    assert_eq!(
        segments(&nested.replace("depth: 2", "depth: 1"), 0).len(),
        0
    );
    let endless = "n = 0\naxiom: A\ninterpretation:\nA -> F A";
    assert_eq!(segments(endless, 0).len(), 1);
    let deepest = endless.replace("interpretation:", "interpretation:\nmaximum depth: 8");
    assert_eq!(segments(&deepest, 0).len(), 8);
}

#[test]
fn decomposition_rules_apply_after_each_step_to_maximum_depth() {
    // L-Py's `decomposition:`: I decomposes into J J right after the step
    // that makes it (not in the axiom), and the next step rewrites the J's.
    let source = "n = 2\naxiom: A\nA -> A I\nJ -> F\ndecomposition:\nI -> J J";
    let g = grammar(source);
    assert!(g.needs_buffer());
    assert_eq!(text(&buffered(&g, 1, 0)), "AJJ");
    assert_eq!(text(&buffered(&g, 2, 0)), "AJJFF");
    assert_eq!(
        text(&buffered(
            &grammar("n = 0\naxiom: I\ndecomposition:\nI -> J J"),
            0,
            0
        )),
        "I"
    );
    // Streaming cannot: it says so, and the simulation reports it.
    assert_eq!(
        Streaming::new().restart(&g, 2, 0),
        Err(LsysError::NeedsBuffer)
    );
    assert_eq!(
        sim_error(source),
        crate::Error::Lsys(LsysError::NeedsBuffer)
    );
    // A chain of three rules fits `maximum depth: 3`; a fourth is not
    // applied (L-Py keeps the deepest rule's modules as they are).
    let chain = "n = 1\naxiom: A\nA -> X\ndecomposition:\nmaximum depth: 3\nX -> Y\nY -> Z\nZ -> W";
    assert_eq!(text(&buffered(&grammar(chain), 1, 0)), "W");
    let fourth = grammar(&format!("{chain}\nW -> V"));
    assert_eq!(text(&buffered(&fourth, 1, 0)), "W");
    // Without `maximum depth:`, one rule (L-Py's default depth 1).
    let one = grammar(&chain.replace("maximum depth: 3\n", ""));
    assert_eq!(text(&buffered(&one, 1, 0)), "Y");
    // Cuts act after decomposition.
    let g = grammar("n = 1\naxiom: A\nA -> [F I F] F\ndecomposition:\nI -> G %");
    assert_eq!(text(&buffered(&g, 1, 0)), "[FG]F");
}

#[test]
fn maximum_depth_is_checked_against_the_capacity_of_the_type() {
    // Interpretation rules nest in the `LSystem`: `A -> F A` draws one F
    // per level, so a depth is visible as a segment count.
    let endless =
        |depth: u32| format!("n = 0\naxiom: A\ninterpretation:\nmaximum depth: {depth}\nA -> F A");
    let capacity = |capacity| {
        crate::Error::Lsys(LsysError::Capacity {
            limit: "INTERPRETATION",
            capacity,
        })
    };
    let mut small: LSystem<Streaming, 32, 256, 32, 1024, 64, 2> =
        LSystem::with_derivation(Streaming::new());
    assert_eq!(small.start(&endless(3), 0), Err(capacity(2)));
    assert_eq!(small.step(&mut Records::default()), Err(capacity(2)));
    assert_eq!(
        capacity(2).to_string(),
        "L-system: capacity INTERPRETATION = 2 exceeded"
    );
    small.start(&endless(2), 0).unwrap();
    assert_eq!(segments_in(&run_sim(&mut small)), 2);
    // The default (8) refuses 9; a larger type draws it.
    let mut default = LSystem::new();
    assert_eq!(default.start(&endless(9), 0), Err(capacity(8)));
    let mut large: LSystem<Streaming, 32, 256, 32, 1024, 64, 9> =
        LSystem::with_derivation(Streaming::new());
    large.start(&endless(9), 0).unwrap();
    assert_eq!(segments_in(&run_sim(&mut large)), 9);
    // Without interpretation rules a depth is never used: none fits.
    let mut none: LSystem<Streaming, 32, 256, 32, 1024, 64, 0> =
        LSystem::with_derivation(Streaming::new());
    none.start("n = 1\naxiom: A\nA -> F F", 0).unwrap();
    assert_eq!(segments_in(&run_sim(&mut none)), 2);
    assert_eq!(
        core::mem::size_of::<LSystem>() - core::mem::size_of_val(&small),
        6 * core::mem::size_of::<super::derive::Frame>()
    );

    // Decomposition rules nest in the `Buffered`: a chain of rules
    // applies one per level.
    fn derived<const DECOMPOSITION: usize>(depth: u32) -> Result<String, LsysError> {
        let g = grammar(&format!(
            "n = 1\naxiom: A\nA -> X\ndecomposition:\nmaximum depth: {depth}\nX -> Y\nY -> Z\nZ -> W"
        ));
        let (mut a, mut b) = (vec![Module::default(); 64], vec![Module::default(); 64]);
        let mut links = vec![Neighbours::default(); 64];
        let mut d = Buffered::<'_, DECOMPOSITION>::over(&mut a, &mut b, &mut links);
        d.restart(&g, 1, 0)?;
        let mut out = Vec::new();
        each_module(&mut d, &g, |m| out.push(m));
        Ok(text(&out))
    }
    let capacity = |capacity| {
        Err(LsysError::Capacity {
            limit: "DECOMPOSITION",
            capacity,
        })
    };
    assert_eq!(derived::<2>(3), capacity(2));
    assert_eq!(derived::<2>(2), Ok("Z".into()));
    // The default (`Buffered::new`, 16) refuses 17; a larger type
    // derives it (the chain ends at W).
    let (mut a, mut b) = ([Module::default(); 1], [Module::default(); 1]);
    let mut links = [Neighbours::default(); 1];
    let deep = grammar("n = 1\naxiom: A\ndecomposition:\nmaximum depth: 17\nA -> F");
    assert_eq!(
        Buffered::new(&mut a, &mut b, &mut links).restart(&deep, 1, 0),
        Err(LsysError::Capacity {
            limit: "DECOMPOSITION",
            capacity: 16
        })
    );
    assert_eq!(derived::<16>(17), capacity(16));
    assert_eq!(derived::<17>(17), Ok("W".into()));
    // Without decomposition rules a depth is never used: none fits.
    let mut d = Buffered::<'_, 0>::over(&mut a, &mut b, &mut links);
    d.restart(&grammar("n = 1\naxiom: A\nA -> F"), 1, 0)
        .unwrap();
}

#[test]
fn section_rules_are_checked_where_they_are_written() {
    use ParseErrorKind as K;
    for (text, line, kind) in [
        (
            "n = 1\naxiom: A\ndecomposition:\nB < A -> F",
            4,
            K::Expected(
                "a rule without context (decomposition and interpretation rules are context-free)",
            ),
        ),
        (
            "n = 1\naxiom: A\ninterpretation:\nA -> (0.5) F",
            4,
            K::Expected(
                "a successor without a probability (decomposition and interpretation rules are deterministic)",
            ),
        ),
        (
            "n = 1\naxiom: A\nmaximum depth: 3",
            3,
            K::InvalidValue(
                "`maximum depth` belongs in a `decomposition:` or `interpretation:` section",
            ),
        ),
        (
            "n = 1\naxiom: A\ndecomposition:\nmaximum depth: 256",
            4,
            K::InvalidValue("`maximum depth` must be a whole number from 1 to 255"),
        ),
        (
            "n = 1\naxiom: A\ninterpretation:\nmaximum depth: 1.5",
            4,
            K::InvalidValue("`maximum depth` must be a whole number from 1 to 255"),
        ),
        (
            "n = 1\naxiom: A\ninterpretation:\nA -> F %",
            4,
            K::Expected(
                "an interpretation successor without `%` (a cut acts on the derivation, which interpretation rules never reach)",
            ),
        ),
    ] {
        let e = parse_err(text);
        assert_eq!((e.line, e.kind), (line, kind), "{text}");
    }
    // L-Py's arrow `-->` reads as `->` (so `-->` cannot make `-` a
    // predecessor: write `- -> …`).
    let g = grammar("n = 1\naxiom: A-\nA --> F B\n- -> +\ninterpretation:\nB --> [+F]");
    assert_eq!(text(&streamed(&g, 1, 0)), "FB+");
    assert_eq!(
        segments("n = 1\naxiom: A\nA --> F B\ninterpretation:\nB --> [+F]", 0).len(),
        2
    );
    // Back to `production:` after a section.
    let g = grammar("n = 1\naxiom: A\ninterpretation:\nA -> F\nproduction:\nA -> B");
    assert_eq!(text(&streamed(&g, 1, 0)), "B");
}

fn polygons(source: &str) -> Vec<Vec<[Fx; 3]>> {
    let mut sim = LSystem::new();
    sim.start(source, 0).unwrap();
    let mut out: Vec<Vec<[Fx; 3]>> = Vec::new();
    for r in run_sim(&mut sim) {
        match r {
            Record::Polygon { vertices, .. } => out.push(Vec::with_capacity(vertices as usize)),
            Record::Point { p } => out.last_mut().unwrap().push(p),
            _ => {}
        }
    }
    out
}

#[test]
fn surfaces_are_polygons_in_the_turtle_frame() {
    use crate::turtle::SURFACES;
    let f = |x: i32| Fx::from_ratio(x, 100);
    // At the start H = +y and L = −x: the leaf's outline point (l, h)
    // lands at (−l, h) in hundredths.
    let leaf = polygons("n = 0\naxiom: ~L");
    assert_eq!(leaf.len(), 1);
    let expected: Vec<[Fx; 3]> = SURFACES[0]
        .2
        .iter()
        .map(|&(l, h)| [f(-l), f(h), Fx::ZERO])
        .collect();
    assert_eq!(leaf[0], expected);
    // Scaled by its parameter, after a move and a quarter turn left
    // (H = −x, L = −y), as a petal: (l, h) lands at (−2h, 1 − 2l).
    let petal = polygons("n = 0\naxiom: F + ~P(2)");
    let expected: Vec<[Fx; 3]> = SURFACES[1]
        .2
        .iter()
        .map(|&(l, h)| [f(-2 * h), Fx::ONE - f(2 * l), Fx::ZERO])
        .collect();
    assert_eq!(petal[0].len(), expected.len());
    for (p, q) in petal[0].iter().zip(&expected) {
        // Within 4 LSB: the turned frame and the scaled ratios round.
        assert!(
            (0..3).all(|i| (p[i].to_bits() - q[i].to_bits()).abs() <= 4),
            "{p:?} vs {q:?}"
        );
    }
    // The preset: seven leaves and five petals, from twelve polygons.
    assert_eq!(polygons(FLOWER).len(), 12);
    // Emitted by productions, with parameters, like any module.
    let g = "n = 2\naxiom: A(1)\nA(s) -> F [+ ~L(s)] A(s * 2)";
    assert_eq!(polygons(g).len(), 2);
    // A letter that names no surface, `~` as a predecessor, or `~` in an
    // open polygon are errors.
    let e = parse_err("n = 0\naxiom: F ~Q");
    assert_eq!((e.column, e.kind), (11, ParseErrorKind::UnknownSurface));
    assert_eq!(parse_err("n = 1\naxiom: F\n~ -> F").column, 1);
    assert_eq!(
        sim_error("n = 0\naxiom: {F ~L F}"),
        crate::Error::Lsys(LsysError::Turtle(crate::turtle::TurtleError::NestedPolygon))
    );
}

#[test]
fn more_than_streaming_steps_derive_buffered_and_streaming_names_its_limit() {
    // A counter and a stochastic choice at every one of 200 steps: the
    // buffered derivation reaches A(200), keyed to the last step.
    let g = grammar("n = 200\naxiom: A(0) B\nA(k) -> A(k + 1)\nB -> (1) B\nB -> (1) C");
    assert!(g.needs_buffer());
    let s = buffered(&g, 200, 0);
    assert_eq!(s[0].args(), [Fx::from_int(200)]);
    // The largest n ends too, at A(255): its step counter cannot pass it.
    let g = grammar("n = 255\naxiom: A(0) B\nA(k) -> A(k + 1)\nB -> (1) B\nB -> (1) C");
    let s = buffered(&g, 255, 0);
    assert_eq!(s[0].args(), [Fx::from_int(255)]);
    assert_eq!(s.len(), 2);
    assert_eq!(
        Streaming::new().restart(&g, 200, 0),
        Err(LsysError::Capacity {
            limit: "STEPS",
            capacity: <Streaming>::STEPS as u32
        })
    );
    assert_eq!(
        sim_error("n = 33\naxiom: F"),
        crate::Error::Lsys(LsysError::Capacity {
            limit: "STEPS",
            capacity: 32
        })
    );
    // At the default STEPS both still agree.
    let g = grammar("n = 32\naxiom: A\nA -> (1) A B\nA -> (1) B A\nB -> C");
    assert!(!g.needs_buffer());
    assert!(streamed(&g, 32, 3) == buffered(&g, 32, 3));
}

// L-Py's own examples of interpretation and decomposition rules, from
// github.com/fredboudon/lpy at f0b604d, translated into this syntax
// (`-->` is `->`, `produce` a successor, an `if` a condition).

/// The segments a buffered simulation draws (decomposition needs it).
fn buffered_segments(source: &str) -> Vec<([Fx; 3], [Fx; 3])> {
    let mut a = vec![Module::default(); 1000];
    let mut b = vec![Module::default(); 1000];
    let mut links = vec![Neighbours::default(); 1000];
    let mut sim = LSystem::<_>::with_derivation(Buffered::new(&mut a, &mut b, &mut links));
    sim.start(source, 0).unwrap();
    run_sim(&mut sim)
        .into_iter()
        .filter_map(|r| match r {
            Record::Segment { a, b, .. } => Some((a, b)),
            _ => None,
        })
        .collect()
}

/// The first parameter of each module, as integers.
fn first_params(modules: &[Module]) -> Vec<i32> {
    modules
        .iter()
        .filter_map(|m| m.args().first().map(|p| p.floor_int()))
        .collect()
}

fn distance(p: [Fx; 3], q: [Fx; 3]) -> f64 {
    p.iter()
        .zip(q)
        .map(|(a, b)| (a.to_f64() - b.to_f64()).powi(2))
        .sum::<f64>()
        .sqrt()
}

#[test]
fn lpy_test_homrule_interprets_n_as_ten_segments() {
    // L-Py test/test_homrule.py lines 6-12: the string
    // "PANNN[+ANNN][-ANNN]AN" under the interpretation rule `N --> F`
    // gives `len(scene) == 10`. The string itself is not rewritten.
    let source = "n = 0\naxiom: PANNN[+ANNN][-ANNN]AN\ninterpretation:\nN -> F";
    assert_eq!(segment_count(source), 10);
    assert_eq!(
        text(&streamed(&grammar(source), 0, 0)),
        "PANNN[+ANNN][-ANNN]AN"
    );
}

#[test]
fn lpy_test_recursiveinterpretation_needs_maximum_depth_2() {
    // L-Py test/lpytest/test_recursiveinterpretation.lpy lines 1-13: axiom
    // A, one step, `interpretation:` with `maximum depth: 2`, A --> B,
    // B --> F; EndEach asserts `len(lscene) == 1`.
    let source = "n = 1\naxiom: A\ninterpretation:\nmaximum depth: 2\nA -> B\nB -> F";
    assert_eq!(segment_count(source), 1);
    // Without the line, L-Py's default depth 1 (src/cpp/lsystem.cpp line
    // 140, `__interpretation_max_depth(1)`; line 1456 recurses only while
    // `maxdepth > 1`) leaves B uninterpreted: nothing is drawn.
    assert_eq!(segment_count(&source.replace("maximum depth: 2\n", "")), 0);
}

#[test]
fn lpy_training_circle_decomposes_into_n_sides() {
    // L-Py share/training/02-circle.lpy lines 1-21: `C(n): if n >= 0:
    // produce S(dl)C(n-1)` under `decomposition:` with `maximum depth: N`,
    // and the homomorphism `S(dl) : produce _(2)-(dalpha)F(dl)`, with
    // dalpha = 360/N and dl = dalpha*r. The file has N = 100; here N = 16,
    // a default `Buffered`'s `DECOMPOSITION`, and `_` (width) is `!`. At depth N the
    // recursion stops (src/cpp/lsystem.cpp lines 1105-1110 append the
    // deepest rule's string as it is), so C(N) becomes N S's and C(0): a
    // closed polygon of N sides, each dl long.
    let source = "n = 1\nN = 16\nr = 1\ndalpha = 360 / N\ndl = dalpha * r\naxiom: C(N)\n\
                  decomposition:\nmaximum depth: N\nC(n) : n >= 0 -> S(dl) C(n - 1)\n\
                  homomorphism:\nS(dl) -> !(2) -(dalpha) F(dl)";
    let g = grammar(source);
    let s = buffered(&g, 1, 0);
    assert_eq!(text(&s), format!("{}C", "S".repeat(16)));
    assert_eq!(s[16].args(), [Fx::ZERO]);
    let segs = buffered_segments(source);
    assert_eq!(segs.len(), 16);
    for &(a, b) in &segs {
        assert!((distance(a, b) - 22.5).abs() < 1e-3, "a side of dl = 22.5");
    }
    let gap = distance(segs[0].0, segs[15].1);
    assert!(gap < 1e-2, "the polygon closes: gap {gap}");
    // One level more and C(0) is decomposed too, leaving C(-1), to which
    // no rule applies: N + 1 sides.
    let deeper = source
        .replace("N = 16", "N = 15")
        .replace("maximum depth: N", "maximum depth: N + 1");
    let s = buffered(&grammar(&deeper), 1, 0);
    assert_eq!(text(&s), format!("{}C", "S".repeat(16)));
    assert_eq!(s[16].args(), [Fx::from_int(-1)]);
}

#[test]
fn lpy_training_fibonacci_decomposes_then_sums_its_left_context() {
    // L-Py share/training/13-fibonacci.lpy lines 3-35: axiom
    // `-(90);(3)A(nbValue)`, `derivation length: nbValue+1`, production
    // `I(j)I(k) < I(i): produce I(k+j)`, decomposition with `maximum
    // depth: nbValue+1` of `A(i): if i>0: produce I(1)A(i-1) else:
    // produce` (nothing), homomorphism `I(i): produce
    // f(1)F(1)[+(135);(4)f(sqrt(2.0)*0.5);(2)@L(str(i))]F(5)`. The file
    // has nbValue = 20; here 15 (depth 16, a default `Buffered`'s),
    // without the colours `;` and the label `@L`, which are not drawn
    // here. The first step decomposes A(15) into fifteen I(1); the next
    // fifteen make each I the sum of its two left neighbours in the
    // previous string, which settles on the Fibonacci numbers.
    let source = "nbValue = 15\nn = nbValue + 1\naxiom: -(90) A(nbValue)\n\
                  I(j) I(k) < I(i) -> I(k + j)\n\
                  decomposition:\nmaximum depth: nbValue + 1\n\
                  A(i) : i > 0 -> I(1) A(i - 1)\nA(i) : i <= 0 ->\n\
                  homomorphism:\nI(i) -> f(1) F(1) [+(135) f(sqrt(2) * 0.5)] F(5)";
    let g = grammar(source);
    let s = buffered(&g, 16, 0);
    assert_eq!(text(&s), format!("-{}", "I".repeat(15)));
    assert_eq!(
        first_params(&s[1..]),
        [1, 1, 2, 3, 5, 8, 13, 21, 34, 55, 89, 144, 233, 377, 610]
    );
    // Each I draws F(1) and F(5) along +x (`-(90)` turns right from +y),
    // 7 units with the f(1): the axis ends at x = 105.
    let segs = buffered_segments(source);
    assert_eq!(segs.len(), 30);
    let end = segs.last().unwrap().1;
    assert!(
        distance(end, [Fx::from_int(105), Fx::ZERO, Fx::ZERO]) < 1e-3,
        "{end:?}"
    );
}

/// A grammar for small pools, `Grammar::<2, 12, 2, 24, 4>`: 2
/// productions, 9 successor modules, 1 context module, 15 bytes of code
/// (`A(1)` 3, `x < k` 6, `A(x + 1)` 6), 2 literals (1 and k's 2).
const SMALL: &str = "n = 3\nk = 2\naxiom: b A(1)\nb < A(x) : x < k -> A(x + 1) F\nA(x) -> B[+F]\n";

type Small = Grammar<2, 12, 2, 24, 4>;

fn small_err(text: &str) -> (u32, ParseErrorKind) {
    let mut g = Small::empty();
    let e = g.parse(text).unwrap_err();
    (e.line, e.kind)
}

#[test]
fn smaller_pools_parse_what_fits_and_name_their_capacity() {
    let mut small = Small::empty();
    small.parse(SMALL).unwrap();
    assert_eq!(small.production_count(), 2);
    // What the module doc says of the pools' memory.
    assert!(core::mem::size_of::<Grammar<8, 64, 8, 256, 16>>() < 1024);
    assert!(core::mem::size_of::<Grammar>() < 3400);
    // The same grammar in the default pools derives the same string.
    let big = grammar(SMALL);
    assert_eq!(big.production_count(), 2);
    let derive = |g: &Small| {
        let mut a = vec![Module::default(); 64];
        let mut b = vec![Module::default(); 64];
        let mut links = vec![Neighbours::default(); 64];
        let mut d = Buffered::new(&mut a, &mut b, &mut links);
        d.restart(g, 3, 0).unwrap();
        let mut out = Vec::new();
        loop {
            match d.next_module(g).unwrap() {
                Next::Module(m) => out.push(m),
                Next::Pending => {}
                Next::End => return out,
            }
        }
    };
    assert_eq!(derive(&small), buffered(&big, 3, 0));
    assert_eq!(text(&derive(&small)), "bB[+F]F");
    let capacity = |limit, capacity| ParseErrorKind::Capacity { limit, capacity };
    // A third production.
    assert_eq!(
        small_err(&format!("{SMALL}C -> F")),
        (6, capacity("PRODUCTIONS", 2))
    );
    // A 13th successor module (the axiom's and the successors' 9, and 4).
    assert_eq!(
        small_err(&SMALL.replace("B[+F]", "B[+F]FFFF")),
        (5, capacity("SUCCESSORS", 12))
    );
    // A third context module.
    assert_eq!(
        small_err(&SMALL.replace("b < A", "b b b < A")),
        (4, capacity("CONTEXTS", 2))
    );
    // More than 24 bytes of expression code (15, and 4 × 3).
    assert_eq!(
        small_err(&SMALL.replace("A(x + 1)", "A(x + 1 + x + x + x + x)")),
        (4, capacity("CODE", 24))
    );
    // A fifth distinct literal (in 24 bytes of code).
    assert_eq!(
        small_err(&SMALL.replace("A(x + 1) F", "A(x + 1) F(3, 4, 5)")),
        (4, capacity("LITERALS", 4))
    );
    // The error reads as the limit of that type.
    let e = Small::empty().parse(&format!("{SMALL}C -> F")).unwrap_err();
    assert_eq!(
        std::format!("{e}"),
        "6:1: capacity PRODUCTIONS = 2 exceeded (see core/src/lsys/mod.rs)"
    );
}

#[test]
fn a_smaller_streaming_derives_as_many_steps_as_its_type_holds() {
    let g = grammar(PLANT_2D);
    let mut four = Streaming::<4>::empty();
    assert_eq!(
        four.restart(&g, 4, 0),
        Err(LsysError::Capacity {
            limit: "STEPS",
            capacity: 4
        })
    );
    let g = grammar(&PLANT_2D.replace("n = 5", "n = 4"));
    four.restart(&g, 4, 0).unwrap();
    let mut out = Vec::new();
    each_module(&mut four, &g, |m| out.push(m));
    assert_eq!(out, streamed(&g, 4, 0));
    assert!(four.positions().eq([2, 12, 62, 312, 1562]));
    assert!(core::mem::size_of::<Streaming<4>>() < core::mem::size_of::<Streaming>() / 4);
}

#[test]
fn a_small_lsystem_streams_the_records_of_the_default_one() {
    // The 2D plant in 4 steps, 2 productions and small pools: the same
    // records as the default simulation, in a fraction of its RAM.
    let text = PLANT_2D.replace("n = 5", "n = 4");
    let mut small = LSystem::<Streaming<4>, 2, 16, 2, 32, 8>::with_derivation(Streaming::empty());
    let mut default = LSystem::new();
    small.start(&text, 1).unwrap();
    default.start(&text, 1).unwrap();
    let records = run_sim(&mut small);
    assert!(records.len() > 400);
    assert_eq!(records, run_sim(&mut default));
    let (small, default) = (
        core::mem::size_of_val(&small),
        core::mem::size_of::<LSystem>(),
    );
    assert!(small * 2 < default, "{small} of {default} bytes");
}
