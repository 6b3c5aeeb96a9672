#!/usr/bin/env python3
"""raster trace media --pixel X,Y: the printed samples' added radiance sums to the printed L, T is
non-increasing from sample to sample and ends at the printed T, each sample's T times e^{-mu*ds} is
the next one's, and the printed colour clamp(L + T*L_bg) is the pixel of `raster render media` at
the same size (decoded here from its PNG), for pixels in the medium, at its edge and beside it.
The same for `cloud` and `smoke-volume`, whose marches are blended over the ground drawn before them:
their printed colour, the shader's rgb + T*dst with dst the pixel before the march's draw, is the
rendered pixel (the same bytes, or within one unit where the trace says so).
  python3 tests/trace_media_test.py build/bin/raster"""
import math
import os
import re
import struct
import subprocess
import sys
import tempfile
import zlib

W, H = 160, 90


def fail(message):
    print("FAIL:", message)
    sys.exit(1)


def read_png(path):
    """8-bit RGB or RGBA, non-interlaced: rows of (r, g, b, ...) bytes."""
    data = open(path, "rb").read()
    pos, idat, width = 8, b"", 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or colour not in (2, 6) or interlace:
                fail(f"unexpected PNG format {depth} {colour} {interlace}")
            channels = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw, stride, rows, prev = zlib.decompress(idat), width * channels, [], bytearray(width * channels)
    for y in range(height):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b, c = prev[i], prev[i - channels] if i >= channels else 0
            p = a + b - c
            pred = [0, a, b, (a + b) // 2, a if abs(p - a) <= abs(p - b) and abs(p - a) <= abs(p - c)
                    else (b if abs(p - b) <= abs(p - c) else c)][f]
            line[i] = (line[i] + pred) & 255
        rows.append(line)
        prev = line
    return rows, channels


def check_pixel(raster, scene, x, y, image, channels):
    out = subprocess.run([raster, "trace", scene, "--width", str(W), "--height", str(H), "--pixel", f"{x},{y}"],
                         capture_output=True, text=True, check=True, timeout=60).stdout
    samples = [list(map(float, l.split())) for l in out.splitlines() if re.match(r"^ +\d+ +[-0-9.]", l)]
    m = re.search(r"^L = \(([^,]+), ([^,]+), ([^)]+)\)  T = (\S+)  L_bg = \(([^,]+), ([^,]+), ([^)]+)\)", out, re.M)
    if not m:
        fail(f"no L/T line at ({x}, {y}):\n{out}")
    L, T, bg = [float(v) for v in m.group(1, 2, 3)], float(m.group(4)), [float(v) for v in m.group(5, 6, 7)]
    for c in range(3):
        total = sum(s[6 + c] for s in samples)
        if abs(total - L[c]) > 1e-6 + 1e-5 * abs(L[c]):
            fail(f"({x}, {y}) channel {c}: the samples add {total}, L = {L[c]}")
    ts = [s[4] for s in samples]
    for a, b in zip(samples, samples[1:]):
        if b[4] > a[4]:
            fail(f"({x}, {y}): T grows from sample {a[0]:.0f} to {b[0]:.0f}")
        if abs(a[4] * math.exp(-a[3]) - b[4]) > 1e-5 * a[4] + 1e-9:
            fail(f"({x}, {y}): T {a[4]}·e^(-{a[3]}) is not the next sample's T {b[4]}")
    if samples and abs(ts[-1] * math.exp(-samples[-1][3]) - T) > 1e-5 * ts[-1] + 1e-9:
        fail(f"({x}, {y}): the last sample's T does not lead to the final T {T}")
    rendered = list(image[y][x * channels:x * channels + 3])
    printed = list(map(int, re.search(r"= rgb8 \((\d+), (\d+), (\d+)\)", out).groups()))
    over = re.search(r"^colour = rgb \+ T\*dst = \(([^,]+), ([^,]+), ([^)]+)\), rgb = \(([^,]+), ([^,]+), ([^)]+)\)"
                     r".* dst = \(([^,]+), ([^,]+), ([^)]+)\)", out, re.M)
    if scene == "media":
        colour = [min(max(L[c] + T * bg[c], 0.0), 1.0) for c in range(3)]
    else:
        if not over:
            fail(f"{scene} ({x}, {y}): no premultiplied colour line:\n{out}")
        rgb, dst = [float(v) for v in over.group(4, 5, 6)], [float(v) for v in over.group(7, 8, 9)]
        colour = [min(max(rgb[c] + T * dst[c], 0.0), 1.0) for c in range(3)]
    expected = [int(math.floor(v * 255 + 0.5)) for v in colour]
    off = max(abs(p - r) for p, r in zip(printed, rendered))
    if max(abs(e - r) for e, r in zip(expected, rendered)) > 1 or off > (0 if scene == "media" else 1):
        fail(f"{scene} ({x}, {y}): the trace's colour {printed} (from L, T: {expected}) is not the rendered {rendered}")
    verdict = "same" if off == 0 else "within one unit"
    if ("rendered pixel: rgb8 (%d, %d, %d) %s" % (*rendered, verdict)) not in out:
        fail(f"{scene} ({x}, {y}): the trace does not report the rendered pixel as {verdict}:\n{out}")
    return len(samples), T


# Pixels in the medium, at its edge and beside it (for cloud and smoke-volume: over the ground too).
PIXELS = {
    "media": ((80, 45), (60, 40), (100, 55), (40, 30), (5, 5), (150, 85)),
    "cloud": ((80, 38), (70, 40), (90, 35), (65, 45), (80, 65), (5, 5)),
    "smoke-volume": ((60, 52), (100, 31), (70, 40), (80, 80), (5, 5), (150, 20)),
}


def main():
    raster = sys.argv[1]
    for scene, pixels in PIXELS.items():
        with tempfile.TemporaryDirectory() as out:
            subprocess.run([raster, "render", scene, "--width", str(W), "--height", str(H), "--out-dir", out],
                           check=True, capture_output=True, timeout=60)
            image, channels = read_png(os.path.join(out, scene + ".png"))
        counts = [check_pixel(raster, scene, x, y, image, channels) for x, y in pixels]
        if not any(n > 5 and t < 0.5 for n, t in counts):
            fail(f"{scene}: no traced pixel crosses much medium: {counts}")
        print(f"trace {scene}: samples and T per pixel", counts)


main()
