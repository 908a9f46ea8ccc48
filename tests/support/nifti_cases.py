#!/usr/bin/python3
"""Writes NIfTI-1 files with nibabel (the independent reference) for every combination the
NIfTI tests check, and, for each, what nibabel reads back: its affine (RAS+ mm, the sform when
sform_code > 0, else the qform) and its scaled voxel values in file order (i fastest) as
float64. Holovox must place and read every voxel the same way.

usage: nifti_cases.py OUT_DIR   (writes OUT_DIR/manifest.json and the files it names)
"""
import itertools
import json
import os
import sys

import nibabel as nib
import numpy as np


def rotation(axis, degrees):
    a = np.radians(degrees)
    c, s = np.cos(a), np.sin(a)
    x, y, z = np.asarray(axis, float) / np.linalg.norm(axis)
    return np.array([[c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s],
                     [y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s],
                     [z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)]])


def affine(rot, zooms, offset, flip_k=False):
    m = np.eye(4)
    m[:3, :3] = rot @ np.diag(zooms)
    if flip_k:
        m[:3, 2] *= -1
    m[:3, 3] = offset
    return m


def main(out):
    os.makedirs(out, exist_ok=True)
    rng = np.random.default_rng(7)
    cases = []

    def write(name, data, qaff, qcode, saff, scode, dtype, slope=None, inter=None, gz=False, big=False, units='mm'):
        img = nib.Nifti1Image(data.astype(dtype), None)
        hdr = img.header
        hdr.set_qform(qaff, code=qcode)
        hdr.set_sform(saff, code=scode)
        hdr.set_xyzt_units(xyz=units)
        if slope is not None:
            hdr.set_slope_inter(slope, inter)
        if big:  # the same image in big-endian byte order
            img = nib.Nifti1Image(data.astype(np.dtype(dtype).newbyteorder('>')), None, header=hdr.as_byteswapped('>'))
        path = os.path.join(out, name + ('.nii.gz' if gz else '.nii'))
        nib.save(img, path)
        back = nib.load(path)
        values = np.asarray(back.dataobj, dtype=np.float64)
        scale = {'mm': 1.0, 'meter': 1000.0, 'micron': 0.001}[units]
        expected = {
            'path': path,
            'name': name,
            'affine': (np.diag([scale, scale, scale, 1.0]) @ back.affine).tolist(),
            'qform_code': int(back.header['qform_code']),
            'sform_code': int(back.header['sform_code']),
            'qfac': float(back.header['pixdim'][0]),
            'shape': list(values.shape),
            'values': os.path.join(out, name + '.f64'),
        }
        values.ravel(order='F').astype('<f8').tofile(expected['values'])
        cases.append(expected)

    rot = rotation([1, 2, 3], 25)
    base_q = affine(rot, [1.1, 0.9, 2.0], [-40.5, 12.25, 7.0])
    # qform/sform codes x qfac x sform handedness x slice counts.
    for qcode, scode, qfac, smirror, nz in itertools.product([0, 1], [0, 2], [1, -1], [False, True], [3, 33, 300]):
        if qcode == 0 and (qfac == -1):
            continue  # qfac means nothing without a qform
        if scode == 0 and smirror:
            continue
        if qcode == 0 and scode == 0:
            continue  # placed by pixdim alone: nibabel's fallback is its own; tested separately
        shape = (5, 4, nz) if nz == 300 else (9, 7, nz)
        data = rng.integers(-2000, 3000, size=shape)
        q = affine(rot, [1.1, 0.9, 2.0], [-40.5, 12.25, 7.0], flip_k=qfac < 0)
        s = affine(rotation([0, 0, 1], 90) @ np.diag([-1 if smirror else 1, 1, 1]), [0.8, 0.8, 1.5], [90, -126, -72])
        s[0, 1] += 0.05  # a little shear: the sform is an affine, not a rotation
        write(f'q{qcode}s{scode}f{qfac:+d}m{int(smirror)}z{nz}', data, q, qcode, s, scode, np.int16, gz=nz == 33)
    # The usual FSL/MNI storage: a negative qfac, qform and sform equal, many slices.
    mni = np.array([[-2.0, 0, 0, 90], [0, 2, 0, -126], [0, 0, 2, -72], [0, 0, 0, 1]])
    write('mni_las', rng.integers(0, 255, size=(91, 109, 91)), mni, 4, mni, 4, np.uint8, gz=True)
    # Types, scaling, byte order and units.
    for dtype in [np.uint8, np.int8, np.int16, np.uint16, np.int32, np.uint32, np.float32, np.float64]:
        info = np.iinfo(dtype) if np.issubdtype(dtype, np.integer) else None
        lo, hi = (max(info.min, -30000), min(info.max, 40000)) if info else (-1000.5, 1000.5)
        data = rng.uniform(lo, hi, size=(6, 5, 4))
        if info:
            data = np.round(data)
        write('type_' + np.dtype(dtype).name, data, base_q, 1, base_q, 0, dtype)
    write('scaled', rng.integers(-100, 100, size=(6, 5, 4)), base_q, 1, base_q, 2, np.int16, slope=2.5, inter=-10.0)
    write('bigendian', rng.integers(-3000, 3000, size=(6, 5, 7)), base_q, 1, base_q, 0, np.int16, big=True)
    write('micron', rng.integers(0, 200, size=(6, 5, 4)), base_q, 1, base_q, 0, np.uint8, units='micron')
    # 4D: three time points.
    write('fourd', rng.integers(-500, 500, size=(6, 5, 4, 3)), base_q, 1, base_q, 2, np.int16)
    # Disagreeing qform and sform: 12 mm apart, and mirrored.
    shifted = base_q.copy()
    shifted[:3, 3] += [12, 0, 0]
    write('disagree_shift', rng.integers(0, 9, size=(4, 4, 4)), base_q, 1, shifted, 2, np.int16)
    mirrored = base_q.copy()
    mirrored[:3, 0] *= -1
    write('disagree_mirror', rng.integers(0, 9, size=(4, 4, 4)), base_q, 1, mirrored, 2, np.int16)
    write('no_orientation', rng.integers(0, 9, size=(4, 4, 4)), base_q, 0, base_q, 0, np.int16)
    with open(os.path.join(out, 'manifest.json'), 'w') as f:
        json.dump(cases, f, indent=1)
    print(f'{len(cases)} NIfTI cases written by nibabel {nib.__version__}')


if __name__ == '__main__':
    main(sys.argv[1])
