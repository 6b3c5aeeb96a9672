#!/usr/bin/env python3
"""Writes the seed images of corpus/fuzz_png/: tiny images in every PNG colour type and bit depth
stb_image reads, interlaced, with every row filter, palettes with transparency, split IDAT chunks,
and a BMP and a PNM, which the decoder must refuse (PNG only: image_io.cpp). Each file is a few
hundred bytes at most. Usage: make_image_seeds.py [out-dir] (default: corpus/fuzz_png beside
this script). The files are committed; this script says how they were made.
"""
import os
import struct
import sys
import zlib


def chunk(kind, data):
    body = kind + data
    return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)


def png(width, height, bit_depth, color_type, rows, interlace=0, extra=b"", split=1):
    """rows: the filtered scanlines (filter byte first), already in interlace order."""
    ihdr = struct.pack(">IIBBBBB", width, height, bit_depth, color_type, 0, 0, interlace)
    data = zlib.compress(b"".join(rows), 9)
    step = max(1, (len(data) + split - 1) // split)
    idats = b"".join(chunk(b"IDAT", data[i:i + step]) for i in range(0, len(data), step))
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + extra + idats + chunk(b"IEND", b"")


def channels(color_type):
    return {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}[color_type]


def raw_rows(width, height, bit_depth, color_type, filters=(0,), seed=1):
    bits_per_row = width * channels(color_type) * bit_depth
    row_bytes = (bits_per_row + 7) // 8
    rows = []
    value = seed
    for y in range(height):
        row = bytearray()
        for _ in range(row_bytes):
            value = (value * 1103515245 + 12345) & 0x7FFFFFFF
            row.append((value >> 16) & 0xFF)
        if color_type == 3:  # palette indices within a 4-entry palette
            mask = (1 << bit_depth) - 1
            row = bytearray(b & (0x55 if bit_depth == 1 else 0x33 if bit_depth >= 2 else mask) for b in row)
        rows.append(bytes([filters[y % len(filters)]]) + bytes(row))
    return rows


def seeds():
    out = {}
    out["rgba8_1x1.png"] = png(1, 1, 8, 6, [b"\x00\xff\x80\x00\x7f"])
    out["rgb8_3x2.png"] = png(3, 2, 8, 2, raw_rows(3, 2, 8, 2))
    out["grey_alpha8_4x4.png"] = png(4, 4, 8, 4, raw_rows(4, 4, 8, 4, filters=(0, 1, 2, 3)))
    out["grey1_5x3.png"] = png(5, 3, 1, 0, raw_rows(5, 3, 1, 0))
    out["grey2_4x2.png"] = png(4, 2, 2, 0, raw_rows(4, 2, 2, 0))
    out["grey4_3x3.png"] = png(3, 3, 4, 0, raw_rows(3, 3, 4, 0))
    out["grey16_2x2.png"] = png(2, 2, 16, 0, raw_rows(2, 2, 16, 0))
    out["rgba16_2x2.png"] = png(2, 2, 16, 6, raw_rows(2, 2, 16, 6, filters=(4,)))
    out["rgb16_2x3.png"] = png(2, 3, 16, 2, raw_rows(2, 3, 16, 2, filters=(1, 4, 2)))
    palette = chunk(b"PLTE", bytes([255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255]))
    trns = chunk(b"tRNS", bytes([0, 128, 255]))
    out["palette2_4x4_trns.png"] = png(4, 4, 2, 3, raw_rows(4, 4, 2, 3), extra=palette + trns)
    out["palette8_3x2.png"] = png(3, 2, 8, 3, [b"\x00\x00\x01\x02", b"\x00\x03\x02\x01"], extra=palette)
    out["rgb8_trns_2x2.png"] = png(2, 2, 8, 2, raw_rows(2, 2, 8, 2), extra=chunk(b"tRNS", b"\x00\x10\x00\x20\x00\x30"))
    out["rgba8_split_idat_6x5.png"] = png(6, 5, 8, 6, raw_rows(6, 5, 8, 6, filters=(0, 1, 2, 3, 4)), split=4)
    # Adam7 interlaced 8x8 RGBA8: the seven passes' rows one after the other.
    passes = [(0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4), (1, 0, 2, 2), (0, 1, 1, 2)]
    rows = []
    for x0, y0, dx, dy in passes:
        w = (8 - x0 + dx - 1) // dx
        h = (8 - y0 + dy - 1) // dy
        rows += raw_rows(w, h, 8, 6, filters=(0, 1, 2, 3, 4), seed=x0 * 8 + y0 + 1)
    out["rgba8_adam7_8x8.png"] = png(8, 8, 8, 6, rows, interlace=1)
    out["gamma_chunks_2x1.png"] = png(2, 1, 8, 2, raw_rows(2, 1, 8, 2),
                                      extra=chunk(b"gAMA", struct.pack(">I", 45455)) + chunk(b"tEXt", b"k\x00v"))
    # Two other formats stb_image knows, which image_io.cpp does not compile in: refused.
    bmp_rows = b"".join(bytes([0, 0, 255, 0, 255, 0]) + b"\x00\x00" for _ in range(2))  # 2x2 24-bit, rows padded to 4
    out["refused_bgr24_2x2.bmp"] = (b"BM" + struct.pack("<IHHI", 54 + len(bmp_rows), 0, 0, 54) +
                                    struct.pack("<IiiHHIIiiII", 40, 2, 2, 1, 24, 0, len(bmp_rows), 2835, 2835, 0, 0) +
                                    bmp_rows)
    out["refused_rgb_2x2.ppm"] = b"P6\n2 2\n255\n" + bytes(range(12))
    return out


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "corpus", "fuzz_png")
    os.makedirs(out_dir, exist_ok=True)
    for name, data in seeds().items():
        with open(os.path.join(out_dir, name), "wb") as f:
            f.write(data)
        print(f"{name}: {len(data)} bytes")


if __name__ == "__main__":
    main()
