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
COUNT = 96
# (tool, radius mm, orientation): every orientation, radii from 0.2 to 1.6 mm.
TOOLS = [(1, 0.4, 3), (2, 0.8, 2), (3, 0.2, 1), (4, 1.2, 4), (5, 0.4, 5), (6, 0.8, 6),
         (7, 0.4, 7), (8, 1.6, 8), (9, 0.4, 9), (10, 0.8, 0), (11, 0.4, 2), (12, 0.8, 3)]
S = 1000.0


def tool_table():
    lines = []
    for t, r, q in TOOLS:
        lines.append("T%d P%d D%.12f Q%d ;r %s mm x1000" % (t, t, 2 * r * S / 25.4, q, r))
    return "\n".join(lines) + "\n"


# Rational rotations (p, q): cos = (p^2 - q^2)/(p^2 + q^2), sin = 2pq/(p^2 + q^2); an arc
# whose start and end are integer vectors from its centre rotated by one has both ends on
# the 1e-4 grid rs274's programs are written in and exactly on its circle (rs274 offsets an
# arc by its radius at the end, the start lying on another within the arc tolerance).
ROTATIONS = [(2, 1), (3, 1), (3, 2), (4, 1), (5, 2), (1, 1), (4, 3), (1, 2), (2, 3)]


def tick(v):
    """Ticks of 1e-4 (of the scaled unit) as a program number."""
    return "%.4f" % (v / 10000.0)


def program(rng, n):
    diameter = rng.random() < 0.5
    xs = 2 if diameter else 1
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
    mm = S * 10000.0  # ticks per mm
    # Points in (z, radius), ticks. Start well away, enter, then a contour.
    z, x = int(10 * mm), int(rng.uniform(25.0, 40.0) * mm)
    pt = lambda: "X%s Z%s" % (tick(xs * x), tick(z))
    lines.append("G0 " + pt())
    # The entry: longer than the radius (or, now and then, not: rs274 refuses it).
    short = rng.random() < 0.04
    entry = (rng.uniform(0.3, 0.9) * comp_r if short else rng.uniform(3.0, 8.0)) * mm
    ang = rng.uniform(0, 2 * math.pi)
    z, x = z + round(entry * math.cos(ang)), x + round(entry * math.sin(ang))
    g = rng.choice(["G0", "G1"])
    lines.append("%s%s %s %s F1000" % (side, d_word, g, pt()))
    # Direction of travel (rad), turning by up to +-150 deg at a corner.
    heading = rng.uniform(0, 2 * math.pi)
    for k in range(rng.randint(3, 8)):
        turn = rng.uniform(-2.6, 2.6)
        if rng.random() < 0.15:
            turn = 0.0  # tangent (line after line)
        heading += turn
        size = rng.uniform(2.0, 9.0) * max(comp_r, 0.5) * mm
        if rng.random() < 0.35:
            # An arc starting along `heading`: the centre to its left (G3) or right (G2),
            # the end the start rotated about it by a rational rotation.
            ccw = rng.random() < 0.5
            p, q = rng.choice(ROTATIONS)
            m = p * p + q * q
            c, s_ = p * p - q * q, 2 * p * q
            side_n = 1 if ccw else -1
            a = round(size / m * -math.sin(heading) * side_n)
            b = round(size / m * math.cos(heading) * side_n)
            wz, wx = a * m, b * m  # centre - start
            uz, ux = -wz, -wx  # start - centre
            if not ccw:
                s_ = -s_
            vz, vx = c * uz - s_ * ux, s_ * uz + c * ux  # (end - centre) m
            cz, cx = z + wz, x + wx
            ez, ex = cz + vz // m, cx + vx // m
            assert vz % m == 0 and vx % m == 0
            lines.append("%s X%s Z%s I%s K%s" % ("G3" if ccw else "G2", tick(xs * ex), tick(ez),
                                               tick(wx), tick(wz)))
            heading += math.atan2(s_, c)
            z, x = ez, ex
        else:
            z, x = z + round(size * math.cos(heading)), x + round(size * math.sin(heading))
            g = "G0" if rng.random() < 0.15 else "G1"
            lines.append("%s %s" % (g, pt()))
    # The exit: G40 with a straight move away.
    away = rng.uniform(3.0, 8.0) * mm
    ang = rng.uniform(0, 2 * math.pi)
    z, x = z + round(away * math.cos(ang)), x + round(away * math.sin(ang))
    lines.append("G40 %s %s" % (rng.choice(["G0", "G1"]), pt()))
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
