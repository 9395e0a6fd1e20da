//! What `morphogen run` writes beyond the stream, through the binary:
//! animated PNGs with a label per frame, charts with axes (PNG and SVG),
//! one `model.glb` per run with vertex colours and every frame, and the
//! `--only` and `--quiet` options.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    reason = "a test stops at the first thing that is not as it expects"
)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn morphogen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_morphogen"))
        .args(args)
        .output()
        .expect("the binary runs")
}

/// Runs `preset` into a fresh folder under `tmp` with `extra` arguments;
/// returns the folder and what the command printed.
fn run(tmp: &Path, preset: &str, extra: &[&str]) -> (PathBuf, Output) {
    let out = tmp.join(preset);
    let out_text = out.to_str().unwrap().to_owned();
    let mut args = vec!["run", preset, "--out", &out_text];
    args.extend_from_slice(extra);
    let o = morphogen(&args);
    assert!(
        o.status.success(),
        "run {preset}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    (out, o)
}

/// An APNG's size, its frames, and each frame's RGB pixels.
struct Apng {
    width: u32,
    height: u32,
    frames: Vec<Vec<u8>>,
}

fn read_apng(path: &Path) -> Apng {
    let file = std::fs::File::open(path).unwrap();
    let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().unwrap();
    let info = reader.info();
    let (width, height) = (info.width, info.height);
    let control = info
        .animation_control()
        .unwrap_or_else(|| panic!("{} is not animated", path.display()));
    let count = control.num_frames;
    let mut frames = Vec::new();
    for _ in 0..count {
        let mut buf = vec![0; reader.output_buffer_size()];
        let frame = reader.next_frame(&mut buf).unwrap();
        assert_eq!((frame.width, frame.height), (width, height));
        buf.truncate(frame.buffer_size());
        frames.push(buf);
    }
    Apng {
        width,
        height,
        frames,
    }
}

/// Which pixels of the top-left `w × h` corner of an RGB frame `width`
/// wide are pure white: a label's text (white on a darkened box), as no
/// picture's background or body is pure white.
fn white_text(frame: &[u8], width: u32, w: u32, h: u32) -> Vec<bool> {
    let row = width as usize * 3;
    (0..h as usize)
        .flat_map(|y| {
            frame[y * row..y * row + w as usize * 3]
                .chunks(3)
                .map(|p| p == [255, 255, 255])
                .collect::<Vec<_>>()
        })
        .collect()
}

/// Checks that frames `a` and `b` of `apng` carry labels (white text in
/// the top-left corner) and that the labels differ.
fn check_labels(apng: &Apng, a: usize, b: usize) {
    let (w, h) = (apng.width / 2, apng.height / 6);
    let first = white_text(&apng.frames[a], apng.width, w, h);
    let second = white_text(&apng.frames[b], apng.width, w, h);
    let count = |m: &[bool]| m.iter().filter(|&&x| x).count();
    assert!(count(&first) > 20 && count(&second) > 20, "no label text");
    assert_ne!(
        first, second,
        "the labels of frames {a} and {b} are the same"
    );
}

/// Checks `dir/animation.png`: `frames` frames of `width × height`, the
/// first two and the last with labels, all different.
fn check_animation(dir: &Path, frames: usize, size: (u32, u32)) {
    let apng = read_apng(&dir.join("animation.png"));
    assert_eq!(apng.frames.len(), frames, "{}", dir.display());
    assert_eq!((apng.width, apng.height), size, "{}", dir.display());
    check_labels(&apng, 0, 1);
    check_labels(&apng, 1, frames - 1);
}

/// Parses `dir/model.glb`; checks its frame nodes and that every mesh
/// has vertex colours.
fn check_glb(dir: &Path, frames: usize) {
    let bytes = std::fs::read(dir.join("model.glb")).unwrap();
    let glb = gltf::Gltf::from_slice(&bytes).unwrap();
    let doc = &glb.document;
    let frame_nodes = doc
        .nodes()
        .filter(|n| n.name().is_some_and(|s| s.starts_with("frame_")))
        .count();
    assert_eq!(frame_nodes, frames, "{}", dir.display());
    assert_eq!(doc.meshes().count(), frames);
    for mesh in doc.meshes() {
        for p in mesh.primitives() {
            assert!(p.get(&gltf::Semantic::Colors(0)).is_some(), "no COLOR_0");
            assert!(p.get(&gltf::Semantic::Positions).is_some());
        }
    }
    assert_eq!(doc.animations().count(), usize::from(frames > 1));
    for a in doc.animations() {
        for s in a.samplers() {
            assert_eq!(s.interpolation(), gltf::animation::Interpolation::Step);
        }
    }
}

/// The files a run wrote into `dir` (not the hidden `.morphogen.lock` it
/// held the folder with).
fn files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != morphogen_cli::folder_lock::LOCK_FILE)
        .collect();
    names.sort();
    names
}

