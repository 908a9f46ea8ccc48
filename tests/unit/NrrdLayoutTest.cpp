// Where a NRRD's data begin and what its axes are: line skip, byte skip (−1: the data are the
// file's last bytes), kinds, several data files, and 4-D files (3D Slicer's sequences) whose
// last axis lists volumes. Each file Holovox reads is also read by
// teem itself (teem-unu, the NRRD format's reference), saved as a plain NRRD, and Holovox's
// voxels of the two must be equal; what Holovox does not read is refused with a sentence.

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "core/volume/NrrdHeader.h"
#include "core/volume/VoxelSourceFactory.h"
#include "tests/support/ErrorOf.h"
#include "tests/support/ProcessRunner.h"
#include "tests/support/TempDir.h"
#include "tests/support/VoxelValues.h"

using namespace hvx;

namespace {
using test::errorOf;

const std::string kHead = "NRRD0004\ntype: short\ndimension: 3\nsizes: 5 4 3\nspace: LPS\n"
                          "space directions: (0.5,0,0) (0,0.5,0) (0,0,2)\nendian: little\n";

std::string voxels() {
    std::string out;
    for (int i = 0; i < 60; ++i) {
        const std::int16_t v = std::int16_t(i * 37 - 900);
        out.append(reinterpret_cast<const char*>(&v), 2);
    }
    return out;
}

/// Holovox's voxels of `file`, and of teem's plain re-save of it: both, for comparing.
std::pair<std::vector<std::int16_t>, std::vector<std::int16_t>> oursAndTeems(test::TempDir& dir, const std::string& file) {
    const std::string plain = dir.file("teem-" + std::to_string(std::hash<std::string>{}(file)) + ".nrrd");
    const auto r = test::runCommand("teem-unu save -f nrrd -e raw -i " + dir.file(file) + " -o " + plain);
    EXPECT_EQ(r.exitCode, 0) << "teem could not read " << file << ": " << r.output;
    auto ours = core::VoxelSourceFactory::open(dir.file(file));
    auto theirs = core::VoxelSourceFactory::open(plain);
    return {test::readAll<std::int16_t>(*ours), test::readAll<std::int16_t>(*theirs)};
}
}  // namespace

TEST(NrrdLayout, LineAndByteSkipsPlaceTheDataAsTeemDoes) {
    test::TempDir dir;
    std::ofstream(dir.file("a.nrrd"), std::ios::binary)
        << kHead << "encoding: raw\nline skip: 2\nbyte skip: 3\n\n" << "a comment\nanother, longer line\nxyz" << voxels();
    std::ofstream(dir.file("tail.nhdr"), std::ios::binary) << kHead << "encoding: raw\nbyte skip: -1\ndata file: tail.raw\n";
    std::ofstream(dir.file("tail.raw"), std::ios::binary) << std::string(1000, '\x7f') << voxels();
    std::ofstream(dir.file("atail.nrrd"), std::ios::binary) << kHead << "encoding: raw\nbyteskip: -1\n\n" << "junk" << voxels();
    for (const char* f : {"a.nrrd", "tail.nhdr", "atail.nrrd"}) {
        SCOPED_TRACE(f);
        const auto [ours, teems] = oursAndTeems(dir, f);
        EXPECT_EQ(ours, teems);
        EXPECT_EQ(ours[0], -900);
        EXPECT_EQ(ours[59], 59 * 37 - 900);
    }
}

