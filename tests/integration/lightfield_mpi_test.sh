#!/usr/bin/env bash
# Distributed light-field views: `mpirun -np 2` splits a projector display's views across two
# ranks (each with its own cache and working set); gathered on rank 0 or written by each rank,
# every view must equal the single-process render byte for byte. The display's pixels are fine
# enough that every rank's cut reaches full resolution, as the single process's does.
set -euo pipefail
cli=${1:?holovox-cli}; mpi=${2:?holovox-lightfield-mpi}
# Under ASan, Open MPI's leaks are suppressed by library (tests/sanitizers/lsan.supp); its
# plug-ins have no frame pointers, so their stacks are unwound in full to be recognised.
if [ -n "${ASAN_OPTIONS:-}" ]; then export ASAN_OPTIONS="$ASAN_OPTIONS:fast_unwind_on_malloc=0"; fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$cli" phantom --size 64x64x48 -o "$work/p.hvo" --quiet
cat > "$work/display.json" <<'JSON'
{"kind":"projector-array","projectors":6,"projectorResolution":[48,36],"screenSizeMm":[300,225],
 "pixelSizeMm":0.05,"beamAngleDegrees":0.1,"fieldOfViewDegrees":40,"projectorDistanceMm":600,
 "observerDistanceMm":800}
JSON
"$cli" lightfield "$work/p.hvo" --display "$work/display.json" --cpu -o "$work/single" > /dev/null
run_mpi() { mpirun --allow-run-as-root --oversubscribe -np 2 "$mpi" "$work/p.hvo" --display "$work/display.json" --cpu "$@"; }
run_mpi -o "$work/gathered"
run_mpi -o "$work/each" --each
for i in 000 001 002 003 004 005; do
  cmp "$work/single/view_$i.png" "$work/gathered/view_$i.png"
  cmp "$work/single/view_$i.png" "$work/each/view_$i.png"
done
[ "$(ls "$work/gathered" | wc -l)" -eq 6 ]
echo "2 MPI ranks (gathered and each-writes) reproduce the single-process views exactly"
