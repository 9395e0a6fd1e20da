//! The built-in bone scenarios against the paper: every vertex on the
//! iso-surface, the fixed-point wrap against the f64 one, growth and
//! chance in the skeletons, limits, and the stream. (The mesh topology
//! checks are unit tests in `core/src/bones/tests.rs`.)
#![allow(clippy::float_arithmetic, clippy::unwrap_used)]

use std::sync::OnceLock;

use morphogen::Error;
use morphogen::bones::{BonesParams, Frames, Grower, MCU_TRIANGLES, MCU_VERTICES, Skeleton};
use morphogen::fx::{Fx, Real};
use morphogen::lsys::{Buffered, LsysError, Module, Neighbours};
use morphogen::preset::{self, Model, Runner};
use morphogen::shrinkwrap::{
    Element, Shrinkwrap, ShrinkwrapError, Weights, WrapParams, worst_level_error,
};
use morphogen::stream::{Record, Sink, SinkError};
use nalgebra::Vector3;

type McuWrap = Shrinkwrap<Fx, MCU_VERTICES, MCU_TRIANGLES>;

/// The built-in bone scenarios the MCU derives (the streaming derivation);
/// `bone-ossification` is context-sensitive, for the host.
const PRESETS: [&str; 4] = ["long-bone", "long-bone-random", "bone-growth", "bone-plate"];

/// Calls `f` with the parameters of the built-in bone scenario `name`.
fn with_bones<R>(name: &str, f: impl FnOnce(&BonesParams<'_>) -> R) -> R {
    let scenario = morphogen_scenario::builtin(name).unwrap();
    scenario.with_preset(|p| {
        let Model::Bones(params) = p.model else {
            unreachable!("{name} is not a bone")
        };
        f(params)
    })
}

/// The (derivation steps, seed) of every frame of `params` from `seed`.
fn setups(params: &BonesParams, seed: u64) -> Vec<(u8, u64)> {
    let mut g = Grower::new();
    g.load(params.grammar).unwrap();
    let n = g.grammar().settings().steps;
    match params.frames {
        Frames::Final => vec![(n, seed)],
        Frames::EveryStep { first } => (first..=n).map(|k| (k, seed)).collect(),
        Frames::Seeds(c) => (0..c as u64).map(|k| (n, seed + k)).collect(),
    }
}

/// The skeleton of every frame of `params` from `seed`.
fn skeletons(params: &BonesParams, seed: u64) -> Vec<Skeleton> {
    let mut g = Grower::new();
    g.load(params.grammar).unwrap();
    setups(params, seed)
        .into_iter()
        .map(|(steps, seed)| {
            let mut s = Skeleton::new();
            g.grow(steps, seed, &mut s).unwrap();
            s
        })
        .collect()
}

/// The wrap of every frame of `params` from `seed`, V0 and ΔV drawn.
fn frame_wraps(params: &BonesParams, seed: u64) -> Vec<WrapParams> {
    setups(params, seed)
        .into_iter()
        .map(|(steps, seed)| params.frame_wrap(seed, steps))
        .collect()
}

fn wrap_fx(s: &Skeleton, wrap: &WrapParams) -> Box<McuWrap> {
    let mut w = Box::new(McuWrap::new(Fx::ZERO));
    w.run(s, wrap).unwrap();
    w
}

/// One wrapped preset frame, fixed point and f64.
struct Wrapped {
    name: &'static str,
    frame: usize,
    target: Fx,
    weights: Weights,
    skeleton: Skeleton,
    fx: Box<McuWrap>,
    f64: Box<Shrinkwrap<f64, MCU_VERTICES, MCU_TRIANGLES>>,
}

/// Every frame of every preset (seed 1), wrapped once for all tests.
fn wrapped() -> &'static [Wrapped] {
    static ALL: OnceLock<Vec<Wrapped>> = OnceLock::new();
    ALL.get_or_init(|| {
        let mut out = Vec::new();
        for name in PRESETS {
            with_bones(name, |p| {
                let wraps = frame_wraps(p, 1);
                for (frame, skeleton) in skeletons(p, 1).into_iter().enumerate() {
                    let wrap = &wraps[frame];
                    let fx = wrap_fx(&skeleton, wrap);
                    let sf: Vec<Element<f64>> =
                        skeleton.iter().map(|e| e.convert(f64::from_fx)).collect();
                    let mut f64 = Box::new(Shrinkwrap::new(0.0));
                    f64.run(&sf, wrap).unwrap();
                    out.push(Wrapped {
                        name,
                        frame,
                        target: wrap.target,
                        weights: p.wrap.weights,
                        skeleton,
                        fx,
                        f64,
                    });
                }
            });
        }
        out
    })
}