#[test]
fn the_growth_curve_chart_has_axes_in_png_and_svg() {
    let tmp = tempfile::tempdir().unwrap();
    let (dir, _) = run(tmp.path(), "growth-curve", &[]);
    let svg = std::fs::read_to_string(dir.join("growth.svg")).unwrap();
    for label in ["time (days)", "daily increment", "growth f(t)"] {
        assert!(svg.contains(label), "{label} missing from growth.svg");
    }
    let png = image_size(&dir.join("growth.png"));
    assert_eq!(png, (900, 500));
    // One frame: no animation, no mesh.
    assert!(!dir.join("animation.png").exists());
    assert!(!dir.join("model.glb").exists());
}

fn image_size(path: &Path) -> (u32, u32) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let reader = decoder.read_info().unwrap();
    (reader.info().width, reader.info().height)
}

#[test]
fn the_ram_horn_animates_its_frames_and_exports_a_coloured_glb() {
    let tmp = tempfile::tempdir().unwrap();
    let (dir, _) = run(tmp.path(), "ram-horn", &[]);
    check_animation(&dir, 16, (400, 400));
    check_glb(&dir, 16);
    let svg = std::fs::read_to_string(dir.join("bend.svg")).unwrap();
    assert!(svg.contains("time (years)") && svg.contains("length (cm)"));
    // The paper's Fig. 11: E1's bending angle over its first four years.
    let fig11 = std::fs::read_to_string(dir.join("e1-bend.svg")).unwrap();
    assert!(fig11.contains("Fig. 11") && fig11.contains("angle (degrees)"));
    assert_eq!(image_size(&dir.join("e1-bend.png")), (900, 500));
    // An OBJ per frame, one group per module, all of them in the horn's
    // material from the library they share.
    let obj = std::fs::read_to_string(dir.join("frame_015.obj")).unwrap();
    assert!(obj.starts_with("# morphogen horn, frame 15"));
    assert!(obj.contains("\nmtllib horn.mtl\n") && obj.contains("\ng module_8\nusemtl horn\n"));
    let mtl = std::fs::read_to_string(dir.join("horn.mtl")).unwrap();
    assert!(mtl.contains("newmtl horn\nKd 0.87059 0.80000 0.65882\n"));
}

#[test]
fn the_trotting_horse_animates_its_side_views_and_charts_its_table() {
    let tmp = tempfile::tempdir().unwrap();
    let (dir, _) = run(tmp.path(), "horse-trot", &["--only", "anim,glb,svg"]);
    // The run's extent at one scale, with every hoof on the ground (none
    // floating above or sunk below it).
    let side = (640, 552);
    check_animation(&dir, 36, side);
    check_glb(&dir, 36);
    let svg = std::fs::read_to_string(dir.join("growth.svg")).unwrap();
    assert!(svg.contains("age (months)") && svg.contains("elbow-to-ground"));
    assert_eq!(
        files(&dir),
        [
            "animation.png",
            "growth.svg",
            "model.glb",
            "stream.bin",
            "summary.txt"
        ]
    );
}

#[test]
fn a_mosaic_animates_its_days_and_counts_its_cells_per_type() {
    let tmp = tempfile::tempdir().unwrap();
    let (dir, _) = run(tmp.path(), "croton-mcu", &["--only", "anim,svg,png"]);
    check_animation(&dir, 36, (900, 720));
    let svg = std::fs::read_to_string(dir.join("cells.svg")).unwrap();
    assert!(svg.contains("time (days)") && svg.contains("F (type 1)"));
    assert!(dir.join("cells.png").exists() && dir.join("day_35.png").exists());
    assert!(!dir.join("cells_day35.csv").exists());
}

