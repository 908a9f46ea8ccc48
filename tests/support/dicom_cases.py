#!/usr/bin/python3
"""Writes DICOM series with pydicom (an independent writer) whose images share positions, as
real multi-volume acquisitions do, in shuffled file-name order:

  echo/       dual-echo MR: EchoNumbers 1 and 2 (TE 10 and 20 ms), 12 slices each
  diffusion/  three b-values (0, 500, 1000 s/mm2), 8 slices each
  dynamic/    ten time points (TemporalPositionIdentifier 1..10), 6 slices each
  twins/      two images at each of 5 positions that nothing tells apart
  offline/    6 slices, the 4th (instance 4) moved 2 mm off the stack's line
  nogeometry/ 4 slices without PixelSpacing and ImageOrientationPatient
  localizer/  one enhanced MR object: 3 frames in each of 3 orientations (a three-plane localizer)
  enhanced1/  a single-frame enhanced MR object whose position and rescale are per-frame only
  dose/       RT dose: 3 planes with absolute GridFrameOffsetVector, and a single plane, scaled
  uint32/     4 slices of 32-bit unsigned pixels at and above 2^31
  windows/    3 CT slices with two windows (WindowCenter/Width and their explanations)
  nm/         an NM multi-frame object (4 frames), which Holovox cannot place
  float/      3 slices of Float Pixel Data; double/: 3 slices of Double Float Pixel Data

Each volume's pixels differ (value = 1000 * volume + 100 * slice + column + 7 * row), so
a mixed volume cannot pass. usage: dicom_cases.py OUT_DIR
"""
import math
import os
import random
import sys

import numpy as np
import pydicom
from pydicom.dataset import Dataset, FileDataset, FileMetaDataset
from pydicom.uid import ExplicitVRLittleEndian, generate_uid

MR = '1.2.840.10008.5.1.4.1.1.4'
ROWS, COLS = 12, 16
ANGLE = math.radians(12)
IOP = [1, 0, 0, 0, math.cos(ANGLE), -math.sin(ANGLE)]
NORMAL = np.cross(IOP[:3], IOP[3:])


def image(series_uid, study_uid, for_uid, number, slice_index, volume, extra, spacing=2.5):
    meta = FileMetaDataset()
    meta.MediaStorageSOPClassUID = MR
    meta.MediaStorageSOPInstanceUID = generate_uid()
    meta.TransferSyntaxUID = ExplicitVRLittleEndian
    ds = FileDataset(None, {}, file_meta=meta, preamble=b'\0' * 128)
    ds.SOPClassUID = MR
    ds.SOPInstanceUID = meta.MediaStorageSOPInstanceUID
    ds.PatientName = 'MULTI^VOLUME'
    ds.PatientID = 'MV1'
    ds.StudyInstanceUID = study_uid
    ds.SeriesInstanceUID = series_uid
    ds.FrameOfReferenceUID = for_uid
    ds.StudyDate = '20240301'
    ds.Modality = 'MR'
    ds.SeriesNumber = 7
    ds.InstanceNumber = number
    ds.ImageType = ['ORIGINAL', 'PRIMARY', 'M', 'ND']
    ds.ImageOrientationPatient = [f'{v:.6f}' for v in IOP]
    pos = np.array([-20.0, -15.0, 30.0]) + NORMAL * spacing * slice_index
    ds.ImagePositionPatient = [f'{v:.4f}' for v in pos]
    ds.PixelSpacing = ['0.9', '1.1']
    ds.SliceThickness = str(spacing)
    ds.Rows, ds.Columns = ROWS, COLS
    ds.SamplesPerPixel = 1
    ds.PhotometricInterpretation = 'MONOCHROME2'
    ds.BitsAllocated = ds.BitsStored = 16
    ds.HighBit = 15
    ds.PixelRepresentation = 1
    r, c = np.mgrid[0:ROWS, 0:COLS]
    ds.PixelData = (1000 * volume + 100 * slice_index + c + 7 * r).astype('<i2').tobytes()
    for k, v in extra.items():
        setattr(ds, k, v)
    return ds