#[test]
fn every_vertex_of_every_preset_frame_is_within_5_percent_of_v0() {
    for w in wrapped() {
        let worst = worst_level_error(&w.skeleton, w.weights, w.fx.mesh().vertices(), w.target);
        assert!(
            worst.to_f64() <= 0.05,
            "{} frame {}: {}",
            w.name,
            w.frame,
            worst.to_f64()
        );
    }
}

/// The fixed-point wrap follows the f64 wrap of the same skeleton. An edge
/// whose midpoint is within rounding of the 5 % threshold may be split in
/// one and not the other, so the meshes need not share their triangles
/// (7 of 16 frames of segments and points do: the paper's weights give
/// meshes of up to 827 vertices, each split a chance to differ). Held
/// instead: vertex counts within 2 %; in every frame of segments and
/// points every fixed-point vertex has an f64 vertex within 0.1 % of the
/// bone's length (8.6) (measured: all of them), and where the triangles
/// agree the twins are within that of each other (measured: 0.0005); and
/// every fixed-point vertex on the exact (f64) iso-surface within 0.5 % of
/// V0 (measured: 0.34 %). A frame with a polygon element (`bone-plate`) is
/// held to the vertex count and the level only: the fixed-point polygon
/// distance is within 10⁻³ of the f64 one (`shrinkwrap::polygon`'s test),
/// far more than a segment's rounding.
#[test]
fn fixed_point_wrap_matches_the_f64_reference() {
    let (mut same, mut worst_distance, mut worst_level) = (0, 0.0f64, 0.0f64);
    let plain = |w: &Wrapped| w.skeleton.iter().all(|e| e.polygon == 0);
    let compared = wrapped().iter().filter(|w| plain(w)).count();
    for w in wrapped() {
        let (a, b) = (w.fx.mesh(), w.f64.mesh());
        let (na, nb) = (a.vertices().len() as f64, b.vertices().len() as f64);
        assert!(
            (na - nb).abs() <= 0.02 * nb,
            "{} frame {}: {na} vs {nb} vertices",
            w.name,
            w.frame
        );
        let alike = a.triangles() == b.triangles();
        if plain(w) {
            let twins = a
                .vertices()
                .iter()
                .filter(|p| {
                    let p = p.map(f64::from_fx);
                    b.vertices()
                        .iter()
                        .any(|q| <f64 as Real>::norm(&(p - q)) <= 0.001 * 8.6)
                })
                .count();
            assert_eq!(
                twins,
                a.vertices().len(),
                "{} frame {}: vertices without an f64 twin",
                w.name,
                w.frame
            );
        }
        if plain(w) && alike {
            same += 1;
            for (p, q) in a.vertices().iter().zip(b.vertices()) {
                worst_distance =
                    worst_distance.max(<f64 as Real>::norm(&(p.map(f64::from_fx) - q)));
            }
        }
        let sf: Vec<Element<f64>> = w.skeleton.iter().map(|e| e.convert(f64::from_fx)).collect();
        let points: Vec<Vector3<f64>> = a.vertices().iter().map(|v| v.map(f64::from_fx)).collect();
        worst_level = worst_level.max(worst_level_error(
            &sf,
            w.weights,
            &points,
            f64::from_fx(w.target),
        ));
    }
    println!(
        "{same} of {compared} frames of segments and points split alike; largest vertex distance {worst_distance:.6}; largest exact |V − V0|/V0 (all {} frames) {worst_level:.6}",
        wrapped().len()
    );
    assert!(worst_distance <= 0.001 * 8.6, "{worst_distance}");
    assert!(worst_level <= 0.005, "{worst_level}");
}

#[test]
fn bone_growth_wraps_every_step_and_the_bone_grows() {
    let s = with_bones("bone-growth", |p| skeletons(p, 0));
    assert_eq!(s.len(), 12);
    // The shaft's 8 segments until the growth plates close, then at each
    // end two condyles of 2 segments and a point each, and a point:
    // 8 + 2 × 7.
    assert_eq!(
        s.iter().map(|s| s.len()).collect::<Vec<_>>(),
        [8, 8, 8, 22, 22, 22, 22, 22, 22, 22, 22, 22]
    );
    let length = |s: &Skeleton| s.iter().map(|e| e.a[1].max(e.b[1])).fold(Fx::MIN, Fx::max);
    assert!(s.windows(2).all(|w| length(&w[1]) > length(&w[0])));
}

