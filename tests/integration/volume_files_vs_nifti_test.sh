#!/usr/bin/env bash
# The MRI template (mricron-data) as nibabel places it, written as a plain MetaImage, a
# zlib-compressed one and a gzip-encoded NRRD (3D Slicer's default), all streamed by Holovox:
# each must build the same geometry as the NIfTI and render bit for bit the same CPU image.
# Then the same volume as float64 and as int32 (which Holovox keeps as float32), written by
# nibabel as NIfTI and here as MetaImage and NRRD (big- and little-endian, plain and
# compressed): each the geometry and the image of nibabel's NIfTI of the same type. Last, VTK's
# own legacy writer's files, which Holovox streams, against nibabel's NIfTI of that grid, and a
# NIfTI with NaN outside a mask (SPM's, FSL's), which is refused where nibabel finds the first.
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
# The wide types: nibabel's NIfTI, and MetaImage and NRRD written here from the same array.
f64 = data.astype(np.float64) * 1.5 - 20.25
i32 = data.astype(np.int32) * 1000 - 5000        # beyond int16
for name, arr in (("f64", f64), ("i32", i32)):
    out = nib.Nifti1Image(arr, A)
    out.set_data_dtype(arr.dtype)
    out.to_filename(sys.argv[2] + "/" + name + ".nii.gz")
def mha(arr, met, big, zipped):
    raw = arr.astype(arr.dtype.newbyteorder(">" if big else "<")).tobytes(order="F")
    extra = "BinaryDataByteOrderMSB = %s\n" % big
    if zipped:
        raw = zlib.compress(raw, 6)
        extra += "CompressedData = True\nCompressedDataSize = %d\n" % len(raw)
    return header(extra).replace(b"MET_UCHAR", met.encode()).replace(b"BinaryDataByteOrderMSB = False\n", b"", 1) + raw
def nrrd_of(arr, typ, big, zipped):
    raw = arr.astype(arr.dtype.newbyteorder(">" if big else "<")).tobytes(order="F")
    head = nrrd.replace(b"type: uint8", ("type: " + typ).encode())
    head = head.replace(b"encoding: gzip", ("encoding: %s\nendian: %s" % ("gzip" if zipped else "raw", "big" if big else "little")).encode())
    return head + (gzip.compress(raw, 6) if zipped else raw)
open(sys.argv[2] + "/f64-msb.mha", "wb").write(mha(f64, "MET_DOUBLE", True, False))
open(sys.argv[2] + "/f64-gzip.nrrd", "wb").write(nrrd_of(f64, "double", False, True))
open(sys.argv[2] + "/i32-zlib.mha", "wb").write(mha(i32, "MET_INT", False, True))
open(sys.argv[2] + "/i32-msb.nrrd", "wb").write(nrrd_of(i32, "int", True, False))
# VTK's own legacy writer (binary STRUCTURED_POINTS, no direction: the axes are LPS's), and
# nibabel's NIfTI of the same array with the affine such a file means.
import vtk
from vtk.util import numpy_support
o_lps = flip @ A[:3, 3]
lps = np.eye(4)
lps[:3, :3], lps[:3, 3] = flip @ np.diag(sp), flip @ o_lps   # RAS affine of an LPS-aligned grid
for name, arr in (("u8", data), ("f64", f64), ("i32", i32)):
    ref = nib.Nifti1Image(arr, lps)
    ref.set_data_dtype(arr.dtype)
    ref.to_filename(sys.argv[2] + "/lps-" + name + ".nii.gz")
    im = vtk.vtkImageData()
    im.SetDimensions(*arr.shape)
    im.SetSpacing(*sp)
    im.SetOrigin(*o_lps)
    scalars = numpy_support.numpy_to_vtk(np.ascontiguousarray(arr.ravel(order="F")), deep=1)
    scalars.SetName("v")
    im.GetPointData().SetScalars(scalars)
    w = vtk.vtkStructuredPointsWriter()
    w.SetInputData(im)
    w.SetFileTypeToBinary()
    w.SetFileName(sys.argv[2] + "/vtk-" + name + ".vtk")
    if w.Write() != 1: sys.exit("VTK could not write vtk-" + name + ".vtk")
# SPM's and FSL's way of saying "no value": NaN outside a mask. nibabel says where the first
# such slice is and how many it holds.
masked = data.astype(np.float32)
masked[data < 30] = np.nan
nib.Nifti1Image(masked, A).to_filename(sys.argv[2] + "/masked.nii.gz")
k = next(k for k in range(masked.shape[2]) if np.isnan(masked[:, :, k]).any())
open(sys.argv[2] + "/masked.expect", "w").write("slice %d holds %d NaN (not-a-number) values" % (k, np.isnan(masked[:, :, k]).sum()))
PY
"$cli" build "$nii" -o "$work/nii.hvo" --quiet
"$cli" render "$work/nii.hvo" --cpu --size 192x192 --tf mr-default -o "$work/nii.png" >/dev/null
geometry() { "$cli" info "$1" | grep -E "^ *(volume|spacing|origin|direction)" | sed "s/, [A-Z]*$//"; }  # not the modality
# same FILE REFERENCE: FILE builds REFERENCE's geometry and renders its image bit for bit
same() {
  "$cli" build "$work/$1" -o "$work/$1.hvo" --quiet
  diff <(geometry "$work/$2.hvo") <(geometry "$work/$1.hvo") || { echo "$1: another geometry than $2's"; exit 1; }
  "$cli" render "$work/$1.hvo" --cpu --size 192x192 --tf mr-default -o "$work/$1.png" >/dev/null
  cmp "$work/$2.png" "$work/$1.png" || { echo "$1 renders unlike $2"; exit 1; }
  echo "$1: the geometry and the image of $2"
}
for f in plain.mha zipped.mha gzip.nrrd; do same "$f" nii; done
for t in f64 i32 lps-u8 lps-f64 lps-i32; do
  "$cli" build "$work/$t.nii.gz" -o "$work/$t.hvo" --quiet
  "$cli" render "$work/$t.hvo" --cpu --size 192x192 --tf mr-default -o "$work/$t.png" >/dev/null
  [[ $t == *u8 ]] || grep -q "float32" <<<"$("$cli" info "$work/$t.hvo")" || { echo "$t: not kept as float32"; exit 1; }
done
for f in f64-msb.mha f64-gzip.nrrd; do same "$f" f64; done
for f in i32-zlib.mha i32-msb.nrrd; do same "$f" i32; done
for t in u8 f64 i32; do same "vtk-$t.vtk" "lps-$t"; done
# the float64 MetaImage is streamed by Holovox, and says what it keeps
said=$("$cli" build "$work/f64-msb.mha" -o "$work/again.hvo" 2>&1)
grep -q "f64-msb.mha: its 64-bit floats are kept as 32-bit floats" <<<"$said" ||
  { echo "f64-msb.mha: no warning that its float64 values are kept as float32: $said"; exit 1; }
# a float volume with NaN voxels is refused at the first such slice, and leaves no octree
if said=$("$cli" build "$work/masked.nii.gz" -o "$work/masked.hvo" 2>&1); then
  echo "masked.nii.gz: a volume with NaN voxels was built"; exit 1
fi
grep -qF "masked.nii.gz: $(cat "$work/masked.expect")" <<<"$said" || { echo "masked.nii.gz: not refused as nibabel counts: $said"; exit 1; }
[ ! -e "$work/masked.hvo" ] || { echo "masked.nii.gz: an octree was left behind"; exit 1; }
echo "masked.nii.gz: refused: $said"
