#!/usr/bin/env bash
# The HTML report in a real browser: writes `simulate --html` (and the report) for a few
# scenes and opens each page in headless Chromium (tests/browser/check.mjs: console errors,
# the 3D view's pixels, a click on a finding, the tables against the report).
# Usage: tests/browser/check.sh [VPCUT_BINARY] (default target/release/vpcut); needs
# node and chromium (CHROMIUM=path to choose one).
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=${1:-${CARGO_TARGET_DIR:-target}/release/vpcut}
chromium=${CHROMIUM:-$(command -v chromium || command -v chromium-browser || command -v google-chrome || true)}
[ -n "$chromium" ] || { echo "no chromium found (apt-get install chromium)"; exit 1; }
out=$(mktemp -d)
scenes=(seed002-equal-tooth seed004-tr100x12 seed000-tool-rub seed003-g76-2in-12tpi seed001-m20x1.5-thread-mill)
args=()
for name in "${scenes[@]}"; do
  "$bin" simulate "scenes/$name/job.toml" --report "$out/$name.json" --html "$out/$name.html" -q
  size=$(stat -c %s "$out/$name.html")
  echo "$name.html: $((size / 1024)) KiB"
  if [ "$size" -gt 15000000 ]; then
    echo "$name.html is over 15 MB"; exit 1
  fi
  args+=("$out/$name.html" "$out/$name.json")
done
node tests/browser/check.mjs "$chromium" "${args[@]}"
echo "pages and screenshots in $out"
