//! Mask images for MClone's control (thesis Sec. 3.2.2): a PBM (plain P1 or
//! raw P4) or a PNG, read into the core [`morphogen::mosaic::Mask`]'s
//! packed rows (1 = white = foreground allowed). Sizes are checked before
//! anything is allocated.

use morphogen::mosaic::Mask;

/// The most pixels a mask may have (4096 × 4096): a mask is stretched over
/// the whole domain, so more detail than cells is never seen.
pub const MAX_PIXELS: u64 = 1 << 24;

/// The first bytes of every PNG file.
const PNG_SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";

/// Reads a mask file's bytes: a PNG (by its signature) or else a PBM.
///
/// # Errors
/// A malformed file, or one beyond [`MAX_PIXELS`], with what is wrong.
pub fn read(bytes: &[u8]) -> Result<(u16, u16, Vec<u8>), String> {
    if bytes.starts_with(PNG_SIGNATURE) {
        read_png(bytes)
    } else {
        read_pbm(bytes)
    }
}

fn size_check(width: u64, height: u64, what: &str) -> Result<(u16, u16), String> {
    if width == 0 || height == 0 || width > 65535 || height > 65535 {
        return Err(format!(
            "{what}: {width}×{height} pixels (allowed: sides of 1 to at most 65535)"
        ));
    }
    if width * height > MAX_PIXELS {
        return Err(format!(
            "{what}: {width}×{height} pixels (allowed: at most {MAX_PIXELS} pixels, scenario::mask::MAX_PIXELS)"
        ));
    }
    Ok((width as u16, height as u16))
}

/// What is wrong with a PNG the decoder refused, in words (its own
/// messages name chunks by their Rust debug form).
#[cfg(feature = "png")]
fn png_error(e: &png::DecodingError) -> String {
    match e {
        png::DecodingError::IoError(e) => e.to_string(),
        png::DecodingError::Format(_) => {
            "damaged or cut short: its data is not a PNG's (a checksum or a chunk is wrong)".into()
        }
        png::DecodingError::Parameter(_) | png::DecodingError::LimitsExceeded => {
            "cannot decode it".into()
        }
    }
}

/// Reads a PNG mask: a pixel is white (allowed) when its alpha and its
/// luminance (Rec. 709 weights of the stored R, G, B) are both ≥ 50 %.
#[cfg(feature = "png")]
fn read_png(bytes: &[u8]) -> Result<(u16, u16, Vec<u8>), String> {
    let be32 = |at: usize| {
        bytes
            .get(at..at + 4)
            .and_then(|b| b.try_into().ok())
            .map(u32::from_be_bytes)
    };
    // The sizes in IHDR (the first chunk), checked before decoding
    // allocates the whole image.
    // The first chunk must be a whole (13-byte) IHDR: a decoder skips an
    // empty one and would take its sizes from a later, unchecked chunk.
    match (bytes.get(8..16), be32(16), be32(20)) {
        (Some(b"\0\0\0\x0dIHDR"), Some(w), Some(h)) => {
            size_check(u64::from(w), u64::from(h), "PNG")?;
        }
        _ => return Err("PNG: cannot decode: the first chunk is not a 13-byte IHDR".into()),
    }
    let pixmap =
        tiny_skia::Pixmap::decode_png(bytes).map_err(|e| format!("PNG: {}", png_error(&e)))?;
    let (width, height) = size_check(u64::from(pixmap.width()), u64::from(pixmap.height()), "PNG")?;
    let stride = Mask::stride(width);
    let mut bits = vec![0u8; stride * usize::from(height)];
    for (i, p) in pixmap.pixels().iter().enumerate() {
        let c = p.demultiply();
        // 10 000·Y, Y = 0.2126 R + 0.7152 G + 0.0722 B; 50 % of 255 is 127.5.
        let luma =
            2126 * u32::from(c.red()) + 7152 * u32::from(c.green()) + 722 * u32::from(c.blue());
        if 2 * luma >= 2_550_000 && 2 * u32::from(c.alpha()) >= 255 {
            let (x, y) = (i % usize::from(width), i / usize::from(width));
            bits[y * stride + x / 8] |= 0x80 >> (x % 8);
        }
    }
    Ok((width, height, bits))
}

