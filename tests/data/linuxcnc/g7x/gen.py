#!/usr/bin/env python3
"""Seeded generator of random LinuxCNC G70/G71/G72 programs for the rs274 conformance tests.

Writes rand-NN.ngc: a contour subroutine (o100 sub) made of random straight and circular
segments (G1, G0 read as G1, G2/G3 with I/K incremental or absolute (G90.1) or R), words X/Z
or the increments U/W, fillets A and chamfers C at corners, pockets (the depth going back
and forth), and a program that roughs it with G71/G72 (pockets), G7x.1 (none) then G7x.2
(from the first pocket), and finishes it with G70 (D, E, P passes). Contours are drawn in a
frame (p along the passes, q the depth) then mirrored onto the part: G71 turning and G72
facing, outside and inside, towards -Z and +Z (-X and +X), in G7 (X a diameter) and G8,
G21 and G20, with and without a work offset, the start point given on the cycle's block or
left where the tool is, a few under G91 (rs274's rapid then reads the words as absolute).

Lengths are real sizes (mm, or inch for G20), 4 decimals: the test compares every move to
rs274's print resolution (0.51e-4 program units), as the corpus comparison does. Where
rs274 refuses a program (a contour it cannot offset, "G7X error: Not monotonic"), the
expected error is kept (`regen.sh` writes NAME.err).

Run from this folder, then make the references with rs274 (`sh regen.sh`). The same seed
writes the same files.
"""

import math
import random

SEED = 27
COUNT = 96


def num(v):
    """A word value with at most 4 decimals, no trailing zeros."""
    s = f"{v:.4f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def profile(rng, pockets, length, q0, q_top):
    """A contour in the (p, q) frame from (0, q0) towards p = -length, ending at q_top.

    Each element: ("line", p, q), ("arc", p, q, pc, qc, ccw) (end and centre), with an
    optional corner ("A" or "C", size) at its end. Segments advance towards -p; straight
    steps (p unchanged) climb; with `pockets` the depth may go back down."""
    segs = []
    p, q = 0.0, q0
    guard = 0
    while p > -length and guard < 12:
        guard += 1
        room_up = q_top - q
        r = rng.random()
        seg_len = rng.uniform(0.15, 0.35) * length
        if r < 0.22:
            segs.append(["line", p - seg_len, q])
        elif r < 0.36 and room_up > 0.5:
            segs.append(["line", p, q + rng.uniform(0.25, 0.6) * room_up])
        elif r < 0.5:
            lo = -min(q - 0.5, 3.0) if pockets else 0.0
            h = rng.uniform(lo, max(lo, min(room_up, 3.0)))
            segs.append(["line", p - seg_len, q + h])
        elif r < 0.66 and room_up > 0.6:
            # A quarter arc climbing: convex (centre at the start's depth, G3 in the frame)
            # or concave (centre above the start, G2).
            rad = rng.uniform(0.3, min(room_up, 4.0))
            if rng.random() < 0.5:
                segs.append(["arc", p - rad, q + rad, p - rad, q, True])
            else:
                segs.append(["arc", p - rad, q + rad, p, q + rad, False])
        elif r < 0.76 and pockets and q > 2.0:
            # A quarter arc going down into a pocket.
            rad = rng.uniform(0.3, min(q - 1.0, 3.0))
            if rng.random() < 0.5:
                segs.append(["arc", p - rad, q - rad, p - rad, q, False])
            else:
                segs.append(["arc", p - rad, q - rad, p, q - rad, True])
        elif r < 0.9:
            # Part of a circle between two angles: counterclockwise on its upper half
            # or clockwise on its lower half.
            rad = rng.uniform(1.0, 6.0)
            a1 = rng.uniform(0.0, 0.7) * math.pi
            a2 = a1 + rng.uniform(0.15, 0.95 * (math.pi - a1) + 0.05)
            a2 = min(a2, math.pi)
            ccw = rng.random() < 0.5
            if ccw:
                pc, qc = p - rad * math.cos(a1), q - rad * math.sin(a1)
                ep, eq = pc + rad * math.cos(a2), qc + rad * math.sin(a2)
            else:
                pc, qc = p - rad * math.cos(a1), q + rad * math.sin(a1)
                ep, eq = pc + rad * math.cos(a2), qc - rad * math.sin(a2)
            if 0.3 < eq < q_top + 0.01 and (pockets or eq >= q - 1e-9):
                segs.append(["arc", ep, eq, pc, qc, ccw])
            else:
                continue
        else:
            continue
        last = segs[-1]
        if last[0] == "line" and len(segs) > 1 and segs[-2][0] == "line" and rng.random() > 0.05:
            # Two straights in a row along one line: rs274 cannot intersect their offsets
            # ("Cannot intersect parallel lines"); a few are kept to show it.
            a = segs[-3] if len(segs) > 2 else [None, 0.0, q0]
            b, cc = segs[-2], last
            d1 = (b[1] - a[1], b[2] - a[2])
            d2 = (cc[1] - b[1], cc[2] - b[2])
            if abs(d1[0] * d2[1] - d1[1] * d2[0]) < 1e-9 * (1.0 + math.hypot(*d1) * math.hypot(*d2)):
                segs.pop()
                continue
        p, q = last[1], last[2]
        if rng.random() < 0.25 and len(segs) > 1:
            # A corner at the end of the segment before (sized to fit both sides).
            prev = segs[-2]
            prev_len = seg_length(segs[-3] if len(segs) > 2 else None, prev)
            this_len = seg_length(prev, last)
            size = rng.uniform(0.1, 0.3) * min(prev_len, this_len)
            if size > 0.05:
                prev.append((rng.choice("AC"), size))
    # Up to the stock (a step, or a taper when the last segment is a step).
    if q < q_top:
        step_last = segs and segs[-1][0] == "line" and segs[-1][1] == (segs[-2][1] if len(segs) > 1 else 0.0)
        if rng.random() < 0.5 and not step_last:
            segs.append(["line", p, q_top])
        else:
            segs.append(["line", p - rng.uniform(0.5, 2.0), q_top])
    return segs


