#!/usr/bin/env python3
"""Writes scenes/spheres.gltf, the glTF example scene: a textured floor, a chrome ball, a
glass ball (KHR_materials_transmission + KHR_materials_ior), a red plastic cube and a rough
gold ball, a camera, a point light and a spot light (KHR_lights_punctual). The three balls
share one set of sphere accessors. Vertex data is embedded as a base64 data: URI; the floor
texture is scenes/textures/testcard.png.

    python3 scripts/make-gltf-example.py scenes/spheres.gltf
"""

import base64
import json
import math
import struct
import sys

buf = bytearray()
views, accessors = [], []


def add_view(data):
    while len(buf) % 4:
        buf.append(0)
    views.append({"buffer": 0, "byteOffset": len(buf), "byteLength": len(data)})
    buf.extend(data)
    return len(views) - 1


def add_accessor(values, kind):
    if kind == "SCALAR":  # indices, unsigned shorts
        data = b"".join(struct.pack("<H", v) for v in values)
        a = {"componentType": 5123, "count": len(values), "type": kind}
    else:
        n = {"VEC2": 2, "VEC3": 3}[kind]
        data = b"".join(struct.pack("<%df" % n, *v) for v in values)
        a = {"componentType": 5126, "count": len(values), "type": kind}
        if kind == "VEC3":
            a["min"] = [min(v[i] for v in values) for i in range(3)]
            a["max"] = [max(v[i] for v in values) for i in range(3)]
    a["bufferView"] = add_view(data)
    accessors.append(a)
    return len(accessors) - 1


def primitive(pos, nrm, uv, idx):
    attributes = {
        "POSITION": add_accessor(pos, "VEC3"),
        "NORMAL": add_accessor(nrm, "VEC3"),
        "TEXCOORD_0": add_accessor(uv, "VEC2"),
    }
    return {"attributes": attributes, "indices": add_accessor(idx, "SCALAR")}


def sphere(n_lon, n_lat):
    pos, uv, idx = [], [], []
    for j in range(n_lat + 1):
        theta = math.pi * j / n_lat
        for i in range(n_lon + 1):
            phi = 2 * math.pi * i / n_lon
            pos.append((math.sin(theta) * math.cos(phi), math.cos(theta),
                        -math.sin(theta) * math.sin(phi)))
            uv.append((i / n_lon, j / n_lat))
    for j in range(n_lat):
        for i in range(n_lon):
            a = j * (n_lon + 1) + i
            b = a + n_lon + 1
            idx += [a, b, a + 1, a + 1, b, b + 1]
    return pos, pos, uv, idx


def cube():
    pos, nrm, uv, idx = [], [], [], []
    for axis in range(3):
        for sign in (-1, 1):
            n = [0, 0, 0]
            n[axis] = sign
            u = [0, 0, 0]
            u[(axis + 1) % 3] = 1
            v = [0, 0, 0]
            v[(axis + 2) % 3] = 1
            if sign < 0:
                u, v = v, u
            base = len(pos)
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                pos.append(tuple(n[k] + a * u[k] + b * v[k] for k in range(3)))
                nrm.append(tuple(n))
                uv.append(((a + 1) / 2, (1 - b) / 2))
            idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    return pos, nrm, uv, idx


def mesh(prim, material):
    return {"primitives": [dict(prim, material=material)]}


def quat(axis, degrees):
    s = math.sin(math.radians(degrees) / 2)
    return [axis[0] * s, axis[1] * s, axis[2] * s, math.cos(math.radians(degrees) / 2)]


floor = primitive([(-1, 0, 1), (1, 0, 1), (1, 0, -1), (-1, 0, -1)], [(0, 1, 0)] * 4,
                  [(0, 4), (4, 4), (4, 0), (0, 0)], [0, 1, 2, 0, 2, 3])
ball = primitive(*sphere(40, 20))
box = primitive(*cube())

doc = {
    "asset": {"version": "2.0", "generator": "prism scripts/make-gltf-example.py"},
    "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_transmission", "KHR_materials_ior"],
    "extensions": {"KHR_lights_punctual": {"lights": [
        {"name": "key", "type": "point", "intensity": 300.0, "color": [1, 0.95, 0.9]},
        {"name": "fill", "type": "spot", "intensity": 60.0, "color": [0.8, 0.9, 1], "spot": {}},
    ]}},
    "scene": 0,
    "scenes": [{"nodes": list(range(8))}],
    "nodes": [
        {"name": "floor", "mesh": 0, "scale": [6, 1, 6]},
        {"name": "chrome ball", "mesh": 1, "translation": [-1.6, 0.8, 0.2], "scale": [0.8] * 3},
        {"name": "glass ball", "mesh": 2, "translation": [0.3, 0.7, 1.6], "scale": [0.7] * 3},
        {"name": "cube", "mesh": 3, "translation": [1.5, 0.6, -0.6], "scale": [0.6] * 3,
         "rotation": quat((0, 1, 0), 40)},
        {"name": "gold ball", "mesh": 4, "translation": [0.0, 0.5, -1.8], "scale": [0.5] * 3},
        {"name": "camera", "camera": 0, "translation": [0, 2.6, 6.5],
         "rotation": quat((1, 0, 0), -22)},
        {"name": "key light", "translation": [-3, 5, 4],
         "extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"name": "fill light", "translation": [4, 3, 3],
         "extensions": {"KHR_lights_punctual": {"light": 1}}},
    ],
    "cameras": [{"type": "perspective",
                 "perspective": {"yfov": 0.7, "aspectRatio": 1.5, "znear": 0.05}}],
    "meshes": [mesh(floor, 0), mesh(ball, 1), mesh(ball, 2), mesh(box, 3), mesh(ball, 4)],
    "materials": [
        {"name": "floor", "pbrMetallicRoughness": {
            "baseColorTexture": {"index": 0}, "metallicFactor": 0.0, "roughnessFactor": 0.6}},
        {"name": "chrome", "pbrMetallicRoughness": {
            "baseColorFactor": [0.9, 0.9, 0.9, 1], "metallicFactor": 1.0, "roughnessFactor": 0.05}},
        {"name": "glass", "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.0},
         "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                        "KHR_materials_ior": {"ior": 1.5}}},
        {"name": "red plastic", "pbrMetallicRoughness": {
            "baseColorFactor": [0.8, 0.05, 0.03, 1], "metallicFactor": 0.0, "roughnessFactor": 0.35}},
        {"name": "rough gold", "pbrMetallicRoughness": {
            "baseColorFactor": [1.0, 0.75, 0.3, 1], "metallicFactor": 1.0, "roughnessFactor": 0.6}},
    ],
    "textures": [{"source": 0}],
    "images": [{"uri": "textures/testcard.png"}],
    "accessors": accessors,
    "bufferViews": views,
    "buffers": [{"byteLength": len(buf), "uri": "data:application/octet-stream;base64,"
                 + base64.b64encode(bytes(buf)).decode()}],
}

with open(sys.argv[1], "w") as f:
    json.dump(doc, f, indent=1)
    f.write("\n")