#[cfg(not(feature = "png"))]
fn read_png(_: &[u8]) -> Result<(u16, u16, Vec<u8>), String> {
    Err("PNG masks need the `png` feature of morphogen-scenario; give a PBM".into())
}

/// A PBM header token, shown in errors at most this long.
const SHOWN: usize = 16;

fn shown(token: &[u8]) -> String {
    let text: String = String::from_utf8_lossy(&token[..token.len().min(SHOWN)])
        .chars()
        .map(|c| if c.is_control() { '?' } else { c })
        .collect();
    if token.len() > SHOWN {
        format!("{text}…")
    } else {
        text
    }
}

/// Reads a PBM mask (plain P1 or raw P4); PBM's 1 is black (not allowed).
fn read_pbm(bytes: &[u8]) -> Result<(u16, u16, Vec<u8>), String> {
    let mut pos = 0;
    let mut token = || -> Result<&[u8], String> {
        loop {
            while pos < bytes.len() && bytes[pos].is_ascii_whitespace() {
                pos += 1;
            }
            if pos < bytes.len() && bytes[pos] == b'#' {
                while pos < bytes.len() && bytes[pos] != b'\n' {
                    pos += 1;
                }
                continue;
            }
            break;
        }
        let start = pos;
        while pos < bytes.len() && !bytes[pos].is_ascii_whitespace() && bytes[pos] != b'#' {
            pos += 1;
        }
        if start == pos {
            return Err(format!("PBM: the header ends at byte {start}"));
        }
        Ok(&bytes[start..pos])
    };
    let magic = token()?;
    let magic = match magic {
        b"P1" | b"P4" => magic[1],
        other => {
            return Err(format!(
                "PBM: magic '{}' is neither P1 nor P4",
                shown(other)
            ));
        }
    };
    let dim = |t: &[u8], what: &str| -> Result<u64, String> {
        std::str::from_utf8(t)
            .ok()
            .filter(|s| s.len() <= 6)
            .and_then(|s| s.parse::<u64>().ok())
            .ok_or_else(|| {
                format!(
                    "PBM: {what} '{}' is not a number (allowed: 1 to 65535)",
                    shown(t)
                )
            })
    };
    let width = dim(token()?, "width")?;
    let height = dim(token()?, "height")?;
    let (width, height) = size_check(width, height, "PBM")?;
    let stride = Mask::stride(width);
    let len = stride * usize::from(height);
    let (w, total) = (usize::from(width), usize::from(width) * usize::from(height));
    if magic == b'4' {
        pos += 1; // the single whitespace after the height
        let data = bytes.get(pos..pos + len).ok_or_else(|| {
            format!(
                "PBM: the raster needs {len} bytes after byte {pos}, the file has {}",
                bytes.len().saturating_sub(pos)
            )
        })?;
        let mut bits: Vec<u8> = data.iter().map(|d| !d).collect();
        // Clear the padding bits of each row.
        let pad = (stride * 8 - w) as u32;
        if pad > 0 {
            for y in 0..usize::from(height) {
                bits[y * stride + stride - 1] &= 0xFFu8 << pad;
            }
        }
        return Ok((width, height, bits));
    }
    // P1: a plain raster has at least one byte per pixel.
    if bytes.len().saturating_sub(pos) < total {
        return Err(format!(
            "PBM: {total} pixels, but only {} bytes follow the header",
            bytes.len().saturating_sub(pos)
        ));
    }
    let mut bits = vec![0u8; len];
    let mut i = 0usize;
    while i < total {
        while pos < bytes.len() && bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        match bytes.get(pos) {
            Some(b'0') => bits[(i / w) * stride + (i % w) / 8] |= 0x80 >> ((i % w) % 8),
            Some(b'1') => {}
            Some(b'#') => {
                while pos < bytes.len() && bytes[pos] != b'\n' {
                    pos += 1;
                }
                continue;
            }
            Some(c) => {
                return Err(format!(
                    "PBM: pixel {i} (byte {pos}): {} is not 0 or 1",
                    shown(&[*c])
                ));
            }
            None => return Err(format!("PBM: {i} of {total} pixels, then the file ends")),
        }
        pos += 1;
        i += 1;
    }
    Ok((width, height, bits))
}

