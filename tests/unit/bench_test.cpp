// Pareto front, budget choice and file formats of vkgi-bench's records.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "vkgi/file_util.hpp"
#include "vkgi/progress.hpp"
#include "vkgi/bench.hpp"
#include "vkgi/vct.hpp"
#include "support/test_env.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

using namespace vkgi;
using namespace vkgi::gi;

namespace {
BenchRecord rec(const char* scene, const char* tech, double ms, double err) {
    BenchRecord r;
    r.scene = scene;
    r.technique = tech;
    r.knobs = std::string("k=") + std::to_string(ms);
    r.totalMs = ms;
    r.relMse = err;
    r.passMs = {{"gi.a", ms * 0.25}, {"gi.b", ms * 0.75}};
    return r;
}
} // namespace

TEST(Bench, ParetoFrontKeepsOnlyUndominatedPoints) {
    std::vector<BenchRecord> r = {
        rec("cornell", "vct", 10, 0.5),  // 0 front
        rec("cornell", "vct", 20, 0.2),  // 1 front
        rec("cornell", "lpv", 15, 0.6),  // 2 dominated by 0 (slower and worse)
        rec("cornell", "lpv", 40, 0.2),  // 3 dominated by 1 (equal error, slower)
        rec("cornell", "vpl", 50, 0.05), // 4 front
        rec("room", "vct", 1, 0.01),     // other scene: ignored
        rec("cornell", "vpl", 5, NAN),   // non-finite error: never on the front
    };
    EXPECT_EQ(paretoFront(r, "cornell"), (std::vector<size_t>{0, 1, 4}));
    EXPECT_EQ(paretoFront(r, "room"), (std::vector<size_t>{5}));
    EXPECT_TRUE(paretoFront(r, "atrium").empty());
}

TEST(Bench, BudgetPicksTheMostAccurateConfigurationThatFits) {
    std::vector<BenchRecord> r = {rec("cornell", "vct", 10, 0.5), rec("cornell", "vct", 20, 0.2),
                                  rec("cornell", "vpl", 50, 0.05), rec("room", "vct", 1, 0.01)};
    EXPECT_EQ(bestWithinBudget(r, "cornell", 9.9), -1);
    EXPECT_EQ(bestWithinBudget(r, "cornell", 10.0), 0);
    EXPECT_EQ(bestWithinBudget(r, "cornell", 49.0), 1);
    EXPECT_EQ(bestWithinBudget(r, "cornell", 1e9), 2);
}

TEST(Bench, CsvHasOneRowPerRecordAndOneColumnPerPass) {
    std::vector<BenchRecord> r = {rec("cornell", "vct", 10, 0.5), rec("room", "lpv", 8, 0.25)};
    r[1].passMs.push_back({"gi.c", 1.0});
    r[1].knobs = "grid=32,steps=8"; // a comma must be quoted
    std::string csv = toCsv(r);
    std::istringstream in(csv);
    std::string header, row1, row2;
    std::getline(in, header);
    std::getline(in, row1);
    std::getline(in, row2);
    EXPECT_EQ(header,
              "scene,technique,knobs,total_ms,profiled_ms,relmse,rmse,relmse_indirect,rmse_indirect,reference_bounces,"
              "relmse_all,rmse_all,relmse_indirect_all,rmse_indirect_all,relmse_dark,relmse_all_dark,device_mib,"
              "direct_ms,hf_ratio,gi.a ms,gi.b ms,gi.c ms");
    EXPECT_EQ(row1.substr(0, 22), "cornell,vct,k=10.00000");
    EXPECT_NE(row2.find("\"grid=32,steps=8\""), std::string::npos);
    EXPECT_EQ(row1.back(), ','); // record 0 has no gi.c pass: empty last field
}