#[test]
fn random_bones_differ_by_seed_and_repeat_by_seed() {
    with_bones("long-bone-random", |p| {
        let a = skeletons(p, 1);
        assert_ne!(a[0], a[1]);
        assert_ne!(a[1], a[2]);
        assert_eq!(a, skeletons(p, 1));
    });
}

#[test]
fn limits_are_errors_naming_them() {
    let (s, wrap) = with_bones("long-bone", |p| (skeletons(p, 0).remove(0), p.wrap));
    let s = &s;
    let mut small = Box::new(Shrinkwrap::<Fx, 300, 600>::new(Fx::ZERO));
    let e = small.run(s, &wrap).unwrap_err();
    assert!(
        matches!(e, Error::Capacity { limit, .. } if limit.contains("vertices")),
        "{e:?}"
    );
    let mut few = wrap;
    few.max_iterations = 5;
    let e = wrap_fx_err(s, &few);
    assert!(matches!(e, Error::Capacity { limit, capacity: 5 } if limit.contains("iterations")));
    let mut bad = wrap;
    bad.parallels = 8;
    assert_eq!(
        wrap_fx_err(s, &bad),
        Error::Shrinkwrap(ShrinkwrapError::Sphere {
            meridians: 24,
            parallels: 8
        })
    );
    bad = wrap;
    bad.step = Fx::ZERO;
    assert_eq!(
        wrap_fx_err(s, &bad),
        Error::Shrinkwrap(ShrinkwrapError::Level)
    );
    assert_eq!(
        wrap_fx_err(&Skeleton::new(), &wrap),
        Error::Shrinkwrap(ShrinkwrapError::NoSkeleton)
    );
}

