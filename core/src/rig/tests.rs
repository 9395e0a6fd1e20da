//! The rig's pictures, pixel by pixel, on `embedded-graphics`' mock display.

use embedded_graphics::mock_display::MockDisplay;
use embedded_graphics::pixelcolor::Rgb888;

use embedded_graphics::geometry::{Point as Px, Size};
use embedded_graphics::primitives::Rectangle;

use super::raster::{clip, line};
use super::*;

fn fx(n: i32) -> Fx {
    Fx::from_int(n)
}

/// Draws `records` on a `w`×`h` crop of a mock display with a view fitted
/// to them and `palette`.
fn render(records: &[Record], w: u32, h: u32, palette: &[Rgb888]) -> MockDisplay<Rgb888> {
    let mut bounds = Bounds::new();
    records.iter().for_each(|r| bounds.include(r));
    let mut display = MockDisplay::new();
    display.set_allow_overdraw(true);
    let mut screen = display.cropped(&Rectangle::new(Px::zero(), Size::new(w, h)));
    let mut plane = std::vec![0; plane_bytes(Size::new(w, h))];
    let mut rig = Rig::new(View::fit(&bounds, Size::new(w, h), 0), palette, &mut plane);
    for r in records {
        rig.draw(r, &mut screen).unwrap();
    }
    display
}

const RGB: [Rgb888; 4] = [Rgb888::BLACK, Rgb888::RED, Rgb888::GREEN, Rgb888::BLUE];

#[test]
fn cells_fill_their_voronoi_regions() {
    // Three cells on an 8×6 screen: red (kind 0: ink 0 is palette[1])
    // top-left, green (1) top-right, blue (2) bottom-centre; y is up in
    // the model.
    let records = [
        Record::FrameStart {
            frame: 0,
            time: Fx::ZERO,
        },
        Record::Cell {
            id: 0,
            kind: 0,
            p: [fx(0), fx(10)],
        },
        Record::Cell {
            id: 1,
            kind: 1,
            p: [fx(14), fx(10)],
        },
        Record::Cell {
            id: 2,
            kind: 2,
            p: [fx(7), fx(0)],
        },
        Record::FrameEnd { frame: 0 },
    ];
    render(&records, 8, 6, &RGB).assert_pattern(&[
        "RRRRGGGG", //
        "RRRRGGGG", //
        "RRRBBGGG", //
        "RRBBBBGG", //
        "BBBBBBBB", //
        "BBBBBBBB", //
    ]);
}

#[test]
fn segments_rings_and_points_are_lines_and_pixels() {
    let p = |x, y| Record::Point {
        p: [fx(x), fx(y), Fx::ZERO],
    };
    let records = [
        Record::FrameStart {
            frame: 0,
            time: Fx::ZERO,
        },
        // A red diagonal (ink 0), a green square ring (module 1 → ink 1).
        Record::Segment {
            a: [fx(0), fx(0), Fx::ZERO],
            b: [fx(7), fx(7), Fx::ZERO],
            width: Fx::DELTA,
            colour: 0,
        },
        Record::Ring {
            module: 1,
            ring: 0,
            points: 4,
        },
        p(4, 1),
        p(6, 1),
        p(6, 3),
        p(4, 3),
        // A lone point: ink 0.
        p(1, 6),
        Record::FrameEnd { frame: 0 },
    ];
    render(&records, 8, 8, &RGB).assert_pattern(&[
        "KKKKKKKR", //
        "KRKKKKRK", //
        "KKKKKRKK", //
        "KKKKRKKK", //
        "KKKRGGGK", //
        "KKRKGKGK", //
        "KRKKGGGK", //
        "RKKKKKKK", //
    ]);
}

#[test]
fn depth_is_drawn_down_and_left_at_half_scale() {
    // z = 4 moves a point by −k·4 = −1.41 on both axes.
    assert_eq!(
        project([fx(2), fx(2), fx(4)]),
        [(2 << 16) - 92_680, (2 << 16) - 92_680]
    );
    assert_eq!(project([fx(2), fx(-3), Fx::ZERO]), [2 << 16, -3 << 16]);
}

