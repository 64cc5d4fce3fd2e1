#!/usr/bin/env python3
"""Writes the paper's Figure 7 bridges and the keystone arch as LDraw files (committed output).

Lattice: x in studs, y in plates up; LDraw: origin at a part's top centre, -y up.
Floor: a column of two 1x3 bricks (3622); 1x8 bricks (3008) end to end on it, holding the first
by 3 knobs; a 1x2 (3004) under (variant a) or over (variant b) each joint.
"""
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def line(color, part, x0, y0, length, z0=0, width=1, height=3):
    cx = 20 * x0 + 10 * length
    cz = 20 * z0 + 10 * width
    top = -8 * (y0 + height)
    return f"1 {color} {cx} {top} {cz} 1 0 0 0 1 0 0 0 1 {part}.dat\n"


def bridge(n, variant):
    out = [f"0 Figure 7 bridge ({variant}), {n} 1x8 bricks\n", f"0 Name: bridge-{variant}-{n:02}.ldr\n",
           "0 Author: legolization tests\n", "0 !LDRAW_ORG Unofficial_Model\n\n"]
    out.append(line(4, "3622", 0, 0, 3))
    out.append(line(4, "3622", 0, 3, 3))
    for k in range(n):
        out.append(line(14, "3008", 8 * k, 6, 8))
    for k in range(1, n):
        out.append(line(4, "3004", 8 * k - 1, 3 if variant == "a" else 9, 2))
    return "".join(out)


def arch(spans=6):
    """A bridge of variant (a) between two pillars: the last 1x8 closes it like a keystone."""
    out = ["0 Arch closed by its keystone in the last step\n", "0 Name: arch-keystone.ldr\n",
           "0 Author: legolization tests\n", "0 !LDRAW_ORG Unofficial_Model\n\n"]
    end = 8 * spans
    for y in (0, 3):
        out.append(line(4, "3622", 0, y, 3))
        out.append(line(4, "3622", end - 3, y, 3))
    out.append("0 STEP\n")
    out.append(line(14, "3008", 0, 6, 8))
    out.append("0 STEP\n")
    for k in range(1, spans):
        out.append(line(4, "3004", 8 * k - 1, 3, 2))
        out.append(line(14 if k < spans - 1 else 1, "3008", 8 * k, 6, 8))
        out.append("0 STEP\n")
    return "".join(out)


def main():
    for variant in "ab":
        for n in range(1, 13):
            with open(os.path.join(HERE, "bridges", f"bridge-{variant}-{n:02}.ldr"), "w") as f:
                f.write(bridge(n, variant))
    with open(os.path.join(HERE, "arch-keystone.ldr"), "w") as f:
        f.write(arch())


if __name__ == "__main__":
    main()