TEST(Bench, JsonRoundTripsTheNumbers) {
    std::vector<BenchRecord> r = {rec("cornell", "vct", 12.5, 0.125)};
    r[0].rmseIndirect = 0.0625;
    r[0].referenceBounces = 3;
    r[0].rmseIndirectAll = 0.25;
    r[0].relMseDark = 0.5;
    r[0].relMseAllDark = 0.75;
    r[0].directMs = 2.5;
    r[0].hfRatio = 1.5;
    auto j = nlohmann::json::parse(toJson(r));
    ASSERT_EQ(j.size(), 1u);
    EXPECT_EQ(j[0]["total_ms"].get<double>(), 12.5);
    EXPECT_EQ(j[0]["direct_ms"].get<double>(), 2.5);
    EXPECT_EQ(j[0]["error"]["relmse"].get<double>(), 0.125);
    EXPECT_EQ(j[0]["error"]["rmse_indirect"].get<double>(), 0.0625);
    EXPECT_EQ(j[0]["error"]["reference_bounces"].get<int>(), 3);
    EXPECT_EQ(j[0]["error_all_bounces"]["rmse_indirect"].get<double>(), 0.25);
    EXPECT_EQ(j[0]["error"]["relmse_dark"].get<double>(), 0.5);
    EXPECT_EQ(j[0]["error_all_bounces"]["relmse_dark"].get<double>(), 0.75);
    EXPECT_EQ(j[0]["error"]["hf_ratio"].get<double>(), 1.5);
    EXPECT_EQ(j[0]["passes"][1]["name"].get<std::string>(), "gi.b");
}

TEST(Bench, MarkdownHasOneTablePerSceneAndMarksTheFront) {
    std::vector<BenchRecord> r = {rec("cornell", "vct", 10, 0.5), rec("room", "lpv", 8, 0.25),
                                  rec("cornell", "lpv", 15, 0.6)};
    r[1].referenceBounces = -1;
    r[1].knobs = "a|b";
    r[0].directMs = 4.0; // the others were not measured against their direct-only frame
    std::string md = toMarkdown(r);
    auto cornell = md.find("### cornell"), room = md.find("### room");
    ASSERT_NE(cornell, std::string::npos);
    ASSERT_NE(room, std::string::npos);
    EXPECT_LT(cornell, room);
    EXPECT_NE(md.find("| vct * | k=10.000000 | 10 | 2.5 |"), std::string::npos) << md; // on cornell's front; 10 / 4
    EXPECT_NE(md.find("| lpv | k=15.000000 | 15 | – |"), std::string::npos) << md;      // dominated by vct
    EXPECT_NE(md.find("| lpv * | a/b | 8 | – | 0 | all | 0.25 | 0 |"), std::string::npos) << md; // '|' kept out of cells
    EXPECT_NE(md.find("| HF ratio |"), std::string::npos) << md;
    size_t rows = 0;
    for (size_t p = md.find("\n| "); p != std::string::npos; p = md.find("\n| ", p + 1))
        ++rows;
    EXPECT_EQ(rows, 2u * 1u + 3u); // a header per scene + one row per record
}

// The voxelization line: medians per VCT grid over the scene's VCT rows, triangles / ms.
TEST(Bench, MarkdownReportsVoxelizationThroughputPerGrid) {
    auto vct = [](const char* knobs, double voxelize) {
        BenchRecord r = rec("atrium", "vct", 100, 0.5);
        r.knobs = knobs;
        r.triangles = 8000;
        r.passMs = {{"gi.gbuffer", 9.0}, {"gi.voxel.clear", 1.0}, {"gi.voxel.voxelize", voxelize},
                    {"gi.voxel.resolve", 1.0}, {"gi.vct.list", 0.5}, {"gi.vct.light", 7.0}};
        return r;
    };
    std::vector<BenchRecord> r = {vct("vct.grid=32", 2.0), vct("vct.grid=32 vct.cones=16", 4.0),
                                  vct("vct.grid=32 vct.step=2", 3.0), vct("vct.cones=4", 8.0),
                                  rec("atrium", "lpv", 15, 0.6), rec("cornell", "lpv", 15, 0.6)};
    EXPECT_EQ(vctGridOf(r[0]), 32u);
    EXPECT_EQ(vctGridOf(r[3]), VctSettings{}.gridResolution);
    std::string md = toMarkdown(r);
    // grid 32: median voxelize 3 ms -> 8000 / 3e-3 s = 2.67 M/s; all voxel-grid passes 3 + 2.5.
    EXPECT_NE(md.find("VCT voxelization (8000 triangles"), std::string::npos) << md;
    EXPECT_NE(md.find("grid 32: voxelize 3 ms = 2.67 M triangles/s, all voxel-grid passes 5.5 ms;"), std::string::npos)
        << md;
    EXPECT_NE(md.find("grid 64: voxelize 8 ms = 1 M triangles/s, all voxel-grid passes 10.5 ms;"), std::string::npos)
        << md;
    EXPECT_EQ(md.find("VCT voxelization"), md.rfind("VCT voxelization")); // not for cornell (no VCT rows)
}

