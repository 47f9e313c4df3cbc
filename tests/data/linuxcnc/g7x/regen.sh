#!/bin/sh
# Regenerates rs274's references for every program here (needs LinuxCNC's standalone
# interpreter: Debian's `linuxcnc-uspace` 2.9.0~pre1, `rs274`). NAME.canon is its canonical
# calls, run with `tool.tbl` (tools of zero radius and offsets, as vpcut's); NAME.err, kept
# only where rs274 stops, is what it prints: the message, then the line it stopped at
# ("rs274 crashed" where it dies on a signal: it reads past its segment list on some
# contours; "rs274 loops for ever" where it is still running after 10 s).
cd "$(dirname "$0")"
for f in *.ngc; do
    n=${f%.ngc}
    timeout 10 rs274 -t tool.tbl -g "$f" "$n.canon" 2> "$n.err" < /dev/null > /dev/null
    rc=$?
    grep -v '^executing$' "$n.err" > "$n.err.tmp"
    mv "$n.err.tmp" "$n.err"
    if [ $rc -eq 124 ]; then
        echo "rs274 loops for ever (stopped after 10 s)" > "$n.err"
        : > "$n.canon"
    elif [ $rc -gt 128 ]; then
        echo "rs274 crashed (signal $((rc - 128)))" > "$n.err"
    fi
    [ -s "$n.err" ] || rm -f "$n.err"
done
