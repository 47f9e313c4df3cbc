#!/bin/sh
# Regenerates rs274's references for every program here (needs LinuxCNC's standalone
# interpreter: Debian's `linuxcnc-uspace`, `rs274`) with the tool table `tool.tbl`.
# NAME.canon is its canonical calls; NAME.err, kept only where rs274 stops with an error,
# is its message ("LINE: text" as rs274 prints it: the message, then the block).
set -e
cd "$(dirname "$0")"
for f in *.ngc; do
    n=${f%.ngc}
    rs274 -t tool.tbl -g "$f" "$n.canon" 2> "$n.err" < /dev/null || true
    grep -v '^executing$' "$n.err" > "$n.err.tmp" || true
    mv "$n.err.tmp" "$n.err"
    [ -s "$n.err" ] || rm -f "$n.err"
done
