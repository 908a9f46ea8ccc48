// DICOM Segmentation objects written by pydicom (tests/support/seg_cases.py: a rotated grid whose
// binary frames are not byte-aligned, frames in shuffled order, only where a segment has
// pixels) read onto the voxels pydicom's own arrays say, binary and fractional; a frame
// without its position is refused; the segments' names and colours make a colour table.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <tuple>

#include <glm/mat3x3.hpp>

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcfilefo.h>

#include "core/octree/OctreeBuilder.h"
#include "core/reference/SliceSampler.h"
#include "dicom/DicomScanner.h"
#include "dicom/SegmentationSource.h"
#include "dicom/StructureSetSource.h"
#include "dicom/StudyDatabase.h"
#include "tests/support/ProcessRunner.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
struct Cases {
    test::TempDir dir;
    Cases() {
        const auto r = test::runCommand("/usr/bin/python3 " + std::string(HVX_SOURCE_DIR) + "/tests/support/seg_cases.py " +
                                        dir.path().string());
        EXPECT_EQ(r.exitCode, 0) << r.output;
    }
};

/// Every voxel centre of the writer's grid: the label found there equals the writer's.
void expectLabelsWhereTheWriterPutThem(const Cases& cases, const std::string& file) {
    dicom::SegmentationSource source(cases.dir.file(file));
    EXPECT_EQ(source.geometry().frameOfReferenceUid, "1.2.826.0.1.3680043.9.7777.60");
    EXPECT_TRUE(source.geometry().isLabel);
    core::BuildOptions o;
    o.brickSize = 16;
    o.labels = true;
    core::JobContext job;
    core::OctreeBuilder(o).build(source, cases.dir.file(file + ".hvo"), job);
    const auto reader = core::OctreeReader::open(cases.dir.file(file + ".hvo"));
    core::BrickCache cache(16u << 20);
    const core::SliceSampler sampler(*reader, cache);
    std::ifstream in(cases.dir.file("labels.txt"));
    double x, y, z;
    int label;
    std::size_t checked = 0, labelled = 0, wrong = 0, outside = 0;
    while (in >> x >> y >> z >> label) {
        const double v = sampler.valueAt({x, y, z}, 0);
        ++checked;
        labelled += label != 0;
        if (std::isnan(v)) {
            // The SEG's grid spans only its frames' slices: outside it there is no label.
            outside += 1;
            EXPECT_EQ(label, 0) << x << "," << y << "," << z;
            continue;
        }
        if (int(v) != label && ++wrong < 5) ADD_FAILURE() << file << " at " << x << "," << y << "," << z << ": " << v << ", not " << label;
    }
    EXPECT_EQ(checked, 30u * 26u * 14u);
    EXPECT_GT(labelled, 500u);
    EXPECT_EQ(wrong, 0u) << file;
    EXPECT_LT(outside, checked);
}
}  // namespace

TEST(Segmentation, BinaryFramesLandOnTheWritersVoxels) {
    Cases cases;
    ASSERT_TRUE(dicom::SegmentationSource::isSegmentation(cases.dir.file("binary.dcm")));
    expectLabelsWhereTheWriterPutThem(cases, "binary.dcm");
    dicom::SegmentationSource source(cases.dir.file("binary.dcm"));
    const auto& t = source.table();
    ASSERT_EQ(t.entries().size(), 2u);
    EXPECT_EQ(t.find(1)->name, "liver");
    EXPECT_EQ(t.find(2)->name, "spleen");
    // CIELab (21000, 45000, 40000) is a light red-brown; (30000, 30000, 20000) a blue.
    EXPECT_GT(t.find(1)->rgba[0], t.find(1)->rgba[2]);
    EXPECT_GT(t.find(2)->rgba[2], t.find(2)->rgba[0]);
    EXPECT_TRUE(source.warnings().empty());
}