def seg_length(prev, seg):
    """Chord length of `seg` from the end of `prev` (or the origin's start)."""
    if prev is None:
        return abs(seg[1]) + 1.0
    return math.hypot(seg[1] - prev[1], seg[2] - prev[2])


def program(rng, n):
    g20 = rng.random() < 0.25
    unit = 1.0 / 25.4 if g20 else 1.0
    diameter = rng.random() < 0.6
    cycle = rng.choice([71, 71, 72, 72])
    inside = rng.random() < 0.3
    sign_p = -1.0 if rng.random() < 0.2 else 1.0  # towards +Z (or +X) when -1
    variant = rng.choice(["full", "full", "split", "finish"])
    pockets = variant != "finish" and rng.random() < 0.6
    length = rng.uniform(15.0, 40.0)
    q_top = rng.uniform(6.0, 14.0)
    q0 = rng.uniform(0.5, 0.5 * q_top)
    segs = profile(rng, pockets, length, q0, q_top)
    offset = rng.random() < 0.2
    incremental = rng.random() < 0.06
    words_uw = rng.random() < 0.3
    ijk_abs = rng.random() < 0.2
    use_r = rng.random() < 0.25

    # The part's frame: radius x and z as functions of (p, q), in mm.
    base = rng.uniform(3.5, 10.0)
    if cycle == 71:
        z0 = rng.uniform(-2.0, 2.0)
        def to_part(p, q):
            x = base + q if not inside else base + q_top + 2.0 - q
            return x, z0 + sign_p * p
    else:
        xo = length + base + rng.uniform(0.0, 4.0)
        def to_part(p, q):
            x = xo + sign_p * p if sign_p > 0 else base + (-p)
            z = q - q_top if not inside else q_top - q
            return x, z
    clear_p = rng.uniform(0.5, 3.0)
    clear_q = rng.uniform(0.3, 3.0)
    start = to_part(clear_p, q_top + clear_q)

    def xw(x):
        return num(x * unit * (2.0 if diameter else 1.0))

    def zw(z):
        return num(z * unit)

    mode = "G7" if diameter else "G8"
    units = "G20" if g20 else "G21"
    feed = "0.008" if g20 else "0.2"
    lines = [
        f"(random G7x {n:02}: seed {SEED}; G{cycle} {variant} {'inside' if inside else 'outside'}"
        f" {'pockets' if pockets else 'no pockets'} {mode} {units})",
        f"G18 {mode} {units} G90 G95 G40",
    ]
    if ijk_abs:
        lines.append("G90.1")
    if offset:
        # (3 decimals: rs274 prints the offset's radius to 4.)
        ox = round(rng.uniform(-3.0, 3.0) * unit * (2.0 if diameter else 1.0), 3)
        lines.append(f"G10 L2 P2 X{num(ox)} Z{zw(rng.uniform(-5.0, 5.0))}")
        lines.append("G55")
    lines.append(f"T1 M6 S{rng.choice([400, 600, 800])} M3 F{feed}")
    lines.append(f"G0 X{xw(start[0])} Z{zw(start[1])}")

    d_rough = rng.choice([0.0, 0.2, 0.5, 1.0])
    i_cut = rng.uniform(0.4, 2.5)
    retract = rng.choice([None, 0.2, 0.5, 1.0])

    def cycle_words(code, d, extra):
        w = f"{code} Q100"
        if rng.random() < 0.7:
            w += f" X{xw(start[0])} Z{zw(start[1])}"
        if d is not None:
            w += f" D{num(d * unit)}"
        return w + extra

    def rough(code, d):
        extra = f" I{num(i_cut * unit)}"
        if retract is not None:
            extra += f" R{num(retract * unit)}"
        return cycle_words(code, d, extra)

    body = []
    g = f"G{cycle}"
    if variant == "full":
        body.append(rough(g, d_rough))
    elif variant == "split":
        body.append(rough(g + ".1", d_rough + 0.5))
        body.append(rough(g + ".2", d_rough))
    if variant != "split" or rng.random() < 0.7:
        passes = rng.choice([1, 1, 2, 3])
        d = rng.choice([0.0, d_rough]) if passes == 1 else d_rough + rng.uniform(0.2, 1.0)
        extra = ""
        e = rng.choice([0.0, 0.0, 0.1])
        if e:
            extra += f" E{num(e * unit)}"
        if passes > 1 or rng.random() < 0.3:
            extra += f" P{passes}"
        body.append(cycle_words("G70", d, extra))
    if incremental:
        body = ["G91"] + [b.replace(f" X{xw(start[0])} Z{zw(start[1])}", "") for b in body] + ["G90"]
    lines += body
    lines.append(f"G0 X{xw(start[0])} Z{zw(start[1])}")
    lines.append("M5")
    lines.append("M2")
    lines.append("")
    lines.append("(the finished contour)")
    lines.append("o100 sub")
    # The direction of arcs on the part: the frame's map may mirror it.
    o, pz, qx = to_part(0.0, 0.0), to_part(1.0, 0.0), to_part(0.0, 1.0)
    det = (pz[1] - o[1]) * (qx[0] - o[0]) - (pz[0] - o[0]) * (qx[1] - o[1])
    dia = 2.0 if diameter else 1.0
    # The first point: a rapid (read as a feed) or a feed onto the contour's start.
    fx, fz = to_part(0.0, q0)
    first = "G0" if rng.random() < 0.5 else "G1"
    if incremental:
        lines.append(f"{first} X{num((fx - start[0]) * unit * dia)} Z{zw(fz - start[1])}")
    else:
        lines.append(f"{first} X{xw(fx)} Z{zw(fz)}")
    if rng.random() < 0.15:
        lines.append("#<depth> = #<_x>  (the current point, as rs274 reads it in a contour)")
    cur = (fx, fz)
    for s in segs:
        ex, ez = to_part(s[1], s[2])
        words = []
        if s[0] == "line":
            words.append(rng.choice(["G1", "G1", "G1", "G0"]))
            corner = s[3] if len(s) > 3 else None
        else:
            ccw_part = s[5] if det > 0 else not s[5]
            words.append("G3" if ccw_part else "G2")
            corner = s[6] if len(s) > 6 else None
        if incremental:
            words.append(f"X{num((ex - cur[0]) * unit * dia)}")
            words.append(f"Z{zw(ez - cur[1])}")
        elif words_uw and s[0] == "line" and rng.random() < 0.7:
            if abs(ex - cur[0]) > 1e-9:
                words.append(f"U{num((ex - cur[0]) * unit * dia)}")
            if abs(ez - cur[1]) > 1e-9:
                words.append(f"W{zw(ez - cur[1])}")
        else:
            if abs(ex - cur[0]) > 1e-9 or rng.random() < 0.5:
                words.append(f"X{xw(ex)}")
            if abs(ez - cur[1]) > 1e-9 or rng.random() < 0.5:
                words.append(f"Z{zw(ez)}")
        if s[0] == "arc":
            cx, cz = to_part(s[3], s[4])
            if use_r:
                words.append(f"R{num(math.hypot(ex - cx, ez - cz) * unit)}")
            elif ijk_abs:
                words.append(f"I{num(cx * unit)} K{num(cz * unit)}")
            else:
                words.append(f"I{num((cx - cur[0]) * unit)} K{num((cz - cur[1]) * unit)}")
        if corner:
            words.append(f"{corner[0]}{num(corner[1] * unit)}")
        if len(words) > 1:
            lines.append(" ".join(words))
        cur = (ex, ez)
    lines.append("o100 endsub")
    lines.append("")
    return "\n".join(lines)


def main():
    rng = random.Random(SEED)
    for n in range(COUNT):
        with open(f"rand-{n:02}.ngc", "w") as f:
            f.write(program(rng, n))


if __name__ == "__main__":
    main()
