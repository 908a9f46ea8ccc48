#!/usr/bin/env bash
# Octree build benchmark: throughput (MB/s of input) and peak RSS of `holovox-cli build`, next to
# the plain cost of reading the same input once (measured in the same run, page cache dropped
# first when running as root so both start cold).
#
#   bash tests/bench/bench_build.sh [--cli PATH] [--dir DIR] [--sizes "1 4"] [--huge]
#
# --sizes: inputs in GiB of int16 voxels (1 = 1024x1024x512, 4 = 2048x2048x512).
# --huge:  also stream a 2048x2048x4096 phantom (32 GiB of voxels, more than this machine's RAM)
#          straight into an .hvo and report time, output size and peak RSS.
set -euo pipefail
cli=build/release/app/holovox-cli
dir=${TMPDIR:-/tmp}/holovox-bench
sizes="1 4"
huge=0
while [ $# -gt 0 ]; do
  case $1 in
    --cli) cli=$2; shift 2 ;;
    --dir) dir=$2; shift 2 ;;
    --sizes) sizes=$2; shift 2 ;;
    --huge) huge=1; shift ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
[ -x "$cli" ] || { echo "build first: cmake --workflow --preset release (or pass --cli)" >&2; exit 2; }
mkdir -p "$dir"
drop() { sync; if [ "$(id -u)" -eq 0 ]; then echo 1 > /proc/sys/vm/drop_caches 2>/dev/null || true; fi; }
timed() { # runs a command, sets T (seconds) and RSS (KiB)
  /usr/bin/time -o "$dir/time.txt" -f "%e %M" "$@" >/dev/null
  read -r T RSS < "$dir/time.txt"
}
printf '%-10s %8s %8s %7s %9s %10s %10s %s\n' input read_s build_s ratio MB/s peakRSS_MiB out_MiB codec
for gib in $sizes; do
  case $gib in
    1) dims=1024x1024x512 ;; 4) dims=2048x2048x512 ;; 2) dims=1024x1024x1024 ;; 8) dims=2048x2048x1024 ;;
    *) echo "unsupported size $gib" >&2; exit 2 ;;
  esac
  in="$dir/phantom-$dims.nrrd"
  [ -f "$in" ] || "$cli" phantom --size "$dims" -o "$in" --quiet >/dev/null
  bytes=$(stat -c %s "$in")
  drop; timed cat "$in"; read_s=$T
  for codec in "zstd" "zstd --level=-1" "lz4"; do
    out="$dir/out.hvo"
    drop; timed "$cli" build "$in" -o "$out" --codec $codec --quiet
    printf '%-10s %8.2f %8.2f %6.2fx %9.0f %10.0f %10.0f %s\n' "${gib}GiB" "$read_s" "$T" \
      "$(echo "$T / $read_s" | bc -l)" "$(echo "$bytes / 1000000 / $T" | bc -l)" \
      "$(echo "$RSS / 1024" | bc -l)" "$(echo "$(stat -c %s "$out") / 1048576" | bc -l)" "$codec"
    rm -f "$out"
  done
done
if [ $huge -eq 1 ]; then
  out="$dir/huge.hvo"
  drop; timed "$cli" build phantom:2048x2048x4096 -o "$out" --quiet
  printf 'phantom 2048x2048x4096 (32 GiB int16) -> .hvo: %.0f s (%.0f MB/s of voxels), %.0f MiB on disk, peak RSS %.0f MiB\n' \
    "$T" "$(echo "34359738368 / 1000000 / $T" | bc -l)" "$(echo "$(stat -c %s "$out") / 1048576" | bc -l)" \
    "$(echo "$RSS / 1024" | bc -l)"
  "$cli" info "$out" | tail -4
  rm -f "$out"
fi
