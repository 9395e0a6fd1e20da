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

/// A framebuffer to compare pictures with: `None` where nothing was drawn.
#[derive(Clone, PartialEq, Debug)]
struct Screen {
    pixels: std::vec::Vec<Option<Rgb888>>,
}

const SCREEN: Size = Size::new(24, 12);

impl Screen {
    fn new() -> Screen {
        Screen {
            pixels: std::vec![None; (SCREEN.width * SCREEN.height) as usize],
        }
    }
}

impl OriginDimensions for Screen {
    fn size(&self) -> Size {
        SCREEN
    }
}

impl DrawTarget for Screen {
    type Color = Rgb888;
    type Error = core::convert::Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(
        &mut self,
        pixels: I,
    ) -> Result<(), Self::Error> {
        for Pixel(p, c) in pixels {
            if let (Ok(x @ 0..24), Ok(y @ 0..12)) = (u32::try_from(p.x), u32::try_from(p.y)) {
                self.pixels[(y * SCREEN.width + x) as usize] = Some(c);
            }
        }
        Ok(())
    }
}

/// A sender's wire: header, extent, then four frames of segments and
/// cells; with each record's frame (`None` for header and extent) and the
/// byte where its frame on the wire ends.
fn sent() -> (std::vec::Vec<u8>, std::vec::Vec<(Option<u32>, usize)>) {
    let mut frames = std::vec::Vec::new();
    for f in 0..4u32 {
        let i = f as i32;
        frames.push((
            f,
            Record::FrameStart {
                frame: f,
                time: fx(i),
            },
        ));
        frames.push((
            f,
            Record::Segment {
                a: [fx(0), fx(i), Fx::ZERO],
                b: [fx(10 + i), fx(3), fx(i)],
                width: Fx::ONE,
                colour: f as u16,
            },
        ));
        for c in 0..3 {
            frames.push((
                f,
                Record::Cell {
                    id: c,
                    kind: (c + f) as u8,
                    p: [fx(2 * c as i32 + i), fx(4 - i)],
                },
            ));
        }
        frames.push((f, Record::FrameEnd { frame: f }));
    }
    let mut bounds = Bounds::new();
    frames.iter().for_each(|(_, r)| bounds.include(r));
    let header = Record::Header(crate::stream::Header {
        version: 1,
        preset: "frames".try_into().unwrap(),
        seed: 1,
        params: 2,
    });
    let mut encoder = crate::stream::Encoder::new(std::vec::Vec::new());
    let mut ends = std::vec::Vec::new();
    let all = [(None, header), (None, bounds.to_record())]
        .into_iter()
        .chain(frames.into_iter().map(|(f, r)| (Some(f), r)));
    for (frame, record) in all {
        crate::stream::Sink::record(&mut encoder, &record).unwrap();
        ends.push((frame, encoder.bytes() as usize));
    }
    (encoder.into_writer(), ends)
}

/// What a receiver shows of `wire`: each shown frame and its picture.
fn received(wire: &[u8]) -> std::vec::Vec<(u32, Screen)> {
    let mut plane = std::vec![0; plane_bytes(SCREEN)];
    let mut receiver = Receiver::new(SCREEN, 1, &RGB, &mut plane);
    let mut reader = crate::stream::Reader::new();
    let mut screen = Screen::new();
    let mut shown = std::vec::Vec::new();
    for &byte in wire {
        if let Some(frame) = reader.push(byte)
            && let Some(done) = receiver.take(&frame, &mut screen).unwrap()
            && done.shown
        {
            shown.push((done.frame, screen.clone()));
        }
    }
    shown
}

#[test]
fn a_receiver_shows_what_the_sender_drew() {
    let (wire, _) = sent();
    let shown = received(&wire);
    assert_eq!(
        shown.iter().map(|(f, _)| *f).collect::<std::vec::Vec<_>>(),
        [0, 1, 2, 3]
    );
    // The same frames through a rig fitted to the whole stream.
    let mut records = std::vec::Vec::new();
    let mut reader = crate::stream::Reader::new();
    records.extend(
        wire.iter()
            .filter_map(|&b| reader.push(b))
            .map(Result::unwrap),
    );
    let mut bounds = Bounds::new();
    records.iter().for_each(|r| bounds.include(r));
    let mut plane = std::vec![0; plane_bytes(SCREEN)];
    let mut rig = Rig::new(View::fit(&bounds, SCREEN, 1), &RGB, &mut plane);
    let mut screen = Screen::new();
    let mut pictures = std::vec::Vec::new();
    for r in &records {
        rig.draw(r, &mut screen).unwrap();
        if let Record::FrameEnd { .. } = r {
            pictures.push(screen.clone());
        }
    }
    for (f, picture) in &shown {
        assert_eq!(picture, &pictures[*f as usize], "frame {f}");
    }
    // Each frame differs from the one before: a stale picture would show.
    assert!(pictures.windows(2).all(|w| w[0] != w[1]));
}

#[test]
fn a_flipped_bit_skips_its_frame_and_nothing_is_drawn_wrong() {
    let (wire, ends) = sent();
    let intact: std::collections::BTreeMap<u32, Screen> = received(&wire).into_iter().collect();
    for i in 0..wire.len() {
        // The records whose frames the flip damages: its own, and the
        // next one too if it hits a delimiter.
        let k = ends.iter().position(|&(_, end)| i < end).unwrap();
        let lost = if i + 1 == ends[k].1 { k..=k + 1 } else { k..=k };
        let fitted = !lost.contains(&0) && !lost.contains(&1);
        let want: std::vec::Vec<u32> = (0..4)
            .filter(|&f| {
                fitted
                    && !lost
                        .clone()
                        .any(|j| ends.get(j).is_some_and(|e| e.0 == Some(f)))
            })
            .collect();
        for bit in 0..8 {
            let mut damaged = wire.clone();
            damaged[i] ^= 1 << bit;
            let shown = received(&damaged);
            let frames: std::vec::Vec<u32> = shown.iter().map(|(f, _)| *f).collect();
            assert_eq!(frames, want, "bit {bit} of byte {i}");
            for (f, picture) in &shown {
                assert_eq!(picture, &intact[f], "frame {f}, bit {bit} of byte {i}");
            }
        }
    }
}

#[test]
fn an_extent_that_no_projection_gives_is_refused() {
    let far = Record::Extent {
        min: [i64::MIN, 0],
        max: [0, 0],
        chart: false,
        frames: 1,
    };
    assert_eq!(Bounds::from_record(&far), None);
    assert_eq!(Bounds::from_record(&Record::FrameEnd { frame: 0 }), None);
    let nothing = Bounds::new();
    assert_eq!(Bounds::from_record(&nothing.to_record()), Some(nothing));
}
