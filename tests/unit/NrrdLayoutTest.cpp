// Where a NRRD's data begin and what its axes are: line skip, byte skip (−1: the data are the
// file's last bytes), kinds and several data files. Each file Holovox reads is also read by
// teem itself (teem-unu, the NRRD format's reference), saved as a plain NRRD, and Holovox's
// voxels of the two must be equal; what Holovox does not read is refused with a sentence.

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

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
