//! Every MClone preset of a figure draws what the figure shows
//! (Ch. 4), measured on its Voronoi pictures as `morphogen run` writes
//! them (`pattern.csv`, `types.csv`, `cells_dayNN.csv`): the watermelon's
//! stripes run along the fruit and widen with w_r (Fig. 4.16), on the
//! fruit itself too (Figs. 4.17–4.18, unrolled onto the control map) and on
//! the MCU's coarse fruit, a cactus
//! clone grows as one spot (Figs. 4.6–4.8), the croton keeps its patches
//! (Fig. 4.1) and turns yellow with age (Fig. 4.3), the philodendron's
//! pale centre is solid and grows with the days (Figs. 4.10, 4.12), and
//! the amanita's red stays on the cap the mask gives it (Fig. 4.15).

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    reason = "a test stops at the first thing that is not as it expects"
)]

use std::path::Path;
use std::process::Command;

use morphogen_tests::release_binary;

/// The figures of one type on one streamed day (`pattern.csv`).
#[derive(Debug, Clone, Copy)]
struct Figures {
    day: u32,
    patches: u32,
    runs_per_row: f64,
    width: f64,
    /// Along u (across the stripes) and along v.
    correlation: [f64; 2],
}

/// Runs `preset` into `dir` (CSV only).
fn run(preset: &str, dir: &Path) {
    let o = Command::new(release_binary())
        .args(["run", preset, "--only", "csv", "--quiet", "--out"])
        .arg(dir)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// The figures of type `name` on every streamed day of a run in `dir`.
fn figures(dir: &Path, name: &str) -> Vec<Figures> {
    let text = std::fs::read_to_string(dir.join("pattern.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("day,type,name,patches,runs_per_row,width,correlation_u,correlation_v")
    );
    lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|f| f[2] == name)
        .map(|f| Figures {
            day: f[0].parse().unwrap(),
            patches: f[3].parse().unwrap(),
            runs_per_row: f[4].parse().unwrap(),
            width: f[5].parse().unwrap(),
            correlation: [f[6].parse().unwrap(), f[7].parse().unwrap()],
        })
        .collect()
}

/// The share of the area of type `name` on `day` (`types.csv`).
fn area_share(dir: &Path, name: &str, day: u32) -> f64 {
    let text = std::fs::read_to_string(dir.join("types.csv")).unwrap();
    let line = text
        .lines()
        .find(|l| l.starts_with(&format!("{day},")) && l.split(',').nth(2) == Some(name))
        .unwrap();
    line.rsplit(',').next().unwrap().parse().unwrap()
}

#[test]
#[cfg_attr(
    not(debug_assertions),
    ignore = "runs the release binary: run it in a debug build"
)]
fn watermelon_stripes_run_along_the_fruit_as_the_mask_lays_them() {
    // Fig. 4.16: the 16 stripes of the mask at w_r 1, 2, 3, widening with
    // w_r; Figs. 4.16–4.18 on the objects themselves, unrolled onto the
    // control cylinder (from pole to pole); and the MCU's fruit, whose 512
    // cells resolve a mask of 8 stripes.
    let tmp = tempfile::tempdir().unwrap();
    let mut widths = Vec::new();
    for (preset, stripes) in [
        ("watermelon-narrow", 16.0),
        ("watermelon", 16.0),
        ("watermelon-wide", 16.0),
        ("watermelon-fruit", 16.0),
        ("watermelon-sphere", 16.0),
        ("watermelon-square", 16.0),
        ("watermelon-mcu", 8.0),
    ] {
        let dir = tmp.path().join(preset);
        run(preset, &dir);
        let last = *figures(&dir, "F").last().unwrap();
        assert!(
            (0.75 * stripes..=1.25 * stripes).contains(&last.runs_per_row),
            "{preset}: {} dark runs across a row, for {stripes} stripes",
            last.runs_per_row
        );
        let [across, along] = last.correlation;
        assert!(
            along >= 3.0 * across,
            "{preset}: correlated over {along} along the fruit, {across} across"
        );
        widths.push(last.width);
    }
    assert!(
        widths[..3].windows(2).all(|w| w[0] < w[1]),
        "stripe widths at w_r 1, 2, 3: {:?}",
        &widths[..3]
    );
}

