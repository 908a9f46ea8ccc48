"""Prints each of pydicom's own character-set files (shipped with Debian's python3-pydicom)
that holds a patient name, a line each: the path, a tab, and the name as pydicom decodes it."""
import glob
import os

import pydicom
import pydicom.data

folder = os.path.join(os.path.dirname(pydicom.data.__file__), "charset_files")
for path in sorted(glob.glob(os.path.join(folder, "*.dcm"))):
    ds = pydicom.dcmread(path)
    if "PatientName" in ds:
        print(path + "\t" + str(ds.PatientName))
