#!/usr/bin/env bash
# Builds the .deb and .tar.gz with CPack, unpacks the .deb into a temporary root and runs the
# installed holovox-cli from there: it must build and describe an octree, and read a VTK image
# through the VTK reader module beside it, which no executable links (VTK is loaded on demand).
# Without the module it must refuse a VTK image with a sentence and read everything else.
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

# VTK is loaded on demand: no installed executable links it, and the module is on their run path.
for exe in holovox-cli holovox; do
  if readelf -d "$work/root/usr/bin/$exe" | grep -q "NEEDED.*libvtk"; then echo "$exe links VTK"; exit 1; fi
  readelf -d "$work/root/usr/bin/$exe" | grep -q 'RUNPATH.*\$ORIGIN/\.\./lib.*/holovox' || { echo "$exe: no run path to its modules"; exit 1; }
done
module=$(find "$work/root/usr/lib" -name libhvx_vtk_reader.so)
[ -n "$module" ] || { echo "missing from .deb: the VTK reader module"; exit 1; }
# A 4x3x2 VTK XML image (read through VTK) and the same as a plain MetaImage (streamed by
# Holovox itself, no VTK needed), voxel values 0..23.
{ printf '<?xml version="1.0"?>\n<VTKFile type="ImageData" version="0.1" byte_order="LittleEndian">\n'
  printf '<ImageData WholeExtent="0 3 0 2 0 1" Origin="0 0 0" Spacing="1 1 2">\n<Piece Extent="0 3 0 2 0 1">\n'
  printf '<PointData Scalars="v">\n<DataArray type="Int16" Name="v" format="ascii">\n'
  seq 0 23; printf '</DataArray>\n</PointData>\n</Piece>\n</ImageData>\n</VTKFile>\n'; } > "$work/s.vti"
{ printf 'ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n'
  printf 'DimSize = 4 3 2\nElementType = MET_SHORT\nElementSpacing = 1 1 2\nElementDataFile = LOCAL\n'
  for v in $(seq 0 23); do printf "\\x$(printf %02x "$v")\\x00"; done; } > "$work/m.mha"
"$work/root/usr/bin/holovox-cli" version | grep -E "VTK +9\." || { echo "installed holovox-cli names no VTK version"; exit 1; }
for f in s.vti m.mha; do
  "$work/root/usr/bin/holovox-cli" build "$work/$f" -o "$work/$f.hvo" --quiet
  out=$("$work/root/usr/bin/holovox-cli" info "$work/$f.hvo" --verify); grep -q "4 x 3 x 2\|4x3x2" <<<"$out" || { echo "$out"; exit 1; }
done
echo "installed holovox-cli read a VTK XML image through $(basename "$module"), and a MetaImage"
rm "$module"
if err=$("$work/root/usr/bin/holovox-cli" build "$work/s.vti" -o "$work/s2.hvo" --quiet 2>&1); then
  echo "a VTK image was read without the VTK reader module"; exit 1
fi
grep -q "s.vti: cannot load Holovox's VTK reader module" <<<"$err" || { echo "unclear refusal: $err"; exit 1; }
[ ! -e "$work/s2.hvo" ] || { echo "a refused build left an output"; exit 1; }
"$work/root/usr/bin/holovox-cli" version | grep -q "VTK.*unavailable" || { echo "version hides the missing module"; exit 1; }
"$work/root/usr/bin/holovox-cli" build "$work/m.mha" -o "$work/m2.hvo" --quiet
{ printf '# vtk DataFile Version 3.0\nhand written\nASCII\nDATASET STRUCTURED_POINTS\n'
  printf 'DIMENSIONS 4 3 2\nORIGIN 0 0 0\nSPACING 1 1 2\nPOINT_DATA 24\nSCALARS v short 1\nLOOKUP_TABLE default\n'
  seq 0 23; } > "$work/a.vtk"
"$work/root/usr/bin/holovox-cli" build "$work/a.vtk" -o "$work/a.hvo" --quiet  # text: streamed by Holovox
"$work/root/usr/bin/holovox-cli" phantom --size 24x20x16 -o "$work/p2.hvo" --quiet
echo "without the module: a VTK image refused ($err); a plain MetaImage, an ASCII legacy VTK image and a phantom still built"
