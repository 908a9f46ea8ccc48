#!/usr/bin/python3
"""Writes DICOM Segmentation objects with pydicom (an independent writer), on a rotated grid of
30 x 26 pixels (not a multiple of 8: binary frames are not byte-aligned) and 14 slice positions:

  binary.dcm      BINARY, segments 1 "liver" (a ball) and 2 "spleen" (a box), frames only where
                  a segment has pixels, in shuffled order, bits packed across frame boundaries
  fractional.dcm  FRACTIONAL (PROBABILITY, max 200): segment 1 as the ball's probability, so
                  that the 50 % threshold gives back the ball
  noposition.dcm  the binary object without its frames' PlanePositionSequence
  labels.txt      "x y z label" (LPS mm) at every voxel centre of the grid: what a reader must
                  find there (0: no segment)
  image/          the CT the segmentation was drawn on: 14 slices of the same grid and frame of
                  reference (40 HU everywhere)
  ball.txt        the ball's centre, "x y z" (LPS mm)

usage: seg_cases.py OUT_DIR"""
import copy
import math
import random
import sys

import numpy as np
from pydicom.dataset import Dataset, FileDataset, FileMetaDataset
from pydicom.sequence import Sequence
from pydicom.uid import ExplicitVRLittleEndian, generate_uid

SEG = '1.2.840.10008.5.1.4.1.1.66.4'
COLS, ROWS, SLICES = 30, 26, 14
SPACING = (0.9, 0.8)  # PixelSpacing: between rows, between columns
STEP = 2.5
a = math.radians(20)
ROW_DIR = np.array([math.cos(a), math.sin(a), 0.0])
COL_DIR = np.array([-math.sin(a) * math.cos(0.3), math.cos(a) * math.cos(0.3), -math.sin(0.3)])
NORMAL = np.cross(ROW_DIR, COL_DIR)
ORIGIN = np.array([-12.0, -9.5, 20.0])
FOR_UID = '1.2.826.0.1.3680043.9.7777.60'


def position(i, j, k):
    return ORIGIN + i * SPACING[1] * ROW_DIR + j * SPACING[0] * COL_DIR + k * STEP * NORMAL


i, j, k = np.meshgrid(np.arange(COLS), np.arange(ROWS), np.arange(SLICES), indexing='ij')
P = ORIGIN + (i[..., None] * SPACING[1] * ROW_DIR + j[..., None] * SPACING[0] * COL_DIR +
              k[..., None] * STEP * NORMAL)
centre = position(10.3, 12.1, 6.2)
dist = np.linalg.norm(P - centre, axis=-1)
ball = dist < 7.0
box = (i >= 20) & (i < 27) & (j >= 3) & (j < 9) & (k >= 2) & (k < 5)
labels = np.zeros(i.shape, np.uint8)
labels[ball] = 1
labels[box] = 2


