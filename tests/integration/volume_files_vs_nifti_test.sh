#!/usr/bin/env bash
# The MRI template (mricron-data) as nibabel places it, written as a plain MetaImage, a
# zlib-compressed one and a gzip-encoded NRRD (3D Slicer's default), all streamed by Holovox:
# each must build the same geometry as the NIfTI and render bit for bit the same CPU image.
# Until 2026-12-06 a MetaImage of more than 32 slices came back as its first 32 slices over and
# over (or aborted), and a gzip NRRD was refused.
set -euo pipefail
cli=${1:?holovox-cli}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
nii=/usr/share/mricron/templates/ch2better.nii.gz
[ -f "$nii" ] || { echo "installer/install-deps.sh installs mricron-data"; exit 1; }
/usr/bin/python3 - "$nii" "$work" <<'PY'
import sys, zlib
import nibabel as nib, numpy as np
img = nib.load(sys.argv[1])
data = np.asarray(img.dataobj).astype(np.uint8)
A = img.affine
flip = np.diag([-1.0, -1.0, 1.0])             # RAS -> LPS
L, o = flip @ A[:3, :3], flip @ A[:3, 3]
sp = np.linalg.norm(L, axis=0)
D = L / sp                                    # columns: each axis's direction
raw = data.tobytes(order='F')                 # i fastest
def header(extra):
    return ("ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
            "TransformMatrix = " + " ".join("%.9g" % x for x in D.T.flatten()) + "\n"
            "Offset = %.9g %.9g %.9g\n" % tuple(o) + "ElementSpacing = %.9g %.9g %.9g\n" % tuple(sp) +
            "DimSize = %d %d %d\n" % data.shape + "ElementType = MET_UCHAR\n" + extra +
            "ElementDataFile = LOCAL\n").encode()
open(sys.argv[2] + "/plain.mha", "wb").write(header("") + raw)
z = zlib.compress(raw, 6)
open(sys.argv[2] + "/zipped.mha", "wb").write(header("CompressedData = True\nCompressedDataSize = %d\n" % len(z)) + z)
import gzip
vec = lambda v: "(%.9g,%.9g,%.9g)" % tuple(v)
nrrd = ("NRRD0004\ntype: uint8\ndimension: 3\nspace: left-posterior-superior\nsizes: %d %d %d\n" % data.shape +
        "space directions: " + " ".join(vec(L[:, a]) for a in range(3)) + "\nkinds: domain domain domain\n" +
        "encoding: gzip\nspace origin: " + vec(o) + "\n\n").encode()
open(sys.argv[2] + "/gzip.nrrd", "wb").write(nrrd + gzip.compress(raw, 6))
PY
"$cli" build "$nii" -o "$work/nii.hvo" --quiet
"$cli" render "$work/nii.hvo" --cpu --size 192x192 --tf mr-default -o "$work/nii.png" >/dev/null
geometry() { "$cli" info "$1" | grep -E "^ *(volume|spacing|origin|direction)" | sed "s/, [A-Z]*$//"; }  # not the modality
for f in plain.mha zipped.mha gzip.nrrd; do
  "$cli" build "$work/$f" -o "$work/$f.hvo" --quiet
  diff <(geometry "$work/nii.hvo") <(geometry "$work/$f.hvo") || { echo "$f: another geometry than the NIfTI's"; exit 1; }
  "$cli" render "$work/$f.hvo" --cpu --size 192x192 --tf mr-default -o "$work/$f.png" >/dev/null
  cmp "$work/nii.png" "$work/$f.png" || { echo "$f renders unlike the NIfTI"; exit 1; }
  echo "$f: the NIfTI's geometry and the same image"
done
