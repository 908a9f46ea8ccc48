#include <gtest/gtest.h>

#include <fstream>

#include "core/base/Error.h"
#include "dicom/DicomFileProbe.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
const std::string corpus = "/usr/lib/python3/dist-packages/pydicom/data/test_files/";
}

TEST(DicomFileProbe, ReadsHeaderFieldsOfARealCtFile) {
    const auto p = dicom::DicomFileProbe::probe(corpus + "CT_small.dcm");
    EXPECT_EQ(p.modality, "CT");
    EXPECT_EQ(p.rows, 128);
    EXPECT_EQ(p.columns, 128);
    EXPECT_EQ(p.frames, 1u);
    EXPECT_EQ(p.sopClassUid, "1.2.840.10008.5.1.4.1.1.2");
    EXPECT_FALSE(p.seriesInstanceUid.empty());
    EXPECT_NE(p.summary().find("CTImageStorage"), std::string::npos) << p.summary();
}

TEST(DicomFileProbe, BigEndianAndNoMetaFilesAreRead) {
    EXPECT_NO_THROW(dicom::DicomFileProbe::probe(corpus + "ExplVR_BigEnd.dcm"));
    EXPECT_NO_THROW(dicom::DicomFileProbe::probe(corpus + "ExplVR_LitEndNoMeta.dcm"));
}

TEST(DicomFileProbe, NonDicomAndTruncatedFilesGiveAnErrorNamingTheFile) {
    test::TempDir dir;
    std::ofstream(dir.file("note.txt")) << "just some text, not DICOM";
    try {
        dicom::DicomFileProbe::probe(dir.file("note.txt"));
        FAIL();
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find(dir.file("note.txt")), std::string::npos);
    }
    std::ifstream in(corpus + "CT_small.dcm", std::ios::binary);
    std::string all((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(dir.file("cut.dcm"), std::ios::binary) << all.substr(0, 300);
    EXPECT_THROW(dicom::DicomFileProbe::probe(dir.file("cut.dcm")), core::Error);
}

TEST(DicomFileProbe, ReportsTheDcmtkVersion) { EXPECT_EQ(dicom::DicomFileProbe::dcmtkVersion().rfind("3.6", 0), 0u); }
