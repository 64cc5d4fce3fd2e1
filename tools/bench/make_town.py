#!/usr/bin/env python3
"""Lays out LDraw models on a grid, as Datsville places its buildings, in one MPD: a town to
measure brickcheck on (issue: a whole town, 300,000 parts).

Each model's blocks are written once, renamed so that two models' blocks never share a name,
the files a model places from its own folder (a street lamp, a minifigure, a custom part) are
written once as blocks of the town too, so that the town is one file that needs only the LDraw
library, and the town's main model places the models' main blocks, cycling through the list until the
town holds at least --parts placed parts (after flattening). Models sit --spacing LDU apart, far
enough that no two touch, each on the town's stud lattice. With --ldraw-dir and --part-info each model's lowest point is set on
the town's ground (y = 0), as each file's own is when it is checked alone.

  tools/bench/make_town.py --parts 100000 --ldraw-dir ../shared/ldraw-library \
      --part-info build/tools/bench/part-info -o town.mpd ../shared/ldraw-corpus/models.txt
"""
import argparse
import math
import os
import re
import sys


def read_blocks(path):
    """The file's blocks as [(name, lines)]; the first is the main model."""
    with open(path, encoding="utf-8", errors="replace") as f:
        lines = f.read().splitlines()
    blocks = []
    for line in lines:
        words = line.split()
        if len(words) >= 3 and words[0] == "0" and words[1].upper() == "FILE":
            blocks.append((line.split(None, 2)[2].strip(), []))
        elif blocks:
            blocks[-1][1].append(line)
        elif line.strip():
            blocks.append((os.path.basename(path), [line]))
    return blocks


def reference(line):
    """The file a type-1 line places, or None."""
    words = line.split(None, 14)
    return words[14].strip() if len(words) == 15 and words[0] == "1" else None


def local_files(blocks, folder, found):
    """Adds to `found` (lower-case reference -> (blocks, whether a part)) every file the blocks place from `folder`
    (LDraw looks in the model's own folder before the library), and those such files place, with
    their own submodels renamed apart as "<file>_<submodel>"."""
    listing = {name.lower(): name for name in os.listdir(folder)}
    names = {name.lower() for name, _ in blocks}
    for _, body in blocks:
        for line in body:
            ref = reference(line)
            if ref is None:
                continue
            key = ref.replace("\\", "/").lower()
            if key in names or ref.lower() in found or key not in listing:
                continue
            file_blocks = read_blocks(os.path.join(folder, listing[key]))
            if not file_blocks:
                continue
            file_blocks = renamed(file_blocks, ref + "_", main_name=ref)
            found[ref.lower()] = (file_blocks, says_part(file_blocks[0][1]))
            local_files(file_blocks, folder, found)


def says_part(body):
    """Whether a file's header names it a part (LDraw's !LDRAW_ORG), which a town places whole."""
    for line in body[:20]:
        org = line.lower().partition("!ldraw_org")
        if org[1]:
            return any(kind in org[2] for kind in ("part", "primitive", "shortcut"))
    return False


def part_count(blocks):
    """Placed parts of the main block, flattened (a block placed twice counts twice)."""
    by_name = {name.lower(): body for name, body in blocks}
    counts = {}

    def count(name, depth):
        key = name.lower()
        if key in counts:
            return counts[key]
        if depth > 64:
            return 0
        total = 0
        for line in by_name[key]:
            ref = reference(line)
            if ref is None:
                continue
            total += count(ref, depth + 1) if ref.lower() in by_name else 1
        counts[key] = total
        return total

    return count(blocks[0][0], 0)


