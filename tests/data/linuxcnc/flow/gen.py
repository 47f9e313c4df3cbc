#!/usr/bin/env python3
"""Seeded random LinuxCNC programs for issue 27 (rs274 as the oracle): subroutines whose
`return` / `endsub` (with and without a value) stand inside nested if/elseif/else, while,
do-while and repeat blocks, with break and continue of the enclosing loops. The labels of
the blocks reuse the subroutine's own number where rs274 allows it (an `o100 if` inside
`o100 sub`: the block labels are local to the sub, `return` names the sub). Each G1's X
records the state (a counter and the argument), so a wrong branch shows as a wrong move.

Run: `python3 gen.py` (writes `rand-NN.ngc`), then `./regen.sh`."""
import random

SEED = 27


def program(rng, n):
    lines = ["(rand-%02d: seeded random return/endsub inside nested blocks, gen.py)" % n,
             "G18 G21 G7 G90 F100"]
    subs = []
    for s in range(rng.randint(1, 3)):
        num = 100 + 100 * s
        named = rng.random() < 0.4
        key = "o<r%d>" % s if named else "o%d" % num
        labels = iter(range(num if not named else 10 * s + 1, 10**6))
        body = []
        state = {"moves": 0}
        # The first block may reuse the sub's own number (a label local to the sub).
        def label():
            return next(labels)
        block(rng, body, key, label, 1, [], state)
        lines.append("%s sub" % key)
        lines += ["  " + l for l in body]
        end = "%s endsub" % key
        if rng.random() < 0.5:
            end += " [%d]" % rng.randint(1, 9)
        lines.append("  G1 X[#1 + 50] Z-%d" % (90 + s))
        lines.append(end)
        subs.append(key)
    for k in range(rng.randint(3, 6)):
        key = rng.choice(subs)
        lines.append("%s call [%d] [%d]" % (key, rng.randint(0, 6), rng.randint(0, 3)))
        lines.append("G1 X[#<_value> + %d] Z[#<_value_returned> - %d]" % (k + 1, k + 1))
    lines.append("M2")
    return "\n".join(lines) + "\n"


def block(rng, out, key, label, depth, loops, state):
    """Appends a random statement list to `out` (each line indented by depth)."""
    pad = "  " * (depth - 1)
    for _ in range(rng.randint(1, 3)):
        r = rng.random()
        if depth < 4 and r < 0.55:
            lab = label()
            kind = rng.choice(["if", "while", "do", "repeat"])
            if kind == "if":
                out.append(pad + "o%d if [#1 GT %d]" % (lab, rng.randint(0, 5)))
                block(rng, out, key, label, depth + 1, loops, state)
                if rng.random() < 0.5:
                    out.append(pad + "o%d elseif [#2 EQ %d]" % (lab, rng.randint(0, 3)))
                    block(rng, out, key, label, depth + 1, loops, state)
                if rng.random() < 0.5:
                    out.append(pad + "o%d else" % lab)
                    block(rng, out, key, label, depth + 1, loops, state)
                out.append(pad + "o%d endif" % lab)
            elif kind == "repeat":
                out.append(pad + "o%d repeat [%d]" % (lab, rng.randint(0, 3)))
                out.append(pad + "  #1 = [#1 + 1]")
                # break/continue cannot leave a repeat (rs274): no loop for them here.
                block(rng, out, key, label, depth + 1, [], state)
                out.append(pad + "o%d endrepeat" % lab)
            else:
                c = "#<c%d>" % lab
                out.append(pad + "%s = 0" % c)
                if kind == "while":
                    out.append(pad + "o%d while [%s LT %d]" % (lab, c, rng.randint(1, 4)))
                else:
                    out.append(pad + "o%d do" % lab)
                out.append(pad + "  %s = [%s + 1]" % (c, c))
                out.append(pad + "  #1 = [#1 + 1]")
                block(rng, out, key, label, depth + 1, loops + [(lab, kind)], state)
                if kind == "while":
                    out.append(pad + "o%d endwhile" % lab)
                else:
                    out.append(pad + "o%d while [%s LT %d]" % (lab, c, rng.randint(1, 4)))
        elif r < 0.75:
            state["moves"] += 1
            out.append(pad + "G1 X[#1 * 2 + %d] Z-%d" % (depth, state["moves"]))
        elif r < 0.87:
            v = " [#1 + %d]" % rng.randint(0, 9) if rng.random() < 0.6 else ""
            word = rng.choice(["return", "return", "endsub"]) if depth > 1 else "return"
            if word == "endsub":
                # An endsub inside a block would end the definition (rs274 reads the
                # first one as the sub's end): a return is the only early exit.
                word = "return"
            out.append(pad + "%s %s%s" % (key, word, v))
        elif loops:
            # Only the innermost loop is left or continued, and a do loop only left: rs274
            # 2.9.0~pre1's `continue` in a do loop runs the closing while's test with its
            # flag still set, and it loops for ever on some programs.
            lab, kind = loops[-1]
            word = rng.choice(["break", "continue"]) if kind == "while" else "break"
            out.append(pad + "o%d %s" % (lab, word))
        else:
            state["moves"] += 1
            out.append(pad + "G0 X[#2 + %d] Z%d" % (depth, state["moves"]))


if __name__ == "__main__":
    rng = random.Random(SEED)
    for n in range(24):
        with open("rand-%02d.ngc" % n, "w") as f:
            f.write(program(rng, n))