TEST(Segmentation, FractionalSegmentsAreTheirVoxelsAboveHalf) {
    Cases cases;
    dicom::SegmentationSource source(cases.dir.file("fractional.dcm"));
    ASSERT_EQ(source.warnings().size(), 1u);
    EXPECT_NE(source.warnings()[0].find("half its maximum (200)"), std::string::npos);
    // The fractional object holds the ball only (segment 1): the box's voxels read as 0 there.
    core::BuildOptions o;
    o.brickSize = 16;
    o.labels = true;
    core::JobContext job;
    core::OctreeBuilder(o).build(source, cases.dir.file("f.hvo"), job);
    const auto reader = core::OctreeReader::open(cases.dir.file("f.hvo"));
    core::BrickCache cache(16u << 20);
    const core::SliceSampler sampler(*reader, cache);
    std::ifstream in(cases.dir.file("labels.txt"));
    double x, y, z;
    int label;
    std::size_t wrong = 0, ball = 0;
    while (in >> x >> y >> z >> label) {
        const double v = sampler.valueAt({x, y, z}, 0);
        const int want = label == 1 ? 1 : 0;
        ball += want;
        if (!std::isnan(v) && int(v) != want) ++wrong;
        if (std::isnan(v)) EXPECT_EQ(want, 0);
    }
    EXPECT_GT(ball, 500u);
    EXPECT_EQ(wrong, 0u);
}

TEST(Segmentation, BadObjectsAreRefusedWithASentence) {
    Cases cases;
    try {
        dicom::SegmentationSource source(cases.dir.file("noposition.dcm"));
        ADD_FAILURE() << "a SEG without frame positions was read";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("has no position (PlanePositionSequence)"), std::string::npos) << e.what();
    }
    std::ofstream(cases.dir.file("junk.dcm")) << "not dicom at all";
    EXPECT_FALSE(dicom::SegmentationSource::isSegmentation(cases.dir.file("junk.dcm")));
    EXPECT_THROW(dicom::SegmentationSource(cases.dir.file("junk.dcm")), core::Error);
    EXPECT_FALSE(dicom::SegmentationSource::isSegmentation(cases.dir.file("absent.dcm")));
    // A frame position or the orientation that is not a number: refused, never cast to a slice.
    auto edited = [&](const DcmTagKey& key, const char* value, const std::string& name) {
        DcmFileFormat ff;
        EXPECT_TRUE(ff.loadFile(cases.dir.file("binary.dcm").c_str()).good());
        DcmElement* e = nullptr;
        EXPECT_TRUE(ff.getDataset()->findAndGetElement(key, e, OFTrue).good());
        EXPECT_TRUE(e->putString(value).good());
        EXPECT_TRUE(ff.saveFile(cases.dir.file(name).c_str(), EXS_LittleEndianExplicit).good());
        return cases.dir.file(name);
    };
    for (const auto& [key, value, says] :
         {std::tuple{DCM_ImagePositionPatient, "nan\\0\\0", "'s position (PlanePositionSequence) is not three numbers"},
          std::tuple{DCM_ImagePositionPatient, "0\\1e999\\0", "'s position (PlanePositionSequence) is not three numbers"},
          std::tuple{DCM_ImageOrientationPatient, "1\\0\\0\\0\\nan\\0", "ImageOrientationPatient holds a value that is not a number"},
          std::tuple{DCM_ImageOrientationPatient, "0\\0\\0\\0\\1\\0", "ImageOrientationPatient's rows or columns have no direction"},
          std::tuple{DCM_SpacingBetweenSlices, "1e999", "SpacingBetweenSlices is not a number"},
          // Every frame would have rounded onto slice 0 of a 1 km grid.
          std::tuple{DCM_SpacingBetweenSlices, "1e6", "mm apart, closer than its SpacingBetweenSlices (1000000.000000 mm)"}}) {
        try {
            dicom::SegmentationSource source(edited(key, value, "edited.dcm"));
            ADD_FAILURE() << value << " was read";
        } catch (const core::Error& e) {
            EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << value << ": " << e.what();
        }
    }
    // Truncated: the pixel data cut off.
    std::ifstream full(cases.dir.file("binary.dcm"), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(full)), std::istreambuf_iterator<char>());
    std::ofstream(cases.dir.file("cut.dcm"), std::ios::binary) << bytes.substr(0, bytes.size() - 200);
    EXPECT_THROW(
        {
            dicom::SegmentationSource source(cases.dir.file("cut.dcm"));
            std::vector<std::uint8_t> slab(std::size_t(source.geometry().voxelCount()));
            source.readSlices(0, source.geometry().dims[2], slab.data());
        },
        core::Error);
}

TEST(Segmentation, TheColourTableRoundTripsThroughSlicersFormat) {
    Cases cases;
    dicom::SegmentationSource source(cases.dir.file("binary.dcm"));
    std::ofstream(cases.dir.file("t.ctbl")) << source.table().toSlicerTable();
    const auto back = core::LabelTable::load(cases.dir.file("t.ctbl"));
    EXPECT_EQ(back.format(), "3D Slicer colour table");
    EXPECT_EQ(back.find(1)->name, "liver");
    EXPECT_EQ(back.find(2)->rgba, source.table().find(2)->rgba);
}

