//! The horn's acceptance checks: continuity between modules, only the
//! youngest positioner moving, fixed point against the f64 reference, and
//! the state staying small.
#![allow(clippy::float_arithmetic, clippy::unwrap_used, clippy::panic)]

use morphogen::Error;
use morphogen::fx::{Fx, Real};
use morphogen::geom::Rigid;
use morphogen::horn::{Emit, Horn, HornError, HornKernel, HornParams, Moment};
use morphogen::preset::{Model, Runner};
use morphogen::sim::Start as _;
use nalgebra::Vector3;

/// Calls `f` with the parameters of the built-in horn scenario `name`.
fn with_horn<R>(name: &str, f: impl FnOnce(&HornParams<'_>) -> R) -> R {
    let scenario = morphogen_scenario::builtin(name).unwrap();
    scenario.with_preset(|p| {
        let Model::Horn(params) = p.model else {
            unreachable!("{name} is not a horn")
        };
        f(params)
    })
}

/// The built-in horn scenarios.
const HORNS: [&str; 2] = ["ram-horn", "ram-horn-animation"];

/// One frame's rings: (module, ring, points).
type Rings<R> = Vec<(u16, u16, Vec<Vector3<R>>)>;

fn frame<R: Real>(kernel: &mut HornKernel<'_, R>, t: Moment) -> Rings<R> {
    kernel.place(t).unwrap();
    let mut rings: Rings<R> = Vec::new();
    kernel
        .emit(&mut |e| {
            match e {
                Emit::Ring { module, ring, .. } => rings.push((module, ring, Vec::new())),
                Emit::Point(p) => rings.last_mut().unwrap().2.push(p),
            }
            Ok(())
        })
        .unwrap();
    rings
}

fn frames<'a>(params: &'a HornParams<'_>) -> impl Iterator<Item = Moment> + 'a {
    (1..=params.frames()).map(|m| Moment::new(m, u32::from(params.frames_per_year)))
}

/// Σ r·α(T): the full-grown horn's length along its path, cm.
fn horn_length(params: &HornParams) -> f64 {
    params
        .modules
        .iter()
        .map(|m| {
            m.path_radius.to_f64() * (m.bend.signed() as f64) / 4_294_967_296.0
                * std::f64::consts::TAU
        })
        .sum()
}

fn lsb(a: Fx, b: Fx) -> i64 {
    (i64::from(a.to_bits()) - i64::from(b.to_bits())).abs()
}

#[test]
fn upper_base_of_module_i_is_the_lower_base_of_module_i_minus_1() {
    let mut worst = 0;
    let mut junctions = 0;
    for name in HORNS {
        with_horn(name, |params| {
            let mut kernel = HornKernel::<Fx>::new(params).unwrap();
            for t in frames(params) {
                let rings = frame(&mut kernel, t);
                let youngest = kernel.local_time().youngest as u16;
                for i in 2..=youngest {
                    let upper = rings.iter().find(|r| r.0 == i).unwrap();
                    let lower = rings.iter().rev().find(|r| r.0 == i - 1).unwrap();
                    assert_eq!(upper.1, 0, "module {i} starts at its upper base");
                    assert_eq!(
                        lower.1,
                        params.rings_per_module,
                        "module {} is complete",
                        i - 1
                    );
                    for (a, b) in upper.2.iter().zip(&lower.2) {
                        let gap = (0..3).map(|c| lsb(a[c], b[c])).max().unwrap();
                        worst = worst.max(gap);
                    }
                    junctions += 1;
                }
            }
        });
    }
    println!("continuity: {junctions} junctions, max gap {worst} LSB");
    assert!(junctions > 300);
    assert!(worst <= 4, "gap {worst} LSB");
}

/// E_1's orientation in the skull frame, and P_n(τ)'s (n the youngest).
fn orientations<R: Real>(kernel: &mut HornKernel<'_, R>, t: Moment) -> (Rigid<R>, Rigid<R>) {
    let local = kernel.place(t).unwrap();
    let n = local.youngest as u16;
    let tau = local.tau.days::<R>(kernel.params().delay_days);
    (
        kernel.placement(1).unwrap(),
        kernel.positioner(n, tau).unwrap(),
    )
}

fn max_entry<R: Real>(m: &nalgebra::Matrix3<R>) -> f64 {
    m.iter().map(|x| x.to_f64().abs()).fold(0.0, f64::max)
}

#[test]
fn only_the_youngest_positioner_moves() {
    with_horn("ram-horn-animation", |animation| {
        // In year n, R_1(t) = R_{P_n}(τ)·F with F fixed: so R_{P_n}(τ)ᵀ·R_1(t)
        // stays put while R_1(t) itself turns.
        let mut fixed = HornKernel::<Fx>::new(animation).unwrap();
        let mut reference = HornKernel::<f64>::new(animation).unwrap();
        for year in 2..=8u32 {
            let times: Vec<Moment> = [1, 4, 6, 9, 12]
                .iter()
                .map(|m| Moment::new((year - 1) * 12 + m, 12))
                .collect();
            let (first_e1, first_p) = orientations(&mut reference, times[0]);
            let base = first_p.rotation.transpose() * first_e1.rotation;
            let (first_e1_fx, first_p_fx) = orientations(&mut fixed, times[0]);
            let base_fx = first_p_fx.rotation.transpose() * first_e1_fx.rotation;
            let mut turned: f64 = 0.0;
            for &t in &times[1..] {
                let (e1, p) = orientations(&mut reference, t);
                let rest = p.rotation.transpose() * e1.rotation;
                assert!(
                    max_entry(&(rest - base)) < 1e-9,
                    "year {year}: older positioners moved"
                );
                turned = turned.max(max_entry(&(e1.rotation - first_e1.rotation)));
                // Fixed point: the same within rounding (16 LSB per entry).
                let (e1, p) = orientations(&mut fixed, t);
                let rest = p.rotation.transpose() * e1.rotation;
                let drift = (rest - base_fx)
                    .iter()
                    .map(|x| x.to_bits().abs())
                    .max()
                    .unwrap();
                assert!(drift <= 16, "year {year}: fixed-point drift {drift} LSB");
                // And every older module keeps its place relative to module n−1.
                let n = reference.local_time().youngest as u16;
                for i in 1..n.saturating_sub(1) {
                    let w = reference
                        .placement(n - 1)
                        .unwrap()
                        .inverse()
                        .compose(&reference.placement(i).unwrap());
                    let positioners = (i + 1..n).rev().fold(Rigid::<f64>::identity(), |acc, j| {
                        acc.compose(&reference.positioner(j, 365.0).unwrap())
                    });
                    // W_{n−1}⁻¹·W_i = P_{n−1}(T)·…·P_{i+1}(T), all fixed.
                    assert!(max_entry(&(w.rotation - positioners.rotation)) < 1e-9);
                }
            }
            assert!(turned > 0.05, "year {year}: E_1 did not turn ({turned})");
        }
    });
}

#[test]
fn fixed_point_tracks_the_f64_reference_within_a_thousandth_of_the_length() {
    for name in HORNS {
        with_horn(name, |params| {
            let length = horn_length(params);
            let mut fixed = HornKernel::<Fx>::new(params).unwrap();
            let mut reference = HornKernel::<f64>::new(params).unwrap();
            let (mut worst, mut vertices) = (0.0f64, 0usize);
            for t in frames(params) {
                let a = frame(&mut fixed, t);
                let b = frame(&mut reference, t);
                assert_eq!(a.len(), b.len());
                for (ra, rb) in a.iter().zip(&b) {
                    assert_eq!((ra.0, ra.1), (rb.0, rb.1));
                    for (p, q) in ra.2.iter().zip(&rb.2) {
                        let d = (0..3)
                            .map(|c| (p[c].to_f64() - q[c]).powi(2))
                            .sum::<f64>()
                            .sqrt();
                        worst = worst.max(d);
                        vertices += 1;
                    }
                }
            }
            println!(
                "f64 reference: {vertices} vertices, max deviation {worst:.6} cm = {:.5} % of {length:.2} cm ({:.0} LSB)",
                100.0 * worst / length,
                worst * 65536.0
            );
            assert!(worst <= 0.001 * length, "{worst} cm");
        });
    }
}

#[test]
fn the_horn_fits_fixed_point_and_has_its_expected_size() {
    with_horn("ram-horn", |ram_horn| {
        let mut kernel = HornKernel::<f64>::new(ram_horn).unwrap();
        let rings = frame(&mut kernel, Moment::new(8, 1));
        let extent = rings
            .iter()
            .flat_map(|r| r.2.iter())
            .flat_map(|p| p.iter())
            .fold(0.0f64, |m, &x| m.max(x.abs()));
        assert!(
            extent > 35.0 && extent < 45.0,
            "|coordinate| up to {extent} cm"
        );
        assert!((horn_length(ram_horn) - 110.66).abs() < 0.05);
        // 8 complete modules of J + 1 rings each.
        assert_eq!(rings.len(), 8 * 25);
        assert_eq!(kernel.ring_count(), 8 * 25);
    });
}

#[test]
fn rings_follow_eq_1_and_the_monthly_grid() {
    with_horn("ram-horn-animation", |animation| {
        with_horn("ram-horn", |ram_horn| {
            let mut kernel = HornKernel::<Fx>::new(animation).unwrap();
            // t = 1 month: module 1 only, rings θ = 0 and θ = T/12 (= τ).
            let rings = frame(&mut kernel, Moment::new(1, 12));
            assert_eq!(
                rings.iter().map(|r| (r.0, r.1)).collect::<Vec<_>>(),
                vec![(1, 0), (1, 1)]
            );
            // The active area of the youngest module sits at the origin, unturned.
            let active = &rings[1].2;
            assert!(active.iter().all(|p| p.x == Fx::ZERO));
            // t = 25 months: modules 1, 2 complete (13 rings), module 3 at τ = T/12.
            let rings = frame(&mut kernel, Moment::new(25, 12));
            assert_eq!(rings.len(), 13 + 13 + 2);
            // Mid-year on a grid of 24 lands on ring 12; off the grid a partial ring follows.
            let mut half = HornKernel::<Fx>::new(ram_horn).unwrap();
            let rings = frame(&mut half, Moment::new(1, 2));
            assert_eq!(rings.last().map(|r| r.1), Some(12));
            assert_eq!(rings.len(), 13);
        });
    });
}

#[test]
fn monthly_rings_bunch_in_winter() {
    with_horn("ram-horn-animation", |animation| {
        // Spacing of consecutive cross-sections along module 2 at the end of
        // year 2: summer gaps are many times the winter ones (annual rings).
        let mut kernel = HornKernel::<f64>::new(animation).unwrap();
        let rings = frame(&mut kernel, Moment::new(24, 12));
        let centre = |pts: &Vec<Vector3<f64>>| {
            pts.iter().fold(Vector3::zeros(), |a, p| a + p) / pts.len() as f64
        };
        let module2: Vec<_> = rings
            .iter()
            .filter(|r| r.0 == 2)
            .map(|r| centre(&r.2))
            .collect();
        let gaps: Vec<f64> = module2
            .windows(2)
            .map(|w| {
                let d = w[1] - w[0];
                d.dot(&d).sqrt()
            })
            .collect();
        let (january, june) = (gaps[0], gaps[5]);
        assert!(
            june > 10.0 * january,
            "June {june} cm vs January {january} cm"
        );
    });
}

#[test]
fn bad_parameters_are_located_errors() {
    with_horn("ram-horn", |ram_horn| {
        let mismatched: [morphogen::horn::Module; 2] = {
            let mut m = [ram_horn.modules[0], ram_horn.modules[1]];
            m[1].positioner_scale = Fx::from_ratio(99, 100);
            m
        };
        let bad = HornParams {
            modules: &mismatched,
            years: 2,
            ..*ram_horn
        };
        assert_eq!(
            HornKernel::<Fx>::new(&bad).err(),
            Some(Error::Horn(HornError::ScaleMismatch { module: 2 }))
        );
        let too_long = HornParams {
            years: 9,
            ..*ram_horn
        };
        assert_eq!(
            HornKernel::<Fx>::new(&too_long).err(),
            Some(Error::Horn(HornError::PastLastModule))
        );
        let too_fine = HornParams {
            ring_points: 65,
            ..*ram_horn
        };
        assert!(matches!(
            HornKernel::<Fx>::new(&too_fine).err(),
            Some(Error::Capacity {
                limit: "horn::MAX_RING_POINTS",
                capacity: 64
            })
        ));
        // Started, the simulation reports it at its first step too, never
        // panics.
        let mut horn = Horn::IDLE;
        assert!(horn.start(&bad, 0).is_err());
        assert!(morphogen::sim::Simulation::step(&mut horn, &mut Counter(0)).is_err());
    });
}

struct Counter(usize);

impl morphogen::stream::Sink for Counter {
    fn record(
        &mut self,
        _: &morphogen::stream::Record,
    ) -> Result<(), morphogen::stream::SinkError> {
        self.0 += 1;
        Ok(())
    }
}

#[test]
fn state_is_small() {
    let horn = core::mem::size_of::<Horn>();
    println!(
        "Horn: {horn} bytes, Runner: {} bytes",
        core::mem::size_of::<Runner>()
    );
    assert!(horn <= 4096, "{horn} bytes");
}
