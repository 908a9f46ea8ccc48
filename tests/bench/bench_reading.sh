#!/usr/bin/env bash
# Reading tools on a large octree (a benchmark, not a test): the statistics of a 50 mm sphere
# (holovox-cli measure, level 0) and 20 oblique slices through it (holovox-cli slice, one process
# each, octree opened each time), with time and peak memory, next to the plain cost of reading
# the whole .hvo file once (cat, page cache warm) in the same run.
#
#   bash tests/bench/bench_reading.sh [--cli PATH] [--size 512x512x512 | --input FILE.hvo]
set -euo pipefail
cli=build/ci/app/holovox-cli
size=512x512x512
input=""
while [ $# -gt 0 ]; do
  case $1 in --cli) cli=$2; shift 2 ;; --size) size=$2; shift 2 ;; --input) input=$2; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;; esac
done
[ -x "$cli" ] || { echo "build first: cmake --workflow --preset ci (or pass --cli)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export HOME="$work/home" XDG_CONFIG_HOME="$work/home/.config" XDG_DATA_HOME="$work/home/.local/share"
if [ -z "$input" ]; then
  input="$work/phantom.hvo"
  "$cli" build "phantom:$size" -o "$input" >/dev/null
fi
timed() {  # prints "seconds peak_MiB" of a command
  /usr/bin/time -f "%e %M" -o "$work/t" "$@" >"$work/out" 2>&1 || { cat "$work/out" >&2; exit 1; }
  read -r s k <"$work/t"; echo "$s $(echo "$k / 1024" | bc -l)"
}
bytes=$(stat -c %s "$input")
read -r cat_s _ < <(timed cat "$input")
cat "$input" >/dev/null
read -r cat_s _ < <(timed cat "$input")  # warm
echo "octree $(basename "$input"): $(echo "$bytes / 1048576" | bc) MiB; reading it whole (cat, warm): ${cat_s} s"
read -r m_s m_mib < <(timed "$cli" measure "$input" --roi sphere:0,0,0,25)
grep -E "voxels|mean" "$work/out" | tr -s ' ' | sed 's/^/  /'
printf '  measure, 50 mm sphere at the centre (level 0):  %6.2f s  peak RSS %6.1f MiB\n' "$m_s" "$m_mib"
total=0; peak=0
for i in $(seq 0 19); do
  a=$(echo "0.05 * $i" | bc -l)
  read -r s mib < <(timed "$cli" slice "$input" --plane "0.3,$a,1" --size 512x512 -o "$work/s.png")
  total=$(echo "$total + $s" | bc -l)
  peak=$(echo "if ($mib > $peak) $mib else $peak" | bc -l)
done
printf '  slice, 20 oblique 512x512 planes (one process each): %6.3f s per slice  peak RSS %6.1f MiB\n' \
  "$(echo "$total / 20" | bc -l)" "$peak"