TEST(Bench, SvgMarksEveryPointAndTheFront) {
    std::vector<BenchRecord> r = {rec("cornell", "vct", 10, 0.5), rec("cornell", "vct", 20, 0.2),
                                  rec("cornell", "lpv", 15, 0.6)};
    std::string svg = toSvgPlot(r, "cornell");
    size_t circles = 0;
    for (size_t p = svg.find("<circle"); p != std::string::npos; p = svg.find("<circle", p + 1))
        ++circles;
    EXPECT_EQ(circles, 3u + 2u); // 3 points + 2 legend markers
    EXPECT_NE(svg.find("Pareto front"), std::string::npos);
    EXPECT_EQ(svg.rfind("</svg>\n"), svg.size() - 7);
}

TEST(FileUtil, AtomicWriteReplacesOrFailsCleanly) {
    auto dir = test::outputDir() / "atomic";
    std::filesystem::create_directories(dir);
    auto file = dir / "a.txt";
    ASSERT_TRUE(writeFileAtomic(file, "first"));
    ASSERT_TRUE(writeFileAtomic(file, "second"));
    std::ifstream in(file);
    std::string s;
    in >> s;
    EXPECT_EQ(s, "second");
    auto bad = writeFileAtomic(dir / "missing" / "b.txt", "x");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("b.txt"), std::string::npos);
    EXPECT_FALSE(std::filesystem::exists(dir / "missing"));
}

TEST(Progress, FormatsDurations) {
    EXPECT_EQ(formatDuration(42.4), "42 s");
    EXPECT_EQ(formatDuration(185), "3 min 05 s");
    EXPECT_EQ(formatDuration(3725), "1 h 02 min");
    Progress quiet("test", 10, false);
    quiet.add(5);
    EXPECT_FALSE(quiet.visible());
}

// 15 MB moved at 7.5 GB/s take 2 ms: a pass of 2 ms streams at the copy rate (ratio 1), one of
// 3 ms is 1.5x slower; unknown bytes or rate give 0, never inf/NaN.
TEST(Bench, StreamRatioIsTimeOverStreamingTime) {
    EXPECT_DOUBLE_EQ(vkgi::gi::streamRatio(2.0, 15e6, 7.5), 1.0);
    EXPECT_DOUBLE_EQ(vkgi::gi::streamRatio(3.0, 15e6, 7.5), 1.5);
    EXPECT_EQ(vkgi::gi::streamRatio(3.0, 0.0, 7.5), 0.0);
    EXPECT_EQ(vkgi::gi::streamRatio(3.0, 15e6, 0.0), 0.0);
}

// ---- vkgi-bench --scaling ----------------------------------------------------------------

namespace {
ScalingRecord point(const char* axis, const char* series, double value, double ms) {
    ScalingRecord r;
    r.axis = axis;
    r.series = series;
    r.technique = series;
    r.value = value;
    r.totalMs = ms;
    r.passMs = {{"gi.gbuffer", 0.5}, {std::string("gi.") + series + ".x", ms - 0.5}};
    return r;
}
} // namespace

// y = c x^k is a line of slope k in log-log: the fit returns k for any c and any x spacing.
TEST(Scaling, LogLogSlopeOfAPowerLawIsItsExponent) {
    std::vector<double> x = {2, 5, 11, 100, 4096};
    for (double k : {1.0, 1.5, 0.0, -0.5, 3.0}) {
        std::vector<double> y;
        for (double v : x)
            y.push_back(3.0 * std::pow(v, k));
        EXPECT_NEAR(fitLogLogSlope(x, y), k, 1e-12) << "k = " << k;
    }
    // Points with x <= 0 or y <= 0 cannot be on a log axis: ignored, not NaN-poisoning.
    EXPECT_NEAR(fitLogLogSlope({0, 1, 2, 4, -1}, {5, 1, 4, 16, 3}), 2.0, 1e-12);
    EXPECT_TRUE(std::isnan(fitLogLogSlope({7, 7}, {1, 2}))); // one distinct x: no slope
    EXPECT_TRUE(std::isnan(fitLogLogSlope({}, {})));
}