#[test]
#[cfg_attr(
    not(debug_assertions),
    ignore = "runs the release binary: run it in a debug build"
)]
fn a_cactus_clone_grows_as_one_spot() {
    // Figs. 4.8–4.9: each of the few initial F cells grows a spot whose
    // border expands as one; spots may merge, they do not scatter.
    let tmp = tempfile::tempdir().unwrap();
    for preset in ["cactus-spots", "cactus-uniform"] {
        let dir = tmp.path().join(preset);
        run(preset, &dir);
        let days = figures(&dir, "F");
        let initial = days[0].patches;
        for d in &days {
            assert!(
                d.patches <= 3 * initial,
                "{preset} day {}: {} F patches from {initial} clones",
                d.day,
                d.patches
            );
        }
    }
}

#[test]
#[cfg_attr(
    not(debug_assertions),
    ignore = "runs the release binary: run it in a debug build"
)]
fn the_croton_keeps_its_patches_and_ages_yellow() {
    // Figs. 4.1–4.3: F patches grow and merge, never break up.
    let tmp = tempfile::tempdir().unwrap();
    for preset in ["croton", "croton-individual", "croton-ageing"] {
        let dir = tmp.path().join(preset);
        run(preset, &dir);
        let days = figures(&dir, "F");
        let first = days[0].patches;
        for d in &days {
            assert!(
                2 * d.patches <= 3 * first,
                "{preset} day {}: {} F patches, {first} on day {}",
                d.day,
                d.patches,
                days[0].day
            );
        }
    }
    // Fig. 4.3: day 5 mostly green, day 30 mostly yellow.
    let ageing = tmp.path().join("croton-ageing");
    let (early, late) = (area_share(&ageing, "F", 5), area_share(&ageing, "F", 30));
    assert!(early < 0.4, "day 5: F on {early}");
    assert!(late > 0.6, "day 30: F on {late}");
}

#[test]
#[cfg_attr(
    not(debug_assertions),
    ignore = "runs the release binary: run it in a debug build"
)]
fn the_philodendron_centre_is_solid_and_grows_with_the_days() {
    // Figs. 4.10 and 4.12: one pale region, without holes, larger on days
    // 23, 27, 30.
    let tmp = tempfile::tempdir().unwrap();
    run("philodendron-ageing", tmp.path());
    let (f, b) = (figures(tmp.path(), "F"), figures(tmp.path(), "B"));
    for (f, b) in f.iter().zip(&b) {
        assert_eq!((f.patches, b.patches), (1, 1), "day {}", f.day);
    }
    let areas: Vec<f64> = f
        .iter()
        .map(|d| area_share(tmp.path(), "F", d.day))
        .collect();
    assert!(
        areas.windows(2).all(|w| w[1] > w[0] * 1.03),
        "F's share of the leaf on days 23, 27, 30: {areas:?}"
    );
}

#[test]
#[cfg_attr(
    not(debug_assertions),
    ignore = "runs the release binary: run it in a debug build"
)]
fn the_amanita_red_stays_on_the_cap() {
    // Figs. 4.14–4.15: the mask lets F start on the cap's top 3/8 of the
    // cylinder (v below 22.5 of 60); F, dividing faster than B, pushes its
    // edge outward by about one repulsion radius (3.0 on day 0:
    // w_r·√(area/C_i)), never down the stem.
    let (edge, radius) = (22.5, 3.0);
    let tmp = tempfile::tempdir().unwrap();
    for preset in ["amanita", "amanita-df8", "amanita-df20"] {
        let dir = tmp.path().join(preset);
        run(preset, &dir);
        let text = std::fs::read_to_string(dir.join("cells_day20.csv")).unwrap();
        // On the cylinder y is the height v.
        let mut v: Vec<f64> = text
            .lines()
            .skip(1)
            .map(|l| l.split(',').collect::<Vec<_>>())
            .filter(|f| f[1] == "1")
            .map(|f| f[3].parse().unwrap())
            .collect();
        v.sort_by(f64::total_cmp);
        let nearly_all = v[v.len() * 999 / 1000];
        let lowest = v[v.len() - 1];
        assert!(
            nearly_all <= edge + radius && lowest <= edge + 2.0 * radius,
            "{preset}: 99.9 % of F above v = {nearly_all}, all above {lowest}, the mask's edge at {edge}"
        );
    }
}
