// NIfTI-1 reading against nibabel, an independent reader: every combination of qform and
// sform codes, qfac +-1, a mirrored and sheared sform, 3 to 300 slices (the chunk boundaries
// of the old VTK reader), every integer and float type, scaling, big-endian, micrometres, 4D
// and gzip. Each voxel's LPS position and value must be nibabel's.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>

#include <nlohmann/json.hpp>

#include "core/base/Error.h"
#include "core/volume/NiftiVoxelSource.h"
#include "core/volume/VoxelSourceFactory.h"
#include "tests/support/ProcessRunner.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {

class NiftiVsNibabel : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = std::make_unique<test::TempDir>();
        const auto r = test::runCommand("/usr/bin/python3 " + std::string(HVX_SOURCE_DIR) +
                                        "/tests/support/nifti_cases.py " + dir_->path().string());
        output_ = r.output;
        if (r.exitCode != 0) return;
        std::ifstream in(dir_->file("manifest.json"));
        manifest_ = nlohmann::json::parse(in);
    }
    static void TearDownTestSuite() { dir_.reset(); }
    void SetUp() override {
        // A missing nibabel is a failure, never a skip: installer/install-deps.sh installs it.
        ASSERT_FALSE(manifest_.empty()) << "nibabel could not write the cases:\n" << output_;
    }
    static const nlohmann::json& find(const std::string& name) {
        for (const auto& c : manifest_)
            if (c["name"] == name) return c;
        throw std::runtime_error("no case " + name);
    }

    static std::unique_ptr<test::TempDir> dir_;
    static nlohmann::json manifest_;
    static std::string output_;
};
std::unique_ptr<test::TempDir> NiftiVsNibabel::dir_;
nlohmann::json NiftiVsNibabel::manifest_;
std::string NiftiVsNibabel::output_;

std::vector<double> readExpected(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::vector<double> v;
    double x;
    while (in.read(reinterpret_cast<char*>(&x), sizeof x)) v.push_back(x);
    return v;
}

/// Every value of one volume, as physical values (stored * slope + intercept), in file order;
/// read a few slices at a time, as the octree builder does.
std::vector<double> readPhysical(core::VoxelSource& src) {
    const auto& g = src.geometry();
    const std::size_t slice = std::size_t(g.dims[0]) * g.dims[1];
    const std::size_t width = core::scalarSize(g.scalarType);
    std::vector<unsigned char> buf;
    std::vector<double> out;
    for (std::uint32_t k = 0; k < g.dims[2]; k += 7) {
        const std::uint32_t n = std::min<std::uint32_t>(7, g.dims[2] - k);
        buf.resize(slice * n * width);
        src.readSlices(k, n, buf.data());
        for (std::size_t i = 0; i < slice * n; ++i) {
            double v = 0;
            switch (g.scalarType) {
            case core::ScalarType::UInt8: v = buf[i]; break;
            case core::ScalarType::Int16: { std::int16_t x; std::memcpy(&x, &buf[i * 2], 2); v = x; break; }
            case core::ScalarType::UInt16: { std::uint16_t x; std::memcpy(&x, &buf[i * 2], 2); v = x; break; }
            case core::ScalarType::Float32: { float x; std::memcpy(&x, &buf[i * 4], 4); v = x; break; }
            }
            out.push_back(v * g.rescaleSlope + g.rescaleIntercept);
        }
    }
    return out;
}

/// nibabel's RAS affine as LPS, next to Holovox's index-to-patient matrix: equal matrices put
/// every voxel in the same place.
void expectSamePlacement(const core::VolumeGeometry& g, const nlohmann::json& c) {
    const glm::dmat4 m = g.indexToPatient();
    for (int r = 0; r < 3; ++r)
        for (int col = 0; col < 4; ++col) {
            const double ras = c["affine"][std::size_t(r)][std::size_t(col)].get<double>();
            const double lps = r < 2 ? -ras : ras;
            EXPECT_NEAR(m[col][r], lps, 1e-4) << c["name"] << " row " << r << " column " << col;
        }
}

bool mentions(const std::vector<std::string>& warnings, const std::string& text) {
    for (const auto& w : warnings)
        if (w.find(text) != std::string::npos) return true;
    return false;
}

}  // namespace