def placements(blocks):
    """Every part the main block places, flattened: (part, rotation rows, position)."""
    by_name = {name.lower(): body for name, body in blocks}
    out = []

    def walk(name, rot, pos, depth):
        if depth > 64:
            return
        for line in by_name[name.lower()]:
            ref = reference(line)
            if ref is None:
                continue
            try:
                v = [float(w) for w in line.split()[2:14]]
            except ValueError:
                continue
            r = [v[3:6], v[6:9], v[9:12]]
            world_rot = [[sum(rot[i][k] * r[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
            world_pos = [pos[i] + sum(rot[i][k] * v[k] for k in range(3)) for i in range(3)]
            if ref.lower() in by_name:
                walk(ref, world_rot, world_pos, depth + 1)
            else:
                out.append((ref, world_rot, world_pos))

    walk(blocks[0][0], [[1, 0, 0], [0, 1, 0], [0, 0, 1]], [0, 0, 0], 0)
    return out


def part_bodies(part_info, library, parts):
    """Each part's body boxes from part-info, by the reference's name."""
    import subprocess

    names = sorted(set(parts))
    run = subprocess.run([part_info, "--ldraw-dir", library] + names, capture_output=True, text=True, errors="replace")
    bodies, current = {}, None
    for line in run.stdout.splitlines():
        if line and not line.startswith(" ") and ":" in line:
            current = line.split(":")[0].strip().lower()
            bodies[current] = []
        elif line.strip().startswith("body") and current is not None:
            spans = re.findall(r"[xyz]\s+(-?[0-9.e+]+?)\.\.(-?[0-9.e+]+)", line)
            if len(spans) == 3:
                bodies[current].append([(float(a), float(b)) for a, b in spans])
    return bodies


def lowest_point(blocks, part_info, library):
    """The lowest (largest y) point of the model's parts' bodies, or None when none is known."""
    placed = placements(blocks)
    bodies = part_bodies(part_info, library, [ref for ref, _, _ in placed])
    lowest = None
    for ref, rot, pos in placed:
        key = ref.lower()
        key = key[:-4] if key.endswith(".dat") else key
        for box in bodies.get(key, []):
            for cx in box[0]:
                for cy in box[1]:
                    for cz in box[2]:
                        y = pos[1] + rot[1][0] * cx + rot[1][1] * cy + rot[1][2] * cz
                        lowest = y if lowest is None else max(lowest, y)
    return lowest


def lattice_phase(blocks):
    """Where most of the model's parts sit across the studs (x, z modulo 20 LDU): the town puts
    every model on one lattice, as Datsville does, where alone each file has its own."""
    votes = {}
    for _, rot, pos in placements(blocks):
        if abs(abs(rot[1][1]) - 1) > 1e-6:
            continue  # not upright
        key = (round(pos[0] % 20, 2) % 20, round(pos[2] % 20, 2) % 20)
        votes[key] = votes.get(key, 0) + 1
    return max(votes, key=votes.get) if votes else (0.0, 0.0)


def renamed(blocks, prefix, main_name=None):
    """The blocks with their names, and the references to them, prefixed; the first block named
    `main_name` instead where given (a file placed by its own name)."""
    names = {name.lower() for name, _ in blocks}
    out = []
    for k, (name, body) in enumerate(blocks):
        lines = []
        for line in body:
            ref = reference(line)
            if ref is not None and ref.lower() in names:
                target = main_name if main_name and ref.lower() == blocks[0][0].lower() else prefix + ref
                head = line[: len(line) - len(line.lstrip())] + " ".join(line.split(None, 14)[:14])
                line = f"{head} {target}"
            lines.append(line)
        out.append((main_name if main_name and k == 0 else prefix + name, lines))
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("models", help="a list of model files, one per line, relative to the list")
    p.add_argument("-o", "--output", required=True, help="the town's MPD (refused if it exists)")
    p.add_argument("--parts", type=int, default=30000, help="at least this many placed parts (0: each model once)")
    p.add_argument("--spacing", type=float, default=2000, help="LDU between models' origins")
    p.add_argument("--only", default="", help="only the models whose file name starts so")
    p.add_argument("--ldraw-dir", help="with --part-info: set each model's lowest point on the ground")
    p.add_argument("--part-info", help="the part-info tool (build/tools/bench/part-info)")
    args = p.parse_args()
    if os.path.exists(args.output):
        sys.exit(f"{args.output}: exists; not overwritten")
    root = os.path.dirname(os.path.abspath(args.models))
    with open(args.models, encoding="utf-8") as f:
        files = [line.strip() for line in f if line.strip() and not line.startswith("#")]
    files = [name for name in files if os.path.basename(name).startswith(args.only)]
    models, local = [], {}
    for k, name in enumerate(files):
        path = os.path.join(root, name)
        blocks = read_blocks(path)
        if blocks:
            mine = {}
            local_files(blocks, os.path.dirname(path), mine)
            local.update(mine)
            # The files a model places whole count as parts; the others are its submodels.
            whole = blocks + [b for file_blocks, part in mine.values() if not part for b in file_blocks]
            drop = 0.0
            if args.ldraw_dir and args.part_info:
                drop = lowest_point(whole, args.part_info, args.ldraw_dir) or 0.0
            models.append((renamed(blocks, f"t{k:03d}_"), part_count(whole), drop, lattice_phase(whole)))
    if not models or sum(m[1] for m in models) == 0:
        sys.exit(f"{args.models}: no parts in its models")
    placed, total = [], 0
    if args.parts <= 0:  # each model once
        placed, total = list(range(len(models))), sum(m[1] for m in models)
    while total < args.parts:
        for k, (_, n, _, _) in enumerate(models):
            placed.append(k)
            total += n
            if total >= args.parts:
                break
    side = math.ceil(math.sqrt(len(placed)))
    with open(args.output, "x", encoding="utf-8", newline="\n") as out:
        out.write("0 FILE town.ldr\n0 A town of the corpus's models\n0 Name: town.ldr\n")
        out.write(f"0 // {len(placed)} models, {total} placed parts\n")
        for i, k in enumerate(placed):
            phase = models[k][3]
            x = (i % side) * args.spacing - phase[0]
            z = (i // side) * args.spacing - phase[1]
            y = -models[k][2]  # its lowest point on the town's ground, y = 0
            out.write(f"1 16 {x:g} {y:g} {z:g} 1 0 0 0 1 0 0 0 1 {models[k][0][0][0]}\n")
        for k in sorted(set(placed)):
            for name, body in models[k][0]:
                out.write(f"0 FILE {name}\n")
                out.write("\n".join(body) + "\n")
        for file_blocks, _ in local.values():
            for name, body in file_blocks:
                out.write(f"0 FILE {name}\n")
                out.write("\n".join(body) + "\n")
    print(f"{args.output}: {len(placed)} models, {total} placed parts")


if __name__ == "__main__":
    main()
