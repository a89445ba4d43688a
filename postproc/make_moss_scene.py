#!/usr/bin/env python3
"""Write the moss paper's scene (spec moss.md chapter 4): a 2 m x 2 m land model, 1.5 m high with
its roof, relief and all three soil types, and a light-blocking roof at the back.

    python3 postproc/make_moss_scene.py input/moss        # writes scene.obj, scene.mtl, soil.png

Frame: +y up, x to the right, +z towards the viewer (front), the back is z = 0.
  ground block  x, z in [0, 2], bottom y = 0, top y = 0.25 + relief (a 40 x 40 grid, 5 cm)
  back wall     x in [0, 2], z in [0, 0.05], y in [0, 1.5]
  roof          x in [0, 2], z in [0, 0.7], y in [1.45, 1.5]
Soil by texture colour (soil.png on the ground top): humus (dark brown #5c3317) for x < 1.2,
sand (ochre #cc9933) for x >= 1.2, an asphalt path (grey #808080) for 1.55 <= x < 1.8.
The sides of the ground block are humus by their material colour (Kd); wall and roof are asphalt.
Pure Python (no numpy): PNG written with zlib."""
import math
import os
import struct
import sys
import zlib

HUMUS = (0x5C, 0x33, 0x17)
SAND = (0xCC, 0x99, 0x33)
ASPHALT = (0x80, 0x80, 0x80)
N = 40          # ground grid cells per side
SIZE = 2.0      # m
TEX = 80        # texture pixels per side (2.5 cm)


def soil_at(x, z):
    if 1.55 <= x < 1.8:
        return ASPHALT
    return HUMUS if x < 1.2 else SAND


def height(x, z):
    """Ground top: base 0.25 m, a 12 cm mound front left, a 6 cm hollow front right, gentle waves."""
    mound = 0.12 * math.exp(-((x - 0.6) ** 2 + (z - 1.4) ** 2) / 0.08)
    hollow = -0.06 * math.exp(-((x - 1.45) ** 2 + (z - 1.5) ** 2) / 0.05)
    waves = 0.015 * math.sin(3 * math.pi * x) * math.sin(2 * math.pi * z)
    return 0.25 + mound + hollow + waves


def write_png(path, w, h, pixel):
    raw = b"".join(b"\x00" + bytes(c for i in range(w) for c in pixel(i, j)) for j in range(h))
    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


class Obj:
    def __init__(self):
        self.v, self.vt, self.lines = [], [], []

    def vert(self, x, y, z):
        self.v.append((x, y, z))
        return len(self.v)

    def tex(self, u, v):
        self.vt.append((u, v))
        return len(self.vt)

    def box(self, lo, hi):
        """Closed axis-aligned box, outward normals (counter-clockwise seen from outside)."""
        c = {}
        for i in (0, 1):
            for j in (0, 1):
                for k in (0, 1):
                    c[i, j, k] = self.vert(*(hi[d] if s else lo[d] for d, s in enumerate((i, j, k))))
        quads = [((0, 0, 0), (0, 0, 1), (0, 1, 1), (0, 1, 0)), ((1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1)),
                 ((0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)), ((0, 1, 0), (0, 1, 1), (1, 1, 1), (1, 1, 0)),
                 ((0, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 0)), ((0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1))]
        for q in quads:
            a, b, cc, d = (c[p] for p in q)
            self.lines += [f"f {a} {b} {cc}", f"f {a} {cc} {d}"]


def main(outdir):
    os.makedirs(outdir, exist_ok=True)
    write_png(os.path.join(outdir, "soil.png"), TEX, TEX,
              lambda i, j: soil_at((i + 0.5) / TEX * SIZE, (j + 0.5) / TEX * SIZE))
    with open(os.path.join(outdir, "scene.mtl"), "w") as f:
        f.write("# moss paper scene materials (postproc/make_moss_scene.py)\n")
        f.write("newmtl ground\nKd 1 1 1\nmap_Kd soil.png\n\n")
        f.write("newmtl ground_side\nKd %.6f %.6f %.6f\n\n" % tuple(c / 255 for c in HUMUS))
        f.write("newmtl asphalt\nKd %.6f %.6f %.6f\n" % tuple(c / 255 for c in ASPHALT))
    o = Obj()
    o.lines += ["o ground", "usemtl ground"]
    top = [[0] * (N + 1) for _ in range(N + 1)]
    uv = [[0] * (N + 1) for _ in range(N + 1)]
    for i in range(N + 1):
        for k in range(N + 1):
            x, z = SIZE * i / N, SIZE * k / N
            top[i][k] = o.vert(x, height(x, z), z)
            # Texture rows go down the image: pixel row j is z; OBJ v is up, so v = 1 - z / SIZE.
            uv[i][k] = o.tex(x / SIZE, 1 - z / SIZE)
    for i in range(N):
        for k in range(N):
            a, b, c, d = top[i][k], top[i][k + 1], top[i + 1][k + 1], top[i + 1][k]
            ta, tb, tc, td = uv[i][k], uv[i][k + 1], uv[i + 1][k + 1], uv[i + 1][k]
            o.lines += [f"f {a}/{ta} {b}/{tb} {c}/{tc}", f"f {a}/{ta} {c}/{tc} {d}/{td}"]
    o.lines += ["usemtl ground_side"]
    bottom = {(i, k): o.vert(SIZE * i, 0.0, SIZE * k) for i in (0, 1) for k in (0, 1)}
    o.lines.append(f"f {bottom[0, 0]} {bottom[1, 0]} {bottom[1, 1]}")
    o.lines.append(f"f {bottom[0, 0]} {bottom[1, 1]} {bottom[0, 1]}")
    sides = [([top[i][0] for i in range(N + 1)], [SIZE * i / N for i in range(N + 1)], "z0"),
             ([top[i][N] for i in range(N + 1)], [SIZE * i / N for i in range(N + 1)], "z1"),
             ([top[0][k] for k in range(N + 1)], [SIZE * k / N for k in range(N + 1)], "x0"),
             ([top[N][k] for k in range(N + 1)], [SIZE * k / N for k in range(N + 1)], "x1")]
    for ring, coord, side in sides:
        low = [o.vert(*((c, 0.0, 0.0) if side == "z0" else (c, 0.0, SIZE) if side == "z1"
                        else (0.0, 0.0, c) if side == "x0" else (SIZE, 0.0, c))) for c in coord]
        for m in range(N):
            a, b, c, d = low[m], low[m + 1], ring[m + 1], ring[m]
            # Outward: -z for z0 and +x for x1 wind one way, the other two the other way.
            if side in ("z0", "x1"):
                o.lines += [f"f {a} {d} {c}", f"f {a} {c} {b}"]
            else:
                o.lines += [f"f {a} {b} {c}", f"f {a} {c} {d}"]
    o.lines += ["o back_wall", "usemtl asphalt"]
    o.box((0.0, 0.0, 0.0), (SIZE, 1.5, 0.05))
    o.lines += ["o roof", "usemtl asphalt"]
    o.box((0.0, 1.45, 0.0), (SIZE, 1.5, 0.7))
    with open(os.path.join(outdir, "scene.obj"), "w") as f:
        f.write("# moss paper scene, +y up (postproc/make_moss_scene.py)\nmtllib scene.mtl\n")
        f.writelines("v %.6f %.6f %.6f\n" % v for v in o.v)
        f.writelines("vt %.6f %.6f\n" % t for t in o.vt)
        f.write("\n".join(o.lines) + "\n")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "input/moss")
