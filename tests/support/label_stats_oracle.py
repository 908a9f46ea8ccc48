"""An independent oracle for holovox-cli label-stats and slice --labels: writes an image and a
label map as NIfTI (RAS affines, the label map rotated and on a coarser grid) with nibabel, and
computes each label's volume and the image's mean and SD at the label voxels' centres with numpy
alone (trilinear, edges replicated, centres outside the image left out), as
    label,voxels,volume_ml,voxels_in_image,mean,sd
Usage: label_stats_oracle.py OUTDIR"""
import sys

import nibabel as nib
import numpy as np

out = sys.argv[1]
rng = np.random.default_rng(5)

# The image: 60x50x30 at 1.2 x 1.1 x 2.5 mm, smooth values plus noise.
dims = np.array([60, 50, 30])
image_aff = np.diag([-1.2, -1.1, 2.5, 1.0])
image_aff[:3, 3] = [35.0, 28.0, -37.0]
i, j, k = np.meshgrid(*[np.arange(d) for d in dims], indexing="ij")
image = (100 + 2 * i - 3 * j + 5 * k + rng.normal(0, 20, dims)).astype(np.int16)
nib.save(nib.Nifti1Image(image, image_aff), f"{out}/image.nii.gz")

# The label map: 30x28x16 at 2.3 x 2.0 x 4.1 mm, turned 20 degrees about the axial axis.
ldims = np.array([30, 28, 16])
a = np.radians(20)
rot = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
label_aff = np.eye(4)
label_aff[:3, :3] = rot @ np.diag([2.3, 2.0, 4.1])
label_aff[:3, 3] = [-30.0, -20.0, -30.0]
li, lj, lk = np.meshgrid(*[np.arange(d) for d in ldims], indexing="ij")
ras = np.stack([li, lj, lk, np.ones_like(li)], -1) @ label_aff.T
labels = np.zeros(ldims, np.uint8)
labels[np.linalg.norm(ras[..., :3] - [5.0, 2.0, 0.0], axis=-1) < 14] = 3
labels[(ras[..., 0] > 18) & (ras[..., 1] > 10)] = 9  # reaches outside the image
nib.save(nib.Nifti1Image(labels, label_aff), f"{out}/labels.nii.gz")

# The image's voxel coordinates of every label voxel's centre.
idx = ras @ np.linalg.inv(image_aff).T
voxel_ml = 2.3 * 2.0 * 4.1 / 1000.0
img = image.astype(np.float64)
for label in sorted(set(np.unique(labels)) - {0}):
    mask = labels == label
    c = idx[mask][:, :3]
    inside = np.all((c >= -0.5) & (c <= dims - 0.5), axis=1)
    c = np.clip(c[inside], 0, dims - 1)
    c0 = np.minimum(np.floor(c).astype(int), dims - 2)
    f = c - c0
    v = np.zeros(len(c))
    for corner in range(8):
        d = np.array([corner & 1, (corner >> 1) & 1, (corner >> 2) & 1])
        w = np.prod(np.where(d, f, 1 - f), axis=1)
        v += w * img[c0[:, 0] + d[0], c0[:, 1] + d[1], c0[:, 2] + d[2]]
    print(f"{label},{mask.sum()},{mask.sum() * voxel_ml:.6f},{len(v)},{v.mean():.6f},{v.std():.6f}")