def dataset(kind, number=300):
    meta = FileMetaDataset()
    meta.MediaStorageSOPClassUID = SEG
    meta.MediaStorageSOPInstanceUID = generate_uid()
    meta.TransferSyntaxUID = ExplicitVRLittleEndian
    ds = FileDataset(None, {}, file_meta=meta, preamble=b'\0' * 128)
    ds.SOPClassUID = SEG
    ds.SOPInstanceUID = meta.MediaStorageSOPInstanceUID
    ds.PatientName, ds.PatientID, ds.PatientBirthDate, ds.PatientSex = 'SEG^PHANTOM', 'SEG1', '19700101', 'O'
    ds.StudyInstanceUID = '1.2.826.0.1.3680043.9.7777.61'
    ds.StudyDate, ds.StudyTime, ds.StudyID, ds.AccessionNumber, ds.ReferringPhysicianName = '20240301', '120000', '1', '', ''
    ds.SeriesInstanceUID = generate_uid()
    ds.SeriesNumber, ds.Modality = number, 'SEG'
    ds.SeriesDescription = f'{kind} segmentation'
    ds.FrameOfReferenceUID, ds.PositionReferenceIndicator = FOR_UID, ''
    ds.Manufacturer, ds.ManufacturerModelName, ds.DeviceSerialNumber, ds.SoftwareVersions = 'pydicom', 'seg_cases', '1', '1'
    ds.InstanceNumber = 1
    ds.ImageType = ['DERIVED', 'PRIMARY']
    ds.ContentLabel, ds.ContentDescription, ds.ContentCreatorName = 'SEGMENTATION', 'test', 'TEST^WRITER'
    ds.ContentDate, ds.ContentTime = '20240301', '120000'
    ds.SamplesPerPixel, ds.PhotometricInterpretation = 1, 'MONOCHROME2'
    ds.Rows, ds.Columns = ROWS, COLS
    ds.PixelRepresentation = 0
    ds.LossyImageCompression = '00'
    if kind == 'binary':
        ds.BitsAllocated, ds.BitsStored, ds.HighBit = 1, 1, 0
        ds.SegmentationType = 'BINARY'
    else:
        ds.BitsAllocated, ds.BitsStored, ds.HighBit = 8, 8, 7
        ds.SegmentationType = 'FRACTIONAL'
        ds.SegmentationFractionalType = 'PROBABILITY'
        ds.MaximumFractionalValue = 200
    segments = []
    for number, name, lab in [(1, 'liver', [21000, 45000, 40000]), (2, 'spleen', [30000, 30000, 20000])]:
        s = Dataset()
        s.SegmentNumber, s.SegmentLabel, s.SegmentAlgorithmType = number, name, 'MANUAL'
        code = Dataset()
        code.CodeValue, code.CodingSchemeDesignator, code.CodeMeaning = '123037004', 'SCT', 'Anatomical Structure'
        s.SegmentedPropertyCategoryCodeSequence = Sequence([code])
        t = Dataset()
        t.CodeValue, t.CodingSchemeDesignator, t.CodeMeaning = ('10200004', 'SCT', 'Liver') if number == 1 else (
            '78961009', 'SCT', 'Spleen')
        s.SegmentedPropertyTypeCodeSequence = Sequence([t])
        s.RecommendedDisplayCIELabValue = lab
        segments.append(s)
    ds.SegmentSequence = Sequence(segments)
    shared = Dataset()
    pm = Dataset()
    pm.PixelSpacing = [f'{v}' for v in SPACING]
    pm.SliceThickness = f'{STEP}'
    pm.SpacingBetweenSlices = f'{STEP}'
    shared.PixelMeasuresSequence = Sequence([pm])
    po = Dataset()
    po.ImageOrientationPatient = [f'{v:.8f}' for v in list(ROW_DIR) + list(COL_DIR)]
    shared.PlaneOrientationSequence = Sequence([po])
    ds.SharedFunctionalGroupsSequence = Sequence([shared])
    dim = Dataset()
    dim.DimensionOrganizationUID = generate_uid()
    ds.DimensionOrganizationSequence = Sequence([dim])
    ds.DimensionOrganizationType = '3D'
    ids = []
    for pointer, group in [(0x0062000B, 0x0062000A), (0x00200032, 0x00209113)]:
        d = Dataset()
        d.DimensionOrganizationUID = dim.DimensionOrganizationUID
        d.DimensionIndexPointer, d.FunctionalGroupPointer = pointer, group
        ids.append(d)
    ds.DimensionIndexSequence = Sequence(ids)
    return ds


def frames(kind):
    """(segment, slice, 2D array rows x cols) for each frame that has something."""
    out = []
    for seg in (1, 2):
        for s in range(SLICES):
            if kind == 'binary':
                plane = (labels[:, :, s] == seg).T.astype(np.uint8)
            else:
                if seg == 2:
                    continue
                # Probability from the distance: above 0.5 exactly inside the ball.
                p = np.clip(0.5 + (7.0 - dist[:, :, s]) / 4.0, 0, 1)
                plane = np.round(p * 200).astype(np.uint8).T
                plane[(plane >= 100) & (~ball[:, :, s].T)] = 99
                plane[(plane < 100) & ball[:, :, s].T] = 100
            if plane.any():
                out.append((seg, s, plane))
    random.Random(3).shuffle(out)
    return out