fn wrap_fx_err(s: &Skeleton, params: &WrapParams) -> Error {
    let mut w = Box::new(McuWrap::new(Fx::ZERO));
    w.run(s, params).unwrap_err()
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

#[test]
fn the_stream_holds_the_skeleton_then_the_mesh_of_each_frame() {
    let scenario = morphogen_scenario::builtin("long-bone-random").unwrap();
    scenario.with_preset(|preset| {
        let Model::Bones(params) = preset.model else {
            unreachable!("long-bone-random is a bone")
        };
        let mut runner = Box::new(Runner::new());
        let mut out = Records::default();
        preset::run(preset, 1, &mut runner, &mut out, &mut |_| {}).unwrap();
        let skeletons = skeletons(params, 1);
        let wraps = frame_wraps(params, 1);
        let starts: Vec<usize> = out
            .0
            .iter()
            .enumerate()
            .filter(|(_, r)| matches!(r, Record::FrameStart { .. }))
            .map(|(i, _)| i)
            .collect();
        assert_eq!(starts.len(), 3);
        for (k, &i) in starts.iter().enumerate() {
            let w = wrap_fx(&skeletons[k], &wraps[k]);
            let (nv, nt) = (w.mesh().vertices().len(), w.mesh().triangles().len());
            let frame = &out.0[i + 1..i + 1 + skeletons[k].len() + nv + nt + 1];
            assert!(
                frame[..skeletons[k].len()]
                    .iter()
                    .all(|r| matches!(r, Record::Segment { .. }))
            );
            assert!(matches!(
                frame[skeletons[k].len()],
                Record::MeshVertex { id: 0, .. }
            ));
            assert!(matches!(frame.last(), Some(Record::FrameEnd { .. })));
        }
    });
}

/// `bone-plate`'s plate is one polygon element: four edges tagged 4 … 1,
/// streamed as a `Polygon` record of 4 vertices and its 4 edges, which
/// the MCU runs.
#[test]
fn the_plate_is_a_polygon_element_in_the_stream() {
    let scenario = morphogen_scenario::builtin("bone-plate").unwrap();
    scenario.with_preset(|preset| {
        assert!(preset.model.fits_mcu());
        let Model::Bones(params) = preset.model else {
            unreachable!("bone-plate is a bone")
        };
        let skeleton = skeletons(params, 0).remove(0);
        assert_eq!(
            skeleton.iter().map(|e| e.polygon).collect::<Vec<_>>(),
            [4, 3, 2, 1, 0, 0, 0]
        );
        let mut runner = Box::new(Runner::new());
        let mut out = Records::default();
        preset::run(preset, 0, &mut runner, &mut out, &mut |_| {}).unwrap();
        let start = out
            .0
            .iter()
            .position(|r| matches!(r, Record::FrameStart { .. }))
            .unwrap();
        assert!(matches!(
            out.0[start + 1],
            Record::Polygon {
                vertices: 4,
                colour: 0
            }
        ));
        for (k, e) in skeleton.iter().take(4).enumerate() {
            assert_eq!(
                out.0[start + 2 + k],
                Record::Segment {
                    a: e.a,
                    b: e.b,
                    width: e.weight,
                    colour: 0
                }
            );
        }
    });
}

/// The skeleton of `text` after 0 … `n` steps, derived buffered.
fn buffered_skeletons(text: &str) -> Vec<Skeleton> {
    let (mut a, mut b) = (vec![Module::default(); 4096], vec![Module::default(); 4096]);
    let mut links = vec![Neighbours::default(); 4096];
    let mut g = Grower::with_derivation(Buffered::new(&mut a, &mut b, &mut links));
    g.load(text).unwrap();
    (0..=g.grammar().settings().steps)
        .map(|steps| {
            let mut s = Skeleton::new();
            g.grow(steps, 0, &mut s).unwrap();
            s
        })
        .collect()
}

/// `bone-ossification` (the paper's context-sensitive L-system, Sec. 3):
/// cartilage becomes shaft only beside bone, so the shaft grows one
/// segment each way per step from the ossification centre, and the end
/// caps become condyles only when it reaches them (step 5). Were the
/// contexts ignored, every cartilage piece and both caps would turn at
/// step 1, as the same rules without their contexts do. The MCU's
/// streaming derivation refuses the grammar by name; the host runs it.
#[test]
fn the_ossifying_bone_follows_its_contexts() {
    with_bones("bone-ossification", |p| {
        let segments = |s: &Skeleton| s.iter().filter(|e| e.a != e.b).count();
        let counted: Vec<usize> = buffered_skeletons(p.grammar).iter().map(segments).collect();
        assert_eq!(counted, [0, 2, 4, 6, 8, 12, 12, 12, 12]);
        // Each side of the centre: the shaft reaches the cap in 4 steps.
        let free: String = p
            .grammar
            .lines()
            .map(|l| {
                let rule = l.split(" < ").last().unwrap();
                let rule = match rule.split_once(" > ") {
                    Some((predecessor, rest)) => {
                        format!("{predecessor} -> {}", rest.split_once(" -> ").unwrap().1)
                    }
                    None => rule.to_string(),
                };
                rule + "\n"
            })
            .collect();
        let counted_free: Vec<usize> = buffered_skeletons(&free).iter().map(segments).collect();
        assert!(counted_free[1] >= 12, "{counted_free:?}");
        // Streaming (the MCU's) refuses it, naming why.
        let mut g = Grower::new();
        g.load(p.grammar).unwrap();
        assert_eq!(
            g.grow(1, 0, &mut Skeleton::new()),
            Err(Error::Lsys(LsysError::NeedsBuffer))
        );
    });
    let scenario = morphogen_scenario::builtin("bone-ossification").unwrap();
    scenario.with_preset(|preset| {
        assert!(!preset.model.fits_mcu());
        let mut runner = Box::new(Runner::new());
        let e = preset::run(preset, 0, &mut runner, &mut Records::default(), &mut |_| {});
        assert_eq!(e.unwrap_err(), Error::Lsys(LsysError::NeedsBuffer));
    });
}

/// A bone skeleton is the derived string itself: interpretation rules,
/// which would change only the drawing, are refused naming them rather
/// than silently ignored.
#[test]
fn interpretation_rules_in_a_bone_grammar_are_refused() {
    let mut grower = Grower::new();
    let text = "n = 2\naxiom: A\nA -> A F(1)\ninterpretation:\nA -> F(1)\n";
    assert!(matches!(
        grower.load(text),
        Err(LsysError::Unsupported(what)) if what.contains("interpretation")
    ));
    assert!(grower.load("n = 2\naxiom: A\nA -> A F(1)\n").is_ok());
}
