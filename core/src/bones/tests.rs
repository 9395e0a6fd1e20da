//! Bones against the paper: every wrapped mesh a closed genus-0 manifold
//! wound outwards, and the skeleton's limits. The built-in scenarios'
//! other checks (the iso-surface, the f64 reference, the stream) are in
//! `tests/tests/bones.rs`.

use nalgebra::Vector3;

use super::*;
use crate::Error;
use crate::fx::{Fx, Real};
use crate::shrinkwrap::{Element, Shrinkwrap, assert_closed_genus_0, signed_volume};
use crate::sim::Start;

type McuWrap = Shrinkwrap<Fx, MCU_VERTICES, MCU_TRIANGLES>;

/// A long bone's skeleton rules (deterministic), as the `long-bone` and
/// `bone-growth` scenarios read them.
const LONG_BONE_GRAMMAR: &str = include_str!("../../../grammars/long-bone.lsys");
/// The same rules with chance in them (`long-bone-random`).
const LONG_BONE_RANDOM_GRAMMAR: &str = include_str!("../../../grammars/long-bone-random.lsys");

/// The shrinkwrap of the built-in bone scenarios: a sphere of 24 × 11
/// vertices, V0 = 3.4 reached in steps of 0.15.
const WRAP: WrapParams = WrapParams {
    meridians: 24,
    parallels: 11,
    target: Fx::from_ratio(17, 5),
    step: Fx::from_ratio(3, 20),
    max_iterations: 64,
    split_tolerance: crate::shrinkwrap::SPLIT_TOLERANCE,
    weights: crate::shrinkwrap::Weights::Constant,
    target_max: None,
    step_max: None,
};

/// The shrinkwrap of `long-bone` and `bone-growth`: the paper's weights
/// (eqs. 1–2), V0 = 0.8 reached in steps of 0.05.
const WRAP_PAPER: WrapParams = WrapParams {
    target: Fx::from_ratio(4, 5),
    step: Fx::from_ratio(1, 20),
    weights: crate::shrinkwrap::Weights::Normalised,
    ..WRAP
};

