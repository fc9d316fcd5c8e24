#!/usr/bin/env python3
"""Writes the example mesh files in scenes/meshes/ that scenes/mesh-room.toml includes.

gems.obj (+ gems.mtl): four objects with their own MTL materials, chosen to show what the
OBJ reader does: a flat-shaded icosahedron (illum 3, a mirror weighted by Ks), a
geodesic sphere with vertex normals (illum 7, Fresnel glass), a five-pointed star prism
whose caps are concave 10-gons (ear-clipped, not fanned), and a card with uvs and a
map_Kd image.

torus.ply: a binary little-endian torus with normals, uvs and vertex colours (which prism
skips), written as quads.

Run from the repository root: python3 scripts/make-example-meshes.py
"""

import math
import os
import struct

OUT = os.path.join(os.path.dirname(__file__), "..", "scenes", "meshes")


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def normalize(a):
    n = math.sqrt(dot(a, a))
    return tuple(x / n for x in a)


def icosahedron():
    """Unit-radius icosahedron, faces counter-clockwise seen from outside."""
    p = (1 + math.sqrt(5)) / 2
    raw = [(-1, p, 0), (1, p, 0), (-1, -p, 0), (1, -p, 0),
           (0, -1, p), (0, 1, p), (0, -1, -p), (0, 1, -p),
           (p, 0, -1), (p, 0, 1), (-p, 0, -1), (-p, 0, 1)]
    verts = [normalize(v) for v in raw]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11),
             (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8),
             (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9),
             (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for a, b, c in faces:
        n = cross(sub(verts[b], verts[a]), sub(verts[c], verts[a]))
        assert dot(n, verts[a]) > 0, "outward winding"
    return verts, faces


def subdivide(verts, faces):
    verts = list(verts)
    midpoints = {}

    def mid(a, b):
        key = (min(a, b), max(a, b))
        if key not in midpoints:
            m = normalize(tuple((x + y) / 2 for x, y in zip(verts[a], verts[b])))
            midpoints[key] = len(verts)
            verts.append(m)
        return midpoints[key]

    out = []
    for a, b, c in faces:
        ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
        out += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    return verts, out


def fmt(x):
    s = f"{x:.6f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


class Obj:
    def __init__(self):
        self.lines = []
        self.nv = self.nvt = self.nvn = 0

    def v(self, p, offset=(0, 0, 0)):
        self.lines.append("v " + " ".join(fmt(a + b) for a, b in zip(p, offset)))
        self.nv += 1
        return self.nv

    def vn(self, n):
        self.lines.append("vn " + " ".join(fmt(a) for a in n))
        self.nvn += 1
        return self.nvn

    def vt(self, t):
        self.lines.append("vt " + " ".join(fmt(a) for a in t))
        self.nvt += 1
        return self.nvt


def write_obj():
    o = Obj()
    o.lines += [
        "# Example meshes for prism: written by scripts/make-example-meshes.py.",
        "# Units: the objects stand on y = 0 in a row along x, one unit apart.",
        "mtllib gems.mtl",
        "",
    ]

    # A flat icosahedron: no normals, so every face is shaded flat.
    verts, faces = icosahedron()
    lift = -min(v[1] for v in verts) * 0.8
    o.lines += ["o icosahedron", "usemtl ruby"]
    base = o.nv
    for v in verts:
        o.v(tuple(c * 0.8 for c in v), (-3.0, lift, 0))
    o.lines += [f"f {base + a + 1} {base + b + 1} {base + c + 1}" for a, b, c in faces]
    o.lines.append("")

    # A geodesic sphere with vertex normals: smooth shading; relative (negative) indices.
    verts, faces = subdivide(*subdivide(*icosahedron()))
    o.lines += ["o geosphere", "usemtl glass"]
    for v in verts:
        o.v(tuple(c * 0.8 for c in v), (-1.0, 0.8, 0))
    for v in verts:
        o.vn(v)
    n = len(verts)
    for a, b, c in faces:
        o.lines.append("f " + " ".join(f"{i - n}//{i - n}" for i in (a, b, c)))
    o.lines.append("")

    # A star prism: its caps are concave 10-gons.
    o.lines += ["o star", "usemtl gold"]
    ring = []
    for k in range(10):
        r = 0.9 if k % 2 == 0 else 0.38
        a = math.pi / 2 + k * math.pi / 5
        ring.append((r * math.cos(a), r * math.sin(a)))
    # The star stands upright, facing +z: x, y from the ring, z across its thickness.
    front = [o.v((x, y, 0.15), (1.2, 0.9, 0)) for x, y in ring]
    back = [o.v((x, y, -0.15), (1.2, 0.9, 0)) for x, y in ring]
    o.lines.append("f " + " ".join(str(i) for i in front))
    o.lines.append("f " + " ".join(str(i) for i in reversed(back)))
    for k in range(10):
        j = (k + 1) % 10
        o.lines.append(f"f {front[k]} {back[k]} {back[j]} {front[j]}")
    o.lines.append("")

    # A card with texture coordinates and an image.
    o.lines += ["o card", "usemtl card"]
    corners = [(-0.7, 0, 0), (0.7, 0, 0), (0.7, 1.4, 0), (-0.7, 1.4, 0)]
    uvs = [(0, 0), (1, 0), (1, 1), (0, 1)]
    vi = [o.v(c, (3.2, 0.02, -0.3)) for c in corners]
    ti = [o.vt(t) for t in uvs]
    o.lines.append("f " + " ".join(f"{v}/{t}" for v, t in zip(vi, ti)))
    o.lines.append("")

    with open(os.path.join(OUT, "gems.obj"), "w") as f:
        f.write("\n".join(o.lines))

    mtl = """# Materials for gems.obj. docs/formats.md says how each statement maps onto prism.

newmtl ruby
Ka 0.6 0.05 0.05
Kd 0.7 0.06 0.08
Ks 0.35 0.35 0.35
Ns 90
illum 3

newmtl glass
Ka 0 0 0
Kd 0.02 0.02 0.02
Ks 0.3 0.3 0.3
Ns 200
Ni 1.5
Tf 0.95 0.98 0.95
illum 7

newmtl gold
Ka 0.3 0.2 0.05
Kd 0.85 0.6 0.15
Ks 0.5 0.45 0.3
Ns 60
illum 2

newmtl card
Ka 0.3 0.3 0.3
Kd 1 1 1
map_Kd ../textures/testcard.png
illum 1
"""
    with open(os.path.join(OUT, "gems.mtl"), "w") as f:
        f.write(mtl)


def write_ply():
    big_r, small_r, nu, nv = 1.0, 0.35, 48, 24
    verts = []
    for i in range(nu):
        u = 2 * math.pi * i / nu
        for j in range(nv):
            v = 2 * math.pi * j / nv
            n = (math.cos(u) * math.cos(v), math.sin(v), math.sin(u) * math.cos(v))
            p = ((big_r + small_r * math.cos(v)) * math.cos(u), small_r * math.sin(v),
                 (big_r + small_r * math.cos(v)) * math.sin(u))
            shade = int(127 + 120 * math.cos(v))
            verts.append((p, n, (i / nu, j / nv), (shade, 80, 255 - shade)))
    faces = []
    for i in range(nu):
        for j in range(nv):
            a = i * nv + j
            b = ((i + 1) % nu) * nv + j
            c = ((i + 1) % nu) * nv + (j + 1) % nv
            d = i * nv + (j + 1) % nv
            faces.append((a, d, c, b))
    # Check the winding against the normals: counter-clockwise seen from outside.
    p = [v[0] for v in verts]
    a, d, c, b = faces[0]
    assert dot(cross(sub(p[d], p[a]), sub(p[c], p[a])), verts[a][1]) > 0

    header = "\n".join([
        "ply",
        "format binary_little_endian 1.0",
        "comment A torus for prism's examples: written by scripts/make-example-meshes.py",
        f"element vertex {len(verts)}",
        "property float x", "property float y", "property float z",
        "property float nx", "property float ny", "property float nz",
        "property float u", "property float v",
        "property uchar red", "property uchar green", "property uchar blue",
        f"element face {len(faces)}",
        "property list uchar int vertex_indices",
        "end_header",
    ]) + "\n"
    body = bytearray()
    for p, n, t, col in verts:
        body += struct.pack("<8f3B", *p, *n, *t, *col)
    for f in faces:
        body += struct.pack("<B4i", len(f), *f)
    with open(os.path.join(OUT, "torus.ply"), "wb") as f:
        f.write(header.encode("ascii") + bytes(body))


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    write_obj()
    write_ply()
