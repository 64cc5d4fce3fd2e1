#!/usr/bin/env python3
"""Writes tests/data/library: a tiny LDraw library drawn the way the official one draws parts
(hollow undersides with a rim, a ceiling, tubes and pins), for tests that run without ../shared.
Run from tests/data: python3 make_library.py"""
import os

HEADER = "0 {title}\n0 Name: {name}\n0 Author: legolization tests\n0 !LDRAW_ORG {org}\n\n"


def quad(a, b, c, d):
    return "4 16 " + " ".join(f"{v:g}" for p in (a, b, c, d) for v in p) + "\n"


def box_faces(x0, x1, y0, y1, z0, z1):
    """The six faces of an axis-aligned box."""
    return (quad((x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)) +
            quad((x0, y1, z1), (x1, y1, z1), (x1, y1, z0), (x0, y1, z0)) +
            quad((x0, y1, z0), (x1, y1, z0), (x1, y0, z0), (x0, y0, z0)) +
            quad((x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)) +
            quad((x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)) +
            quad((x1, y1, z0), (x1, y1, z1), (x1, y0, z1), (x1, y0, z0)))


def hollow(x0, x1, z0, z1, height, wall=4, ceiling=4):
    """A body open at the bottom: top, outer walls, the rim, inner walls, the ceiling."""
    h = height
    out = quad((x0, 0, z0), (x1, 0, z0), (x1, 0, z1), (x0, 0, z1))
    out += quad((x0, h, z0), (x1, h, z0), (x1, 0, z0), (x0, 0, z0))
    out += quad((x0, 0, z1), (x1, 0, z1), (x1, h, z1), (x0, h, z1))
    out += quad((x0, 0, z0), (x0, 0, z1), (x0, h, z1), (x0, h, z0))
    out += quad((x1, h, z0), (x1, h, z1), (x1, 0, z1), (x1, 0, z0))
    i0, i1, k0, k1 = x0 + wall, x1 - wall, z0 + wall, z1 - wall
    out += quad((x0, h, z0), (x1, h, z0), (i1, h, k0), (i0, h, k0))  # rim
    out += quad((x1, h, z0), (x1, h, z1), (i1, h, k1), (i1, h, k0))
    out += quad((x1, h, z1), (x0, h, z1), (i0, h, k1), (i1, h, k1))
    out += quad((x0, h, z1), (x0, h, z0), (i0, h, k0), (i0, h, k1))
    out += quad((i0, ceiling, k0), (i1, ceiling, k0), (i1, h, k0), (i0, h, k0))  # inner walls
    out += quad((i0, h, k1), (i1, h, k1), (i1, ceiling, k1), (i0, ceiling, k1))
    out += quad((i0, h, k0), (i0, h, k1), (i0, ceiling, k1), (i0, ceiling, k0))
    out += quad((i1, ceiling, k0), (i1, ceiling, k1), (i1, h, k1), (i1, h, k0))
    out += quad((i0, ceiling, k1), (i1, ceiling, k1), (i1, ceiling, k0), (i0, ceiling, k0))
    return out


def ref(x, y, z, name, sy=1):
    return f"1 16 {x:g} {y:g} {z:g} 1 0 0 0 {sy:g} 0 0 0 1 {name}\n"


def studs(cells):
    return "".join(ref(x, 0, z, "stud.dat") for x, z in cells)


def diamond(radius, height):
    """A tube or pin drawn as a diamond prism from y = 0 to y = height (round enough here)."""
    r = radius
    pts = [(r, 0), (0, r), (-r, 0), (0, -r)]
    out = ""
    for i in range(4):
        (ax, az), (bx, bz) = pts[i], pts[(i + 1) % 4]
        out += quad((ax, 0, az), (bx, 0, bz), (bx, height, bz), (ax, height, az))
    return out


def write(path, title, org, body):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    name = path.split("/", 1)[1].replace("/", "\\") if path.startswith("parts/s/") else os.path.basename(path)
    with open(path, "w") as f:
        f.write(HEADER.format(title=title, name=name, org=org) + body)


os.chdir(os.path.join(os.path.dirname(os.path.abspath(__file__)), "library"))
write("p/stud.dat", "Stud", "Primitive", box_faces(-6, 6, -4, 0, -6, 6))
write("p/stud4.dat", "Stud Tube Open", "Primitive", diamond(8, 4))
write("p/stud3.dat", "Stud Tube Solid", "Primitive", diamond(4, 4))
write("p/stug-2x2.dat", "Stud Group 2 x 2", "Primitive",
      studs([(-10, -10), (-10, 10), (10, -10), (10, 10)]))
