// The measurement list: labels that survive deletions, CSV that Python's csv module reads back
// field for field (quoting of names with commas and quotes), JSON with the patient, study and
// series UIDs and LPS points that reads back to the same list, and refusals of other text.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <sstream>
#include <fstream>

#include "core/base/Error.h"
#include "core/reference/MeasurementList.h"
#include "tests/support/ProcessRunner.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
core::MeasurementList sample() {
    core::MeasurementList list;
    core::Measurement d;
    d.kind = core::Measurement::Kind::Distance;
    d.view = "axial";
    d.a = {10, -20, 30};
    d.b = {13, -16, 30};
    list.add(d);
    core::Measurement r;
    r.kind = core::Measurement::Kind::Region;
    r.view = "coronal";
    r.region = core::MeasureRegion::disc({1.5, 2.5, -3.5}, {0, 1, 0}, 12.0, 1.0);
    core::RegionStatistics st;
    st.voxels = 452;
    st.mean = 41.25;
    st.sd = 7.5;
    st.min = -3;
    st.max = 88;
    st.units = "HU";
    st.areaMm2 = 452.0;
    st.volumeMm3 = 452.0;
    r.stats = st;
    list.add(r);
    return list;
}

core::MeasurementSource source() {
    return {"DOE, \"JJ\"^JANE", "P1", "1.2.3", "1.2.3.4", "/data/ct.hvo"};
}
}  // namespace

TEST(MeasurementList, LabelsSurviveDeletions) {
    auto list = sample();
    ASSERT_EQ(list.items().size(), 2u);
    EXPECT_EQ(list.items()[0].label, "M1");
    EXPECT_EQ(list.items()[1].label, "M2");
    EXPECT_DOUBLE_EQ(list.items()[0].lengthMm(), 5.0);
    EXPECT_TRUE(list.remove("M1"));
    EXPECT_FALSE(list.remove("M1"));
    EXPECT_EQ(list.items()[0].label, "M2");
    EXPECT_EQ(list.add(core::Measurement{}).label, "M3");
}

TEST(MeasurementList, CsvReadsBackInPython) {
    test::TempDir dir;
    const std::string csv = sample().toCsv(source());
    std::ofstream(dir.file("m.csv")) << csv;
    // Python's csv module, not Holovox, reads the file: every row has the header's fields.
    const auto r = test::runCommand("/usr/bin/python3 -c \"import csv,sys; rows=list(csv.DictReader(open('" +
                                    dir.file("m.csv") +
                                    "'))); print(len(rows)); print(rows[0]['length_mm'], rows[0]['a_x_lps'], rows[0]['b_y_lps']);"
                                    " print(rows[1]['mean'], rows[1]['voxels'], rows[1]['units'], rows[1]['region']);"
                                    " print(rows[1]['patient_name']); print(rows[0]['series_uid'], rows[0]['study_uid'])\"");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output, "2\n5 10 -16\n41.25 452 HU disc\nDOE, \"JJ\"^JANE\n1.2.3.4 1.2.3\n");
}

TEST(MeasurementList, JsonCarriesTheUidsAndReadsBack) {
    const auto list = sample();
    const std::string json = list.toJson(source());
    EXPECT_NE(json.find("\"seriesInstanceUid\": \"1.2.3.4\""), std::string::npos) << json;
    EXPECT_NE(json.find("LPS"), std::string::npos);
    auto back = core::MeasurementList::fromJson(json);
    ASSERT_EQ(back.items().size(), 2u);
    EXPECT_EQ(back.items()[0].label, "M1");
    EXPECT_EQ(back.items()[0].b, list.items()[0].b);
    ASSERT_TRUE(back.items()[1].stats && back.items()[1].region);
    EXPECT_EQ(back.items()[1].stats->voxels, 452u);
    EXPECT_EQ(back.items()[1].region->kind, core::MeasureRegion::Kind::Disc);
    EXPECT_DOUBLE_EQ(back.items()[1].region->radius, 12.0);
    EXPECT_EQ(back.add(core::Measurement{}).label, "M3") << "new labels follow the highest read";
    for (const char* bad : {"", "[]", "{\"measurements\": [{\"kind\": \"distance\"}]}",
                            "{\"measurements\": [{\"label\": \"M1\", \"kind\": \"distance\", \"a\": [1,2], \"b\": [1,2,3]}]}"})
        EXPECT_THROW(core::MeasurementList::fromJson(bad), core::Error) << bad;
}