TEST(Scaling, TechniquePassesAreTheTechniquesOwn) {
    EXPECT_TRUE(isTechniquePass("gi.vct.trace", "vct"));
    EXPECT_TRUE(isTechniquePass("gi.voxel.voxelize.dynamic", "vct"));
    EXPECT_TRUE(isTechniquePass("vpl.gather", "vpl"));
    EXPECT_TRUE(isTechniquePass("gi.lpv.propagate[3]", "lpv"));
    EXPECT_FALSE(isTechniquePass("gi.gbuffer", "vct"));
    EXPECT_FALSE(isTechniquePass("gi.light[0].spot", "lpv"));
    EXPECT_FALSE(isTechniquePass("gi.vctx", "vct"));
    EXPECT_FALSE(isTechniquePass("gi.composite", "none"));
}

TEST(Scaling, CsvAndJsonHaveOneRowPerPoint) {
    std::vector<ScalingRecord> r = {point("pixels", "vct", 4096, 10), point("pixels", "lpv", 4096, 20),
                                    point("voxels", "vct", 32768, 5)};
    r[2].knobs = "vct.grid=32";
    r[2].wallMs = 7.5;
    std::istringstream in(toScalingCsv(r));
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);)
        lines.push_back(line);
    ASSERT_EQ(lines.size(), 4u);
    EXPECT_EQ(lines[0], "axis,value,series,technique,knobs,scene,width,height,triangles,total_ms,technique_ms,wall_ms,"
                        "gi.gbuffer ms,gi.vct.x ms,gi.lpv.x ms");
    EXPECT_EQ(lines[3].substr(0, 37), "voxels,32768,vct,vct,vct.grid=32,,0,0");
    auto j = nlohmann::json::parse(toScalingJson(r));
    ASSERT_EQ(j.size(), 3u);
    EXPECT_EQ(j[1]["total_ms"].get<double>(), 20.0);
    EXPECT_EQ(j[2]["wall_ms"].get<double>(), 7.5);
    EXPECT_EQ(j[2]["passes"][1]["ms"].get<double>(), 4.5);
}

// On decades 10..1000 both axes span the plot exactly: x 10 -> 70 (left margin), 1000 -> 470,
// y 10 -> 370 (bottom), 1000 -> 40 (top). A series y = x and the slope-1 reference line through
// its first point are the same diagonal; y = x^2 / 10 is a second line with its fitted slope 2.
TEST(Scaling, SvgDrawsOneLinePerSeriesAndTheLinearReference) {
    std::vector<ScalingRecord> r = {point("pixels", "vct", 10, 10),  point("pixels", "vct", 100, 100),
                                    point("pixels", "vct", 1000, 1000), point("pixels", "lpv", 100, 1000),
                                    point("pixels", "lpv", 10, 10),  point("voxels", "vct", 5, 5)};
    std::string svg = toScalingSvgPlot(r, "pixels");
    auto count = [&](const std::string& what) {
        size_t n = 0;
        for (size_t p = svg.find(what); p != std::string::npos; p = svg.find(what, p + 1))
            ++n;
        return n;
    };
    EXPECT_EQ(count("<polyline"), 2u);
    EXPECT_EQ(count("<circle"), 5u); // the voxels point belongs to another plot
    EXPECT_NE(svg.find("points=\"70,370 270,205 470,40 \""), std::string::npos) << svg;
    EXPECT_NE(svg.find("<line x1=\"70\" y1=\"370\" x2=\"470\" y2=\"40\" stroke=\"#888\""), std::string::npos);
    EXPECT_NE(svg.find("vct (slope 1)"), std::string::npos);
    EXPECT_NE(svg.find("lpv (slope 2)"), std::string::npos);
    EXPECT_NE(svg.find("slope 1 (linear)"), std::string::npos);
    EXPECT_EQ(svg.rfind("</svg>\n"), svg.size() - 7);
    std::string empty = toScalingSvgPlot(r, "triangles");
    EXPECT_NE(empty.find("no positive measurements"), std::string::npos);
}
