#include "tests/support/PacsFixtures.h"

#include <cstring>
#include <fstream>
#include <iterator>

#include "core/base/JobContext.h"
#include "core/volume/PhantomVoxelSource.h"
#include "dicom/DicomHeaderReader.h"

namespace hvx::test {

std::vector<std::string> writeSeries(const std::string& dir, std::array<std::uint32_t, 3> dims,
                                     dicom::DicomWriteOptions o) {
    core::PhantomVoxelSource p(dims, 5);
    core::JobContext job;
    return dicom::DicomSeriesWriter::write(p, dir, o, job);
}

Seeded makeStudies(const std::string& dir) {
    Seeded s;
    s.studyA = "1.2.826.0.1.3680043.9.7777.10";
    s.studyB = "1.2.826.0.1.3680043.9.7777.20";
    s.seriesA1 = "1.2.826.0.1.3680043.9.7777.11";
    s.seriesA2 = "1.2.826.0.1.3680043.9.7777.12";
    s.seriesB1 = "1.2.826.0.1.3680043.9.7777.21";
    dicom::DicomWriteOptions a;
    a.patientName = "DOE^JANE";
    a.patientId = "P1";
    a.studyDate = "20240301";
    a.studyDescription = "CT CHEST";
    a.accessionNumber = "ACC1";
    a.studyUid = s.studyA;
    a.seriesUid = s.seriesA1;
    a.modality = "CT";
    for (auto& f : writeSeries(dir + "/a1", {32, 32, 20}, a)) s.files.push_back(f);
    a.seriesUid = s.seriesA2;
    a.seriesNumber = 2;
    a.seriesDescription = "Bone";
    for (auto& f : writeSeries(dir + "/a2", {32, 32, 10}, a)) s.files.push_back(f);
    dicom::DicomWriteOptions b;
    b.patientName = "ROE^RICHARD";
    b.patientId = "P2";
    b.studyDate = "20231115";
    b.studyDescription = "MR BRAIN";
    b.studyUid = s.studyB;
    b.seriesUid = s.seriesB1;
    b.modality = "MR";
    for (auto& f : writeSeries(dir + "/b1", {24, 24, 8}, b)) s.files.push_back(f);
    return s;
}

std::string datasetBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string all((std::istreambuf_iterator<char>(in)), {});
    if (all.size() < 144 || all.compare(128, 4, "DICM") != 0) return all;
    std::uint32_t groupLength = 0;
    std::memcpy(&groupLength, all.data() + 140, 4);
    return all.substr(144 + groupLength);
}

std::map<std::string, std::string> bySop(const std::vector<std::string>& files) {
    std::map<std::string, std::string> m;
    for (const auto& f : files) {
        dicom::DicomInstance in;
        dicom::DicomHeaderReader::read(f, in);
        m[in.sopInstanceUid] = f;
    }
    return m;
}

}  // namespace hvx::test