// A volume whose source gave no spacing: both exports say its lengths are not mm (Python's csv
// module reads the column), where they had said "mm" like any other.
TEST(MeasurementList, ExportsSayWhenTheSpacingWasAssumed) {
    test::TempDir dir;
    auto assumed = source();
    assumed.spacingAssumed = true;
    std::ofstream(dir.file("m.csv")) << sample().toCsv(assumed);
    std::ofstream(dir.file("p.csv")) << sample().toCsv(source());
    const auto r = test::runCommand("/usr/bin/python3 -c \"import csv; a = list(csv.DictReader(open('" + dir.file("m.csv") +
                                    "'))); p = list(csv.DictReader(open('" + dir.file("p.csv") +
                                    "'))); print(a[0]['spacing_assumed'] + '|' + a[1]['spacing_assumed'] + '|' + "
                                    "p[0]['spacing_assumed'] + '|')\"");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output, "yes: lengths are not mm|yes: lengths are not mm||\n");
    const std::string json = sample().toJson(assumed);
    EXPECT_NE(json.find("\"spacingAssumed\": true"), std::string::npos) << json;
    EXPECT_NE(json.find("lengths, areas and volumes are not mm"), std::string::npos) << json;
    EXPECT_EQ(core::MeasurementList::fromJson(json).items().size(), 2u);
    EXPECT_NE(sample().toJson(source()).find("\"spacingAssumed\": false"), std::string::npos);
}

