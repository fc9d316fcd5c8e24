#!/usr/bin/env python3
"""Writes the image pairs of crates/prism-lab/tests/flip.rs (tests/data/flip/NAME-{ref,test}.png,
8-bit sRGB) and prints each pair's mean LDR-FLIP from NVIDIA's reference implementation
(the flip-evaluator package on PyPI), at the 67 pixels per degree prism uses by default:

    python3 -m venv /tmp/flipenv && /tmp/flipenv/bin/pip install flip-evaluator
    /tmp/flipenv/bin/python scripts/flip-pairs.py

The pairs are computed, not sampled: they depend on nothing but this file."""
import math, os, struct, sys, zlib

OUT = os.path.join(os.path.dirname(__file__), "..", "crates", "prism-lab", "tests", "data", "flip")
W, H = 64, 48


def png(path, pixels):
    """pixels: H rows of W (r, g, b) byte triples."""
    raw = b"".join(b"\0" + bytes(c for p in row for c in p) for row in pixels)
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    ihdr = struct.pack(">IIBBBBB", W, H, 8, 2, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def image(f):
    return [[tuple(max(0, min(255, int(round(v)))) for v in f(x, y)) for x in range(W)] for y in range(H)]


def noise(x, y, k):
    """A fixed pseudo-random value in [-1, 1] per pixel and channel."""
    h = (x * 73856093) ^ (y * 19349663) ^ (k * 83492791)
    h = (h * 2654435761) & 0xFFFFFFFF
    return (h / 0xFFFFFFFF) * 2.0 - 1.0


def checker(x, y):
    v = 230 if ((x // 8) + (y // 8)) % 2 == 0 else 25
    return (v, v, v)


def blurred_checker(x, y):
    acc = [0.0, 0.0, 0.0]
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            c = checker(min(max(x + dx, 0), W - 1), min(max(y + dy, 0), H - 1))
            acc = [a + b / 9.0 for a, b in zip(acc, c)]
    return acc


def gradient(x, y):
    return (255.0 * x / (W - 1), 255.0 * y / (H - 1), 128.0)


def noisy_gradient(x, y):
    return [v + 24.0 * noise(x, y, k) for k, v in enumerate(gradient(x, y))]


def square(colour):
    def f(x, y):
        inside = 16 <= x < 48 and 12 <= y < 36
        return colour if inside else (128, 128, 128)
    return f


def rings(x, y):
    r = math.hypot(x - W / 2, y - H / 2)
    v = 127.5 + 127.5 * math.cos(r * 0.9)
    return (v, 0.6 * v, 255 - v)


def shifted_rings(x, y):
    return rings(x + 1, y)


PAIRS = {
    "checker-blur": (checker, blurred_checker),
    "gradient-noise": (gradient, noisy_gradient),
    "red-orange": (square((200, 30, 30)), square((220, 120, 30))),
    "rings-shift": (rings, shifted_rings),
}


def main():
    os.makedirs(OUT, exist_ok=True)
    for name, (ref, test) in PAIRS.items():
        png(os.path.join(OUT, f"{name}-ref.png"), image(ref))
        png(os.path.join(OUT, f"{name}-test.png"), image(test))
    try:
        import flip_evaluator as flip
    except ImportError:
        sys.exit("wrote the pairs; install flip-evaluator for the reference values")
    for name in PAIRS:
        _, mean, _ = flip.evaluate(os.path.join(OUT, f"{name}-ref.png"), os.path.join(OUT, f"{name}-test.png"),
                                   "LDR", parameters={"ppd": 67.0})
        print(f'("{name}", {mean:.7f}),')


main()