# Plate 4 x 4: stud groups on top, nine tubes under it.
write("parts/3031.dat", "Plate  4 x  4", "Part",
      hollow(-40, 40, -40, 40, 8) +
      "".join(ref(x, 0, z, "stug-2x2.dat") for x in (-20, 20) for z in (-20, 20)) +
      "".join(ref(x, 4, z, "stud4.dat") for x in (-20, 0, 20) for z in (-20, 0, 20)))
# Tile 2 x 2 with Groove: its body in a subpart, one tube, no stud.
write("parts/3068b.dat", "Tile  2 x  2 with Groove", "Part", ref(0, 0, 0, "s\\3068bs01.dat"))
write("parts/s/3068bs01.dat", "~Tile  2 x  2 body", "Subpart",
      hollow(-20, 20, -20, 20, 8) + ref(0, 4, 0, "stud4.dat"))
# Brick 2 x 2 Corner: three cells of a 2 x 2, the fourth corner open.
corner = (quad((-20, 0, -20), (20, 0, -20), (20, 0, 0), (-20, 0, 0)) +
          quad((-20, 0, 0), (0, 0, 0), (0, 0, 20), (-20, 0, 20)) +
          quad((-20, 24, -20), (20, 24, -20), (20, 0, -20), (-20, 0, -20)) +
          quad((20, 0, -20), (20, 0, 0), (20, 24, 0), (20, 24, -20)) +
          quad((20, 24, 0), (0, 24, 0), (0, 0, 0), (20, 0, 0)) +
          quad((0, 0, 0), (0, 0, 20), (0, 24, 20), (0, 24, 0)) +
          quad((0, 24, 20), (-20, 24, 20), (-20, 0, 20), (0, 0, 20)) +
          quad((-20, 0, 20), (-20, 0, -20), (-20, 24, -20), (-20, 24, 20)) +
          quad((-16, 4, -16), (16, 4, -16), (16, 4, -4), (-16, 4, -4)) +
          quad((-16, 4, -4), (-4, 4, -4), (-4, 4, 16), (-16, 4, 16)) +
          quad((-16, 24, -16), (16, 24, -16), (16, 4, -16), (-16, 4, -16)) +
          quad((16, 4, -16), (16, 4, -4), (16, 24, -4), (16, 24, -16)) +
          quad((16, 24, -4), (-4, 24, -4), (-4, 4, -4), (16, 4, -4)) +
          quad((-4, 4, -4), (-4, 4, 16), (-4, 24, 16), (-4, 24, -4)) +
          quad((-4, 24, 16), (-16, 24, 16), (-16, 4, 16), (-4, 4, 16)) +
          quad((-16, 4, 16), (-16, 4, -16), (-16, 24, -16), (-16, 24, 16)) +
          ref(0, 4, 0, "stud4.dat", 5))
write("parts/2357.dat", "Brick  2 x  2 Corner", "Part",
      corner + studs([(-10, -10), (10, -10), (-10, 10)]))
# Plate 1 x 2 with 1 Stud (a jumper): one stud in the middle, a pin under it.
write("parts/3794b.dat", "Plate  1 x  2 with 1 Stud with Groove", "Part",
      hollow(-20, 20, -10, 10, 8) + ref(0, 4, 0, "stud3.dat") + studs([(0, 0)]))
# Brick 1 x 1 with Stud on 1 Side: a stud on top and one pointing to -z, half way down.
write("parts/87087.dat", "Brick  1 x  1 with Stud on 1 Side", "Part",
      hollow(-10, 10, -10, 10, 24) + studs([(0, 0)]) +
      "1 16 0 10 -10 1 0 0 0 0 -1 0 1 0 stud.dat\n")
# Hinge Brick 1 x 2: a hinge half with studs and a cavity, carried by its name.
for part, half in (("3937", "Base"), ("3938", "Top")):
    write(f"parts/{part}.dat", f"Hinge  1 x  2 {half}", "Part",
          hollow(-20, 20, -10, 10, 24) + ref(0, 4, 0, "stud3.dat", 5) + studs([(-10, 0), (10, 0)]))
