#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "core/base/Error.h"
#include "dicom/DicomHeaderReader.h"
#include "dicom/DicomScanner.h"
#include "dicom/SegmentationSource.h"
#include "dicom/DicomSeriesSource.h"
#include "dicom/PixelDecoder.h"
#include "dicom/SeriesAssembler.h"
#include "core/volume/ScalarType.h"
#include "tests/support/ProcessRunner.h"
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

// A folder with a DICOMDIR: what it references and the files it does not list (a series copied
// in beside it had been ignored without a word), each file once.
TEST(DicomCorpus, AFolderWithADicomdirKeepsTheFilesItDoesNotList) {
    test::TempDir dir;
    std::filesystem::copy(corpus + "dicomdirtests", dir.file("cd"), std::filesystem::copy_options::recursive);
    std::filesystem::copy_file(corpus + "CT_small.dcm", dir.file("cd/EXTRA.dcm"));
    core::JobContext job;
    const auto listed = dicom::DicomScanner::filesOfDicomdir(dir.file("cd/DICOMDIR"));
    const auto scan = dicom::DicomScanner::scan({dir.file("cd")}, job);
    std::set<std::string> paths, sops;
    for (const auto& in : scan.instances) paths.insert(in.path), sops.insert(in.sopInstanceUid);
    EXPECT_TRUE(paths.count(dir.file("cd/EXTRA.dcm"))) << "the unlisted file";
    for (const auto& f : listed) EXPECT_TRUE(paths.count(f)) << f;
    EXPECT_EQ(paths.size(), scan.instances.size()) << "each file once";
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
    // The file whose pixels were cut is refused when scanned, naming what is missing (it had
    // been imported and failed only when its series was built).
    for (const auto& found : scan.instances) EXPECT_EQ(found.path.find("pixels-cut"), std::string::npos) << found.path;
    bool named = false;
    for (const auto& r : scan.brokenReasons)
        named = named || (r.find("pixels-cut.dcm: the file's") != std::string::npos && r.find("truncated") != std::string::npos);
    EXPECT_TRUE(named) << ::testing::PrintToString(scan.brokenReasons);
}