namespace {
/// The grid seg_cases.py wrote its objects on (grid.txt), as a geometry.
core::VolumeGeometry writersGrid(const Cases& cases) {
    std::ifstream in(cases.dir.file("grid.txt"));
    core::VolumeGeometry g;
    in >> g.dims[0] >> g.dims[1] >> g.dims[2] >> g.spacing.x >> g.spacing.y >> g.spacing.z;
    glm::dvec3 r, c, n;
    in >> g.origin.x >> g.origin.y >> g.origin.z >> r.x >> r.y >> r.z >> c.x >> c.y >> c.z >> n.x >> n.y >> n.z;
    g.direction = glm::dmat3(r, c, n);
    g.frameOfReferenceUid = "1.2.826.0.1.3680043.9.7777.60";
    g.modality = "CT";
    return g;
}
}  // namespace

TEST(StructureSet, ContoursFillTheVoxelsPydicomsPolygonsEnclose) {
    Cases cases;
    ASSERT_TRUE(dicom::StructureSetSource::isStructureSet(cases.dir.file("rtstruct.dcm")));
    EXPECT_FALSE(dicom::StructureSetSource::isStructureSet(cases.dir.file("binary.dcm")));
    const auto grid = writersGrid(cases);
    dicom::StructureSetSource source(cases.dir.file("rtstruct.dcm"), grid);
    EXPECT_TRUE(source.geometry().isLabel);
    EXPECT_EQ(source.geometry().dims, grid.dims);
    std::vector<std::uint8_t> labels(std::size_t(grid.voxelCount()));
    source.readSlices(0, grid.dims[2], labels.data());
    std::ifstream in(cases.dir.file("rt_labels.txt"));
    double x, y, z;
    int want;
    std::size_t n = 0, wrong = 0;
    std::map<int, std::size_t> count;
    while (in >> x >> y >> z >> want) {
        ++count[want];
        if (labels[n] != want && ++wrong < 5) ADD_FAILURE() << "voxel " << n << " at " << x << "," << y << "," << z << ": " << int(labels[n]) << ", not " << want;
        ++n;
    }
    EXPECT_EQ(n, labels.size());
    EXPECT_EQ(wrong, 0u);
    EXPECT_GT(count[1], 300u);
    EXPECT_GT(count[2], 300u);  // the ring, its hole left empty
    const auto& t = source.table();
    EXPECT_EQ(t.find(1)->name, "GTV");
    EXPECT_EQ(t.find(2)->name, "R\u00fcckenmark");  // Latin-1 in the file, UTF-8 here
    EXPECT_EQ(t.find(2)->rgba, (std::array<std::uint8_t, 4>{0, 200, 255, 255}));
    ASSERT_EQ(source.warnings().size(), 1u);
    EXPECT_NE(source.warnings()[0].find("1 contour(s) of beyond lie past the image's slices: left out"), std::string::npos)
        << source.warnings()[0];
}