/// The built-in bone scenarios' parameters (`scenarios/long-bone.toml`,
/// `long-bone-random.toml`, `bone-growth.toml`).
static PRESETS: [(&str, BonesParams<'static>); 3] = [
    (
        "long-bone",
        BonesParams {
            grammar: LONG_BONE_GRAMMAR,
            wrap: WRAP_PAPER,
            frames: Frames::Final,
        },
    ),
    (
        "long-bone-random",
        BonesParams {
            grammar: LONG_BONE_RANDOM_GRAMMAR,
            wrap: WRAP,
            frames: Frames::Seeds(3),
        },
    ),
    (
        "bone-growth",
        BonesParams {
            grammar: LONG_BONE_GRAMMAR,
            wrap: WRAP_PAPER,
            frames: Frames::EveryStep { first: 1 },
        },
    ),
];

/// The skeleton of every frame of `params` (steps, seed) from `seed`.
fn skeletons(params: &BonesParams, seed: u64) -> std::vec::Vec<Skeleton> {
    let mut g = Grower::new();
    g.load(params.grammar).unwrap();
    let n = g.grammar().settings().steps;
    let setups: std::vec::Vec<(u8, u64)> = match params.frames {
        Frames::Final => vec![(n, seed)],
        Frames::EveryStep { first } => (first..=n).map(|k| (k, seed)).collect(),
        Frames::Seeds(c) => (0..c as u64).map(|k| (n, seed + k)).collect(),
    };
    setups
        .into_iter()
        .map(|(steps, seed)| {
            let mut s = Skeleton::new();
            g.grow(steps, seed, &mut s).unwrap();
            s
        })
        .collect()
}

#[test]
fn every_preset_mesh_is_a_closed_genus_0_manifold_wound_outwards() {
    // Every frame of every preset (seed 1).
    for (name, p) in &PRESETS {
        for (frame, skeleton) in skeletons(p, 1).into_iter().enumerate() {
            let mut w = Box::new(McuWrap::new(Fx::ZERO));
            w.run(&skeleton, &p.wrap).unwrap();
            let m = w.mesh();
            let edges = assert_closed_genus_0(m.vertices().len(), m.triangles());
            assert_eq!(3 * m.triangles().len(), 2 * edges, "{name} frame {frame}");
            let v: std::vec::Vec<Vector3<f64>> =
                m.vertices().iter().map(|v| v.map(f64::from_fx)).collect();
            assert!(
                signed_volume(&v, m.triangles()) > 0.0,
                "{name} frame {frame}"
            );
        }
    }
}

/// The field cache of a host's run ([`HOST_FIELD_CACHE`]) changes no bit:
/// every frame of every preset wraps to the same vertices and triangles
/// with it and without it, also when the skeleton changes between two
/// iterations of one run (the cache is then dropped), and with a cache
/// smaller than the mesh.
#[test]
fn the_field_cache_changes_no_bit() {
    fn same<const C: usize>(a: &McuWrap, b: &Shrinkwrap<Fx, MCU_VERTICES, MCU_TRIANGLES, C>) {
        assert_eq!(a.mesh().vertices(), b.mesh().vertices());
        assert_eq!(a.mesh().triangles(), b.mesh().triangles());
        assert_eq!((a.phase(), a.iterations()), (b.phase(), b.iterations()));
    }
    for (name, p) in &PRESETS {
        let frames = skeletons(p, 1);
        for skeleton in &frames {
            let mut plain = Box::new(McuWrap::new(Fx::ZERO));
            let mut cached = Box::new(Shrinkwrap::<
                Fx,
                MCU_VERTICES,
                MCU_TRIANGLES,
                HOST_FIELD_CACHE,
            >::new(Fx::ZERO));
            let mut small = Box::new(Shrinkwrap::<Fx, MCU_VERTICES, MCU_TRIANGLES, 100>::new(
                Fx::ZERO,
            ));
            plain.run(skeleton, &p.wrap).unwrap();
            cached.run(skeleton, &p.wrap).unwrap();
            small.run(skeleton, &p.wrap).unwrap();
            same(&plain, &cached);
            same(&plain, &small);
        }
        // Started on the first frame's skeleton, iterated on the last one's.
        let (first, last) = (&frames[0], &frames[frames.len() - 1]);
        let mut plain = Box::new(McuWrap::new(Fx::ZERO));
        let mut cached = Box::new(Shrinkwrap::<
            Fx,
            MCU_VERTICES,
            MCU_TRIANGLES,
            HOST_FIELD_CACHE,
        >::new(Fx::ZERO));
        plain.start(first, &p.wrap).unwrap();
        cached.start(first, &p.wrap).unwrap();
        for k in 0..6 {
            let s = if k < 2 { first } else { last };
            plain.iterate(s).unwrap();
            cached.iterate(s).unwrap();
            same(&plain, &cached);
        }
        assert!(!plain.mesh().vertices().is_empty(), "{name}");
    }
}

#[test]
fn a_grammar_that_never_draws_ends_with_a_named_limit() {
    let mut g = Grower::new();
    g.load("n = 20\naxiom: A\nA -> AA").unwrap();
    let e = g.grow(20, 0, &mut Skeleton::new()).unwrap_err();
    assert!(matches!(
        e,
        Error::Capacity {
            limit: "MAX_SKELETON_MODULES",
            ..
        }
    ));
    // One that erases what it grows: 2^27 modules, none given.
    g.load("n = 28\naxiom: A(0)\nA(x) : x < 27 -> A(x + 1) A(x + 1)\nA(x) : x >= 27 ->")
        .unwrap();
    let e = g.grow(28, 0, &mut Skeleton::new()).unwrap_err();
    assert!(matches!(
        e,
        Error::Capacity {
            limit: "MAX_SKELETON_VISITS",
            ..
        }
    ));
    g.load("n = 7\naxiom: F\nF -> FF").unwrap();
    let e = g.grow(7, 0, &mut Skeleton::new()).unwrap_err();
    assert!(matches!(
        e,
        Error::Capacity {
            limit: "MAX_ELEMENTS",
            ..
        }
    ));
}

/// Frames from a step past the grammar's `n` are refused at the start,
/// not derived: the grammar's steps are the run's.
#[test]
fn frames_past_the_grammars_last_step_are_refused() {
    let params = BonesParams {
        frames: Frames::EveryStep { first: 13 },
        ..PRESETS[2].1
    };
    let mut bones = Bones::<MCU_VERTICES, MCU_TRIANGLES>::new();
    let refused = Err(Error::Bones(BonesError::FirstStepPastEnd {
        first: 13,
        steps: 12,
    }));
    assert_eq!(bones.start(&params, 0), refused);
    let last = BonesParams {
        frames: Frames::EveryStep { first: 12 },
        ..params
    };
    assert_eq!(bones.start(&last, 0), Ok(()));
}

/// |v| in f64 (nalgebra's `norm` needs its `libm` feature).
fn length(v: Vector3<f64>) -> f64 {
    v.dot(&v).sqrt()
}

/// The winding number of the closed mesh around `p` (the solid angle of
/// its triangles seen from `p`, Van Oosterom and Strackee, over 4π): 1
/// inside, 0 outside.
fn winding_number(vertices: &[Vector3<f64>], triangles: &[[u16; 3]], p: Vector3<f64>) -> f64 {
    let mut sum = 0.0;
    for t in triangles {
        let [a, b, c] = t.map(|i| vertices[usize::from(i)] - p);
        let (la, lb, lc) = (length(a), length(b), length(c));
        let numerator = a.dot(&b.cross(&c));
        let denominator = la * lb * lc + a.dot(&b) * lc + b.dot(&c) * la + c.dot(&a) * lb;
        sum += 2.0 * numerator.atan2(denominator);
    }
    sum / (4.0 * std::f64::consts::PI)
}

/// A square plate `{ … }` (one convex polygon element, ρ = 0.5) wraps to a
/// slab around it: the surface covers the plate's centre, 0.5 = ρ / V0
/// above and below it. Its four edges as plain segments instead leave the
/// centre outside the level (V = 4 · 0.5 / 3 there), and no surface lies
/// 0.5 above it.
#[test]
fn a_polygon_element_is_wrapped_as_a_plate() {
    let params = WrapParams {
        target: Fx::ONE,
        step: Fx::from_ratio(1, 20),
        ..WRAP
    };
    let mut g = Grower::new();
    g.load("n = 0\naxiom: !(0.5) { f(6) +(90) f(6) +(90) f(6) +(90) }")
        .unwrap();
    let mut plate = Skeleton::new();
    g.grow(0, 0, &mut plate).unwrap();
    assert_eq!(
        plate
            .iter()
            .map(|e| e.polygon)
            .collect::<std::vec::Vec<_>>(),
        [4, 3, 2, 1]
    );
    let corners: std::vec::Vec<Vector3<f64>> = plate
        .iter()
        .map(|e| Vector3::from(e.a).map(f64::from_fx))
        .collect();
    let centre = corners.iter().sum::<Vector3<f64>>() / 4.0;
    assert!(
        length(centre - Vector3::new(-3.0, 3.0, 0.0)) < 1e-3,
        "{centre}"
    );
    let rings: Skeleton = plate.iter().map(|e| Element { polygon: 0, ..*e }).collect();
    let near_axis = |skeleton: &Skeleton| {
        let mut w = Box::new(McuWrap::new(Fx::ZERO));
        w.run(skeleton, &params).unwrap();
        let m = w.mesh();
        assert_closed_genus_0(m.vertices().len(), m.triangles());
        let v: std::vec::Vec<Vector3<f64>> =
            m.vertices().iter().map(|v| v.map(f64::from_fx)).collect();
        let heights: std::vec::Vec<f64> = v
            .iter()
            .filter(|p| (p.x - centre.x).hypot(p.y - centre.y) < 1.0)
            .map(|p| p.z)
            .collect();
        (winding_number(&v, m.triangles(), centre), heights)
    };
    let (winding, heights) = near_axis(&plate);
    assert!((winding - 1.0).abs() < 1e-6, "{winding}");
    assert!(heights.iter().any(|&z| z > 0.0) && heights.iter().any(|&z| z < 0.0));
    assert!(
        heights.iter().all(|z| (z.abs() - 0.5).abs() < 0.03),
        "{heights:?}"
    );
    let (_, ring_heights) = near_axis(&rings);
    assert!(
        !ring_heights.iter().any(|z| (z.abs() - 0.5).abs() < 0.03),
        "{ring_heights:?}"
    );
    let v = crate::shrinkwrap::potential(
        &rings,
        &centre.map(|c| Fx::from_fixed(fixed::types::I16F16::from_num(c))),
    );
    assert!(v < Fx::ONE, "{v:?}");
}

/// A polygon that is not convex, or has more vertices than the turtle
/// records, stops the skeleton with an error naming why.
#[test]
fn bad_polygons_are_errors() {
    let mut g = Grower::new();
    let grow = |g: &mut Grower, text: &str| {
        g.load(text).unwrap();
        g.grow(0, 0, &mut Skeleton::new()).unwrap_err()
    };
    assert!(matches!(
        grow(
            &mut g,
            "n = 0\naxiom: { f(4) +(90) f(4) +(135) f(2) -(90) f(2) }"
        ),
        Error::Shrinkwrap(crate::shrinkwrap::ShrinkwrapError::PolygonNotConvex { .. })
    ));
    assert!(matches!(
        grow(&mut g, "n = 0\naxiom: { f(4) +(90) f(4) +(90) &(30) f(4) }"),
        Error::Shrinkwrap(crate::shrinkwrap::ShrinkwrapError::PolygonNotPlanar { .. })
    ));
    let many = format!("n = 0\naxiom: {{ {} }}", "f(1) +(10) ".repeat(30));
    assert_eq!(
        grow(&mut g, &many),
        Error::Lsys(crate::lsys::LsysError::Turtle(
            crate::turtle::TurtleError::TooManyVertices
        ))
    );
}

/// Collects records.
#[derive(Default)]
struct Records(std::vec::Vec<crate::stream::Record>);

impl crate::stream::Sink for Records {
    fn record(&mut self, r: &crate::stream::Record) -> Result<(), crate::stream::SinkError> {
        self.0.push(r.clone());
        Ok(())
    }
}

/// Every record of a bone run of `params` from `seed`.
fn run_records(params: &BonesParams<'_>, seed: u64) -> std::vec::Vec<crate::stream::Record> {
    use crate::sim::Simulation;
    let mut bones = Box::new(Bones::<MCU_VERTICES, MCU_TRIANGLES>::new());
    bones.start(params, seed).unwrap();
    let mut out = Records::default();
    while !bones.step(&mut out).unwrap().finished() {}
    out.0
}

/// One point O(1) with constant weights, wrapped on a small sphere: it
/// wraps to a sphere of radius 1/V0, drawn in [2, 4] per frame.
const POINT: BonesParams<'static> = BonesParams {
    grammar: "n = 0\naxiom: O(1)\n",
    wrap: WrapParams {
        meridians: 8,
        parallels: 5,
        target: Fx::from_int(2),
        step: Fx::from_ratio(1, 4),
        max_iterations: 64,
        split_tolerance: crate::shrinkwrap::SPLIT_TOLERANCE,
        weights: crate::shrinkwrap::Weights::Constant,
        target_max: Some(Fx::from_int(4)),
        step_max: Some(Fx::from_ratio(1, 2)),
    },
    frames: Frames::Seeds(4),
};

