#!/usr/bin/env python3
"""LDR-FLIP computed directly, to check raster's compareFlip (tests/image_compare_test.cpp,
CompareFlip.MatchesADirectRendition) on a picture where every filter matters.

    flip_direct.py [ppd]

Everything in double, plain Python (no NumPy), laid out as the paper and its reference code state the
metric: the 2D kernels as written (not factored into passes), correlation with the border read as the
edge pixel, YCxCz with its scale and offset, the inverse matrix taken numerically. raster instead
filters separably in float and applies the zero-sum kernels as differences, so the two agree to about
1e-6, not to the bit. Prints the mean error and the errors at the pixels the test checks, for the
pair of 30x20 images the test builds (picture() and blended() below mirror the test's).
"""
import math
import sys

WIDTH, HEIGHT = 30, 20
# Linear sRGB to XYZ (D65); the rows' sums are the white point.
RGB_TO_XYZ = [[10135552 / 24577794, 8788810 / 24577794, 4435075 / 24577794],
              [2613072 / 12288897, 8788810 / 12288897, 887015 / 12288897],
              [1425312 / 73733382, 8788810 / 73733382, 70074185 / 73733382]]
WHITE = [sum(row) for row in RGB_TO_XYZ]
SAMPLES = [(0, 0), (5, 3), (15, 10), (22, 9), (10, 15), (29, 19)]


def picture(shift):
    """A gradient, a blue checkerboard and a disc, RGBA8 row by row (the test's picture())."""
    pixels = []
    for y in range(HEIGHT):
        for x in range(WIDTH):
            dx, dy = x - WIDTH // 2 - shift, y - HEIGHT // 2
            disc = dx * dx + dy * dy < HEIGHT * HEIGHT // 9
            pixels += [220 if disc else x * 255 // WIDTH, 60 if disc else y * 255 // HEIGHT,
                       200 if (x // 4 + y // 4) & 1 else 40, 255]
    return pixels


def blended(pixels, seed):
    """Three parts `pixels`, one part the test's noise(), in red, green and blue."""
    out = []
    for i, v in enumerate(pixels):
        seed = (seed * 1664525 + 1013904223) % 2**32
        out.append(v if i % 4 == 3 else (v * 3 + (seed >> 24)) // 4)
    return out


def correlate(plane, kernel):
    r = len(kernel) // 2
    out = []
    for y in range(HEIGHT):
        for x in range(WIDTH):
            s = 0.0
            for j in range(-r, r + 1):
                row = min(max(y + j, 0), HEIGHT - 1) * WIDTH
                for i in range(-r, r + 1):
                    s += kernel[j + r][i + r] * plane[row + min(max(x + i, 0), WIDTH - 1)]
            out.append(s)
    return out


def csf_kernel(ppd, a1, b1, a2, b2):
    r = math.ceil(3 * math.sqrt(0.04 / (2 * math.pi**2)) * ppd)
    def weight(x, y):
        d2 = (x * x + y * y) / (ppd * ppd)
        return sum(a * math.sqrt(math.pi / b) * math.exp(-math.pi**2 * d2 / b) for a, b in ((a1, b1), (a2, b2)))
    k = [[weight(x, y) for x in range(-r, r + 1)] for y in range(-r, r + 1)]
    total = sum(map(sum, k))
    return [[v / total for v in row] for row in k]


def feature_kernels(ppd, kind):
    sd = 0.5 * 0.082 * ppd
    r = math.ceil(3 * sd)
    def weight(x, y):
        g = math.exp(-(x * x + y * y) / (2 * sd * sd))
        return -x * g if kind == "edge" else (x * x / (sd * sd) - 1) * g
    k = [[weight(x, y) for x in range(-r, r + 1)] for y in range(-r, r + 1)]
    pos = sum(v for row in k for v in row if v > 0)
    neg = -sum(v for row in k for v in row if v < 0)
    k = [[v / pos if v > 0 else v / neg for v in row] for row in k]
    return k, [list(col) for col in zip(*k)]


def inverse(m):
    (a, b, c), (d, e, f), (g, h, i) = m
    det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    return [[(e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det],
            [(f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det],
            [(d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det]]


def linear(v):
    c = v / 255
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055)**2.4


def hunt_lab(rgb):
    def f(t):
        return t**(1 / 3) if t > (6 / 29)**3 else t / (3 * (6 / 29)**2) + 4 / 29
    fx, fy, fz = (f(sum(RGB_TO_XYZ[i][j] * rgb[j] for j in range(3)) / WHITE[i]) for i in range(3))
    lightness = 116 * fy - 16
    return lightness, 0.01 * lightness * 500 * (fx - fy), 0.01 * lightness * 200 * (fy - fz)


def prepare(pixels, ppd):
    """Per pixel: Hunt-adjusted L*a*b* of the filtered colour; edge and point magnitudes."""
    ycxcz = [[], [], []]
    for p in range(WIDTH * HEIGHT):
        rgb = [linear(pixels[4 * p + c]) for c in range(3)]
        x, y, z = (sum(RGB_TO_XYZ[i][j] * rgb[j] for j in range(3)) / WHITE[i] for i in range(3))
        for c, v in enumerate((116 * y - 16, 500 * (x - y), 200 * (y - z))):
            ycxcz[c].append(v)
    kernels = [csf_kernel(ppd, 1, 0.0047, 0, 1e-5), csf_kernel(ppd, 1, 0.0053, 0, 1e-5),
               csf_kernel(ppd, 34.1, 0.04, 13.5, 0.025)]
    filtered = [correlate(ycxcz[c], kernels[c]) for c in range(3)]
    to_rgb = inverse(RGB_TO_XYZ)
    lab = []
    for p in range(WIDTH * HEIGHT):
        y = (filtered[0][p] + 16) / 116
        xyz = [(y + filtered[1][p] / 500) * WHITE[0], y * WHITE[1], (y - filtered[2][p] / 200) * WHITE[2]]
        lab.append(hunt_lab([min(1.0, max(0.0, sum(to_rgb[i][j] * xyz[j] for j in range(3)))) for i in range(3)]))
    luminance = [(v + 16) / 116 for v in ycxcz[0]]
    magnitudes = []
    for kind in ("edge", "point"):
        kx, ky = feature_kernels(ppd, kind)
        magnitudes.append([math.hypot(a, b) for a, b in zip(correlate(luminance, kx), correlate(luminance, ky))])
    return lab, magnitudes[0], magnitudes[1]


def hyab(p, q):
    return abs(p[0] - q[0]) + math.hypot(p[1] - q[1], p[2] - q[2])


def main(ppd):
    (lab_a, edge_a, point_a), (lab_b, edge_b, point_b) = (
        prepare(picture(0), ppd), prepare(blended(picture(2), 5), ppd))
    cmax = hyab(hunt_lab([0, 1, 0]), hunt_lab([0, 0, 1]))**0.7
    knee = 0.4 * cmax
    errors = []
    for p in range(WIDTH * HEIGHT):
        e = hyab(lab_a[p], lab_b[p])**0.7
        color = e * 0.95 / knee if e < knee else 0.95 + (e - knee) / (cmax - knee) * 0.05
        feature = (max(abs(edge_a[p] - edge_b[p]), abs(point_a[p] - point_b[p])) / math.sqrt(2))**0.5
        errors.append(color**(1 - feature))
    print("mean %.7f" % (sum(errors) / len(errors)))
    for x, y in SAMPLES:
        print("(%d, %d) %.7f" % (x, y, errors[y * WIDTH + x]))


if __name__ == "__main__":
    main(float(sys.argv[1]) if len(sys.argv) > 1 else 67.0)
