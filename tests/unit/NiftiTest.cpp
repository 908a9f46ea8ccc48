// NIfTI-1 reading against nibabel, an independent reader: every combination of qform and
// sform codes, qfac +-1, a mirrored and sheared sform, 3 to 300 slices (the chunk boundaries
// of the old VTK reader), every integer and float type, scaling, big-endian, micrometres, 4D
// and gzip. Each voxel's LPS position and value must be nibabel's.
#include <gtest/gtest.h>

#include <cmath>
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
}
