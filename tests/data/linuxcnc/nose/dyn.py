#!/usr/bin/env python3
"""Writes dyn-NN.ngc: LinuxCNC's dynamic compensation G41.1/G42.1 D L (issue 27).

Each is nose-NN.ngc (gen.py's random contours, NN = 00..31) with every G41/G42 (and the D
word naming a tool table entry) replaced by G41.1/G42.1 with a diameter D and an
orientation L drawn here (seed 2702): radii 0.2 to 1.6 mm (program units are mm x 1000, so
D = 2 r 1000), orientations 0 to 9 (L left out now and then: rs274 takes 0), a negative D
(rs274 swaps the side) one time in five. regen.sh writes rs274's canon or error for them
as for the others.
"""
import random
import re

rng = random.Random(2702)
for n in range(32):
    src = open(f"nose-{n:02}.ngc").read().splitlines()
    out = [f"(dyn-{n:02}: dyn.py from nose-{n:02}, seed 2702)"]
    for line in src[1:]:
        m = re.search(r"\bG4([12])(?![.\d])", line)
        if m:
            r = rng.choice([0.2, 0.4, 0.8, 1.2, 1.6])
            d = 2 * r * 1000 * (-1 if rng.random() < 0.2 else 1)
            q = rng.randrange(10)
            words = f"G4{m.group(1)}.1 D{d:.0f}" + ("" if rng.random() < 0.15 else f" L{q}")
            line = re.sub(r"\s*\bD\d+\b", "", line)
            m = re.search(r"\bG4[12](?![.\d])", line)
            line = line[: m.start()] + words + line[m.end():]
        out.append(line)
    open(f"dyn-{n:02}.ngc", "w").write("\n".join(out) + "\n")