def code(value, scheme, meaning):
    c = Dataset()
    c.CodeValue, c.CodingSchemeDesignator, c.CodeMeaning = value, scheme, meaning
    return c


CT_SERIES, CT_INSTANCES = '', []  # the image series the SEG and RTSTRUCT refer to (image_series)


def image_references(sequence_item):
    """The CT's instances, as a Referenced Instance or Contour Image Sequence names them."""
    refs = []
    for uid in CT_INSTANCES:
        r = Dataset()
        r.ReferencedSOPClassUID, r.ReferencedSOPInstanceUID = '1.2.840.10008.5.1.4.1.1.2', uid
        refs.append(r)
    return Sequence(refs)


def write(path, kind, number, positions=True):
    ds = dataset(kind, number)
    ref = Dataset()
    ref.SeriesInstanceUID = CT_SERIES
    ref.ReferencedInstanceSequence = image_references(ref)
    ds.ReferencedSeriesSequence = Sequence([ref])
    fr = frames(kind)
    per = []
    for n, (seg, s, _) in enumerate(fr):
        f = Dataset()
        fc = Dataset()
        fc.DimensionIndexValues = [seg, s + 1]
        f.FrameContentSequence = Sequence([fc])
        if positions:
            pp = Dataset()
            pp.ImagePositionPatient = [f'{v:.6f}' for v in position(0, 0, s)]
            f.PlanePositionSequence = Sequence([pp])
        si = Dataset()
        si.ReferencedSegmentNumber = seg
        f.SegmentIdentificationSequence = Sequence([si])
        # Derived from the CT slice at the same position, as segmentation tools write it.
        src = Dataset()
        src.ReferencedSOPClassUID, src.ReferencedSOPInstanceUID = '1.2.840.10008.5.1.4.1.1.2', CT_INSTANCES[s]
        src.PurposeOfReferenceCodeSequence = Sequence([code('121322', 'DCM', 'Source image for image processing operation')])
        der = Dataset()
        der.SourceImageSequence = Sequence([src])
        der.DerivationCodeSequence = Sequence([code('113076', 'DCM', 'Segmentation')])
        f.DerivationImageSequence = Sequence([der])
        per.append(f)
    ds.PerFrameFunctionalGroupsSequence = Sequence(per)
    ds.NumberOfFrames = len(fr)
    if kind == 'binary':
        bits = np.concatenate([p.reshape(-1) for _, _, p in fr])
        data = np.packbits(bits, bitorder='little').tobytes()
    else:
        data = b''.join(p.tobytes() for _, _, p in fr)
    if len(data) % 2:
        data += b'\0'
    ds.PixelData = data
    ds['PixelData'].VR = 'OB'
    ds.save_as(path, write_like_original=False)


def image_series(folder):
    import os
    global CT_SERIES
    os.makedirs(folder, exist_ok=True)
    series = CT_SERIES = generate_uid()
    for s in range(SLICES):
        ds = dataset('binary')
        for tag in ['SegmentationType', 'SegmentSequence', 'SharedFunctionalGroupsSequence', 'DimensionOrganizationSequence',
                    'DimensionOrganizationType', 'DimensionIndexSequence', 'ContentLabel', 'ContentDescription',
                    'ContentCreatorName', 'LossyImageCompression']:
            delattr(ds, tag)
        ds.SOPClassUID = ds.file_meta.MediaStorageSOPClassUID = '1.2.840.10008.5.1.4.1.1.2'
        ds.Modality, ds.SeriesInstanceUID, ds.SeriesNumber, ds.InstanceNumber = 'CT', series, 2, s + 1
        ds.SeriesDescription = 'CT'
        ds.ImageType = ['ORIGINAL', 'PRIMARY', 'AXIAL']
        ds.ImageOrientationPatient = [f'{v:.8f}' for v in list(ROW_DIR) + list(COL_DIR)]
        ds.ImagePositionPatient = [f'{v:.6f}' for v in position(0, 0, s)]
        ds.PixelSpacing = [f'{v}' for v in SPACING]
        ds.SliceThickness = f'{STEP}'
        ds.BitsAllocated, ds.BitsStored, ds.HighBit, ds.PixelRepresentation = 16, 16, 15, 1
        ds.RescaleIntercept, ds.RescaleSlope = '-1024', '1'
        ds.PixelData = np.full((ROWS, COLS), 1064, np.int16).tobytes()
        ds['PixelData'].VR = 'OW'
        CT_INSTANCES.append(ds.SOPInstanceUID)
        ds.save_as(f'{folder}/ct{s:02d}.dcm', write_like_original=False)


