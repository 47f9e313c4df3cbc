#!/usr/bin/env python3
"""Seeded random LinuxCNC lathe programs with tool nose radius compensation (G41/G42/G40)
for rs274 as the oracle (issue 27): contours of G0/G1 lines and G2/G3 arcs (I/K centres)
entered with G41 or G42 (optionally `D` naming another tool table entry), left with G40,
for tools of every orientation (0 to 9) and several nose radii (`tool.tbl`), in diameter
(G7) and radius (G8) mode. Corners turn both ways (inner corners meet at the offset paths'
intersection, outer ones go round on an arc); some contours are meant to gouge, so that
rs274's refusals are tested too.

Every length is in mm x 1000 (rs274 prints 4 decimals), the nose radii too: `tool.tbl` is
in inches (rs274's standalone tool table), so a radius r mm is written as the diameter
`2 r 1000 / 25.4`.

Run: `python3 gen.py` (writes `nose-NN.ngc` and `tool.tbl`), then `./regen.sh`."""
import math
import random

SEED = 2701
COUNT = 48
# (tool, radius mm, orientation): every orientation, radii from 0.2 to 1.6 mm.
TOOLS = [(1, 0.4, 3), (2, 0.8, 2), (3, 0.2, 1), (4, 1.2, 4), (5, 0.4, 5), (6, 0.8, 6),
         (7, 0.4, 7), (8, 1.6, 8), (9, 0.4, 9), (10, 0.8, 0), (11, 0.4, 2), (12, 0.8, 3)]
S = 1000.0


def fmt(v):
    return "%.4f" % v


def tool_table():
    lines = []
    for t, r, q in TOOLS:
        lines.append("T%d P%d D%.12f Q%d ;r %s mm x1000" % (t, t, 2 * r * S / 25.4, q, r))
    return "\n".join(lines) + "\n"


def program(rng, n):
    diameter = rng.random() < 0.5
    xs = 2.0 if diameter else 1.0
    tool, r, _ = rng.choice(TOOLS)
    side = rng.choice(["G41", "G42"])
    d_word = ""
    comp_r = r
    if rng.random() < 0.25:
        other = rng.choice(TOOLS)
        d_word = " D%d" % other[0]
        comp_r = other[1]
    lines = ["(nose-%02d: gen.py, seed %d)" % (n, SEED),
             "G18 G21 %s G90 G94" % ("G7" if diameter else "G8"),
             "T%d M6" % tool]
    # Points in (z, radius), mm. Start well away, enter, then a contour.
    z, x = 10.0, rng.uniform(25.0, 40.0)
    lines.append("G0 X%s Z%s" % (fmt(xs * x * S), fmt(z * S)))
    # The entry: longer than the radius (or, now and then, not: rs274 refuses it).
    short = rng.random() < 0.04
    entry = rng.uniform(0.3, 0.9) * comp_r if short else rng.uniform(3.0, 8.0)
    ang = rng.uniform(0, 2 * math.pi)
    z, x = z + entry * math.cos(ang), x + entry * math.sin(ang)
    g = rng.choice(["G0", "G1"])
    lines.append("%s%s %s X%s Z%s F1000" % (side, d_word, g, fmt(xs * x * S), fmt(z * S)))
    # Direction of travel (rad), turning by up to +-150 deg at a corner.
    heading = rng.uniform(0, 2 * math.pi)
    for k in range(rng.randint(3, 8)):
        turn = rng.uniform(-2.6, 2.6)
        if rng.random() < 0.15:
            turn = 0.0  # tangent (line after line)
        heading += turn
        length = rng.uniform(2.0, 9.0) * max(comp_r, 0.5)
        kind = rng.random()
        if kind < 0.35:
            # An arc: the chord along `heading`, bulging either way (sagitta a share of it).
            h = rng.uniform(0.1, 0.45) * length * rng.choice([-1, 1])
            cz, cx = math.cos(heading), math.sin(heading)
            ez, ex = z + length * cz, x + length * cx
            mz, mx = (z + ez) / 2, (x + ex) / 2
            nz, nx = -cx, cz  # left normal of the chord
            half = length / 2
            rad = (half * half + h * h) / (2 * abs(h))
            # The centre on the normal through the middle, opposite the bulge.
            pz = mz + nz * h
            px = mx + nx * h
            sgn = 1 if h > 0 else -1
            oz, ox = pz - nz * rad * sgn, px - nx * rad * sgn
            # Counter-clockwise (G3) when the bulge is to the right of the chord.
            ccw = h < 0
            lines.append("%s X%s Z%s I%s K%s" % ("G3" if ccw else "G2", fmt(xs * ex * S),
                                               fmt(ez * S), fmt((ox - x) * S),
                                               fmt((oz - z) * S)))
            # The direction at the end: tangent of the arc there.
            rz, rx = ez - oz, ex - ox
            heading = math.atan2(rz, -rx) if ccw else math.atan2(-rz, rx)
            z, x = ez, ex
        else:
            z, x = z + length * math.cos(heading), x + length * math.sin(heading)
            g = "G0" if rng.random() < 0.15 else "G1"
            lines.append("%s X%s Z%s" % (g, fmt(xs * x * S), fmt(z * S)))
    # The exit: G40 with a straight move away.
    away = rng.uniform(3.0, 8.0)
    ang = rng.uniform(0, 2 * math.pi)
    z, x = z + away * math.cos(ang), x + away * math.sin(ang)
    lines.append("G40 %s X%s Z%s" % (rng.choice(["G0", "G1"]), fmt(xs * x * S), fmt(z * S)))
    lines.append("M2")
    return "\n".join(lines) + "\n"


def main():
    rng = random.Random(SEED)
    with open("tool.tbl", "w") as f:
        f.write(tool_table())
    for n in range(COUNT):
        with open("nose-%02d.ngc" % n, "w") as f:
            f.write(program(rng, n))


main()
