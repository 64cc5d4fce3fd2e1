#!/usr/bin/env python3
"""Writes the sample meshes in samples/ (run from anywhere; standard library only).

- table.obj: a long top on four legs, in millimetres on the LEGO grid (--scale 1 gives one
  voxel per stud and brick). With a weight on it, its first layout is unstable: the middle of
  the span hangs on the seams of the top, and the refinement has to stagger them.
- globe.ply: a sphere with painted continents as vertex colours, on a small stand.
- crate.obj (+ crate.mtl, crate.png): a box textured with planks and a red band, for texture
  colours.
"""
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "samples")
STUD, BRICK = 8.0, 9.6  # mm


def box(x0, y0, z0, x1, y1, z1):
    """Vertices and outward-facing quads of an axis-aligned box."""
    v = [(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)]
    # index = 4*ix + 2*iy + iz
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return v, faces


def write_obj(path, boxes, header):
    with open(path, "w") as f:
        f.write(header)
        base = 1
        for b in boxes:
            v, faces = box(*b)
            for p in v:
                f.write("v %.3f %.3f %.3f\n" % p)
            for q in faces:
                f.write("f %s\n" % " ".join(str(base + i) for i in q))
            base += len(v)


def on_grid(x0, y0, z0, x1, y1, z1):
    """A box of whole studs and bricks, shrunk by a tenth of a millimetre so that no face lies
    on a voxel boundary; faces on the model's minimum planes stay, as the grid starts there."""
    e = 0.1
    lo = [c + (e if c > 0 else 0) for c in (x0 * STUD, y0 * BRICK, z0 * STUD)]
    hi = [c - e for c in (x1 * STUD, y1 * BRICK, z1 * STUD)]
    return (*lo, *hi)


def long_table():
    # Four 2x2 legs under a long top two bricks thick: the middle of the span hangs on the
    # seams between the top's bricks.
    top_w, top_d, top_h, leg, leg_h = 36, 8, 2, 2, 5  # studs, studs, bricks, studs, bricks
    legs = [on_grid(x, 0, z, x + leg, leg_h, z + leg)
            for x in (0, top_w - leg) for z in (0, top_d - leg)]
    top = on_grid(0, leg_h, 0, top_w, leg_h + top_h, top_d)
    write_obj(os.path.join(OUT, "table.obj"), legs + [top],
              "# A long table on the LEGO grid, millimetres (legolize --scale 1).\n"
              "# Written by tools/make_samples.py.\n")


def continent(lat, lon):
    """A made-up but recognisable world: blobs of land by latitude and longitude (degrees)."""
    blobs = [(50, 10, 25), (10, 20, 30), (-20, 25, 20), (45, 90, 35), (20, 80, 15),
             (-25, 135, 15), (45, -100, 30), (15, -90, 12), (-15, -60, 22), (72, -40, 12)]
    for la, lo, r in blobs:
        d = math.degrees(math.acos(max(-1, min(1, math.sin(math.radians(lat)) * math.sin(math.radians(la)) +
                                               math.cos(math.radians(lat)) * math.cos(math.radians(la)) *
                                               math.cos(math.radians(lon - lo))))))
        if d < r:
            return True
    return False


def globe():
    rows, cols, r = 48, 96, 1.0
    verts, colors, faces = [], [], []
    for i in range(rows + 1):
        lat = 90 - 180 * i / rows
        for j in range(cols):
            lon = -180 + 360 * j / cols
            la, lo = math.radians(lat), math.radians(lon)
            verts.append((r * math.cos(la) * math.cos(lo), 1.35 + r * math.sin(la), r * math.cos(la) * math.sin(lo)))
            if abs(lat) > 70:
                colors.append((244, 244, 244))  # ice
            elif continent(lat, lon):
                colors.append((0, 133, 43) if abs(lat) < 45 else (215, 186, 140))
            else:
                colors.append((30, 90, 168))  # sea
    for i in range(rows):
        for j in range(cols):
            a, b = i * cols + j, i * cols + (j + 1) % cols
            c, d = a + cols, b + cols
            faces.append((a, c, d, b))
    # A stand: a short post and a foot, brown.
    base = len(verts)
    stand = []
    for b in [(-0.15, 0.2, -0.15, 0.15, 0.45, 0.15), (-0.6, 0.0, -0.6, 0.6, 0.2, 0.6)]:
        v, fs = box(*b)
        off = len(verts)
        verts += v
        colors += [(95, 49, 9)] * len(v)
        faces += [tuple(off + k for k in q) for q in fs]
    del base, stand
    with open(os.path.join(OUT, "globe.ply"), "w") as f:
        f.write("ply\nformat ascii 1.0\ncomment A globe with painted continents, written by "
                "tools/make_samples.py\n")
        f.write("element vertex %d\nproperty float x\nproperty float y\nproperty float z\n" % len(verts))
        f.write("property uchar red\nproperty uchar green\nproperty uchar blue\n")
        f.write("element face %d\nproperty list uchar int vertex_indices\nend_header\n" % len(faces))
        for p, c in zip(verts, colors):
            f.write("%.5f %.5f %.5f %d %d %d\n" % (p + c))
        for q in faces:
            f.write("%d %s\n" % (len(q), " ".join(map(str, q))))


def png(path, w, h, pixel):
    raw = b"".join(b"\x00" + bytes(c for x in range(w) for c in pixel(x, y)) for y in range(h))
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def crate():
    def pixel(x, y):
        if 26 <= y < 38:
            return (180, 0, 0)  # a red band around the crate
        return (215, 186, 140) if (x // 16) % 2 else (137, 125, 98)  # planks, tan and dark tan
    png(os.path.join(OUT, "crate.png"), 64, 64, pixel)
    with open(os.path.join(OUT, "crate.mtl"), "w") as f:
        f.write("# Written by tools/make_samples.py\nnewmtl wood\nKd 1 1 1\nmap_Kd crate.png\n")
    v, faces = box(0, 0, 0, 1, 1, 1)
    # One texture square per face: u along the face's first edge, v along its second.
    with open(os.path.join(OUT, "crate.obj"), "w") as f:
        f.write("# A textured crate, written by tools/make_samples.py\nmtllib crate.mtl\nusemtl wood\n")
        for p in v:
            f.write("v %g %g %g\n" % p)
        f.write("vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n")
        for q in faces:
            # Keep the band horizontal on the side faces: v runs up the crate.
            ys = [v[i][1] for i in q]
            uv = [1, 2, 3, 4]
            if len(set(ys)) == 2:
                start = min(range(4), key=lambda k: (ys[k], ys[(k + 1) % 4] == ys[k] and 0 or 1))
                uv = [[1, 2, 3, 4][(k - start) % 4] for k in range(4)]
                if ys[(start + 1) % 4] != ys[start]:
                    uv = [[1, 4, 3, 2][(k - start) % 4] for k in range(4)]
            f.write("f %s\n" % " ".join("%d/%d" % (i + 1, t) for i, t in zip(q, uv)))


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    long_table()
    globe()
    crate()