out = sys.argv[1]
image_series(f'{out}/image')
with open(f'{out}/ball.txt', 'w') as f:
    f.write(' '.join(f'{v:.6f}' for v in centre) + '\n')
write(f'{out}/binary.dcm', 'binary', 300)
write(f'{out}/fractional.dcm', 'fractional', 301)
write(f'{out}/noposition.dcm', 'binary', 302, positions=False)
with open(f'{out}/labels.txt', 'w') as f:
    for kk in range(SLICES):
        for jj in range(ROWS):
            for ii in range(COLS):
                p = P[ii, jj, kk]
                f.write(f'{p[0]:.6f} {p[1]:.6f} {p[2]:.6f} {labels[ii, jj, kk]}\n')


# --- An RT Structure Set on the same grid -------------------------------------------------------
# rtstruct.dcm   ROI 1 "GTV": a 40-gon of radius 6 mm on slices 4-8; ROI 2 "ring": a 20 x 20 mm
#                square with an 8 x 8 mm square hole (two contours, even-odd) on slices 2-3;
#                ROI 3 "beyond": one contour on a plane past the image's last slice
# rt_labels.txt  "x y z label" at every voxel centre (even-odd point-in-polygon, numpy)
# grid.txt       the grid: dims, spacing (columns, rows, slices), origin, row, column, normal
def rt_contours():
    out = []  # (roi, slice, [(i, j) fractional pixel coordinates])
    ci, cj = 14.2, 11.7
    for s in range(4, 9):
        pts = [(ci + 6.0 / SPACING[1] * math.cos(t), cj + 6.0 / SPACING[0] * math.sin(t))
               for t in np.linspace(0, 2 * math.pi, 40, endpoint=False)]
        out.append((1, s, pts))
    for s in (2, 3):
        for half in (10.0, 4.0):
            out.append((2, s, [(ci + dx * half / SPACING[1], cj + dy * half / SPACING[0])
                               for dx, dy in [(-1, -1), (1, -1), (1, 1), (-1, 1)]]))
    out.append((3, SLICES + 6, [(5, 5), (9, 5), (9, 9)]))
    return out


def inside(px, py, poly):
    """Crossing number of a ray from (px, py) towards +x (the classic point-in-polygon test)."""
    c = np.zeros(px.shape, bool)
    n = len(poly)
    for e in range(n):
        (x0, y0), (x1, y1) = poly[e], poly[(e + 1) % n]
        crosses = (y0 > py) != (y1 > py)
        with np.errstate(divide='ignore', invalid='ignore'):
            xc = x0 + (py - y0) * (x1 - x0) / (y1 - y0)
        c ^= crosses & (px < xc)
    return c