def series(out, name, volumes, slices, extra_of, twins=False):
    folder = os.path.join(out, name)
    os.makedirs(folder, exist_ok=True)
    study, uid, frame = generate_uid(), generate_uid(), generate_uid()
    images = []
    n = 0
    for v in range(volumes):
        for s in range(slices):
            n += 1
            images.append(image(uid, study, frame, n, s, 0 if twins else v, extra_of(v)))
    random.Random(name).shuffle(images)
    for i, ds in enumerate(images):
        ds.save_as(os.path.join(folder, f'IM{i:04d}'), write_like_original=False)
    return uid


def save(ds, path):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    ds.save_as(path, write_like_original=False)


def extras(out):
    uid, study, frame = generate_uid(), generate_uid(), generate_uid()
    for s in range(6):
        ds = image(uid, study, frame, s + 1, s, 0, {})
        if s == 3:
            pos = [float(v) for v in ds.ImagePositionPatient]
            ds.ImagePositionPatient = [f'{pos[0] + 2.0:.4f}', f'{pos[1]:.4f}', f'{pos[2]:.4f}']
        save(ds, os.path.join(out, 'offline', f'IM{s}'))
    uid = generate_uid()
    for s in range(4):
        ds = image(uid, study, frame, s + 1, s, 0, {})
        del ds.PixelSpacing
        del ds.ImageOrientationPatient
        save(ds, os.path.join(out, 'nogeometry', f'IM{s}'))

    def enhanced(frames, name):
        """frames: list of (iop, ipp, slope, intercept); pixels = 1000 * frame + column."""
        ds = image(generate_uid(), study, frame, 1, 0, 0, {})
        ds.SOPClassUID = ds.file_meta.MediaStorageSOPClassUID = '1.2.840.10008.5.1.4.1.1.4.1'
        for k in ['ImageOrientationPatient', 'ImagePositionPatient', 'PixelSpacing', 'SliceThickness']:
            delattr(ds, k)
        shared = Dataset()
        pm = Dataset()
        pm.PixelSpacing = ['0.9', '1.1']
        pm.SliceThickness = '3'
        shared.PixelMeasuresSequence = [pm]
        ds.SharedFunctionalGroupsSequence = [shared]
        per = []
        for iop, ipp, slope, intercept in frames:
            item = Dataset()
            po = Dataset()
            po.ImageOrientationPatient = [f'{v:.6f}' for v in iop]
            pp = Dataset()
            pp.ImagePositionPatient = [f'{v:.4f}' for v in ipp]
            tr = Dataset()
            tr.RescaleSlope = str(slope)
            tr.RescaleIntercept = str(intercept)
            tr.RescaleType = 'US'
            item.PlaneOrientationSequence = [po]
            item.PlanePositionSequence = [pp]
            item.PixelValueTransformationSequence = [tr]
            per.append(item)
        ds.PerFrameFunctionalGroupsSequence = per
        ds.NumberOfFrames = len(frames)
        r, c = np.mgrid[0:ROWS, 0:COLS]
        ds.PixelData = b''.join((1000 * f + c + 0 * r).astype('<i2').tobytes() for f in range(len(frames)))
        save(ds, os.path.join(out, name, 'IM0'))

    axial = [1, 0, 0, 0, 1, 0]
    coronal = [1, 0, 0, 0, 0, -1]
    sagittal = [0, 1, 0, 0, 0, -1]
    frames = []
    for p in range(3):  # interleaved, as scanners store them
        frames.append((axial, [-10, -8, 5.0 + 4 * p], 1, 0))
        frames.append((coronal, [-10, 3.0 + 4 * p, 20], 1, 0))
        frames.append((sagittal, [2.0 + 4 * p, -8, 20], 1, 0))
    enhanced(frames, 'localizer')
    enhanced([(axial, [11.5, -7.25, 42.0], 2, -100)], 'enhanced1')

    def dose(name, planes, offsets):
        ds = image(generate_uid(), study, frame, 1, 0, 0, {})
        ds.SOPClassUID = ds.file_meta.MediaStorageSOPClassUID = '1.2.840.10008.5.1.4.1.1.481.2'
        ds.Modality = 'RTDOSE'
        ds.ImageOrientationPatient = ['1', '0', '0', '0', '1', '0']
        ds.ImagePositionPatient = ['-10', '-8', '-40']
        ds.PixelRepresentation = 0
        ds.DoseGridScaling = '0.001'
        ds.DoseUnits = 'GY'
        ds.NumberOfFrames = planes
        if offsets is not None:
            ds.GridFrameOffsetVector = [str(o) for o in offsets]
        r, c = np.mgrid[0:ROWS, 0:COLS]
        ds.PixelData = b''.join((1000 * (f + 1) + c).astype('<u2').tobytes() for f in range(planes))
        save(ds, os.path.join(out, name, 'IM0'))

    dose('dose', 3, [-40, -37, -34])   # absolute: the first is the plane at ImagePositionPatient
    dose('dose1', 1, None)
    uid = generate_uid()
    for s in range(4):
        ds = image(uid, study, frame, s + 1, s, 0, {})
        ds.BitsAllocated = ds.BitsStored = 32
        ds.HighBit = 31
        ds.PixelRepresentation = 0
        r, c = np.mgrid[0:ROWS, 0:COLS]
        ds.PixelData = (2147483648 + 1000 * s + c + 0 * r).astype('<u4').tobytes()
        save(ds, os.path.join(out, 'uint32', f'IM{s}'))
    uid = generate_uid()
    for s in range(3):
        ds = image(uid, study, frame, s + 1, s, 0, {})
        ds.Modality = 'CT'
        ds.RescaleSlope, ds.RescaleIntercept = '1', '-1024'
        ds.WindowCenter = ['40', '300']
        ds.WindowWidth = ['400', '1500']
        ds.WindowCenterWidthExplanation = ['SOFT TISSUE', 'BONE']
        save(ds, os.path.join(out, 'windows', f'IM{s}'))
    ds = image(generate_uid(), study, frame, 1, 0, 0, {})
    ds.SOPClassUID = ds.file_meta.MediaStorageSOPClassUID = '1.2.840.10008.5.1.4.1.1.20'
    ds.Modality = 'NM'
    ds.NumberOfFrames = 4
    ds.PixelData = ds.PixelData * 4
    save(ds, os.path.join(out, 'nm', 'IM0'))
    def float_series(name, element, dtype, bits, pixels):
        """Three slices of Float (32) or Double Float (64) Pixel Data, pixels(s) giving slice s."""
        uid = generate_uid()
        for s in range(3):
            ds = image(uid, study, frame, s + 1, s, 0, {})
            del ds.PixelData
            del ds.PixelRepresentation
            del ds.BitsStored
            del ds.HighBit
            ds.BitsAllocated = bits
            setattr(ds, element, pixels(s).astype(dtype).tobytes())
            save(ds, os.path.join(out, name, f'IM{s}'))
    r, c = np.mgrid[0:ROWS, 0:COLS]
    for name, element, dtype, bits in [('float', 'FloatPixelData', '<f4', 32), ('double', 'DoubleFloatPixelData', '<f8', 64)]:
        float_series(name, element, dtype, bits, lambda s: 0.125 * c - 0.5 * r + 1000.25 * s - 3.75)
    # A parametric map's "no value" (NaN) in the float series' second slice, and a float64
    # beyond what a float32 holds in the double series' third.
    def with_bad(slice_, bad):
        def pixels(s):
            v = np.full((ROWS, COLS), 7.5)
            if s == slice_:
                v[3, 4] = v[5, 6] = bad
            return v
        return pixels
    float_series('float-nan', 'FloatPixelData', '<f4', 32, with_bad(1, np.nan))
    float_series('double-huge', 'DoubleFloatPixelData', '<f8', 64, with_bad(2, 1e300))
    padding_cases(out, study, frame)


