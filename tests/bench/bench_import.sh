#!/usr/bin/env bash
# DICOM import benchmark, with peers measured in the same run (page cache dropped before each
# timed step when running as root, so every tool starts cold):
#   1. a 1000-slice 512x512 CT series (uncompressed, written by this script) imported into the
#      study database and built into an .hvo  vs  dcm2niix converting it to NIfTI;
#   2. header scan of 10,000 small files into the database  vs  dcmdump -M reading the same files.
#
#   bash tests/bench/bench_import.sh [--cli PATH] [--dir DIR] [--slices 1000] [--files 10000]
set -euo pipefail
cli=build/release/app/holovox-cli
dir=${TMPDIR:-/tmp}/holovox-bench-import
slices=1000
files=10000
while [ $# -gt 0 ]; do
  case $1 in
    --cli) cli=$2; shift 2 ;; --dir) dir=$2; shift 2 ;;
    --slices) slices=$2; shift 2 ;; --files) files=$2; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
[ -x "$cli" ] || { echo "build first: cmake --workflow --preset release (or pass --cli)" >&2; exit 2; }
command -v dcm2niix >/dev/null || { echo "dcm2niix missing: bash installer/install-deps.sh" >&2; exit 2; }
mkdir -p "$dir"
drop() { sync; if [ "$(id -u)" -eq 0 ]; then echo 1 > /proc/sys/vm/drop_caches 2>/dev/null || true; fi; }
timed() { /usr/bin/time -o "$dir/time.txt" -f "%e %M" "$@" >"$dir/last.log" 2>&1; read -r T RSS < "$dir/time.txt"; }
ratio() { echo "$1 / $2" | bc -l; }

ct="$dir/ct-512x512x$slices"
if [ ! -d "$ct" ]; then
  "$cli" export-dicom "phantom:512x512x$slices" -o "$ct" --patient "BENCH^CT" --study "benchmark" >/dev/null
fi
n=$(ls "$ct" | wc -l); bytes=$(du -sb "$ct" | cut -f1)
rm -rf "$dir/nii" "$dir/db.sqlite"* "$dir/octrees"; mkdir -p "$dir/nii"
drop; timed dcm2niix -z n -o "$dir/nii" -f ct "$ct"; peer=$T
drop; timed "$cli" import "$ct" --db "$dir/db.sqlite" --build; hvx=$T; hvxRss=$RSS
printf 'import of %d files (%.0f MB), 512x512x%d CT:\n' "$n" "$(echo "$bytes/1000000" | bc -l)" "$slices"
printf '  dcm2niix to NIfTI           %7.2f s  %7.0f files/s  %6.0f MB/s\n' "$peer" "$(ratio "$n" "$peer")" "$(ratio "$bytes/1000000" "$peer")"
printf '  holovox import + octree     %7.2f s  %7.0f files/s  %6.0f MB/s  peak RSS %.0f MiB\n' "$hvx" \
  "$(ratio "$n" "$hvx")" "$(ratio "$bytes/1000000" "$hvx")" "$(echo "$hvxRss/1024" | bc -l)"
printf '  ratio holovox / dcm2niix    %7.2f (target <= 1)\n' "$(ratio "$hvx" "$peer")"

many="$dir/many-$files"
if [ ! -d "$many" ]; then
  "$cli" export-dicom "phantom:64x64x$files" -o "$many" --patient "BENCH^MANY" >/dev/null
fi
rm -f "$dir/db2.sqlite"*
drop; timed dcmdump -q -M +sd +r "$many"; peer=$T
drop; timed "$cli" import "$many" --db "$dir/db2.sqlite"; hvx=$T
printf 'header scan of %d files:\n' "$files"
printf '  dcmdump -M (one process)    %7.2f s  %7.0f files/s\n' "$peer" "$(ratio "$files" "$peer")"
printf '  holovox import (db, no build) %5.2f s  %7.0f files/s  (ratio %.2f)\n' "$hvx" "$(ratio "$files" "$hvx")" "$(ratio "$hvx" "$peer")"
