#include <gtest/gtest.h>

#include <fstream>

#include "core/base/Error.h"
#include "dicom/DicomHeaderReader.h"
#include "dicom/DicomScanner.h"
#include "dicom/DicomSeriesSource.h"
#include "dicom/PixelDecoder.h"
#include "dicom/SeriesAssembler.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
const std::string corpus = "/usr/lib/python3/dist-packages/pydicom/data/test_files/";

std::vector<std::int32_t> decodeFile(const std::string& name, std::uint32_t frame = 0) {
    dicom::DicomInstance in;
    EXPECT_EQ(dicom::DicomHeaderReader::read(corpus + name, in), dicom::DicomHeaderReader::Kind::Dicom);
    dicom::PixelDecoder d;
    std::vector<std::int32_t> out;
    d.decode(in, frame, out);
    return out;
}
}  // namespace

TEST(DicomCorpus, EveryEncodingOfMrSmallDecodesToTheSamePixels) {
    // pydicom ships one MR image in many transfer syntaxes.
    const auto reference = decodeFile("MR_small.dcm");
    ASSERT_EQ(reference.size(), 64u * 64u);
    for (const char* f : {"MR_small_RLE.dcm", "MR_small_bigendian.dcm", "MR_small_expb.dcm", "MR_small_implicit.dcm",
                          "MR_small_jp2klossless.dcm", "MR_small_jpeg_ls_lossless.dcm"}) {
        EXPECT_EQ(decodeFile(f), reference) << f;
    }
}

TEST(DicomCorpus, DeflateJpegAndJpeg2000FilesDecode) {
    EXPECT_EQ(decodeFile("image_dfl.dcm").size(), 512u * 512u);
    EXPECT_FALSE(decodeFile("JPEG2000.dcm").empty());
    EXPECT_FALSE(decodeFile("JPEG-lossy.dcm").empty());
    const auto ct = decodeFile("CT_small.dcm");
    ASSERT_EQ(ct.size(), 128u * 128u);
    // CT_small: signed 16-bit, stored 128..2191 with intercept -1024 (checked against pydicom).
    EXPECT_EQ(*std::min_element(ct.begin(), ct.end()), 128);
    EXPECT_EQ(*std::max_element(ct.begin(), ct.end()), 2191);
}

TEST(DicomCorpus, WholeCorpusScansAndDecodesWithoutCrashing) {
    core::JobContext job;
    const auto scan = dicom::DicomScanner::scan({corpus}, job);
    EXPECT_GT(scan.instances.size(), 100u);
    EXPECT_GT(scan.broken, 0u);  // the corpus has deliberately broken files
    EXPECT_FALSE(scan.brokenReasons.empty());
    for (const auto& r : scan.brokenReasons) EXPECT_EQ(r.rfind(corpus, 0), 0u) << "reason must name the file: " << r;
    std::vector<std::string> notes;
    const auto volumes = dicom::SeriesAssembler::assemble(scan.instances, notes);
    EXPECT_FALSE(notes.empty());  // SR, RT plans, waveforms ... are named, not volumes
    std::size_t decoded = 0, refused = 0;
    for (const auto& v : volumes) {
        try {
            dicom::DicomSeriesSource src(v);
            const auto& g = src.geometry();
            std::vector<char> buf(std::size_t(g.dims[0]) * g.dims[1] * core::scalarSize(g.scalarType));
            for (std::uint32_t z = 0; z < g.dims[2]; ++z) src.readSlices(z, 1, buf.data());
            ++decoded;
        } catch (const core::Error& e) {
            ++refused;  // a clear message, never a crash
            EXPECT_NE(std::string(e.what()).find(corpus), std::string::npos) << e.what();
        }
    }
    EXPECT_GT(decoded, 20u);
    std::printf("corpus: %zu instances, %zu broken, %zu volumes decoded, %zu refused with a message\n",
                scan.instances.size(), scan.broken, decoded, refused);
}

TEST(DicomCorpus, DicomdirListsItsReferencedFiles) {
    const auto files = dicom::DicomScanner::filesOfDicomdir(corpus + "dicomdirtests/DICOMDIR");
    EXPECT_GT(files.size(), 10u);
    for (const auto& f : files) EXPECT_TRUE(std::filesystem::exists(f)) << f;
}

TEST(DicomCorpus, TruncatedAndForeignFilesAreReportedNotCrashed) {
    test::TempDir dir;
    std::ifstream in(corpus + "CT_small.dcm", std::ios::binary);
    std::string all((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(dir.file("header-cut.dcm"), std::ios::binary) << all.substr(0, 400);
    std::ofstream(dir.file("pixels-cut.dcm"), std::ios::binary) << all.substr(0, all.size() - 5000);
    std::ofstream(dir.file("notes.txt")) << "not dicom";
    std::string noMeta = all.substr(0, 128) + "XXXX" + all.substr(132);
    std::ofstream(dir.file("bad-magic.dcm"), std::ios::binary) << noMeta;
    core::JobContext job;
    const auto scan = dicom::DicomScanner::scan({dir.path().string()}, job);
    EXPECT_GE(scan.notDicom, 1u);
    std::vector<std::string> notes;
    for (const auto& v : dicom::SeriesAssembler::assemble(scan.instances, notes)) {
        dicom::DicomSeriesSource src(v);
        std::vector<char> buf(std::size_t(v.geometry.dims[0]) * v.geometry.dims[1] * 8);
        try {
            for (std::uint32_t z = 0; z < v.geometry.dims[2]; ++z) src.readSlices(z, 1, buf.data());
        } catch (const core::Error& e) {
            EXPECT_NE(std::string(e.what()).find(dir.path().string()), std::string::npos) << e.what();
        }
    }
    EXPECT_EQ(scan.instances.size() + scan.notDicom + scan.broken, 4u);
}