TEST_F(NiftiVsNibabel, EveryVoxelWhereAndWhatNibabelSays) {
    int checked = 0;
    for (const auto& c : manifest_) {
        const std::string name = c["name"];
        if (name == "no_orientation" || name == "fourd") continue;  // below
        SCOPED_TRACE(name);
        auto src = core::VoxelSourceFactory::open(c["path"].get<std::string>());
        const auto& g = src->geometry();
        const auto shape = c["shape"];
        for (int a = 0; a < 3; ++a) ASSERT_EQ(g.dims[std::size_t(a)], shape[std::size_t(a)].get<std::uint32_t>());
        expectSamePlacement(g, c);
        const auto expected = readExpected(c["values"]);
        const auto got = readPhysical(*src);
        ASSERT_EQ(got.size(), expected.size());
        std::size_t wrong = 0;
        for (std::size_t i = 0; i < got.size(); ++i)
            if (std::abs(got[i] - expected[i]) > 1e-6 * std::max(1.0, std::abs(expected[i]))) ++wrong;
        EXPECT_EQ(wrong, 0u) << "voxels differing from nibabel";
        ++checked;
    }
    EXPECT_GE(checked, 35);
}

TEST_F(NiftiVsNibabel, NegativeQfacWithManySlicesKeepsSliceOrder) {
    for (const std::string name : {"q1s0f-1m0z300", "q1s0f-1m0z33", "mni_las"}) {
        SCOPED_TRACE(name);
        const auto& c = find(name);
        core::NiftiVoxelSource src(c["path"]);
        expectSamePlacement(src.geometry(), c);
        EXPECT_EQ(readPhysical(src), readExpected(c["values"]));
    }
}

TEST_F(NiftiVsNibabel, SformIsPreferredAndDisagreementIsNamed) {
    {
        core::NiftiVoxelSource src(find("disagree_shift")["path"]);
        expectSamePlacement(src.geometry(), find("disagree_shift"));
        EXPECT_TRUE(mentions(src.warnings(), "disagree by up to 12 mm")) << ::testing::PrintToString(src.warnings());
    }
    {
        core::NiftiVoxelSource src(find("disagree_mirror")["path"]);
        expectSamePlacement(src.geometry(), find("disagree_mirror"));
        EXPECT_TRUE(mentions(src.warnings(), "handedness")) << ::testing::PrintToString(src.warnings());
    }
    core::NiftiVoxelSource agree(find("mni_las")["path"]);
    EXPECT_TRUE(agree.warnings().empty()) << ::testing::PrintToString(agree.warnings());
}

TEST_F(NiftiVsNibabel, NoOrientationIsAWarningNotASilentGuess) {
    const auto& c = find("no_orientation");
    core::NiftiVoxelSource src(c["path"]);
    EXPECT_TRUE(mentions(src.warnings(), "left and right are not known"));
    EXPECT_TRUE(src.geometry().orientationAssumed) << "the views must draw no orientation letters for it";
    EXPECT_FALSE(src.geometry().spacingAssumed);
    EXPECT_EQ(readPhysical(src), readExpected(c["values"]));
}

TEST_F(NiftiVsNibabel, FourDimensionalFileOpensEachVolume) {
    const auto& c = find("fourd");
    const auto expected = readExpected(c["values"]);
    const std::size_t per = expected.size() / 3;
    for (std::uint32_t t = 0; t < 3; ++t) {
        auto src = core::VoxelSourceFactory::open(c["path"].get<std::string>(), {}, t);
        expectSamePlacement(src->geometry(), c);
        const auto got = readPhysical(*src);
        ASSERT_EQ(got.size(), per);
        for (std::size_t i = 0; i < per; ++i) ASSERT_EQ(got[i], expected[t * per + i]) << "volume " << t << " voxel " << i;
        EXPECT_TRUE(mentions(src->warnings(), "4D file of 3 volumes"));
    }
    EXPECT_THROW(core::VoxelSourceFactory::open(c["path"].get<std::string>(), {}, 3), core::Error);
}