def padding_cases(out, study, frame):
    """CT padding: row 0 is the padding value (-2000), row 1 lies inside the Pixel Padding Range
    Limit (-1600, limit -1500) in 'range'; slice 0's rescale differs from the others' in
    'rescale'; the padding value is written US (63536) beside signed pixels in 'us'. Every
    other pixel is HU 100 + 2c after the rescale. Then a decimal comma, PALETTE COLOR
    pixels, and an orientation that differs by 2e-6 between slices."""
    def ct(uid, s, name, edit):
        ds = image(uid, study, frame, s + 1, s, 0, {})
        ds.Modality = 'CT'
        r, c = np.mgrid[0:ROWS, 0:COLS]
        slope, inter = (2.0, -2048.0) if (name == 'pad-rescale' and s == 0) else (1.0, -1024.0)
        stored = ((100 + 2 * c + 0 * r) - inter) / slope  # even HU: whole stored values under slope 2
        stored[0, :] = -2000
        if name == 'pad-range':
            stored[1, :] = -1600
        ds.RescaleSlope, ds.RescaleIntercept = f'{slope:g}', f'{inter:g}'
        ds.PixelData = stored.astype('<i2').tobytes()
        ds.add_new(0x00280120, 'SS', -2000)  # Pixel Padding Value
        edit(ds)
        save(ds, os.path.join(out, name, f'IM{s}'))
    def range_limit(ds):
        ds.add_new(0x00280121, 'SS', -1500)  # Pixel Padding Range Limit
    def unsigned_padding(ds):
        del ds[0x00280120]
        ds.add_new(0x00280120, 'US', 63536)  # the bits of -2000, written as if unsigned
    for name, edit in [('pad-rescale', lambda ds: None), ('pad-range', range_limit), ('pad-us', unsigned_padding)]:
        uid = generate_uid()
        for s in range(4):
            ct(uid, s, name, edit)
    uid = generate_uid()
    for s in range(3):  # written as -20.5, then its bytes turned into a decimal comma
        ds = image(uid, study, frame, s + 1, s, 0, {})
        ds.ImagePositionPatient = ['-20.5', '-15', f'{30 + 2.5 * s:.1f}']
        path = os.path.join(out, 'decimal-comma', f'IM{s}')
        save(ds, path)
        with open(path, 'rb') as f:
            data = f.read()
        assert b'-20.5\\-15' in data
        with open(path, 'wb') as f:
            f.write(data.replace(b'-20.5\\-15', b'-20,5\\-15'))
    uid = generate_uid()
    for s in range(3):
        ds = image(uid, study, frame, s + 1, s, 0, {})
        ds.PhotometricInterpretation = 'PALETTE COLOR'
        ds.PixelRepresentation = 0
        save(ds, os.path.join(out, 'palette', f'IM{s}'))
    uid = generate_uid()
    for s in range(8):  # cosines 0.000051 and 0.000049 on alternate slices: one stack
        ds = image(uid, study, frame, s + 1, s, 0, {})
        iop = [float(v) for v in ds.ImageOrientationPatient]
        iop[2] = 0.000051 if s % 2 == 0 else 0.000049
        ds.ImageOrientationPatient = [f'{v:.6f}' for v in iop]
        save(ds, os.path.join(out, 'iop-jitter', f'IM{s}'))


