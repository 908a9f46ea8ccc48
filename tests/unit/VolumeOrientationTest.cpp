// Orientation of the non-DICOM, non-NIfTI inputs: a VTK XML image's Direction (written and
// placed by VTK itself, python3-vtk9, as the oracle), a MetaImage TransformMatrix (worked by
// hand from the MetaIO convention: row a is axis a's direction), and every NRRD space.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

#include "core/base/Error.h"
#include "core/volume/RawVoxelSource.h"
#include "core/volume/VoxelSourceFactory.h"
#include "tests/support/ProcessRunner.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
glm::dvec3 patientOf(const core::VolumeGeometry& g, glm::dvec3 index) {
    return glm::dvec3(g.indexToPatient() * glm::dvec4(index, 1.0));
}

bool mentions(const std::vector<std::string>& w, const std::string& text) {
    for (const auto& s : w)
        if (s.find(text) != std::string::npos) return true;
    return false;
}

std::string refusal(const std::string& path) {
    try {
        core::VoxelSourceFactory::open(path);
    } catch (const core::Error& e) {
        return e.what();
    }
    return "accepted";
}
}  // namespace

TEST(VolumeOrientation, VtiDirectionIsWhereVtkPutsEachVoxel) {
    test::TempDir dir;
    const std::string script = R"(
import sys, vtk
img = vtk.vtkImageData()
img.SetDimensions(5, 4, 3)
img.SetSpacing(0.5, 0.75, 2.0)
img.SetOrigin(10.0, 20.0, 30.0)
img.SetDirectionMatrix(0.0, -0.8, 0.6,  1.0, 0.0, 0.0,  0.0, 0.6, 0.8)
img.AllocateScalars(vtk.VTK_SHORT, 1)
for k in range(3):
    for j in range(4):
        for i in range(5):
            img.SetScalarComponentFromDouble(i, j, k, 0, i + 10 * j + 100 * k)
w = vtk.vtkXMLImageDataWriter()
w.SetFileName(sys.argv[1] + '/d.vti')
w.SetInputData(img)
w.Write()
with open(sys.argv[1] + '/points.txt', 'w') as f:
    for idx in [(0, 0, 0), (4, 0, 0), (0, 3, 0), (0, 0, 2), (3, 2, 1)]:
        p = [0.0, 0.0, 0.0]
        img.TransformIndexToPhysicalPoint(list(idx), p)
        f.write('%d %d %d %.9f %.9f %.9f\n' % (idx + tuple(p)))
)";
    std::ofstream(dir.file("w.py")) << script;
    const auto r = test::runCommand("/usr/bin/python3 " + dir.file("w.py") + " " + dir.path().string());
    ASSERT_EQ(r.exitCode, 0) << "python3-vtk9 (installer/install-deps.sh) could not write the file:\n" << r.output;
    auto src = core::VoxelSourceFactory::open(dir.file("d.vti"));
    std::ifstream points(dir.file("points.txt"));
    int checked = 0;
    for (double i, j, k, x, y, z; points >> i >> j >> k >> x >> y >> z; ++checked) {
        const glm::dvec3 p = patientOf(src->geometry(), {i, j, k});
        EXPECT_NEAR(glm::length(p - glm::dvec3(x, y, z)), 0.0, 1e-6) << i << "," << j << "," << k;
    }
    EXPECT_EQ(checked, 5);
    std::vector<std::int16_t> v(5 * 4 * 3);
    src->readSlices(0, 3, v.data());
    EXPECT_EQ(v[(1 * 4 + 2) * 5 + 3], 3 + 20 + 100);
}