def rtstruct(path):
    ds = dataset('binary')
    for tag in ['SegmentationType', 'SegmentSequence', 'SharedFunctionalGroupsSequence', 'DimensionOrganizationSequence',
                'DimensionOrganizationType', 'DimensionIndexSequence', 'ContentLabel', 'ContentDescription',
                'ContentCreatorName', 'LossyImageCompression', 'SamplesPerPixel', 'PhotometricInterpretation', 'Rows',
                'Columns', 'PixelRepresentation', 'BitsAllocated', 'BitsStored', 'HighBit', 'ImageType',
                ]:
        delattr(ds, tag)
    ds.OperatorsName = ''
    ds.SOPClassUID = ds.file_meta.MediaStorageSOPClassUID = '1.2.840.10008.5.1.4.1.1.481.3'
    ds.Modality, ds.SeriesNumber, ds.SeriesDescription = 'RTSTRUCT', 400, 'structures'
    ds.StructureSetLabel, ds.StructureSetDate, ds.StructureSetTime = 'phantom', '20240301', '120000'
    ref = Dataset()
    ref.FrameOfReferenceUID = FOR_UID
    study = Dataset()  # the CT's study and series, its images as contour images
    study.ReferencedSOPClassUID, study.ReferencedSOPInstanceUID = '1.2.840.10008.3.1.2.3.1', ds.StudyInstanceUID
    series = Dataset()
    series.SeriesInstanceUID = CT_SERIES
    series.ContourImageSequence = image_references(series)
    study.RTReferencedSeriesSequence = Sequence([series])
    ref.RTReferencedStudySequence = Sequence([study])
    ds.ReferencedFrameOfReferenceSequence = Sequence([ref])
    rois, roic = [], []
    colours = {1: [255, 0, 0], 2: [0, 200, 255], 3: [0, 255, 0]}
    names = {1: 'GTV', 2: 'R\u00fcckenmark', 3: 'beyond'}  # written in Latin-1, as the set says
    ds.SpecificCharacterSet = 'ISO_IR 100'
    for number in (1, 2, 3):
        r = Dataset()
        r.ROINumber, r.ReferencedFrameOfReferenceUID, r.ROIName, r.ROIGenerationAlgorithm = number, FOR_UID, names[number], 'MANUAL'
        rois.append(r)
        c = Dataset()
        c.ReferencedROINumber, c.ROIDisplayColor = number, colours[number]
        seq = []
        for roi, s, pts in rt_contours():
            if roi != number:
                continue
            ct = Dataset()
            ct.ContourGeometricType = 'CLOSED_PLANAR'
            ct.NumberOfContourPoints = len(pts)
            ct.ContourData = [f'{v:.5f}' for (pi, pj) in pts for v in position(pi, pj, s)]
            seq.append(ct)
        c.ContourSequence = Sequence(seq)
        roic.append(c)
    ds.StructureSetROISequence = Sequence(rois)
    ds.ROIContourSequence = Sequence(roic)
    obs = []
    for number in (1, 2, 3):
        o = Dataset()
        o.ObservationNumber, o.ReferencedROINumber, o.RTROIInterpretedType, o.ROIInterpreter = number, number, 'ORGAN', ''
        obs.append(o)
    ds.RTROIObservationsSequence = Sequence(obs)
    ds.save_as(path, write_like_original=False)
    # The expected label of every voxel centre: ROIs in number order, a later one over an earlier.
    rt = np.zeros(labels.shape, np.uint8)
    ii, jj = np.meshgrid(np.arange(COLS), np.arange(ROWS), indexing='ij')
    for number in (1, 2):
        for s in range(SLICES):
            polys = [pts for roi, sl, pts in rt_contours() if roi == number and sl == s]
            if not polys:
                continue
            m = np.zeros(ii.shape, bool)
            for poly in polys:
                m ^= inside(ii.astype(float), jj.astype(float), poly)
            rt[:, :, s][m] = number
    with open(path.replace('rtstruct.dcm', 'rt_labels.txt'), 'w') as f:
        for kk in range(SLICES):
            for jj2 in range(ROWS):
                for ii2 in range(COLS):
                    p = P[ii2, jj2, kk]
                    f.write(f'{p[0]:.6f} {p[1]:.6f} {p[2]:.6f} {rt[ii2, jj2, kk]}\n')
    with open(path.replace('rtstruct.dcm', 'grid.txt'), 'w') as f:
        f.write(f'{COLS} {ROWS} {SLICES}\n{SPACING[1]} {SPACING[0]} {STEP}\n')
        for v in (ORIGIN, ROW_DIR, COL_DIR, NORMAL):
            f.write(' '.join(f'{x:.10f}' for x in v) + '\n')


rtstruct(f'{out}/rtstruct.dcm')
