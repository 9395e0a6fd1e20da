#!/usr/bin/env python3
"""The emulated OLED's pictures, taken and compared.

Usage:
  oled-screens.py capture --while PID SYNC_SOCKET QMP_SOCKET OUT_DIR
  oled-screens.py compare QEMU_DIR REFERENCE_DIR NAME...
  oled-screens.py feed --while PID UART_SOCKET FILE [CAPTURE]

capture and feed wait for QEMU's sockets for as long as the QEMU process PID
runs (it creates them as it starts), however slowly it starts.

capture: connects to QEMU's UART1 (a `-serial unix:SYNC_SOCKET,server=on` chardev)
and QMP (`-qmp unix:QMP_SOCKET,server=on,wait=off`). The firmware, started
with `--screen-sync`, writes each preset's name and a newline on UART1 once
its last frame is on the OLED, and waits; this script then asks QMP for a
`screendump` of the SSD0323 (512×256: QEMU draws each pixel as 4×4 and grey
level g as 17·g), scales it back to the panel's 128×64 pixels, saves
OUT_DIR/NAME.qemu.png, and answers with one byte. It ends when UART1 closes
(QEMU exited), prints the names it captured and writes them, one per line,
to OUT_DIR/captured.txt.

compare: for each NAME, QEMU_DIR/NAME.qemu.png against the host's
REFERENCE_DIR/NAME/rig-128x64-grey4.png (`morphogen listen --rig
128x64:grey4` or `morphogen run NAME --rig 128x64:grey4`) or, where there
is none, another emulated board's REFERENCE_DIR/NAME.qemu.png (the
sender's, for the receiver), pixel for pixel; copies the reference to
QEMU_DIR/NAME.host.png (or NAME.sender.png) and, on a difference, writes
QEMU_DIR/NAME.diff.png (red where they differ). Fails on any differing
pixel, a missing picture, or a picture with nothing drawn (every pixel the
background).

feed: connects to QEMU's UART (a `-serial unix:UART_SOCKET,server=on`
chardev), writes a zero byte and FILE into it — QEMU takes bytes as the
UART's receive FIFO empties, so the program reads them all — and reads what
the program writes until QEMU exits, into CAPTURE if given; prints how much
it has fed every 256 KiB (the firmware check watches that as progress).
Standard library only.
"""
import json
import os
import socket
import sys
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from thumbnail import read_png, write_png  # noqa: E402

MAGNIFY = 4


def running(pid):
    try:
        os.kill(pid, 0)
        return True
    except ProcessLookupError:
        return False


def connect(path, qemu):
    """Connects to a UNIX socket that QEMU (process `qemu`) creates as it
    starts."""
    while True:
        try:
            s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
            s.connect(path)
            return s
        except OSError:
            s.close()
            if not running(qemu):
                sys.exit(f"oled-screens: QEMU (process {qemu}) ended before it opened {path}")
            time.sleep(0.05)


class Qmp:
    def __init__(self, path, qemu):
        self.sock = connect(path, qemu)
        self.file = self.sock.makefile("rwb", buffering=0)
        self.reply()  # the greeting
        self.call("qmp_capabilities")

    def reply(self):
        while True:
            line = self.file.readline()
            if not line:
                sys.exit("oled-screens: QMP closed")
            msg = json.loads(line)
            if "event" not in msg:
                return msg

    def call(self, command, **arguments):
        self.file.write(json.dumps({"execute": command, "arguments": arguments}).encode() + b"\n")
        msg = self.reply()
        if "error" in msg:
            sys.exit(f"oled-screens: QMP {command}: {msg['error']}")
        return msg["return"]