#[test]
fn samples_are_stretched_into_curves() {
    // Series 0 rises over x = 0..=30 while y goes 0..=1: a chart fills
    // the screen on both axes despite the 30:1 aspect.
    let mut records = std::vec![Record::FrameStart {
        frame: 0,
        time: Fx::ZERO
    }];
    for x in 0..=30 {
        records.push(Record::Sample {
            series: 0,
            x: fx(x),
            y: Fx::from_ratio(x, 30),
        });
    }
    render(&records, 4, 4, &RGB).assert_pattern(&[
        "KKKR", //
        "KKRR", //
        "KRRK", //
        "RKKK", //
    ]);
}

#[test]
fn a_small_cell_plane_is_an_error_naming_the_limit() {
    let mut display = MockDisplay::<Rgb888>::new();
    let mut screen = display.cropped(&Rectangle::new(Px::zero(), Size::new(4, 4)));
    let mut plane = [0; 7];
    let mut rig = Rig::new(View::unit(), &RGB, &mut plane);
    let cell = Record::Cell {
        id: 0,
        kind: 0,
        p: [Fx::ZERO; 2],
    };
    assert_eq!(
        rig.draw(&cell, &mut screen),
        Err(RigError::Capacity {
            limit: "cell plane bytes",
            capacity: 7
        })
    );
}

#[test]
fn cells_reach_seven_pixels_and_no_further() {
    // One cell at the centre of pixel (0, 0) of a 10×1 screen: pixel 7
    // is 7 px away, pixel 8 is 8.
    let records = [
        Record::FrameStart {
            frame: 0,
            time: Fx::ZERO,
        },
        Record::Cell {
            id: 0,
            kind: 0,
            p: [Fx::ZERO; 2],
        },
        Record::FrameEnd { frame: 0 },
    ];
    let mut display = MockDisplay::<Rgb888>::new();
    display.set_allow_overdraw(true);
    let mut screen = display.cropped(&Rectangle::new(Px::zero(), Size::new(10, 1)));
    let mut plane = [0; 5];
    let view = View {
        origin: [-(1 << 15), 1 << 15],
        ..View::unit()
    };
    let mut rig = Rig::new(view, &RGB, &mut plane);
    for r in &records {
        rig.draw(r, &mut screen).unwrap();
    }
    display.assert_pattern(&["RRRRRRRRKK"]);
}

#[test]
fn triangles_facing_the_viewer_are_filled_and_the_others_skipped() {
    let vertex = |id, x, y| Record::MeshVertex {
        id,
        p: [fx(x), fx(y), Fx::ZERO],
    };
    let frame = |v| {
        [
            Record::FrameStart {
                frame: 0,
                time: Fx::ZERO,
            },
            vertex(0, 0, 0),
            vertex(1, 5, 0),
            vertex(2, 0, 5),
            Record::Triangle { v },
            Record::FrameEnd { frame: 0 },
        ]
    };
    // Counter-clockwise seen from +z (the viewer): filled in ink 0. (A
    // 6×6 rig's plane holds 18 bytes: 4 vertices.) Pixel centres on the
    // bottom edge and the hypotenuse (a right edge) belong to the
    // neighbours a mesh has there: only the vertices' own pixels show.
    render(&frame([0, 1, 2]), 6, 6, &RGB).assert_pattern(&[
        "RKKKKK", //
        "RKKKKK", //
        "RRKKKK", //
        "RRRKKK", //
        "RRRRKK", //
        "RKKKKR", //
    ]);
    // Clockwise: its back; only the vertices' pixels show.
    render(&frame([0, 2, 1]), 6, 6, &RGB).assert_pattern(&[
        "RKKKKK", //
        "KKKKKK", //
        "KKKKKK", //
        "KKKKKK", //
        "KKKKKK", //
        "RKKKKR", //
    ]);
}

#[test]
fn far_away_lines_are_clipped_not_walked() {
    assert_eq!(
        clip([-1_000_000_000, 5], [1_000_000_000, 5], [0, 0], [9, 9]),
        Some(([0, 5], [9, 5]))
    );
    assert_eq!(clip([-50, -50], [-10, -40], [0, 0], [9, 9]), None);
    let mut display = MockDisplay::<Rgb888>::new();
    let mut screen = display.cropped(&Rectangle::new(Px::zero(), Size::new(3, 1)));
    line(
        &mut screen,
        PixelPos([i64::MIN / 2, 0]),
        PixelPos([i64::MAX / 2, 0]),
        Rgb888::RED,
        1,
    )
    .unwrap();
    display.assert_pattern(&["RRR"]);
}