// NRRD's text encoding, as teem writes it (teem-unu save -e ascii, one value a line, and
// a float volume whose values need their digits), read as teem reads it; and text data that
// contradict the header refused naming the voxel.
TEST(NrrdLayout, TextEncodingIsReadAsTeemReadsIt) {
    test::TempDir dir;
    std::ofstream(dir.file("raw.nrrd"), std::ios::binary) << kHead << "encoding: raw\n\n" << voxels();
    auto r = test::runCommand("teem-unu save -f nrrd -e ascii -i " + dir.file("raw.nrrd") + " -o " + dir.file("text.nrrd"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::ofstream(dir.file("crlf.nhdr"), std::ios::binary) << kHead << "encoding: text\nline skip: 1\ndata file: crlf.txt\n";
    std::string text = "a line teem skips\n";
    for (int i = 0; i < 60; ++i) text += std::to_string(i * 37 - 900) + (i % 5 == 4 ? "\r\n" : "\t");
    std::ofstream(dir.file("crlf.txt"), std::ios::binary) << text;
    for (const char* f : {"text.nrrd", "crlf.nhdr"}) {
        SCOPED_TRACE(f);
        const auto [ours, teems] = oursAndTeems(dir, f);
        EXPECT_EQ(ours, teems);
        EXPECT_EQ(ours[0], -900);
        EXPECT_EQ(ours[59], 59 * 37 - 900);
        auto src = core::VoxelSourceFactory::open(dir.file(f));
        EXPECT_EQ(src->geometry().spacing, glm::dvec3(0.5, 0.5, 2));
    }
    // Names in capitals, which teem reads as it reads them in lower case.
    std::ofstream(dir.file("caps.nrrd"), std::ios::binary)
        << "NRRD0004\ntype: SHORT\ndimension: 3\nsizes: 5 4 3\nendian: LITTLE\nencoding: RAW\n\n" << voxels();
    EXPECT_EQ(oursAndTeems(dir, "caps.nrrd").first, oursAndTeems(dir, "caps.nrrd").second);
    // Floats: teem's text, parsed here, equals teem's own binary re-save bit for bit.
    std::string floats;
    for (int i = 0; i < 60; ++i) {
        const float v = float(i) * 0.1f - 2.5e-3f * float(i * i) + 1e-7f;
        floats.append(reinterpret_cast<const char*>(&v), 4);
    }
    std::ofstream(dir.file("f.nrrd"), std::ios::binary)
        << "NRRD0004\ntype: float\ndimension: 3\nsizes: 5 4 3\nendian: little\nencoding: raw\n\n" << floats;
    r = test::runCommand("teem-unu save -f nrrd -e ascii -i " + dir.file("f.nrrd") + " -o " + dir.file("ftext.nrrd"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = test::runCommand("teem-unu save -f nrrd -e raw -i " + dir.file("ftext.nrrd") + " -o " + dir.file("fteem.nrrd"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    auto ours = core::VoxelSourceFactory::open(dir.file("ftext.nrrd"));
    auto teems = core::VoxelSourceFactory::open(dir.file("fteem.nrrd"));
    EXPECT_EQ(test::readAll<float>(*ours), test::readAll<float>(*teems));
    // Text that ends early, or holds a word, is refused naming the voxel.
    std::ofstream(dir.file("short.nrrd"), std::ios::binary) << kHead << "encoding: ascii\n\n" << text.substr(18, 150);
    EXPECT_NE(errorOf([&] { test::readAll<std::int16_t>(*core::VoxelSourceFactory::open(dir.file("short.nrrd"))); })
                  .find("its text data end after "),
              std::string::npos);
    std::ofstream(dir.file("word.nrrd"), std::ios::binary) << kHead << "encoding: ascii\n\n" << "1 2 three " << text.substr(18);
    EXPECT_NE(errorOf([&] { test::readAll<std::int16_t>(*core::VoxelSourceFactory::open(dir.file("word.nrrd"))); })
                  .find("its voxel (2, 0, 0) (value number 3), 'three', is not a number"),
              std::string::npos);
}

TEST(NrrdLayout, WhatHolovoxDoesNotReadIsRefusedWithASentence) {
    test::TempDir dir;
    auto refusal = [&](const std::string& text) {
        std::ofstream(dir.file("r.nhdr"), std::ios::binary) << text;
        const std::string e = errorOf([&] { test::readAll<std::int16_t>(*core::VoxelSourceFactory::open(dir.file("r.nhdr"))); });
        EXPECT_EQ(e.rfind(dir.file("r.nhdr") + ": ", 0), 0u) << e;
        return e;
    };
    auto has = [](const std::string& e, const char* part) { return e.find(part) != std::string::npos; };
    EXPECT_TRUE(has(refusal(kHead + "encoding: raw\ndata file: LIST\ns0.raw\ns1.raw\ns2.raw\n"),
                    "NRRD data in several files ('data file: LIST') is not read by Holovox"));
    EXPECT_TRUE(has(refusal(kHead + "encoding: raw\ndata file: s%03d.raw 0 2 1\n"), "NRRD data in several files"));
    EXPECT_TRUE(has(refusal(kHead + "encoding: raw\nkinds: RGB-color domain domain\n\n" + voxels()),
                    "NRRD axis kind 'RGB-color' is not spatial"));
    EXPECT_TRUE(has(refusal(kHead + "encoding: gzip\nbyte skip: 4\n\n"), "byte skip with gzip encoding is not read"));
    EXPECT_TRUE(has(refusal(kHead + "encoding: raw\nbyte skip: -2\n\n" + voxels()), "is not a byte count or -1"));
    EXPECT_TRUE(has(refusal(kHead + "encoding: raw\nline skip: 3\n\n" + "one\ntwo\n"), "line skip 3 passes the end"));
    EXPECT_TRUE(has(refusal(kHead + "encoding: raw\nbyte skip: -1\n\n" + voxels().substr(2)), "need 120 bytes at the end"));
}

namespace {
/// Three volumes of 5x4x3 int16 one after the other, each its own ramp.
std::string threeVolumes() {
    std::string out;
    for (int v = 0; v < 3; ++v)
        for (int i = 0; i < 60; ++i) {
            const std::int16_t x = std::int16_t(v * 1000 + i * 7 - 200);
            out.append(reinterpret_cast<const char*>(&x), 2);
        }
    return out;
}

const std::string kSequence = "NRRD0004\ntype: short\ndimension: 4\nspace: right-anterior-superior\nsizes: 5 4 3 3\n"
                              "space directions: (0,-0.8,0) (0.9,0,0) (0,0,2.5) none\nkinds: domain domain domain list\n"
                              "endian: little\nspace origin: (12,-30,40)\n";
}  // namespace

TEST(NrrdLayout, FourDimensionalFilesAreReadOneVolumeAtATimeAsTeemSlicesThem) {
    test::TempDir dir;
    std::ofstream(dir.file("seq.nrrd"), std::ios::binary) << kSequence << "encoding: raw\n\n" << threeVolumes();
    std::ofstream(dir.file("seq-gz.nrrd"), std::ios::binary) << kSequence << "encoding: gzip\n\n";
    {
        gzFile f = gzopen(dir.file("seq-gz.nrrd").c_str(), "ab");
        ASSERT_NE(f, nullptr);
        const std::string data = threeVolumes();
        ASSERT_EQ(gzwrite(f, data.data(), unsigned(data.size())), int(data.size()));
        gzclose(f);
    }
    for (const char* file : {"seq.nrrd", "seq-gz.nrrd"}) {
        SCOPED_TRACE(file);
        EXPECT_EQ(core::VoxelSourceFactory::volumesIn(dir.file(file)), 3u);
        for (std::uint32_t v : {2u, 0u, 1u}) {  // out of order: a gzip stream restarts
            SCOPED_TRACE(v);
            const std::string teem = dir.file("teem-" + std::to_string(v) + ".nrrd");
            const auto r = test::runCommand("teem-unu slice -a 3 -p " + std::to_string(v) + " -i " + dir.file(file) + " -o " + teem);
            ASSERT_EQ(r.exitCode, 0) << r.output;
            auto ours = core::VoxelSourceFactory::open(dir.file(file), {}, v);
            auto theirs = core::VoxelSourceFactory::open(teem);
            const auto a = ours->geometry().indexToPatient(), b = theirs->geometry().indexToPatient();
            for (int c = 0; c < 4; ++c)
                for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[c][k], b[c][k], 1e-9) << "column " << c;
            const auto got = test::readAll<std::int16_t>(*ours);
            EXPECT_EQ(got, test::readAll<std::int16_t>(*theirs));
            EXPECT_EQ(got[0], std::int16_t(v * 1000 - 200));
        }
    }
    const std::string e = errorOf([&] { core::VoxelSourceFactory::open(dir.file("seq.nrrd"), {}, 3); });
    EXPECT_EQ(e, dir.file("seq.nrrd") + ": holds 3 volumes; there is no volume 4");
}

TEST(NrrdLayout, FourDimensionalFilesThatDoNotListVolumesLastAreRefused) {
    test::TempDir dir;
    auto refusal = [&](const std::string& text, std::uint32_t volume = 0, const char* name = "r.nrrd") {
        std::ofstream(dir.file(name), std::ios::binary) << text;
        return errorOf([&] { test::readAll<std::int16_t>(*core::VoxelSourceFactory::open(dir.file(name), {}, volume)); });
    };
    auto has = [](const std::string& e, const char* part) { return e.find(part) != std::string::npos; };
    const std::string plain4d = "NRRD0004\ntype: short\ndimension: 4\nsizes: 5 4 3 3\nendian: little\nencoding: raw\n";
    EXPECT_TRUE(has(refusal(plain4d + "spacings: 1 1 1 nan\n\n" + threeVolumes()), "must say that its last axis lists volumes"));
    EXPECT_TRUE(has(refusal(plain4d + "kinds: list domain domain domain\n\n" + threeVolumes()),
                    "NRRD axis kind 'list' is not spatial (values interleaved per voxel, as a DWI's)"));
    EXPECT_TRUE(has(refusal(plain4d + "space: LPS\nspace directions: none (1,0,0) (0,1,0) (0,0,1)\n\n" + threeVolumes()),
                    "are not three vectors and a last 'none'"));
    EXPECT_TRUE(has(refusal(kSequence + "encoding: raw\n\n" + threeVolumes().substr(10), 0),
                    "3 volumes of 120 bytes need"));
    EXPECT_TRUE(has(refusal("NRRD0004\ntype: short\ndimension: 5\n"), "only 3-D single-component NRRD volumes"));
    // a volume other than the first of a file that holds one is refused, never the first shown
    std::ofstream(dir.file("one.mha"), std::ios::binary)
        << "ObjectType = Image\nNDims = 3\nDimSize = 5 4 3\nElementType = MET_SHORT\nElementDataFile = LOCAL\n"
        << voxels();
    const std::string e = errorOf([&] { core::VoxelSourceFactory::open(dir.file("one.mha"), {}, 1); });
    EXPECT_TRUE(has(e, "one.mha: holds one volume; a volume other than the first")) << e;
    EXPECT_TRUE(has(refusal(kHead + "encoding: raw\n\n" + voxels(), 1, "three.nrrd"), "holds 1 volume; there is no volume 2"));
}