TEST_F(NiftiVsNibabel, BrokenFilesAreRefusedWithASentence) {
    const std::string src = find("type_int16")["path"];
    std::ifstream in(src, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto variant = [&](const std::string& name, std::string b) {
        const std::string path = dir_->file(name);
        std::ofstream(path, std::ios::binary).write(b.data(), std::streamsize(b.size()));
        return path;
    };
    auto message = [](const std::string& path) {
        try {
            core::NiftiVoxelSource s(path);
            std::vector<unsigned char> buf(s.geometry().byteSize());
            s.readSlices(0, s.geometry().dims[2], buf.data());
        } catch (const core::Error& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_NE(message(variant("trunc.nii", bytes.substr(0, bytes.size() - 10))).find("truncated"), std::string::npos);
    EXPECT_NE(message(variant("short.nii", bytes.substr(0, 100))).find("too short"), std::string::npos);
    std::string b = bytes;
    b[70] = 32;  // datatype 32: complex64
    EXPECT_NE(message(variant("complex.nii", b)).find("not supported"), std::string::npos);
    b = bytes;
    b[40] = 9;  // dim[0] = 9
    EXPECT_NE(message(variant("dim0.nii", b)).find("dim[0]"), std::string::npos);
    b = bytes;
    b[42] = 0, b[43] = char(0x80);  // dim[1] = -32768
    EXPECT_NE(message(variant("negdim.nii", b)).find("is not a size"), std::string::npos);
    b = bytes;
    b[0] = 0x1c, b[1] = 0x02, b[2] = 0, b[3] = 0;  // sizeof_hdr 540: NIfTI-2
    EXPECT_NE(message(variant("two.nii", b)).find("NIfTI-2"), std::string::npos);
    b = bytes;
    const float offset = 1e30f;
    std::memcpy(&b[108], &offset, 4);
    EXPECT_NE(message(variant("offset.nii", b)).find("vox_offset"), std::string::npos);
    EXPECT_NE(message(variant("garbage.nii.gz", std::string(4000, '\x1f'))).find(".nii"), std::string::npos);
    // A gzipped header promising more than deflate can hold (dims 30000 x 30000 x 1000 over a
    // few bytes) is refused when opened: it had taken 5.9 GB of memory before failing.
    b = bytes;
    for (const auto& [at, v] : {std::pair{42, 30000}, {44, 30000}, {46, 1000}}) {
        const auto d = std::int16_t(v);
        std::memcpy(&b[std::size_t(at)], &d, 2);
    }
    const std::string gz = dir_->file("big.nii.gz");
    gzFile f = gzopen(gz.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    gzwrite(f, b.data(), unsigned(b.size()));
    gzclose(f);
    EXPECT_NE(message(gz).find("bytes of compressed data can hold (deflate packs at most 1032 bytes into one)"), std::string::npos)
        << message(gz);
}

namespace {
/// A 4 x 3 x 2 int16 NIfTI-1 written field by field, for the header rules nibabel's writer
/// will not produce: identity quaternion, qoffset (1, 2, 3), sform rows of `spacing` with the
/// same offset plus `sformShift` in x, codes, units and scaling as given.
struct HandHeader {
    float pixdim0 = 1, spacing = 2, sformShift = 0, slope = 0, inter = 0;
    std::int16_t qformCode = 1, sformCode = 1;
    std::uint8_t units = 2;  // NIFTI_UNITS_MM
    std::string write(const std::string& path) const {
        std::string b(352 + 4 * 3 * 2 * 2, '\0');
        auto put = [&](std::size_t at, auto v) { std::memcpy(&b[at], &v, sizeof v); };
        put(0, std::int32_t(348));
        const std::int16_t dim[8] = {3, 4, 3, 2, 1, 1, 1, 1};
        for (int i = 0; i < 8; ++i) put(40 + 2 * std::size_t(i), dim[i]);
        put(70, std::int16_t(4));   // datatype int16
        put(72, std::int16_t(16));  // bitpix
        const float pix[4] = {pixdim0, spacing, spacing, spacing};
        for (int i = 0; i < 4; ++i) put(76 + 4 * std::size_t(i), pix[i]);
        put(108, 352.0f);
        put(112, slope);
        put(116, inter);
        b[123] = char(units);
        put(252, qformCode);
        put(254, sformCode);
        put(268, 1.0f), put(272, 2.0f), put(276, 3.0f);  // qoffset
        const float srow[3][4] = {{spacing, 0, 0, 1 + sformShift}, {0, spacing, 0, 2}, {0, 0, spacing, 3}};
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) put(280 + 16 * std::size_t(r) + 4 * std::size_t(c), srow[r][c]);
        std::memcpy(&b[344], "n+1\0", 4);
        std::ofstream(path, std::ios::binary).write(b.data(), std::streamsize(b.size()));
        return path;
    }
};

std::string refusal(const std::string& path) {
    try {
        core::NiftiVoxelSource s(path);
    } catch (const core::Error& e) {
        return e.what();
    }
    return "accepted";
}
}  // namespace

// The qform/sform disagreement is measured in millimetres whatever the file's unit (it had been
// compared in the file's unit against 0.01 mm times the unit: a metre file 50 mm off said
// nothing and a micrometre file 0.0005 mm off was called out).
TEST(NiftiHeaderRules, DisagreementIsMeasuredInMillimetres) {
    test::TempDir dir;
    HandHeader metres;
    metres.units = 1, metres.spacing = 0.002f, metres.sformShift = 0.05f;
    core::NiftiVoxelSource m(metres.write(dir.file("m.nii")));
    EXPECT_TRUE(mentions(m.warnings(), "disagree by up to 50 mm")) << ::testing::PrintToString(m.warnings());
    HandHeader microns;
    microns.units = 3, microns.spacing = 500, microns.sformShift = 0.5f;
    core::NiftiVoxelSource u(microns.write(dir.file("u.nii")));
    EXPECT_TRUE(u.warnings().empty()) << ::testing::PrintToString(u.warnings());
    microns.sformShift = 20;  // 0.02 mm
    core::NiftiVoxelSource u2(microns.write(dir.file("u2.nii")));
    EXPECT_TRUE(mentions(u2.warnings(), "disagree by up to 0.02 mm")) << ::testing::PrintToString(u2.warnings());
}

// A qform that cannot place the volume (a zero voxel size, a qfac neither 1 nor -1, where
// nifti1_io and nibabel read opposite slice orders) is refused when it is the placement, and
// set aside with a note when the sform places the volume; a NaN intercept beside a slope leaves
// the values unknown and is refused.
TEST(NiftiHeaderRules, AnUnusableQformIsRefusedOnlyWhereItPlacesTheVolume) {
    test::TempDir dir;
    HandHeader zero;
    zero.pixdim0 = 1;
    zero.spacing = 2;
    std::string path = zero.write(dir.file("z.nii"));
    {  // pixdim[1] = 0 beside a usable sform
        std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
        const float none = 0;
        f.seekp(80);
        f.write(reinterpret_cast<const char*>(&none), 4);
    }
    core::NiftiVoxelSource bySform(path);
    EXPECT_TRUE(mentions(bySform.warnings(), "its qform is not used (pixdim[1] = 0")) << ::testing::PrintToString(bySform.warnings());
    EXPECT_EQ(bySform.geometry().spacing, glm::dvec3(2.0));
    HandHeader odd;
    odd.pixdim0 = -0.5f;
    core::NiftiVoxelSource oddBySform(odd.write(dir.file("q.nii")));
    EXPECT_TRUE(mentions(oddBySform.warnings(), "pixdim[0] (qfac) = -0.5")) << ::testing::PrintToString(oddBySform.warnings());
    odd.sformCode = 0;
    EXPECT_NE(refusal(odd.write(dir.file("q0.nii"))).find("is neither 1 nor -1"), std::string::npos);
    HandHeader nan;
    nan.slope = 2, nan.inter = std::nanf("");
    EXPECT_NE(refusal(nan.write(dir.file("n.nii"))).find("scl_inter is not a number"), std::string::npos);
    nan.slope = 0;  // no scaling: the intercept does not matter
    EXPECT_EQ(refusal(nan.write(dir.file("n0.nii"))), "accepted");
}

// A NIfTI names no modality: "OT", unless dcm2niix's BIDS sidecar beside it says so.
TEST(NiftiHeaderRules, ModalityComesFromABidsSidecarOrIsUnknown) {
    test::TempDir dir;
    const std::string path = HandHeader{}.write(dir.file("scan.nii"));
    EXPECT_EQ(core::NiftiVoxelSource(path).geometry().modality, "OT");
    std::ofstream(dir.file("scan.json")) << R"({"Modality": "CT", "Manufacturer": "X", "SliceThickness": 1})";
    EXPECT_EQ(core::NiftiVoxelSource(path).geometry().modality, "CT");
    std::ofstream(dir.file("scan.json")) << R"({"Modality": "ct"})";
    core::NiftiVoxelSource lower(path);
    EXPECT_EQ(lower.geometry().modality, "OT");
    EXPECT_TRUE(mentions(lower.warnings(), "not a DICOM modality code")) << ::testing::PrintToString(lower.warnings());
    std::ofstream(dir.file("scan.json")) << "{\"Modality\": ";
    core::NiftiVoxelSource broken(path);
    EXPECT_EQ(broken.geometry().modality, "OT");
    EXPECT_TRUE(mentions(broken.warnings(), "cannot be read as JSON")) << ::testing::PrintToString(broken.warnings());
}
