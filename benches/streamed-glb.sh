#!/usr/bin/env bash
# Issue 20, fourth round (benches/README.md): `--gltf` streamed against the full-grid
# `--gltf` of a base build and the report-only run, best of N interleaved runs each, and
# the two .glb files compared byte for byte.
#
#   benches/streamed-glb.sh BASE_VPCUT NEW_VPCUT [ROUNDS]
#
# BASE_VPCUT: a build whose --gltf keeps the whole grid (main before the streamed model);
# it is given --max-dexels 2e9 so the long screws fit. Prints one line per job and run:
# best wall, user and system seconds of the best-wall run, peak RSS.
set -euo pipefail
base=$1
new=$2
rounds=${3:-3}
here=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
jobs=(scenes/seed002-equal-tooth/job.toml scenes/seed004-tr100x12/job.toml
      benches/jobs/screw-1m.toml benches/jobs/screw-3m.toml)
for job in "${jobs[@]}"; do
  name=$(basename "$(dirname "$job")")
  [ "$name" = jobs ] && name=$(basename "$job" .toml)
  for r in $(seq "$rounds"); do
    /usr/bin/time -f "%e %U %S %M" -o "$tmp/$name.report.$r" \
      "$new" simulate "$here/$job" -q >/dev/null
    /usr/bin/time -f "%e %U %S %M" -o "$tmp/$name.streamed.$r" \
      "$new" simulate "$here/$job" -q --gltf "$tmp/$name.new.glb" >/dev/null
    /usr/bin/time -f "%e %U %S %M" -o "$tmp/$name.grid.$r" \
      "$base" simulate "$here/$job" -q --gltf "$tmp/$name.base.glb" --max-dexels 2000000000 >/dev/null
  done
  for run in report streamed grid; do
    best=$(cat "$tmp/$name.$run".* | sort -n | head -1)
    printf '%-22s %-9s %s\n' "$name" "$run" "$best" |
      awk '{printf "%-22s %-9s %6.2f s wall %6.2f s user %5.2f s sys %8.0f MB\n", $1, $2, $3, $4, $5, $6/1024}'
  done
  if cmp -s "$tmp/$name.new.glb" "$tmp/$name.base.glb"; then
    echo "$name: .glb identical ($(stat -c %s "$tmp/$name.new.glb") bytes)"
  else
    echo "$name: .glb DIFFERS"
    exit 1
  fi
done
