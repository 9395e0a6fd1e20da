//! Montages: pictures of several frames side by side, each tile
//! labelled with its time, drawn at twice their size and halved.

use anyhow::{Result, bail};
use tiny_skia::Pixmap;

use super::animation::{self, Pixels};
use super::picture;

/// The pixels of `pixmap`, a montage drawn at twice its size (opaque),
/// halved ([`picture::half_rgb`]) as RGB bytes, each label drawn
/// ([`animation::draw_label`]) into the top-left corner of its tile
/// `[x, y, width, height]` of the halved picture.
///
/// # Errors
/// When `pixmap` is less than 2 pixels wide or high, or a tile is not
/// inside the halved picture.
pub fn montage(pixmap: &Pixmap, labels: &[([u32; 4], String)]) -> Result<Vec<u8>> {
    let rgb = picture::half_rgb(pixmap)?;
    labelled(rgb, (pixmap.width() / 2, pixmap.height() / 2), labels)
}

/// [`montage`] of a montage already halved: `rgb`, `pw × ph` RGB pixels
/// row by row, its labels drawn in.
///
/// # Errors
/// When a tile is not inside the picture.
pub fn labelled(
    mut rgb: Vec<u8>,
    (pw, ph): (u32, u32),
    labels: &[([u32; 4], String)],
) -> Result<Vec<u8>> {
    for &([x, y, w, h], ref label) in labels {
        if x.checked_add(w).is_none_or(|r| r > pw) || y.checked_add(h).is_none_or(|b| b > ph) {
            bail!("the tile {x},{y} {w}×{h} is outside the {pw}×{ph} picture");
        }
        let origin = [x as usize, y as usize];
        animation::Label::new(w, h, label)?.draw(&mut rgb, pw as usize, origin, Pixels::Rgb);
    }
    Ok(rgb)
}

/// Copies `tile`, RGB bytes row by row, into the box `[x, y, w, h]` of
/// `rgb`, a picture `width` RGB pixels wide.
///
/// # Errors
/// When the box is not inside the picture or `tile` is not `w × h`.
pub fn paste_rgb(rgb: &mut [u8], width: u32, [x, y, w, h]: [u32; 4], tile: &[u8]) -> Result<()> {
    let (stride, x, w, h) = (
        3 * width as usize,
        3 * x as usize,
        3 * w as usize,
        h as usize,
    );
    if tile.len() != w * h || x + w > stride || rgb.len() / stride.max(1) < y as usize + h {
        bail!("the tile does not fit the picture");
    }
    let rows = rgb.chunks_exact_mut(stride).skip(y as usize);
    for (row, from) in rows.zip(tile.chunks_exact(w)) {
        row[x..x + w].copy_from_slice(from);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_montage_is_its_tiles_halved_and_labelled_each_as_a_picture_of_its_own() {
        // Two 160×120 tiles side by side, drawn at twice their size.
        let mut pixmap = Pixmap::new(640, 240).unwrap();
        for (k, p) in pixmap.pixels_mut().iter_mut().enumerate() {
            let v = (k % 640 / 5 + k / 640 / 7) as u8;
            *p = tiny_skia::PremultipliedColorU8::from_rgba(v, 255 - v, v / 2, 255).unwrap();
        }
        let labels = [
            ([0, 0, 160, 120], "day 3".to_string()),
            ([160, 0, 160, 120], "age 6.0 months".to_string()),
        ];
        let shown = montage(&pixmap, &labels).unwrap();
        let whole = picture::half_rgb(&pixmap).unwrap();
        for ([x, _, w, h], label) in &labels {
            let (x, w) = (*x as usize, *w as usize);
            let mut tile: Vec<u8> = whole
                .chunks_exact(320 * 3)
                .flat_map(|row| row[x * 3..(x + w) * 3].to_vec())
                .collect();
            animation::draw_label(&mut tile, w as u32, *h, Pixels::Rgb, label).unwrap();
            let shown: Vec<u8> = shown
                .chunks_exact(320 * 3)
                .flat_map(|row| row[x * 3..(x + w) * 3].to_vec())
                .collect();
            assert_eq!(shown, tile, "{label}");
        }
        let outside = [([200, 0, 160, 120], "x".to_string())];
        let e = montage(&pixmap, &outside).unwrap_err().to_string();
        assert_eq!(e, "the tile 200,0 160×120 is outside the 320×120 picture");
    }
}