TEST(VolumeOrientation, MetaImageTransformMatrixIsHonoured) {
    test::TempDir dir;
    {
        std::ofstream f(dir.file("m.mha"), std::ios::binary);
        // Rows: axis i towards -y, axis j towards +x (0.8) and +z (0.6), axis k the cross.
        f << "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
             "TransformMatrix = 0 -1 0 0.8 0 0.6 -0.6 0 0.8\nOffset = 1 2 3\nElementSpacing = 0.5 0.75 2\n"
             "DimSize = 4 3 2\nElementType = MET_SHORT\nElementDataFile = LOCAL\n";
        for (short s = 0; s < 24; ++s) f.write(reinterpret_cast<const char*>(&s), 2);
    }
    auto src = core::VoxelSourceFactory::open(dir.file("m.mha"));
    // (1, 2, 1): 1*0.5*(0,-1,0) + 2*0.75*(0.8,0,0.6) + 1*2*(-0.6,0,0.8) + (1,2,3).
    const glm::dvec3 expected = glm::dvec3(0, -0.5, 0) + glm::dvec3(1.2, 0, 0.9) + glm::dvec3(-1.2, 0, 1.6) + glm::dvec3(1, 2, 3);
    EXPECT_NEAR(glm::length(patientOf(src->geometry(), {1, 2, 1}) - expected), 0.0, 1e-9);
    {
        std::ofstream f(dir.file("bad.mha"), std::ios::binary);
        f << "ObjectType = Image\nNDims = 3\nTransformMatrix = 1 0 0 1 0 0 0 0 1\nDimSize = 2 2 2\n"
             "ElementType = MET_UCHAR\nElementDataFile = LOCAL\n" << std::string(8, '\0');
    }
    EXPECT_NE(refusal(dir.file("bad.mha")).find("dependent directions"), std::string::npos) << refusal(dir.file("bad.mha"));
}

TEST(VolumeOrientation, EveryNrrdPatientSpaceBecomesLps) {
    test::TempDir dir;
    auto write = [&](const std::string& name, const std::string& space) {
        std::ofstream f(dir.file(name), std::ios::binary);
        f << "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n";
        if (!space.empty()) f << "space: " << space << "\n";
        if (!space.empty()) f << "space directions: (0,2,0) (-1.5,0,0) (0,0,3)\nspace origin: (10,20,30)\n";
        f << "\n" << std::string(8, '\0');
        return dir.file(name);
    };
    // Index (1, 1, 1) is (10 - 1.5, 20 + 2, 30 + 3) in the file's own space.
    const glm::dvec3 own(8.5, 22, 33);
    struct Case {
        const char* space;
        glm::dvec3 lps;
    };
    for (const Case& c : {Case{"left-posterior-superior", own}, Case{"LPS", own},
                          Case{"right-anterior-superior", {-8.5, -22, 33}}, Case{"RAS", {-8.5, -22, 33}},
                          Case{"left-anterior-superior", {8.5, -22, 33}}, Case{"LAS", {8.5, -22, 33}},
                          Case{"scanner-xyz", own}, Case{"Right-Anterior-Superior", {-8.5, -22, 33}},
                          Case{"ras", {-8.5, -22, 33}}}) {  // teem reads the names in any case
        SCOPED_TRACE(c.space);
        auto src = core::VoxelSourceFactory::open(write(std::string(c.space) + ".nrrd", c.space));
        EXPECT_NEAR(glm::length(patientOf(src->geometry(), {1, 1, 1}) - c.lps), 0.0, 1e-9);
        EXPECT_EQ(mentions(src->warnings(), "scanner-xyz is taken as LPS"), std::string(c.space) == "scanner-xyz");
    }
    auto none = core::VoxelSourceFactory::open(write("none.nrrd", ""));
    EXPECT_TRUE(mentions(none->warnings(), "no space: orientation unknown"));
    EXPECT_TRUE(none->geometry().orientationAssumed);  // the views draw "?" for its letters
    EXPECT_TRUE(none->geometry().spacingAssumed);      // nor any spacing: 1 mm is not a measurement
    EXPECT_TRUE(mentions(none->warnings(), "no spacings or space directions: 1 mm assumed"));
    auto placed = core::VoxelSourceFactory::open(dir.file("LPS.nrrd"));
    EXPECT_FALSE(placed->geometry().orientationAssumed);
    EXPECT_FALSE(placed->geometry().spacingAssumed);
    for (const char* space : {"3D-right-handed", "right-anterior-superior-time", "scanner-xyz-time"})
        EXPECT_NE(refusal(write("r.nrrd", space)).find("not a patient space"), std::string::npos) << space;
}

