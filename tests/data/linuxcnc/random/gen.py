#!/usr/bin/env python3
"""Seeded generator of random LinuxCNC threading programs for the rs274 conformance tests.

Writes g76-NN.ngc (random G76 cycles: every taper mode L0..L3 with E, Q angles, H spring
passes, R degression, I/J/K, internal and external, G7 and G8, G20 and G21, threads towards
-Z and +Z) and g33-NN.ngc (random straight and tapered G33 blocks and chains of them, with
rapids between, absolute and incremental) in this folder. Lengths are scaled as the
README of the folder above says (rs274 prints 4 decimals): mm x 1000 and inch x 10000, so
the printed values are exact to 1e-7 mm (mm) and 2.54e-7 mm (inch).

Run from this folder, then make the references with rs274:
    python3 gen.py && for f in g*.ngc; do rs274 -g $f ${f%.ngc}.canon; done
The same seed writes the same files (the test reads the .ngc and .canon kept here).
"""

import random

SEED = 17


def num(v):
    """A word value with at most 4 decimals, no trailing zeros."""
    s = f"{v:.4f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def units(rng):
    """(G20/G21 word, scale of lengths, a typical length in program units before scale)."""
    if rng.random() < 0.35:
        return "G20", 10000.0, 1.0 / 25.4
    return "G21", 1000.0, 1.0


def g76(rng, n):
    g_units, scale, u = units(rng)
    diameter = rng.random() < 0.6
    internal = rng.random() < 0.35
    mode = "G7" if diameter else "G8"
    to_plus = rng.random() < 0.15
    # Geometry in mm, then converted to program units (x u) and scaled.
    pitch = rng.choice([0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0, 2.5, 3.0, 25.4 / 13, 25.4 / 20])
    depth = 0.6134 * pitch * rng.uniform(0.8, 1.1)  # K, radial thread depth
    crest_r = rng.uniform(5.0, 30.0)
    i_off = rng.uniform(0.2, 2.0)  # |I|: drive line to crest
    r = rng.choice([1.0, 1.0, 1.5, 2.0, 2.5, 3.0, rng.uniform(1.0, 3.0)])
    # J from the pass count wanted: n passes < (K/J)^R.
    passes = rng.randint(2, 25)
    j = depth / passes ** (1.0 / r) * rng.uniform(0.9, 1.1)
    j = min(j, depth * 0.9)
    q = rng.choice([0.0, 29.5, 30.0, 27.5, rng.uniform(0.0, 30.0)])
    h = rng.randint(0, 3)
    length = rng.uniform(8.0, 40.0)
    z_start = rng.uniform(1.0, 6.0)
    z_end = z_start + length if to_plus else z_start - length
    taper_mode = n % 4  # every mode in turn
    e = rng.uniform(0.3, 0.45) * length / (2 if taper_mode == 3 else 1)
    if rng.random() < 0.1:
        e = 0.0  # rs274 tapers nothing with E0
    drive_r = crest_r - i_off if internal else crest_r + i_off
    i_word = i_off if internal else -i_off

    def w(v, dia=False):
        return num(v * u * scale * (2.0 if dia else 1.0))

    lines = [
        f"(random G76 {n:02}: seed {SEED}; {g_units} {mode} "
        f"{'internal' if internal else 'external'} L{taper_mode} R{num(r)} Q{num(q)} H{h}; "
        f"lengths x {int(scale)})",
        f"G18 {mode} {g_units} G90",
        "M3 S500",
    ]
    lines.append(f"G0 X{w(drive_r, diameter)} Z{w(z_start)}")
    # In G7, I J K are diameter values: twice the radial offset.
    i_val = i_word * (2.0 if diameter else 1.0)
    j_val = j * (2.0 if diameter else 1.0)
    k_val = depth * (2.0 if diameter else 1.0)
    words = (
        f"G76 P{w(pitch)} Z{w(z_end)} I{w(i_val)} J{w(j_val)} K{w(k_val)}"
        f" R{num(r)} Q{num(q)} H{h}"
    )
    if taper_mode or rng.random() < 0.3:
        words += f" E{w(e)} L{taper_mode}"
    lines.append(words)
    lines.append(f"G0 X{w(drive_r + (-3.0 if internal else 3.0), diameter)}")
    lines.append("M5")
    lines.append("M2")
    return "\n".join(lines) + "\n"


def g33(rng, n):
    g_units, scale, u = units(rng)
    diameter = rng.random() < 0.5
    mode = "G7" if diameter else "G8"

    def w(v, dia=False):
        return num(v * u * scale * (2.0 if dia else 1.0))

    lines = [
        f"(random G33 {n:02}: seed {SEED}; {g_units} {mode}; straight and tapered blocks "
        f"and chains; lengths x {int(scale)})",
        f"G18 {mode} {g_units} G90",
        "M3 S400",
    ]
    r = rng.uniform(6.0, 25.0)
    z = rng.uniform(1.0, 5.0)
    lines.append(f"G0 X{w(r + 2.0, diameter)} Z{w(z)}")
    for _pass in range(rng.randint(1, 3)):
        chain = rng.randint(1, 4)
        pitch = rng.choice([0.8, 1.0, 1.5, 2.0, 2.5, 25.4 / 8, 25.4 / 11.5, rng.uniform(0.5, 4.0)])
        x, zz = r - rng.uniform(0.1, 1.0), z
        lines.append(f"G0 X{w(x, diameter)}")
        incremental = rng.random() < 0.2
        if incremental:
            lines.append("G91")
        sense = -1.0 if rng.random() < 0.85 else 1.0
        for _ in range(chain):
            dz = sense * rng.uniform(2.0, 15.0)
            dx = rng.choice([0.0, 0.0, rng.uniform(-3.0, 3.0), dz * rng.uniform(-0.4, 0.4)])
            k = pitch * rng.choice([1.0, 1.0, rng.uniform(0.5, 2.0)])
            if incremental:
                lines.append(f"G33 X{w(dx, diameter)} Z{w(dz)} K{w(k)}")
            elif dx == 0.0 and rng.random() < 0.5:
                lines.append(f"G33 Z{w(zz + dz)} K{w(k)}")
            else:
                lines.append(f"G33 X{w(x + dx, diameter)} Z{w(zz + dz)} K{w(k)}")
            x, zz = x + dx, zz + dz
        if incremental:
            lines.append("G90")
        lines.append(f"G0 X{w(r + 3.0, diameter)}")
        lines.append(f"Z{w(z)}")
    lines.append("M5")
    lines.append("M2")
    return "\n".join(lines) + "\n"


def main():
    rng = random.Random(SEED)
    for n in range(64):
        with open(f"g76-{n:02}.ngc", "w") as f:
            f.write(g76(rng, n))
    for n in range(32):
        with open(f"g33-{n:02}.ngc", "w") as f:
            f.write(g33(rng, n))


if __name__ == "__main__":
    main()