def acquisition_cases(out):
    """Where only some attributes tell acquisitions apart:
      gated/      acquisitions 1 and 2 at the same 5 positions, a TriggerTime different on
                  every image (as gated scanners write it): two volumes, not ten of one slice
      echo-te/    two echoes both numbered 1, TE 10 and 80 ms: two volumes
      offset/     acquisitions 1 and 2 of 5 slices 2.5 mm apart, the second 0.3 mm higher
                  (pre- and post-contrast): two volumes, never interleaved into one
      near/       two images 2 um apart at each of 5 positions, nothing tells them apart:
                  refused (they had been resampled to some 6000 slices)
      unplaced/   5 slices, the middle one without ImagePositionPatient: left out
      skew/       5 slices whose rows and columns are 80 degrees apart: refused
      skew-small/ 5 slices whose rows and columns are 89.8 degrees apart: placed, with a warning
      pad-unsigned/ 3 unsigned CT slices, intercept -1000, PixelPaddingValue 0: padding is
                  -1000 HU (the lowest the type holds), and the warning says so
      dti-two-b0/ two b0 and two b1000 volumes of 4 slices, an AcquisitionNumber each: four
                  volumes named by b-value first (not by acquisition alone)
      interleaved/ one stack of 10 slices whose odd and even slices carry AcquisitionNumber 2
                  and 1, slice 8 lost: one volume with a missing slice, not two at twice the spacing
      noplace-echo/ two echoes of 3 slices, none with ImagePositionPatient: two volumes (the
                  echoes had been stacked together in file order)
      iodine/     3 CT slices of a dual-energy iodine map, RescaleType MGML, slope 0.001, with
                  PixelPaddingValue -5: its values are not HU (and padding is not made -1024)
    Volume v's pixels are 1000 * v + 100 * slice + column + 7 * row, as elsewhere."""
    study, frame = generate_uid(), generate_uid()
    def write(name, images):
        for i, ds in enumerate(images):
            save(ds, os.path.join(out, name, f'IM{i:04d}'))
    uid, images, n = generate_uid(), [], 0
    for v in range(2):
        for s in range(5):
            n += 1
            images.append(image(uid, study, frame, n, s, v, {'AcquisitionNumber': v + 1, 'TriggerTime': str(37 * n)}))
    write('gated', images)
    uid, images, n = generate_uid(), [], 0
    for v in range(2):
        for s in range(5):
            n += 1
            images.append(image(uid, study, frame, n, s, v, {'EchoNumbers': 1, 'EchoTime': ['10', '80'][v]}))
    write('echo-te', images)
    uid, images, n = generate_uid(), [], 0
    for v in range(2):
        for s in range(5):
            n += 1
            ds = image(uid, study, frame, n, s, v, {'AcquisitionNumber': v + 1})
            pos = np.array([-20.0, -15.0, 30.0]) + NORMAL * (2.5 * s + 0.3 * v)
            ds.ImagePositionPatient = [f'{x:.4f}' for x in pos]
            images.append(ds)
    write('offset', images)
    uid, images, n = generate_uid(), [], 0
    for v in range(2):
        for s in range(5):
            n += 1
            ds = image(uid, study, frame, n, s, v, {})
            pos = np.array([-20.0, -15.0, 30.0]) + NORMAL * (2.5 * s + 0.002 * v)
            ds.ImagePositionPatient = [f'{x:.4f}' for x in pos]
            images.append(ds)
    write('near', images)
    uid, images = generate_uid(), []
    for s in range(5):
        ds = image(uid, study, frame, s + 1, s, 0, {})
        if s == 2:
            del ds.ImagePositionPatient
        images.append(ds)
    write('unplaced', images)
    for name, degrees in [('skew', 80.0), ('skew-small', 89.8)]:
        uid, images = generate_uid(), []
        a = math.radians(degrees)
        for s in range(5):
            ds = image(uid, study, frame, s + 1, s, 0, {})
            ds.ImageOrientationPatient = [f'{x:.6f}' for x in [1, 0, 0, math.cos(a), math.sin(a), 0]]
            ds.ImagePositionPatient = ['0', '0', f'{2.5 * s:.1f}']
            images.append(ds)
        write(name, images)
    uid, images = generate_uid(), []
    for s in range(3):
        ds = image(uid, study, frame, s + 1, s, 0, {})
        ds.Modality = 'CT'
        ds.PixelRepresentation = 0
        ds.RescaleSlope, ds.RescaleIntercept = '1', '-1000'
        r, c = np.mgrid[0:ROWS, 0:COLS]
        stored = 1100 + 2 * c + 0 * r
        stored[0, :] = 0
        ds.PixelData = stored.astype('<u2').tobytes()
        ds.add_new(0x00280120, 'US', 0)  # Pixel Padding Value
        images.append(ds)
    write('pad-unsigned', images)
    uid, images = generate_uid(), []
    for s in range(3):
        ds = image(uid, study, frame, s + 1, s, 0, {})
        ds.Modality = 'CT'
        ds.RescaleSlope, ds.RescaleIntercept, ds.RescaleType = '0.001', '0', 'MGML'
        r, c = np.mgrid[0:ROWS, 0:COLS]
        stored = 7000 + 0 * c + 0 * r  # 7 mg/ml everywhere but row 0
        stored[0, :] = -5
        ds.PixelData = stored.astype('<i2').tobytes()
        ds.add_new(0x00280120, 'SS', -5)  # Pixel Padding Value
        images.append(ds)
    write('iodine', images)
    uid, images, n = generate_uid(), [], 0
    for v in range(2):
        for s in range(3):
            n += 1
            ds = image(uid, study, frame, n, s, v, {'EchoNumbers': v + 1, 'EchoTime': ['10', '20'][v]})
            del ds.ImagePositionPatient
            images.append(ds)
    write('noplace-echo', images)
    uid, images, n = generate_uid(), [], 0
    for v, (b, g) in enumerate([(0.0, [0.0, 0.0, 0.0]), (0.0, [0.0, 0.0, 0.0]), (1000.0, [0.6, 0.8, 0.0]),
                                (1000.0, [0.0, 0.6, 0.8])]):
        for s in range(4):
            n += 1
            images.append(image(uid, study, frame, n, s, v, {'AcquisitionNumber': v + 1, 'DiffusionBValue': b,
                                                             'DiffusionGradientOrientation': g}))
    write('dti-two-b0', images)
    uid, images = generate_uid(), []
    for s in range(10):
        if s == 8:
            continue  # lost
        images.append(image(uid, study, frame, s + 1, s, 0, {'AcquisitionNumber': 1 + s % 2}))
    write('interleaved', images)