// NRRD lengths in other units are converted to mm (they had been taken as mm: a file in metres
// built 1000 times too small), said, and a unit that is not a length is refused; without a
// space, sample 0 lies at the axis min, half a spacing in when cell-centred (the NRRD format's
// definition; it had been put at 0).
TEST(VolumeOrientation, NrrdUnitsAndAxisMinsPlaceTheVolumeInMillimetres) {
    test::TempDir dir;
    auto write = [&](const std::string& name, const std::string& fields) {
        std::ofstream(dir.file(name), std::ios::binary)
            << "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n" << fields << "\n" << std::string(8, '\0');
        return dir.file(name);
    };
    const std::string placed = "space: LPS\nspace directions: (0.002,0,0) (0,0.003,0) (0,0,0.004)\nspace origin: (0.01,0.02,0.03)\n";
    auto metres = core::VoxelSourceFactory::open(write("m.nrrd", placed + "space units: \"m\" \"m\" \"m\"\n"));
    EXPECT_NEAR(glm::length(metres->geometry().spacing - glm::dvec3(2, 3, 4)), 0.0, 1e-9);
    EXPECT_NEAR(glm::length(patientOf(metres->geometry(), {1, 1, 1}) - glm::dvec3(12, 23, 34)), 0.0, 1e-9);
    EXPECT_TRUE(mentions(metres->warnings(), "space units are not millimetres: Holovox converts them to mm"));
    auto mm = core::VoxelSourceFactory::open(write("mm.nrrd", placed + "space units: \"mm\" \"mm\" \"mm\"\n"));
    EXPECT_NEAR(mm->geometry().spacing.x, 0.002, 1e-12);
    EXPECT_FALSE(mentions(mm->warnings(), "units"));
    auto microns = core::VoxelSourceFactory::open(write("u.nrrd", placed + "space units: \"microns\" \"um\" \"um\"\n"));
    EXPECT_NEAR(microns->geometry().spacing.y, 0.000003, 1e-15);
    EXPECT_NE(refusal(write("f.nrrd", placed + "space units: \"furlong\" \"mm\" \"mm\"\n")).find("'furlong' is not a length"),
              std::string::npos);
    auto node = core::VoxelSourceFactory::open(write("n.nrrd", "spacings: 2 3 4\naxis mins: 100 200 300\n"));
    EXPECT_NEAR(glm::length(node->geometry().origin - glm::dvec3(100, 200, 300)), 0.0, 1e-9);
    auto cell = core::VoxelSourceFactory::open(write("c.nrrd", "spacings: 2 3 4\naxis mins: 100 200 300\ncenterings: cell cell cell\n"));
    EXPECT_NEAR(glm::length(cell->geometry().origin - glm::dvec3(101, 201.5, 302)), 0.0, 1e-9);
    auto cm = core::VoxelSourceFactory::open(write("cm.nrrd", "spacings: 2 3 4\naxis mins: 1 2 3\nunits: \"cm\" \"cm\" \"cm\"\n"));
    EXPECT_NEAR(glm::length(cm->geometry().spacing - glm::dvec3(20, 30, 40)), 0.0, 1e-9);
    EXPECT_NEAR(glm::length(cm->geometry().origin - glm::dvec3(10, 20, 30)), 0.0, 1e-9);
    EXPECT_TRUE(mentions(cm->warnings(), "NRRD units are not millimetres"));
}

