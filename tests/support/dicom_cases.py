#!/usr/bin/python3
"""Writes DICOM series with pydicom (an independent writer) whose images share positions, as
real multi-volume acquisitions do, in shuffled file-name order:

  echo/       dual-echo MR: EchoNumbers 1 and 2 (TE 10 and 20 ms), 12 slices each
  diffusion/  three b-values (0, 500, 1000 s/mm2), 8 slices each
  dynamic/    ten time points (TemporalPositionIdentifier 1..10), 6 slices each
  twins/      two images at each of 5 positions that nothing tells apart

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


def main(out):
    os.makedirs(out, exist_ok=True)
    series(out, 'echo', 2, 12, lambda v: {'EchoNumbers': v + 1, 'EchoTime': str(10 * (v + 1))})
    series(out, 'diffusion', 3, 8, lambda v: {'DiffusionBValue': [0.0, 500.0, 1000.0][v],
                                               'DiffusionGradientOrientation': [0.0, 0.0, 0.0] if v == 0
                                               else [0.6, 0.8, 0.0]})
    series(out, 'dynamic', 10, 6, lambda v: {'TemporalPositionIdentifier': v + 1,
                                             'NumberOfTemporalPositions': 10, 'EchoTime': '5'})
    series(out, 'twins', 2, 5, lambda v: {}, twins=True)
    print('written', sorted(os.listdir(out)))


if __name__ == '__main__':
    main(sys.argv[1])