// pydicom as the oracle for pixels: every grey image of its corpus that pydicom
// itself decodes (uncompressed in each byte order and VR encoding, deflated, RLE; CT, MR, CR,
// RT dose) is imported by Holovox to the same physical values (pydicom's modality LUT, and an
// RT dose's DoseGridScaling, which pydicom leaves to its caller), pixel
// for pixel: the sum, the sum of squares and a position-weighted sum agree, so that a value,
// a scale or a pixel's place that differs fails.
TEST(DicomCorpus, EveryImagePydicomDecodesImportsToPydicomsValues) {
    test::TempDir dir;
    const std::string script =
        "import sys, os, glob, warnings\n"
        "warnings.filterwarnings('ignore')\n"
        "import numpy as np, pydicom\n"
        "from pydicom.pixel_data_handlers.util import apply_modality_lut\n"
        "root = sys.argv[1]\n"
        "for path in sorted(glob.glob(os.path.join(root, '**', '*'), recursive=True)):\n"
        "    if not os.path.isfile(path): continue\n"
        "    try:\n"
        "        ds = pydicom.dcmread(path)\n"
        "        if 'PixelData' not in ds or int(ds.get('SamplesPerPixel', 1)) != 1: continue\n"
        "        if ds.SOPClassUID == '1.2.840.10008.5.1.4.1.1.66.4': continue  # SEG: not an image\n"
        "        frames = int(ds.get('NumberOfFrames', 1) or 1)\n"
        "        a = apply_modality_lut(ds.pixel_array, ds).astype(np.float64)\n"
        "        if 'DoseGridScaling' in ds: a *= float(ds.DoseGridScaling)  # RT dose: in Gy\n"
        "    except Exception:\n"
        "        continue\n"
        "    if a.ndim != (2 if frames == 1 else 3): continue\n"
        "    w = np.arange(a.size, dtype=np.float64).reshape(a.shape) % 7\n"
        "    print(path, a.shape[-1], a.shape[-2], frames, repr(float(a.sum())), repr(float((a * a).sum())),\n"
        "          repr(float((a * w).sum())))\n";
    std::ofstream(dir.file("oracle.py")) << script;
    const auto py = test::runCommand("/usr/bin/python3 " + dir.file("oracle.py") + " " + corpus);
    ASSERT_EQ(py.exitCode, 0) << py.output;
    std::istringstream lines(py.output);
    int files = 0, refused = 0;
    for (std::string path; lines >> path;) {
        std::uint32_t cols = 0, rows = 0, frames = 0;
        double sum = 0, squares = 0, weighted = 0;
        lines >> cols >> rows >> frames >> sum >> squares >> weighted;
        ++files;
        core::JobContext job;
        const auto scan = dicom::DicomScanner::scan({path}, job);
        std::vector<std::string> notes;
        const auto volumes = dicom::SeriesAssembler::assemble(scan.instances, notes);
        ASSERT_EQ(volumes.size(), 1u) << path;
        const auto& g = volumes[0].geometry;
        ASSERT_EQ(g.dims[0], cols) << path;
        ASSERT_EQ(g.dims[1], rows) << path;
        ASSERT_EQ(g.dims[2], frames) << path;
        // (A multi-frame object's frames are stacked by position, not in file order: its
        // position-weighted sum is pydicom's only for one frame.)
        const std::size_t n = std::size_t(cols) * rows * frames;
        std::vector<double> values(n);
        try {
            dicom::DicomSeriesSource src(volumes[0]);
            core::dispatchScalar(g.scalarType, [&](auto tag) {
                using T = decltype(tag);
                std::vector<T> raw(n);
                src.readSlices(0, frames, raw.data());
                for (std::size_t i = 0; i < n; ++i) values[i] = double(raw[i]) * g.rescaleSlope + g.rescaleIntercept;
            });
        } catch (const core::Error& e) {
            // Refused in words that name the file: only 1-bit segmentations (DICOM SEG, which the
            // label-map issue imports as labels, not as an image).
            const std::string why = e.what();
            EXPECT_NE(why.find(path), std::string::npos) << why;
            EXPECT_NE(why.find("BitsAllocated 1"), std::string::npos) << why;
            ++refused;
            continue;
        }
        double s = 0, q = 0, w = 0;
        for (std::size_t i = 0; i < n; ++i) s += values[i], q += values[i] * values[i], w += values[i] * double(i % 7);
        const auto near = [](double a, double b) { return std::abs(a - b) <= 1e-6 * (1.0 + std::abs(b)); };
        EXPECT_TRUE(near(s, sum) && near(q, squares) && (frames > 1 || near(w, weighted)))
            << path << ": Holovox sum " << s << ", squares " << q << ", weighted " << w << "; pydicom " << sum << ", "
            << squares << ", " << weighted;
    }
    std::printf("%d corpus images compared with pydicom's decode, %d refused (1-bit segmentations)\n", files - refused,
                refused);  // 45 and 2 on Debian 12 (pydicom 2.3: no JPEG handler for its JPEG files)
    EXPECT_GE(files, 40) << "pydicom decoded fewer of its corpus images than it does on Debian 12";
}

// The corpus' two segmentation objects (1-bit, 512 x 512, no functional groups dcmseg accepts):
// never stacked as images by import, and refused with a sentence naming the file, not read as
// something else.
TEST(DicomCorpus, SegmentationObjectsAreNotImagesAndBrokenOnesAreRefused) {
    for (const char* name : {"liver_1frame.dcm", "liver_expb_1frame.dcm"}) {
        const std::string path = corpus + name;
        core::JobContext job;
        const auto scan = dicom::DicomScanner::scan({path}, job);
        std::vector<std::string> notes;
        EXPECT_TRUE(dicom::SeriesAssembler::assemble(scan.instances, notes).empty()) << name;
        bool said = false;
        for (const auto& n : notes) said = said || n.find("segmentation objects (SEG") != std::string::npos;
        EXPECT_TRUE(said) << name;
        EXPECT_TRUE(dicom::SegmentationSource::isSegmentation(path));
        try {
            dicom::SegmentationSource source(path);
            ADD_FAILURE() << name << " was read";
        } catch (const core::Error& e) {
            EXPECT_NE(std::string(e.what()).find(path + ": "), std::string::npos) << e.what();
        }
    }
}
