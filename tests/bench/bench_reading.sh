#!/usr/bin/env bash
# Reading tools on a large octree (a benchmark, not a test), next to the same on the MRI template
# (Debian's mricron-data ch2better, 301x370x316) in the same run: the statistics of a 50 mm
# sphere at the volume's centre (holovox-cli measure, level 0), and scrolling through 100
# oblique 512x512 slices a slice apart (holovox-cli slice --scroll 100, one process, as the wheel
# steps in a slice view), with time and peak memory, next to the plain cost of reading the whole
# .hvo file once (cat, page cache warm).
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
template=/usr/share/mricron/templates/ch2better.nii.gz
volumes=("$input")
if [ -f "$template" ]; then
  "$cli" build "$template" -o "$work/template.hvo" >/dev/null
  volumes+=("$work/template.hvo")
else
  echo "(no MRI template at $template: install mricron-data for the comparison)"
fi
timed() {  # prints "seconds peak_MiB" of a command
  /usr/bin/time -f "%e %M" -o "$work/t" "$@" >"$work/out" 2>&1 || { cat "$work/out" >&2; exit 1; }
  read -r s k <"$work/t"; echo "$s $(echo "$k / 1024" | bc -l)"
}
for hvo in "${volumes[@]}"; do
  bytes=$(stat -c %s "$hvo")
  cat "$hvo" >/dev/null
  read -r cat_s _ < <(timed cat "$hvo")  # warm
  echo "octree $(basename "$hvo"): $(echo "$bytes / 1048576" | bc) MiB; reading it whole (cat, warm): ${cat_s} s"
  # The volume's centre, as the slice command reports it for a plane through the default point.
  centre=$("$cli" slice "$hvo" --plane axial --size 8x8 -o "$work/c.png" | sed -n 's/.*through (\([^)]*\)).*/\1/p' | tr -d ' ')
  read -r m_s m_mib < <(timed "$cli" measure "$hvo" --roi "sphere:$centre,25")
  grep -E "voxels|mean" "$work/out" | tr -s ' ' | sed 's/^/  /'
  printf '  measure, 50 mm sphere at the centre (level 0):  %6.2f s  peak RSS %6.1f MiB\n' "$m_s" "$m_mib"
  read -r s_s s_mib < <(timed "$cli" slice "$hvo" --plane 0.3,0.2,1 --size 512x512 --scroll 100 -o "$work/s.png")
  grep -E "scrolled" "$work/out" | sed 's/^/  /'
  printf '  slice, 100 oblique 512x512 planes scrolled in one process: %6.2f s in all  peak RSS %6.1f MiB\n' \
    "$s_s" "$s_mib"
done