// The time points of a 4D series are shown in each other's place only on the same grid with
// the same rescale: every difference is named, a thousandth of a voxel is the same place.
TEST(VolumeGeometry, GridDifferenceNamesWhatDiffers) {
    core::VolumeGeometry a;
    a.dims = {64, 64, 8};
    a.spacing = {0.8, 0.8, 3.0};
    a.origin = {-25, -25, 10};
    auto b = a;
    EXPECT_EQ(a.gridDifference(b), "");
    b.origin.x += 0.0001;
    EXPECT_EQ(a.gridDifference(b), "") << "a ten-thousandth of a millimetre is the same place";
    b = a;
    b.dims[2] = 6;
    EXPECT_EQ(a.gridDifference(b), "dimensions 64x64x6, not 64x64x8");
    b = a;
    b.origin.z += 1.5;
    EXPECT_EQ(a.gridDifference(b), "another position");
    b = a;
    b.spacing.y = 0.81;
    EXPECT_EQ(a.gridDifference(b), "another voxel spacing");
    b = a;
    b.direction = glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, -1, 0));
    EXPECT_EQ(a.gridDifference(b), "another orientation");
    b = a;
    b.rescaleSlope = 2.0;
    EXPECT_NE(a.gridDifference(b).find("another rescale"), std::string::npos);
}