def read_ppm(path):
    data = open(path, "rb").read()
    fields, pos = [], 0
    while len(fields) < 4:  # magic, width, height, maxval, each after blanks/comments
        while data[pos : pos + 1].isspace():
            pos += 1
        if data[pos : pos + 1] == b"#":
            pos = data.index(b"\n", pos)
            continue
        end = pos
        while not data[end : end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    if fields[0] != b"P6" or fields[3] != b"255":
        sys.exit(f"oled-screens: {path} is not an 8-bit P6 PPM")
    width, height = int(fields[1]), int(fields[2])
    return width, height, data[pos + 1 :]


def panel_rows(ppm):
    """The 128×64 panel pixels of a 512×256 screendump (each 4×4 px block
    is one pixel), as RGB rows."""
    width, height, pixels = read_ppm(ppm)
    if (width, height) != (128 * MAGNIFY, 64 * MAGNIFY):
        sys.exit(f"oled-screens: {ppm} is {width}×{height}, not the SSD0323's 512×256")
    rows = []
    for y in range(0, height, MAGNIFY):
        row = bytearray()
        for x in range(0, width, MAGNIFY):
            at = (y * width + x) * 3
            row += pixels[at : at + 3]
        rows.append(row)
    return rows


def capture(qemu, sync_path, qmp_path, out):
    os.makedirs(out, exist_ok=True)
    sync = connect(sync_path, qemu)
    qmp = Qmp(qmp_path, qemu)
    captured, pending = [], b""
    while True:
        chunk = sync.recv(256)
        if not chunk:
            break
        pending += chunk
        while b"\n" in pending:
            line, pending = pending.split(b"\n", 1)
            name = line.decode("ascii", "replace")
            ppm = os.path.join(out, f"{name}.qemu.ppm")
            qmp.call("screendump", filename=ppm)
            rows = panel_rows(ppm)
            os.remove(ppm)
            write_png(os.path.join(out, f"{name}.qemu.png"), 128, 64, rows)
            captured.append(name)
            sync.sendall(b"k")
    with open(os.path.join(out, "captured.txt"), "w", encoding="ascii") as f:
        f.writelines(f"{name}\n" for name in captured)
    print(f"oled-screens: {len(captured)} pictures: {' '.join(captured)}")


def pixels(path):
    """The picture's pixels as (r, g, b) rows."""
    width, height, channels, rows = read_png(path)
    return width, height, [[tuple(row[x * channels : x * channels + 3]) for x in range(width)] for row in rows]


def compare(qemu_dir, host_dir, names):
    failures = []
    for name in names:
        qemu = os.path.join(qemu_dir, f"{name}.qemu.png")
        host = os.path.join(host_dir, name, "rig-128x64-grey4.png")
        kind = "host"
        if not os.path.exists(host) and os.path.exists(os.path.join(host_dir, f"{name}.qemu.png")):
            host, kind = os.path.join(host_dir, f"{name}.qemu.png"), "sender"
        missing = [p for p in (qemu, host) if not os.path.exists(p)]
        if missing:
            failures.append(f"{name}: no picture {' '.join(missing)}")
            continue
        (qw, qh, q), (hw, hh, h) = pixels(qemu), pixels(host)
        with open(host, "rb") as src, open(os.path.join(qemu_dir, f"{name}.{kind}.png"), "wb") as dst:
            dst.write(src.read())
        if (qw, qh) != (hw, hh):
            failures.append(f"{name}: QEMU {qw}×{qh}, {kind} {hw}×{hh}")
            continue
        differ = sum(a != b for qr, hr in zip(q, h) for a, b in zip(qr, hr))
        background = (0, 0, 0)  # PALETTE_GRAY4[0]
        drawn = sum(p != background for row in q for p in row)
        print(f"oled-screens: {name}: {drawn} pixels drawn, {differ} differ from the {kind}")
        if differ:
            diff_rows = [bytearray(b"".join(bytes((255, 0, 0) if a != b else a) for a, b in zip(qr, hr)))
                         for qr, hr in zip(q, h)]
            write_png(os.path.join(qemu_dir, f"{name}.diff.png"), qw, qh, diff_rows)
            failures.append(f"{name}: {differ} pixels differ (see {name}.diff.png)")
        elif drawn == 0:
            failures.append(f"{name}: nothing drawn")
    for f in failures:
        print(f"oled-screens: FAIL {f}", file=sys.stderr)
    return 1 if failures or not names else 0


FED_EVERY = 256 * 1024


def feed(qemu, uart_path, path, capture=None):
    # A zero byte first: QEMU's UART model drops what it holds when the
    # program enables its FIFO, and the first byte can come before that; a
    # zero byte only ends an empty frame.
    data = b"\x00" + open(path, "rb").read()
    uart = connect(uart_path, qemu)
    out = open(capture, "wb") if capture else None
    # Written from a thread: the program answers before it has read all.
    failure = []

    def send():
        try:
            for at in range(0, len(data), 4096):
                piece = data[at : at + 4096]
                uart.sendall(piece)
                if (at + len(piece)) // FED_EVERY > at // FED_EVERY:
                    print(f"oled-screens: fed {at + len(piece)} of {len(data)} bytes", flush=True)
        except OSError as e:
            failure.append(e)

    sender = threading.Thread(target=send)
    sender.start()
    received = 0
    while True:
        chunk = uart.recv(4096)
        if not chunk:
            break
        received += len(chunk)
        if out:
            out.write(chunk)
    sender.join()
    if out:
        out.close()
    if failure:
        sys.exit(f"oled-screens: only part of {path} was read: {failure[0]}")
    print(f"oled-screens: fed {len(data) - 1} bytes of {path}, received {received}")


def main():
    watched = len(sys.argv) > 3 and sys.argv[2] == "--while" and sys.argv[3].isdigit()
    if watched and len(sys.argv) == 7 and sys.argv[1] == "capture":
        capture(int(sys.argv[3]), *sys.argv[4:])
    elif watched and len(sys.argv) in (6, 7) and sys.argv[1] == "feed":
        feed(int(sys.argv[3]), *sys.argv[4:])
    elif len(sys.argv) >= 4 and sys.argv[1] == "compare":
        sys.exit(compare(sys.argv[2], sys.argv[3], sys.argv[4:]))
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