/// The paper's random parameter values (Summary; Fig. 3): each frame's V0
/// and ΔV are drawn in their ranges, differ from seed to seed, repeat
/// with the seed, and the frame's mesh lies on the drawn level (a point's
/// sphere of radius 1/V0).
#[test]
fn a_wrap_range_draws_each_frames_level_and_repeats_with_the_seed() {
    let drawn: std::vec::Vec<WrapParams> = (0..4).map(|k| POINT.frame_wrap(5 + k, 0)).collect();
    for w in &drawn {
        assert!(Fx::from_int(2) <= w.target && w.target <= Fx::from_int(4));
        assert!(Fx::from_ratio(1, 4) <= w.step && w.step <= Fx::from_ratio(1, 2));
        assert_eq!((w.target_max, w.step_max), (None, None));
    }
    for pair in drawn.windows(2) {
        assert_ne!(pair[0].target, pair[1].target);
        assert_ne!(pair[0].step, pair[1].step);
    }
    // Not the derivation's streams: V0 and ΔV are not the same draw.
    assert_ne!(
        (drawn[0].target - Fx::from_int(2)) / Fx::from_int(2),
        (drawn[0].step - Fx::from_ratio(1, 4)) * Fx::from_int(4)
    );
    let run = run_records(&POINT, 5);
    assert_eq!(run, run_records(&POINT, 5));
    assert_ne!(run, run_records(&POINT, 6));
    // Frame k is seed 5 + k's: its vertices at 1/V0 of that draw.
    let mut frame = 0usize;
    for r in &run {
        match r {
            crate::stream::Record::FrameStart { frame: k, .. } => frame = *k as usize,
            crate::stream::Record::MeshVertex { p, .. } => {
                let radius = p
                    .iter()
                    .map(|c| c.to_f64() * c.to_f64())
                    .sum::<f64>()
                    .sqrt();
                let expected = 1.0 / drawn[frame].target.to_f64();
                assert!(
                    (radius - expected).abs() < 0.05 * expected,
                    "frame {frame}: {radius} against {expected}"
                );
            }
            _ => {}
        }
    }
    assert_eq!(frame, 3);
}

/// A range of width 0 is the plain number: the same records, bit for bit.
#[test]
fn a_wrap_range_of_width_0_is_the_plain_number() {
    let plain = BonesParams {
        wrap: WrapParams {
            target: Fx::from_ratio(5, 2),
            target_max: None,
            step_max: None,
            ..POINT.wrap
        },
        ..POINT
    };
    let narrow = BonesParams {
        wrap: WrapParams {
            target_max: Some(plain.wrap.target),
            step_max: Some(plain.wrap.step),
            ..plain.wrap
        },
        ..plain
    };
    assert_eq!(run_records(&narrow, 5), run_records(&plain, 5));
}