/// The value of `mosaic.mask` (a `--set`) that puts the mask file `bytes`
/// into a scenario: its plain PBM inline (`{ text = "P1 …" }`), so the
/// scenario stays self-contained (`morphogen run --mask`, the web page).
///
/// # Errors
/// As [`read`].
pub fn set_value(bytes: &[u8]) -> Result<String, String> {
    let (width, height, bits) = read(bytes)?;
    let pbm = to_pbm(&Mask {
        width,
        height,
        bits: &bits,
    });
    Ok(crate::inline_text(pbm).to_string())
}

/// A mask as a plain PBM (P1): PBM's 1 is black, i.e. *not* allowed.
#[must_use]
pub fn to_pbm(mask: &Mask<'_>) -> String {
    let mut s = format!(
        "P1\n# morphogen mosaic mask: white (0) allows foreground cells\n{} {}\n",
        mask.width, mask.height
    );
    for y in 0..u32::from(mask.height) {
        let row: Vec<&str> = (0..u32::from(mask.width))
            .map(|x| if mask.pixel(x, y) { "0" } else { "1" })
            .collect();
        s.push_str(&row.join(" "));
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn p1_and_p4_agree_and_sizes_are_checked_before_allocating() {
        let p1 = b"P1\n# c\n10 2\n0 1 0 1 0 1 0 1 0 1\n1111111111\n";
        let (w, h, bits) = read(p1).unwrap();
        assert_eq!((w, h), (10, 2));
        assert_eq!(bits, vec![0b1010_1010, 0b1000_0000, 0, 0]);
        let mut p4 = b"P4 10 2\n".to_vec();
        p4.extend([!0b1010_1010u8, !0b1000_0000, 0xFF, 0xFF]);
        assert_eq!(read(&p4).unwrap(), (w, h, bits));
        let huge = b"P4 65535 65535\n";
        assert!(read(huge).unwrap_err().contains("MAX_PIXELS"));
        let long = format!("P1 {} 1\n0", "9".repeat(1_000_000));
        let e = read(long.as_bytes()).unwrap_err();
        assert!(e.len() < 120, "{e}");
        assert!(
            read(b"P4 8 8\n\x00")
                .unwrap_err()
                .contains("raster needs 8 bytes")
        );
        assert!(read(b"\x89PNG\r\n\x1a\n").unwrap_err().contains("IHDR"));
        // Found by fuzzing: an empty first IHDR, then one of 12 × 704 643 080
        // pixels that a decoder would have allocated.
        let empty_ihdr: &[u8] = b"\x89PNG\r\n\x1a\n\0\0\0\0IHDR\0\0\0\x20\0\0\0\x0dIHDR\0\0\0\x0c\x2a\0\0\x08\x08\x06\0\0\0\xcd\xe4\x1e\xf1\0\0\0\x27IDAT\x82\x60\x82";
        assert!(read(empty_ihdr).unwrap_err().contains("13-byte IHDR"));
    }

    #[test]
    fn a_mask_round_trips_through_pbm() {
        let bits = [0b1010_0000u8, 0b0101_0000];
        let mask = Mask {
            width: 4,
            height: 2,
            bits: &bits,
        };
        let (w, h, read_bits) = read(to_pbm(&mask).as_bytes()).unwrap();
        assert_eq!((w, h, read_bits.as_slice()), (4, 2, &bits[..]));
    }
}

#[cfg(all(test, feature = "png"))]
mod moved_tests {
    use super::*;
    use tiny_skia::{ColorU8, Pixmap};

    #[test]
    fn pbm_round_trips_and_rejects_garbage() {
        // Rows of 9 bits take 2 bytes each; the 7 padding bits stay clear.
        static BITS: [u8; 4] = [0b1010_0000, 0b1000_0000, 0, 0b1000_0000];
        let mask = Mask {
            width: 9,
            height: 2,
            bits: &BITS,
        };
        let text = to_pbm(&mask);
        let (w, h, bits) = read_pbm(text.as_bytes()).unwrap();
        assert_eq!((w, h, bits.as_slice()), (9, 2, &BITS[..]));
        let mut raw = b"P4\n9 2\n".to_vec();
        raw.extend(BITS.iter().map(|b| !b));
        assert_eq!(read_pbm(&raw).unwrap().2, BITS.to_vec());
        assert!(
            read_pbm(b"P1\n2 2\n0 1 2 0")
                .unwrap_err()
                .to_string()
                .contains("not 0 or 1")
        );
        assert!(
            read_pbm(b"P4\n9 2\n\x00")
                .unwrap_err()
                .to_string()
                .contains("raster needs 4 bytes")
        );
        assert!(read_pbm(b"P3\n1 1\n").is_err());
    }

    #[test]
    fn png_pixels_are_white_from_half_luminance_and_half_alpha() {
        // One row of 9 pixels: (R, G, B, A) and whether it allows F.
        let row: [([u8; 4], bool); 9] = [
            ([255, 255, 255, 255], true),
            ([0, 0, 0, 255], false),
            ([128, 128, 128, 255], true),  // Y = 50.2 %
            ([127, 127, 127, 255], false), // Y = 49.8 %
            ([0, 255, 0, 255], true),      // Y = 71.5 %
            ([255, 0, 0, 255], false),     // Y = 21.3 %
            ([255, 255, 255, 128], true),  // A = 50.2 %
            ([255, 255, 255, 127], false), // A = 49.8 %
            ([255, 255, 255, 0], false),
        ];
        let mut pixmap = Pixmap::new(9, 2).unwrap();
        for (p, ([r, g, b, a], _)) in pixmap.pixels_mut().iter_mut().zip(&row) {
            *p = ColorU8::from_rgba(*r, *g, *b, *a).premultiply();
        }
        let (width, height, bits) = read_png(&pixmap.encode_png().unwrap()).unwrap();
        assert_eq!((width, height), (9, 2));
        let mask = Mask {
            width,
            height,
            bits: bits.leak(),
        };
        assert!(mask.is_valid());
        let allowed: Vec<bool> = (0..9).map(|x| mask.pixel(x, 0)).collect();
        let expected: Vec<bool> = row.iter().map(|(_, white)| *white).collect();
        assert_eq!(allowed, expected);
        // Row 1 is transparent black: nothing allowed, padding clear.
        assert_eq!(&mask.bits[2..], &[0, 0]);
        assert!(
            read_png(b"\x89PNG\r\n\x1a\nnot really")
                .unwrap_err()
                .to_string()
                .contains("PNG: cannot decode")
        );
        let wide = Pixmap::new(70_000, 1).unwrap().encode_png().unwrap();
        assert!(
            read_png(&wide)
                .unwrap_err()
                .to_string()
                .contains("at most 65535")
        );
        // A huge size is refused from the header, before any decoding.
        let mut huge = wide[..16].to_vec();
        huge.extend(100_000u32.to_be_bytes().repeat(2));
        assert_eq!(
            read_png(&huge).unwrap_err(),
            "PNG: 100000×100000 pixels (allowed: sides of 1 to at most 65535)"
        );
    }
}
