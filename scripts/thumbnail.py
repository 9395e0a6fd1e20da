#!/usr/bin/env python3
"""Scales a PNG (8-bit RGB or RGBA, as morphogen writes them) down to a
given height by averaging boxes of pixels: `thumbnail.py IN OUT HEIGHT`.
Standard library only, for the documentation pictures
(scripts/mosaic-pictures.sh)."""

import struct
import sys
import zlib


def read_png(path):
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat, header, palette = 8, b"", None, None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos : pos + 4])
        kind = data[pos + 4 : pos + 8]
        body = data[pos + 8 : pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"PLTE":
            palette = [body[i : i + 3] for i in range(0, len(body), 3)]
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    assert interlace == 0 and (colour == 3 or depth == 8), "8-bit RGB(A) or indexed only"
    assert colour in (2, 3, 6), "RGB(A) or indexed only"
    channels = {2: 3, 3: 1, 6: 4}[colour]
    raw = zlib.decompress(idat)
    stride = (width * channels * depth + 7) // 8
    filter_step = max(1, channels * depth // 8)
    rows, prev = [], bytearray(stride)
    for y in range(height):
        start = y * (stride + 1)
        kind, line = raw[start], bytearray(raw[start + 1 : start + 1 + stride])
        for i in range(stride):
            a = line[i - filter_step] if i >= filter_step else 0
            b = prev[i]
            c = prev[i - filter_step] if i >= filter_step else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pred) & 255
        rows.append(line)
        prev = line
    if colour == 3:
        # Unpack the indices and look them up: RGB rows.
        per_byte, mask = 8 // depth, (1 << depth) - 1
        rgb_rows = []
        for line in rows:
            out = bytearray()
            for x in range(width):
                byte = line[x // per_byte]
                index = (byte >> (8 - depth * (x % per_byte + 1))) & mask
                out += palette[index]
            rgb_rows.append(out)
        return width, height, 3, rgb_rows
    return width, height, channels, rows


def write_png(path, width, height, rows):
    raw = b"".join(b"\x00" + bytes(r) for r in rows)
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    open(path, "wb").write(png)


def main():
    src, dst, target = sys.argv[1], sys.argv[2], int(sys.argv[3])
    width, height, channels, rows = read_png(src)
    scale = height / target
    out_w, out_h = max(1, round(width / scale)), target
    out = []
    for y in range(out_h):
        y0, y1 = int(y * scale), max(int(y * scale) + 1, int((y + 1) * scale))
        line = bytearray()
        for x in range(out_w):
            x0, x1 = int(x * scale), max(int(x * scale) + 1, int((x + 1) * scale))
            n, acc = 0, [0, 0, 0]
            for yy in range(y0, min(y1, height)):
                row = rows[yy]
                for xx in range(x0, min(x1, width)):
                    i = xx * channels
                    acc[0] += row[i]
                    acc[1] += row[i + 1]
                    acc[2] += row[i + 2]
                    n += 1
            line += bytes(v // max(n, 1) for v in acc)
        out.append(line)
    write_png(dst, out_w, out_h, out)


if __name__ == "__main__":
    main()
