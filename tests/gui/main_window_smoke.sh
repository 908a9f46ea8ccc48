#!/usr/bin/env bash
# Starts the GUI under Xvfb on an octree, grabs the window to PNG and checks that it shows
# the octree's summary (the PNG is kept under the build tree as a test artefact).
set -euo pipefail
gui=${1:?holovox}; cli=${2:?holovox-cli}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$cli" phantom --size 40x40x40 -o "$work/p.hvo" --quiet
art="$(dirname "$gui")/../test-artifacts"
mkdir -p "$art"
xvfb-run -a -s "-screen 0 1280x1024x24" "$gui" --screenshot "$art/main_window.png" --dump-summary "$work/summary.txt" "$work/p.hvo"
grep -q "40 x 40 x 40 int16, CT" "$work/summary.txt"
size=$(stat -c %s "$art/main_window.png")
[ "$size" -gt 5000 ] || { echo "screenshot too small ($size bytes): blank window?"; exit 1; }
echo "GUI showed the octree summary; screenshot $art/main_window.png ($size bytes)"
