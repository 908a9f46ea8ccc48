#!/usr/bin/env bash
# Builds the .deb and .tar.gz with CPack, unpacks the .deb into a temporary root and runs the
# installed holovox-cli from there: it must build and describe an octree.
set -euo pipefail
build=${1:?build dir}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
(cd "$build" && cpack -G "DEB;TGZ" -B "$work/pkg" >"$work/cpack.log" 2>&1) || { cat "$work/cpack.log"; exit 1; }
deb=$(ls "$work"/pkg/holovox_*.deb)
tgz=$(ls "$work"/pkg/holovox-*.tar.gz)
echo "packages: $(basename "$deb") $(basename "$tgz")"
info=$(dpkg-deb --info "$deb"); grep -q "Package: holovox" <<<"$info"
dpkg-deb -x "$deb" "$work/root"
for f in usr/bin/holovox-cli usr/bin/holovox usr/share/applications/holovox.desktop; do
  [ -e "$work/root/$f" ] || { echo "missing from .deb: $f"; exit 1; }
done
listing=$(tar -tzf "$tgz"); grep -q "bin/holovox-cli" <<<"$listing" || { echo "tarball lacks holovox-cli"; exit 1; }
"$work/root/usr/bin/holovox-cli" version
"$work/root/usr/bin/holovox-cli" phantom --size 48x40x32 -o "$work/p.hvo" --quiet
out=$("$work/root/usr/bin/holovox-cli" info "$work/p.hvo" --verify); grep -q "verified" <<<"$out"
echo "installed holovox-cli built and verified an octree"
