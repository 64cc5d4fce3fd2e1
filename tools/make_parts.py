#!/usr/bin/env python3
"""Draws our LDraw part files from ldraw_parts/catalog.csv (the single source of part sizes).

Each part is a closed box body with its origin at the top centre (LDraw: -y is up, the body spans
y = 0 .. height*8), knobs placed through our own stud primitive p/stud.dat, BFC-certified CCW
(the right-hand normal of every polygon points out of the body).
Run it after editing the catalog; the generated files are committed.
"""
import csv
import math
import os
import sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "ldraw_parts")
HEADER = """0 {title}
0 Name: {name}
0 Author: legolization project
0 !LDRAW_ORG Unofficial_{kind}
0 !LICENSE Licensed under CC BY 4.0 : see the legolization README

0 BFC CERTIFY CCW

"""


def fmt(v):
    s = f"{v:.4f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def oriented(points, outward):
    """Returns the polygon with its vertex order such that its right-hand normal points outward."""
    a, b, c = points[0], points[1], points[2]
    u = [b[i] - a[i] for i in range(3)]
    v = [c[i] - a[i] for i in range(3)]
    n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    if sum(n[i] * outward[i] for i in range(3)) < 0:
        return list(reversed(points))
    return points


def poly(points, outward, color=16):
    pts = oriented(points, outward)
    kind = len(pts)
    return f"{kind} {color} " + " ".join(fmt(c) for p in pts for c in p) + "\n"


def box_lines(x, y0, y1, z):
    """A closed box |x'| <= x, y0 <= y' <= y1, |z'| <= z with edges."""
    out = []
    out.append(poly([(-x, y0, -z), (x, y0, -z), (x, y0, z), (-x, y0, z)], (0, -1, 0)))
    out.append(poly([(-x, y1, -z), (x, y1, -z), (x, y1, z), (-x, y1, z)], (0, 1, 0)))
    out.append(poly([(-x, y0, -z), (x, y0, -z), (x, y1, -z), (-x, y1, -z)], (0, 0, -1)))
    out.append(poly([(-x, y0, z), (x, y0, z), (x, y1, z), (-x, y1, z)], (0, 0, 1)))
    out.append(poly([(-x, y0, -z), (-x, y0, z), (-x, y1, z), (-x, y1, -z)], (-1, 0, 0)))
    out.append(poly([(x, y0, -z), (x, y0, z), (x, y1, z), (x, y1, -z)], (1, 0, 0)))
    corners = [(-x, -z), (x, -z), (x, z), (-x, z)]
    for i in range(4):
        (ax, az), (bx, bz) = corners[i], corners[(i + 1) % 4]
        for yy in (y0, y1):
            out.append(f"2 24 {fmt(ax)} {fmt(yy)} {fmt(az)} {fmt(bx)} {fmt(yy)} {fmt(bz)}\n")
        out.append(f"2 24 {fmt(ax)} {fmt(y0)} {fmt(az)} {fmt(ax)} {fmt(y1)} {fmt(az)}\n")
    return out


def stud():
    """Knob: radius 6 LDU, 4 LDU tall, standing on y = 0 (like the LDraw standard stud)."""
    seg = 16
    ring = [(6 * math.cos(2 * math.pi * i / seg), 6 * math.sin(2 * math.pi * i / seg)) for i in range(seg)]
    out = [HEADER.format(title="Stud", name="stud.dat", kind="Primitive")]
    for i in range(seg):
        (ax, az), (bx, bz) = ring[i], ring[(i + 1) % seg]
        mid = ((ax + bx) / 2, 0, (az + bz) / 2)
        out.append(poly([(ax, 0, az), (bx, 0, bz), (bx, -4, bz), (ax, -4, az)], mid))
        out.append(poly([(0, -4, 0), (ax, -4, az), (bx, -4, bz)], (0, -1, 0)))
        out.append(f"2 24 {fmt(ax)} -4 {fmt(az)} {fmt(bx)} -4 {fmt(bz)}\n")
        out.append(f"2 24 {fmt(ax)} 0 {fmt(az)} {fmt(bx)} 0 {fmt(bz)}\n")
    return "".join(out)


def part(row):
    length, width, height = int(row["length"]), int(row["width"]), int(row["height"])
    hx, hz, h = length * 10, width * 10, height * 8
    out = [HEADER.format(title=row["name"], name=row["part"] + ".dat", kind="Part")]
    out += box_lines(hx, 0, h, hz)
    out.append("\n")
    for i in range(length):
        for j in range(width):
            x, z = -hx + 10 + 20 * i, -hz + 10 + 20 * j
            out.append(f"1 16 {fmt(x)} 0 {fmt(z)} 1 0 0 0 1 0 0 0 1 stud.dat\n")
    return "".join(out)


def main():
    with open(os.path.join(ROOT, "catalog.csv"), newline="") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    os.makedirs(os.path.join(ROOT, "parts"), exist_ok=True)
    os.makedirs(os.path.join(ROOT, "p"), exist_ok=True)
    with open(os.path.join(ROOT, "p", "stud.dat"), "w") as f:
        f.write(stud())
    for row in rows:
        with open(os.path.join(ROOT, "parts", row["part"] + ".dat"), "w") as f:
            f.write(part(row))
    print(f"wrote {len(rows)} parts and p/stud.dat", file=sys.stderr)


if __name__ == "__main__":
    main()