// Angles: the size at the vertex, checked against numpy's arccos of the normalised dot product
// (an independent computation), near 0 and 180 degrees too; exported to CSV and JSON and read back.
TEST(MeasurementList, AnglesAgreeWithNumpyAndReadBack) {
    const std::vector<std::array<glm::dvec3, 3>> cases{
        {glm::dvec3(10, 0, 0), glm::dvec3(0, 0, 0), glm::dvec3(0, 7, 0)},             // 90
        {glm::dvec3(1, 2, 3), glm::dvec3(-4, 5, 0.5), glm::dvec3(7, -1, 2)},           // oblique, in 3D
        {glm::dvec3(100, 0.001, 0), glm::dvec3(0, 0, 0), glm::dvec3(100, 0, 0)},       // almost 0
        {glm::dvec3(-50, 0, 0), glm::dvec3(0, 0, 0), glm::dvec3(50, 0.0005, 0)},       // almost 180
    };
    std::string script = "import numpy as np\n";
    core::MeasurementList list;
    for (const auto& k : cases) {
        core::Measurement m;
        m.kind = core::Measurement::Kind::Angle;
        m.view = "sagittal";
        m.a = k[0], m.b = k[1], m.c = k[2];
        list.add(m);
        char line[1024];
        std::snprintf(line, sizeof line,
                      "u=np.array([%.17g,%.17g,%.17g])-np.array([%.17g,%.17g,%.17g]); "
                      "v=np.array([%.17g,%.17g,%.17g])-np.array([%.17g,%.17g,%.17g]); "
                      "print('%%.9f' %% np.degrees(np.arctan2(np.linalg.norm(np.cross(u,v)), np.dot(u,v))))\n",
                      k[0].x, k[0].y, k[0].z, k[1].x, k[1].y, k[1].z, k[2].x, k[2].y, k[2].z, k[1].x, k[1].y, k[1].z);
        script += line;
    }
    test::TempDir dir;
    std::ofstream(dir.file("a.py")) << script;
    const auto r = test::runCommand("/usr/bin/python3 " + dir.file("a.py"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::istringstream numpy(r.output);
    for (const auto& m : list.items()) {
        double expected = 0;
        numpy >> expected;
        EXPECT_NEAR(m.angleDegrees(), expected, 1e-9) << m.label;
    }
    EXPECT_NEAR(list.items()[0].angleDegrees(), 90.0, 1e-12);
    core::Measurement flat;
    flat.kind = core::Measurement::Kind::Angle;  // an arm of no length: no angle, not NaN
    EXPECT_EQ(flat.angleDegrees(), 0.0);

    std::ofstream(dir.file("m.csv")) << list.toCsv(source());
    const auto csv = test::runCommand("/usr/bin/python3 -c \"import csv; rows=list(csv.DictReader(open('" +
                                      dir.file("m.csv") + "'))); print(rows[0]['kind'], rows[0]['angle_deg'], rows[0]['c_y_lps'])\"");
    EXPECT_EQ(csv.output, "angle 90 7\n");
    const auto back = core::MeasurementList::fromJson(list.toJson(source()));
    ASSERT_EQ(back.items().size(), cases.size());
    EXPECT_EQ(back.items()[1].kind, core::Measurement::Kind::Angle);
    EXPECT_EQ(back.items()[1].c, cases[1][2]);
    EXPECT_DOUBLE_EQ(back.items()[1].angleDegrees(), list.items()[1].angleDegrees());
    EXPECT_THROW(core::MeasurementList::fromJson("{\"measurements\": [{\"kind\": \"angle\", \"a\": [0,0,0]}]}"), core::Error);
}

// A polygon region keeps its outline through JSON; CSV names its shape.
TEST(MeasurementList, PolygonOutlinesReadBack) {
    core::MeasurementList list;
    core::Measurement m;
    m.kind = core::Measurement::Kind::Region;
    m.view = "axial";
    m.region = core::MeasureRegion::polygon({{0, 0, 5}, {10, 0, 5}, {10, 7, 5}, {3, 9, 5}}, {0, 0, 1}, 2.0);
    list.add(m);
    const auto back = core::MeasurementList::fromJson(list.toJson(source()));
    ASSERT_EQ(back.items().size(), 1u);
    ASSERT_TRUE(back.items()[0].region);
    EXPECT_EQ(back.items()[0].region->kind, core::MeasureRegion::Kind::Polygon);
    EXPECT_EQ(back.items()[0].region->outline, m.region->outline);
    EXPECT_NE(list.toCsv(source()).find(",polygon,"), std::string::npos);
}

// An ellipse keeps its axes and a rectangle its corners through JSON; CSV names their shapes and
// gives the ellipse's second semi-axis.
TEST(MeasurementList, EllipsesAndRectanglesReadBack) {
    core::MeasurementList list;
    core::Measurement m;
    m.kind = core::Measurement::Kind::Region;
    m.view = "coronal";
    m.region = core::MeasureRegion::ellipse({1, 2, 3}, {0, 1, 0}, {1, 0, 1}, 7.5, 3.25, 2.0);
    list.add(m);
    m.region = core::MeasureRegion::rectangle({0, 4, 0}, {10, 4, 6}, {0, 1, 0}, {1, 0, 0}, 1.5);
    list.add(m);
    const auto back = core::MeasurementList::fromJson(list.toJson(source()));
    ASSERT_EQ(back.items().size(), 2u);
    const auto& e = *back.items()[0].region;
    EXPECT_EQ(e.kind, core::MeasureRegion::Kind::Ellipse);
    EXPECT_EQ(e.axis, list.items()[0].region->axis);
    EXPECT_DOUBLE_EQ(e.radius2, 3.25);
    EXPECT_EQ(back.items()[1].region->kind, core::MeasureRegion::Kind::Rectangle);
    EXPECT_EQ(back.items()[1].region->outline, m.region->outline);
    const std::string csv = list.toCsv(source());
    EXPECT_NE(csv.find(",ellipse,"), std::string::npos);
    EXPECT_NE(csv.find(",rectangle,"), std::string::npos);
    EXPECT_NE(csv.find(",3.25,\n"), std::string::npos) << csv;
    EXPECT_THROW(core::MeasurementList::fromJson(
                     "{\"measurements\": [{\"kind\": \"region\", \"region\": {\"shape\": \"rectangle\", \"centre\": [0,0,0], "
                     "\"radiusMm\": 0, \"low\": [0,0,0], \"high\": [0,0,0], \"normal\": [0,0,1], \"thicknessMm\": 1, "
                     "\"outline\": [[0,0,0],[1,0,0],[1,1,0]]}}]}"),
                 core::Error);
}

// An edited measurement keeps its label and its place in the list.
TEST(MeasurementList, ReplaceKeepsLabelAndOrder) {
    core::MeasurementList list;
    core::Measurement m;
    m.b = {10, 0, 0};
    list.add(m);
    list.add(m);
    core::Measurement edited = list.items()[0];
    edited.b = {0, 20, 0};
    EXPECT_TRUE(list.replace(edited));
    EXPECT_EQ(list.items()[0].label, "M1");
    EXPECT_DOUBLE_EQ(list.items()[0].lengthMm(), 20.0);
    EXPECT_DOUBLE_EQ(list.items()[1].lengthMm(), 10.0);
    edited.label = "M9";
    EXPECT_FALSE(list.replace(edited));
    EXPECT_EQ(list.add(m).label, "M3");
}
