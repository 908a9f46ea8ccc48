#!/usr/bin/env bash
# Starts the `holovox` binary under Xvfb on an octree given on the command line, waits for the
# first frame, grabs the window to PNG (kept as a test artefact) and checks, reading it back with
# VTK, its size and that the volume is drawn in it.
set -euo pipefail
gui=${1:?holovox}; cli=${2:?holovox-cli}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$cli" phantom --size 64x64x48 -o "$work/p.hvo" --quiet
art="$(dirname "$gui")/../test-artifacts"
mkdir -p "$art"
export HOLOVOX_DB="$work/db.sqlite" HOLOVOX_PACS_CONFIG="$work/pacs.json" XDG_CONFIG_HOME="$work/config"
# A first run (no saved layout) on three screens: the window takes the screen's available size
# and shows the volume; the screenshots are kept.
for screen in 1366x768 1920x1080 2560x1440; do
  rm -rf "$work/config"
  png="$art/main_window-$screen.png"
  xvfb-run -a -s "-screen 0 ${screen}x24" "$gui" --screenshot "$png" "$work/p.hvo"
  # Read back by VTK's PNG reader (python3-vtk9): the whole window, and the volume drawn in it
  # (the CT transfer function's warm colours: red above blue, where the UI's chrome is grey).
  read -r width height warm < <(/usr/bin/python3 - "$png" <<'PY'
import sys
from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.util.numpy_support import vtk_to_numpy
r = vtkPNGReader(); r.SetFileName(sys.argv[1]); r.Update()
d = r.GetOutput().GetDimensions()
a = vtk_to_numpy(r.GetOutput().GetPointData().GetScalars()).astype(int).reshape(d[1], d[0], -1)[::-1]
mid = a[: int(d[1] * 0.55), int(d[0] * 0.33): int(d[0] * 0.66)]  # the 3D view, in the default layout
warm = ((mid[..., 0] - mid[..., 2] > 20) & (mid[..., 0] > 80)).mean()
print(d[0], d[1], f"{warm:.4f}")
PY
)
  echo "screen $screen: screenshot $png ${width}x${height}; ${warm} of the 3D view's pixels in the volume's colours"
  [ "${width}x${height}" = "$screen" ] || { echo "the first window does not take the screen ($screen)"; exit 1; }
  awk -v w="$warm" 'BEGIN { exit !(w > 0.01) }' || { echo "no volume drawn in the window at $screen (blank 3D view?)"; exit 1; }
done
echo "holovox opened the octree and drew it, on a first run at 1366x768, 1920x1080 and 2560x1440"
