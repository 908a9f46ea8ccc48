#!/usr/bin/env bash
# Starts the `holovox` binary under Xvfb on an octree given on the command line, waits for the
# first frame, grabs the window to PNG and checks that it is not blank (kept as a test artefact).
set -euo pipefail
gui=${1:?holovox}; cli=${2:?holovox-cli}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$cli" phantom --size 64x64x48 -o "$work/p.hvo" --quiet
art="$(dirname "$gui")/../test-artifacts"
mkdir -p "$art"
export HOLOVOX_DB="$work/db.sqlite" HOLOVOX_PACS_CONFIG="$work/pacs.json" XDG_CONFIG_HOME="$work/config"
xvfb-run -a -s "-screen 0 1400x1000x24" "$gui" --screenshot "$art/main_window.png" "$work/p.hvo"
size=$(stat -c %s "$art/main_window.png")
[ "$size" -gt 20000 ] || { echo "screenshot too small ($size bytes): blank window?"; exit 1; }
echo "holovox opened the octree and drew it; screenshot $art/main_window.png ($size bytes)"