def charset_cases(out):
    """charsets/: one image per SpecificCharacterSet, the patient's name in it, pydicom encoding:
    IM0 ISO_IR 100 Müller^Jürgen, IM1 ISO_IR 144 Иванов^Иван, IM2 GB18030 王^小明."""
    study, frame = generate_uid(), generate_uid()
    for i, (charset, name) in enumerate([('ISO_IR 100', 'Müller^Jürgen'), ('ISO_IR 144', 'Иванов^Иван'),
                                         ('GB18030', '王^小明')]):
        ds = image(generate_uid(), study, frame, 1, 0, 0, {})
        ds.SpecificCharacterSet = charset
        ds.PatientName = name
        ds.StudyDescription = name.split('^')[0]
        save(ds, os.path.join(out, 'charsets', f'IM{i}'))


def main(out):
    os.makedirs(out, exist_ok=True)
    series(out, 'echo', 2, 12, lambda v: {'EchoNumbers': v + 1, 'EchoTime': str(10 * (v + 1))})
    series(out, 'diffusion', 3, 8, lambda v: {'DiffusionBValue': [0.0, 500.0, 1000.0][v],
                                               'DiffusionGradientOrientation': [0.0, 0.0, 0.0] if v == 0
                                               else [0.6, 0.8, 0.0]})
    series(out, 'dynamic', 10, 6, lambda v: {'TemporalPositionIdentifier': v + 1,
                                             'NumberOfTemporalPositions': 10, 'EchoTime': '5'})
    series(out, 'twins', 2, 5, lambda v: {}, twins=True)
    extras(out)
    acquisition_cases(out)
    charset_cases(out)
    print('written', sorted(os.listdir(out)))


if __name__ == '__main__':
    main(sys.argv[1])