// A contour's point that is not a number, or absurdly far, is refused; one a little outside the
// image is clipped: its polygon fills up to the image's edge, as a polygon clipped by hand.
TEST(StructureSet, PointsOutsideTheImageAreClippedAndNonsenseIsRefused) {
    Cases cases;
    const auto grid = writersGrid(cases);
    std::vector<std::uint8_t> before(std::size_t(grid.voxelCount())), after(before.size());
    dicom::StructureSetSource(cases.dir.file("rtstruct.dcm"), grid).readSlices(0, grid.dims[2], before.data());
    // The first contour (GTV's, a 40-gon) gets a spike: a vertex inserted after its first one,
    // at that vertex's row and slice, 50 voxels past the image's last column (or `x` as written).
    auto withSpike = [&](const std::string& x, const std::string& name) {
        DcmFileFormat ff;
        EXPECT_TRUE(ff.loadFile(cases.dir.file("rtstruct.dcm").c_str()).good());
        DcmElement* e = nullptr;
        EXPECT_TRUE(ff.getDataset()->findAndGetElement(DCM_ContourData, e, OFTrue).good());
        Float64 p[3] = {0, 0, 0};
        for (unsigned long c = 0; c < 3; ++c) e->getFloat64(p[c], c);
        OFString all;
        e->getOFStringArray(all);
        std::string rest = all.c_str();
        for (int n = 0; n < 3; ++n) rest = rest.substr(rest.find('\\') + 1);  // the points after the first
        const glm::dvec4 at = glm::inverse(grid.indexToPatient()) * glm::dvec4(p[0], p[1], p[2], 1.0);
        const glm::dvec4 far = grid.indexToPatient() * glm::dvec4(grid.dims[0] + 50.0, at.y, at.z, 1.0);
        char spike[160];
        std::snprintf(spike, sizeof spike, "%.10g\\%.10g\\%.10g\\%s\\%.10g\\%.10g\\", p[0], p[1], p[2],
                      x.empty() ? std::to_string(far.x).c_str() : x.c_str(), far.y, far.z);
        e->putString((spike + rest).c_str());
        EXPECT_TRUE(ff.saveFile(cases.dir.file(name).c_str(), EXS_LittleEndianExplicit).good());
        return cases.dir.file(name);
    };
    dicom::StructureSetSource(withSpike("", "spike.dcm"), grid).readSlices(0, grid.dims[2], after.data());
    std::size_t kept = 0, edge = 0, lost = 0;
    for (std::size_t v = 0; v < before.size(); ++v) {
        if (before[v] == 1 && after[v] == 1) ++kept;
        if (before[v] == 1 && after[v] != 1) ++lost;
        if (after[v] == 1 && v % grid.dims[0] == grid.dims[0] - 1) ++edge;
    }
    EXPECT_GT(kept, 0u);
    EXPECT_EQ(lost, 0u);  // the spike only adds
    EXPECT_GT(edge, 0u);  // and reaches the edge
    for (const char* nonsense : {"nan", "1e300"}) {
        try {
            dicom::StructureSetSource s(withSpike(nonsense, "bad.dcm"), grid);
            ADD_FAILURE() << nonsense << " was read";
        } catch (const core::Error& e) {
            EXPECT_NE(std::string(e.what()).find("a contour of GTV has a point "), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("(point 2)"), std::string::npos) << e.what();
        }
    }
}

TEST(StructureSet, AnotherFrameOrAnotherGridIsRefused) {
    Cases cases;
    auto grid = writersGrid(cases);
    grid.frameOfReferenceUid = "1.2.3.4";
    try {
        dicom::StructureSetSource source(cases.dir.file("rtstruct.dcm"), grid);
        ADD_FAILURE() << "read in another frame of reference";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("the image is in 1.2.3.4"), std::string::npos) << e.what();
    }
    // A grid whose slices lie between the contours' planes: refused, never rounded onto one.
    grid = writersGrid(cases);
    grid.origin += grid.direction[2] * (grid.spacing.z * 0.5);
    try {
        dicom::StructureSetSource source(cases.dir.file("rtstruct.dcm"), grid);
        ADD_FAILURE() << "contours between slices were read";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("lies between two slices"), std::string::npos) << e.what();
    }
    EXPECT_THROW(dicom::StructureSetSource(cases.dir.file("binary.dcm"), writersGrid(cases)), core::Error);
}

// Import keeps the image series a SEG and an RTSTRUCT were drawn on (written by pydicom in
// their Referenced Series and RT Referenced Series Sequences), so that the browser lists them
// under it; an image series refers to nothing.
TEST(Segmentation, ImportKnowsTheImageSeriesEachSegmentationRefersTo) {
    Cases cases;
    core::JobContext job;
    const auto scan = dicom::DicomScanner::scan({cases.dir.path().string()}, job);
    dicom::StudyDatabase db(cases.dir.file("s.sqlite"));
    db.addInstances(scan.instances);
    std::string ct;
    std::map<std::string, std::vector<std::string>> refersTo;  // modality -> what each refers to
    for (const auto& se : db.seriesOfStudy("1.2.826.0.1.3680043.9.7777.61")) {
        if (se.modality == "CT") ct = se.seriesUid;
        refersTo[se.modality].push_back(se.refersTo);
    }
    ASSERT_FALSE(ct.empty());
    EXPECT_EQ(refersTo["CT"], std::vector<std::string>{""});
    EXPECT_EQ(refersTo["SEG"], (std::vector<std::string>{ct, ct, ct}));
    EXPECT_EQ(refersTo["RTSTRUCT"], std::vector<std::string>{ct});
}
