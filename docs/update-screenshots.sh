#!/usr/bin/env bash
# Copies the screenshots the GUI suite takes (build/ci/test-artifacts) to docs/images/first-steps,
# where the README's "First steps" shows them, so that they show the product as it is:
#
#   ctest --preset ci -L gui && bash docs/update-screenshots.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
art=${1:-$root/build/ci/test-artifacts}
out=$root/docs/images/first-steps
mkdir -p "$out"
copy() { [ -f "$art/$1" ] || { echo "missing $art/$1: run the GUI suite first (ctest --preset ci -L gui)" >&2; exit 1; }
         cp "$art/$1" "$out/$2"; echo "docs/images/first-steps/$2 <- $1"; }
copy gui/pacs-search.png 1-find-a-study.png
copy gui/demo-first-start.png 2-open-it.png
copy gui/soft-tissue.png 3-transfer-function.png
copy gui/tools.png 4-probe.png
copy gui/slice-measurements.png 5-measure.png
copy gui/volume-sphere.png 5-measure-3d.png
copy gui/lightfield-preview-window.png 6-light-field.png
copy main_window-1366x768.png first-run-1366x768.png