#[test]
fn a_mosaic_on_an_unrolled_cylinder_is_put_back_on_the_cylinder() {
    let tmp = tempfile::tempdir().unwrap();
    // croton-mcu's 15 × 12 leaf, its u axis wrapped round a stem.
    let (dir, _) = run(
        tmp.path(),
        "croton-mcu",
        &[
            "--set",
            "mosaic.domain.periodic=[true, false]",
            "--only",
            "csv,png,obj",
        ],
    );
    let radius = 15.0 / std::f64::consts::TAU;
    let text = std::fs::read_to_string(dir.join("cells_day35.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("id,type,x,y,z"));
    let mut cells = 0;
    for line in lines {
        let p: Vec<f64> = line
            .split(',')
            .skip(2)
            .map(|x| x.parse().unwrap())
            .collect();
        let off = ((p[0] * p[0] + p[2] * p[2]).sqrt() - radius).abs();
        assert!(
            off < 1e-9 && (0.0..12.0).contains(&p[1]),
            "{line}: {off} off the stem"
        );
        cells += 1;
    }
    assert!(cells > 1000, "{cells} cells");
    // The bare stem, the mosaic coloured on it, the object on every day.
    let faces = |name: &str| {
        let obj = std::fs::read_to_string(dir.join(name)).unwrap();
        assert!(obj.lines().filter(|l| l.starts_with("v ")).all(|l| {
            let v: Vec<f64> = l.split(' ').skip(1).map(|x| x.parse().unwrap()).collect();
            ((v[0] * v[0] + v[2] * v[2]).sqrt() - radius).abs() < 1e-4
        }));
        obj.lines().filter(|l| l.starts_with("f ")).count()
    };
    assert!(faces("surface.obj") > 100 && faces("mosaic.obj") > 10_000);
    let mosaic = std::fs::read_to_string(dir.join("mosaic.obj")).unwrap();
    let coloured = mosaic.lines().find(|l| l.starts_with("v ")).unwrap();
    assert_eq!(
        coloured.split(' ').count(),
        7,
        "a colour per vertex: {coloured}"
    );
    for day in ["surface_day00.png", "surface_day35.png", "surface.png"] {
        assert!(dir.join(day).exists(), "{day}");
    }
    // The last day's pictures again, byte for byte.
    let bytes = |name: &str| std::fs::read(dir.join(name)).unwrap();
    assert_eq!(bytes("surface.png"), bytes("surface_day35.png"));
    assert_eq!(bytes("mosaic.png"), bytes("day_35.png"));
}

#[test]
fn a_flat_mosaic_has_its_cells_at_z_0_and_no_object_picture() {
    let tmp = tempfile::tempdir().unwrap();
    let (dir, _) = run(tmp.path(), "croton-mcu", &["--only", "csv,png"]);
    let text = std::fs::read_to_string(dir.join("cells_day00.csv")).unwrap();
    assert!(
        text.lines().skip(1).all(|l| l.ends_with(",0")),
        "z = 0 on the plane"
    );
    assert!(!dir.join("surface.png").exists() && !dir.join("surface_day00.png").exists());
}

#[test]
fn a_mosaic_gives_each_types_share_of_the_cells_and_of_the_area() {
    let tmp = tempfile::tempdir().unwrap();
    let (dir, _) = run(tmp.path(), "croton-mcu", &["--only", "csv"]);
    let text = std::fs::read_to_string(dir.join("types.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("day,type,name,cells,cell_share,area_share")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // Two types on each of the 36 streamed days.
    assert_eq!(rows.len(), 2 * 36);
    for day in rows.chunks(2) {
        assert_eq!((day[0][2], day[1][2]), ("B", "F"));
        let share = |k: usize| -> f64 {
            day[0][k].parse::<f64>().unwrap() + day[1][k].parse::<f64>().unwrap()
        };
        assert!(
            (share(4) - 1.0).abs() < 2e-4 && (share(5) - 1.0).abs() < 2e-4,
            "{day:?}"
        );
        // Every type with cells covers some of the area.
        for row in day {
            assert!(
                row[3] == "0" || row[5].parse::<f64>().unwrap() > 0.0,
                "{row:?}"
            );
        }
    }
}

#[test]
fn a_single_bone_has_one_glb_frame_and_no_animation() {
    let tmp = tempfile::tempdir().unwrap();
    let (dir, _) = run(tmp.path(), "long-bone", &[]);
    check_glb(&dir, 1);
    assert!(!dir.join("animation.png").exists());
    assert!(dir.join("frame_000.obj").exists() && dir.join("bones.png").exists());
    let obj = std::fs::read_to_string(dir.join("frame_000.obj")).unwrap();
    assert!(obj.contains("\nmtllib bone.mtl\n") && obj.contains("\nusemtl bone\n"));
    assert!(
        std::fs::read_to_string(dir.join("bone.mtl"))
            .unwrap()
            .contains("newmtl bone\n")
    );
    // How the wrap converged: the run done again, iteration by iteration.
    let svg = std::fs::read_to_string(dir.join("wrap.svg")).unwrap();
    assert!(svg.contains("iteration (count)") && svg.contains("split tolerance"));
    assert!(dir.join("wrap.png").exists());
    let summary = std::fs::read_to_string(dir.join("summary.txt")).unwrap();
    assert!(
        summary.contains("the shrinkwrap of frame 0: 13 iterations"),
        "{summary}"
    );
}

#[test]
fn a_plant_has_a_coloured_glb_and_animates_its_derivation_steps() {
    let tmp = tempfile::tempdir().unwrap();
    let (dir, _) = run(tmp.path(), "abop-2d-plant", &[]);
    check_glb(&dir, 1);
    assert!(!dir.join("animation.png").exists());
    // Each segment in the material of its colour index.
    let obj = std::fs::read_to_string(dir.join("plant.obj")).unwrap();
    assert!(obj.contains("\nmtllib plant.mtl\n") && obj.contains("\nusemtl colour_"));
    let mtl = std::fs::read_to_string(dir.join("plant.mtl")).unwrap();
    assert_eq!(mtl.matches("newmtl colour_").count(), 13);
    // The same grammar emitting every derivation step: 6 frames (n = 5).
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../grammars/abop-2d-plant.lsys"),
    )
    .unwrap();
    let grammar = tmp.path().join("steps.lsys");
    std::fs::write(&grammar, format!("animate = 1\n{text}")).unwrap();
    let out = tmp.path().join("steps");
    let o = morphogen(&[
        "run",
        "--grammar",
        grammar.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--only",
        "anim",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let apng = read_apng(&out.join("animation.png"));
    assert_eq!(apng.frames.len(), 6);
    check_labels(&apng, 0, 5);
}

#[test]
fn only_png_writes_no_meshes_and_quiet_prints_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let (dir, o) = run(tmp.path(), "ram-horn", &["--only", "png", "--quiet"]);
    assert!(
        o.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    let names = files(&dir);
    assert!(
        names
            .iter()
            .all(|n| n.ends_with(".png") || n == "stream.bin"),
        "{names:?}"
    );
    assert!(!names.contains(&"animation.png".to_owned()));
    assert!(names.contains(&"horn.png".to_owned()));
    let (_, loud) = run(tmp.path(), "growth-curve", &[]);
    assert!(String::from_utf8_lossy(&loud.stdout).contains("wrote"));
}

#[test]
fn plot_svg_is_written_when_asked_for_and_a_model_without_strokes_says_so() {
    let tmp = tempfile::tempdir().unwrap();
    let (dir, _) = run(tmp.path(), "long-bone", &["--only", "plot", "--quiet"]);
    assert_eq!(files(&dir), ["plot.svg", "stream.bin", "summary.txt"]);
    let svg = std::fs::read_to_string(dir.join("plot.svg")).unwrap();
    assert!(
        svg.contains(r#"height="297mm" viewBox="0 0 210 297" width="210mm""#),
        "a bone is tall: A4 portrait, in mm: {svg}"
    );
    assert!(svg.contains(r#"inkscape:label="1 outline""#), "{svg}");
    assert!(svg.contains("<path d=\"M"), "{svg}");
    let (dir, o) = run(tmp.path(), "growth-curve", &["--only", "plot,csv"]);
    assert!(!dir.join("plot.svg").exists());
    let note = String::from_utf8_lossy(&o.stderr);
    assert!(note.contains("no plot.svg"), "{note}");
    let (dir, o) = run(tmp.path(), "abop-2d-plant", &["--quiet"]);
    assert!(!dir.join("plot.svg").exists(), "plot is not a default kind");
    assert!(o.stdout.is_empty());
}

#[test]
fn a_run_replaces_an_earlier_runs_series_whole() {
    // 32 frames, then 16 into the same folder: frames 16 to 31 would mix
    // two runs; then `--only png` leaves the OBJ series alone.
    let tmp = tempfile::tempdir().unwrap();
    let frames = |dir: &Path| {
        files(dir)
            .into_iter()
            .filter(|n| n.starts_with("frame_"))
            .collect::<Vec<_>>()
    };
    let (dir, _) = run(tmp.path(), "ram-horn", &["--set", "horn.frames_per_year=4"]);
    assert_eq!(frames(&dir).len(), 32);
    let (_, o) = run(tmp.path(), "ram-horn", &[]);
    let expected: Vec<String> = (0..16).map(|k| format!("frame_{k:03}.obj")).collect();
    assert_eq!(frames(&dir), expected);
    let stdout = String::from_utf8_lossy(&o.stdout);
    let removed = format!(
        "  removed an earlier run's {}/frame_016.obj … frame_031.obj (16 files, ",
        dir.display()
    );
    assert!(stdout.contains(&removed), "{stdout}");
    let (_, o) = run(
        tmp.path(),
        "ram-horn",
        &["--only", "png", "--set", "horn.years=2"],
    );
    assert_eq!(frames(&dir), expected);
    assert!(!String::from_utf8_lossy(&o.stdout).contains("removed"));
}

#[test]
fn an_unknown_output_kind_is_an_error_listing_the_allowed_ones() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("x");
    let o = morphogen(&[
        "run",
        "growth-curve",
        "--out",
        out.to_str().unwrap(),
        "--only",
        "png,gif",
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("'gif'") && err.contains("png, obj, glb, anim, svg, csv, jsonl"),
        "{err}"
    );
    let help = morphogen(&["run", "--help"]);
    let help = String::from_utf8_lossy(&help.stdout);
    assert!(
        help.contains("--only") && help.contains("--quiet"),
        "{help}"
    );
}

#[test]
fn a_ws2812_matrix_gets_every_frame_in_chain_order_as_smart_leds_corrects_it() {
    let tmp = tempfile::tempdir().unwrap();
    let (dir, _) = run(
        tmp.path(),
        "croton-mcu",
        &["--only", "png", "--rig", "16x16:ws2812:64"],
    );
    let chain = std::fs::read(dir.join("rig-16x16-ws2812.bin")).unwrap();
    // A frame per day: the fixture's 36 frame ends, 3 bytes an LED.
    let per_frame = 16 * 16 * 3;
    assert_eq!(chain.len(), 36 * per_frame);
    // The last frame is the rig's picture, LED by LED: rows from the top,
    // odd rows right to left, gamma then brightness 64, green first.
    let picture = tiny_skia::Pixmap::load_png(dir.join("rig-16x16.png")).unwrap();
    let leds = (0..16u32).flat_map(|y| {
        let row: Vec<u32> = if y % 2 == 0 {
            (0..16).collect()
        } else {
            (0..16).rev().collect()
        };
        row.into_iter().map(move |x| (x, y))
    });
    let colours = leds.map(|(x, y)| {
        let p = picture.pixel(x, y).unwrap();
        smart_leds::RGB8::new(p.red(), p.green(), p.blue())
    });
    let want: Vec<u8> = smart_leds::brightness(smart_leds::gamma(colours), 64)
        .flat_map(|c| [c.g, c.r, c.b])
        .collect();
    assert_eq!(chain[35 * per_frame..], want[..]);
    // The days differ: the chain is not one picture repeated.
    assert_ne!(chain[..per_frame], chain[35 * per_frame..]);
    let listen = morphogen(&["listen", "x.bin", "--rig", "16x16:ws2812"]);
    assert!(!listen.status.success());
    assert!(String::from_utf8_lossy(&listen.stderr).contains("writes a chain's bytes"));
}