TEST(VolumeGeometry, ValidationRefusesNanDirectionsParallelAxesAndFarOrigins) {
    core::VolumeGeometry g;
    g.dims = {64, 64, 8};
    g.spacing = {0.8, 0.8, 3.0};
    g.origin = {-25, -25, 10};
    auto refusal = [](const core::VolumeGeometry& x) {
        try {
            x.validate("f.vtk");
        } catch (const core::Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_EQ(refusal(g), "");
    auto b = g;
    b.direction[1] = glm::dvec3(std::nan(""), 0, 0);
    EXPECT_EQ(refusal(b), "f.vtk: direction cosines are not unit vectors");
    b = g;
    b.direction[2] = b.direction[0];
    EXPECT_EQ(refusal(b), "f.vtk: direction cosines are dependent (two axes are parallel)");
    b = g;
    b.direction[1] = glm::normalize(glm::dvec3(1, 0.5, 0));  // sheared (a NIfTI sform may be): kept
    EXPECT_EQ(refusal(b), "");
    b = g;
    b.origin.x = 1e308;
    EXPECT_EQ(refusal(b).rfind("f.vtk: its voxels lie more than 1 km from the patient coordinates' origin", 0), 0u);
    b = g;
    b.origin.z = 999000;  // 999 m away, its last slice 21 mm further: within reach
    EXPECT_EQ(refusal(b), "");
    b.spacing.z = 200;  // its last slice 1.4 m further, beyond 1 km: refused
    EXPECT_NE(refusal(b), "");
    b = g;
    b.origin.y = std::nan("");
    EXPECT_NE(refusal(b), "");
}

// What a file does not say is never shown as known: a MetaImage without ElementSpacing, a NRRD
// whose spacings are not numbers, a raw file (no orientation ever; spacing unless given).
TEST(VolumeOrientation, WhatAFileLeavesOpenIsFlaggedNotAssumedSilently) {
    test::TempDir dir;
    std::ofstream(dir.file("a.mha"), std::ios::binary)
        << "ObjectType = Image\nNDims = 3\nBinaryData = True\nDimSize = 2 2 2\nElementType = MET_UCHAR\n"
           "ElementDataFile = LOCAL\n"
        << std::string(8, '\0');
    auto mha = core::VoxelSourceFactory::open(dir.file("a.mha"));
    EXPECT_TRUE(mha->geometry().spacingAssumed);
    EXPECT_FALSE(mha->geometry().orientationAssumed);  // MetaImage is LPS by ITK's convention
    EXPECT_TRUE(mentions(mha->warnings(), "no ElementSpacing: 1 mm assumed"));

    std::ofstream(dir.file("nan.nrrd"), std::ios::binary)
        << "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nspacings: 1 nan 1\nencoding: raw\n\n"
        << std::string(8, '\0');
    EXPECT_NE(refusal(dir.file("nan.nrrd")).find("spacings '1 nan 1' are not three numbers"), std::string::npos)
        << refusal(dir.file("nan.nrrd"));

    std::ofstream(dir.file("v.raw"), std::ios::binary) << std::string(8, '\0');
    core::RawVoxelSource::Options o;
    o.dims = {2, 2, 1};
    o.element = core::FileElement::UInt16;
    EXPECT_TRUE(core::RawVoxelSource(dir.file("v.raw"), o).geometry().orientationAssumed);
    EXPECT_TRUE(core::RawVoxelSource(dir.file("v.raw"), o).geometry().spacingAssumed);
    o.spacingAssumed = false;  // --spacing given
    EXPECT_FALSE(core::RawVoxelSource(dir.file("v.raw"), o).geometry().spacingAssumed);
}

// A native plane lands on a layer of voxel centres: an axial through the middle of eight 3 mm
// slices (between layers 3 and 4) moves to the nearest one; a gantry-tilted stack's layers are
// found along their own normal; a reformat (an axial of a sagittal-tilted grid) stays put.
TEST(VolumeGeometry, NativePlanesLandOnTheNearestLayerOfVoxels) {
    core::VolumeGeometry g;
    g.dims = {16, 16, 8};
    g.spacing = {0.5, 0.8, 3.0};
    g.origin = {-10, 4, 20};
    const glm::dvec3 middle(g.indexToPatient() * glm::dvec4(7.5, 7.5, 3.5, 1.0));
    const glm::dvec3 axial = g.onNearestLayer(middle, {0, 0, 1});
    const glm::dvec3 index(glm::inverse(g.indexToPatient()) * glm::dvec4(axial, 1.0));
    EXPECT_NEAR(index.z, 4.0, 1e-9) << "3.5 rounds to layer 4, as the slice readout rounds it";
    EXPECT_NEAR(index.x, 7.5, 1e-9) << "only along the normal";
    EXPECT_NEAR(glm::length(g.onNearestLayer(middle, {0, 0, -1}) - axial), 0.0, 1e-9) << "either side";
    const glm::dvec3 centre = g.nearestVoxelCentre(middle);
    EXPECT_NEAR(glm::length(centre - glm::dvec3(g.indexToPatient() * glm::dvec4(8, 8, 4, 1.0))), 0.0, 1e-9);

    core::VolumeGeometry tilted = g;  // gantry tilt: k runs 15 degrees off the slice normal
    const double t = glm::radians(15.0);
    tilted.direction[2] = glm::dvec3(0, std::sin(t), std::cos(t));
    const glm::dvec3 between(tilted.indexToPatient() * glm::dvec4(5, 5, 2.25, 1.0));
    const glm::dvec3 landed = tilted.onNearestLayer(between, {0, 0, 1});  // the layers stay axial
    const glm::dvec3 tIndex(glm::inverse(tilted.indexToPatient()) * glm::dvec4(landed, 1.0));
    EXPECT_NEAR(tIndex.z, 2.0, 1e-9);
    EXPECT_NEAR(landed.x, between.x, 1e-9);
    EXPECT_NEAR(landed.y, between.y, 1e-9) << "moved along the plane's normal, not along k";

    core::VolumeGeometry oblique = g;  // rows turned 20 degrees about y: no layer faces the axial
    const double r = glm::radians(20.0);
    oblique.direction[0] = glm::dvec3(std::cos(r), 0, -std::sin(r));
    oblique.direction[2] = glm::dvec3(std::sin(r), 0, std::cos(r));
    EXPECT_EQ(oblique.onNearestLayer(middle, {0, 0, 1}), middle);
}
