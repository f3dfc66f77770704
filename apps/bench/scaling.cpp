// vkgi-bench --scaling: DESIGN.md's budget claim made measurable. Cost should grow linearly with
// pixels and voxels and stay flat in triangle count once the scene is voxelized. Each technique
// is timed while one axis varies and the others stay at their defaults:
//   pixels     cornell, image 64^2 .. 512^2
//   voxels     cornell at 128^2, vct.grid 32/64/128, lpv.grid 16/32/64 (techniques with a grid)
//   triangles  bunny_box at 128^2, bunny icosphere level 3..6 (1.3k .. 82k triangles, same shape)
// Every measured frame changes the light (its intensity steps to the next float and back), so
// shadows, injection, propagation, voxel light and bounce all run, while the geometry stays put:
// the voxel grid is voxelized once, before the measured frames. For vct the triangles axis also
// has "vct voxelize/frame": every frame invalidated (GiSystem::invalidate, as vkgi-bench's sweep
// does), so the whole scene is re-voxelized each frame; its gi.voxel.voxelize pass gives
// triangles per second.
#include "scaling.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <sstream>

#include "vkgi/builtin_scenes.hpp"
#include "vkgi/file_util.hpp"
#include "vkgi/progress.hpp"
#include "vkgi/knobs.hpp"

namespace vkgi::bench {

namespace {

constexpr const char* kRevoxelized = "vct voxelize/frame";
// Frames before the measured ones: lavapipe compiles shaders at first dispatch, and in the first
// frames of a GiSystem its timestamps can put a pass's work into another pass (docs/vpl.md).
constexpr uint32_t kWarmup = 3;

struct Job {
    std::string axis;
    std::string series;
    std::string technique;
    std::string knobs;
    size_t scene = 0; // into the scene list
    uint32_t size = 0;
    bool revoxelize = false; // invalidate every frame (re-voxelize) instead of changing the light
};

uint64_t triangleCount(const Scene& s) {
    uint64_t n = 0;
    for (const Instance& i : s.instances)
        n += s.meshes[i.mesh].triangleCount();
    return n;
}

double voxelizeMs(const gi::ScalingRecord& r) {
    double ms = 0.0;
    for (const auto& [name, passMs] : r.passMs)
        if (name.rfind("gi.voxel.voxelize", 0) == 0)
            ms += passMs;
    return ms;
}

std::string slopeText(double k) {
    if (!std::isfinite(k))
        return "   -";
    char buf[16];
    std::snprintf(buf, sizeof buf, "%5.2f", k);
    return buf;
}

// The sweep's values per axis (smaller with --quick).
struct Axes {
    std::vector<uint32_t> sizes;
    uint32_t fixedSize = 0;
    std::map<std::string, std::vector<uint32_t>> grids;
    std::vector<uint32_t> levels; // bunny icosphere subdivisions
};

Axes axesFor(bool quick) {
    Axes a;
    a.sizes = quick ? std::vector<uint32_t>{16, 32} : std::vector<uint32_t>{64, 128, 256, 512};
    a.fixedSize = quick ? 32 : 128;
    a.grids = {{"vct", quick ? std::vector<uint32_t>{16, 32} : std::vector<uint32_t>{32, 64, 128}},
               {"lpv", quick ? std::vector<uint32_t>{8, 16} : std::vector<uint32_t>{16, 32, 64}}};
    a.levels = quick ? std::vector<uint32_t>{2, 3} : std::vector<uint32_t>{3, 4, 5, 6};
    return a;
}

// cornell, then bunny_box at each level.
Result<std::vector<Scene>> scalingScenes(const std::vector<uint32_t>& levels) {
    std::vector<Scene> scenes;
    auto cornell = makeBuiltinScene("cornell");
    if (!cornell)
        return cornell.error();
    scenes.push_back(std::move(*cornell));
    for (uint32_t level : levels) {
        BuiltinSceneParams p;
        p.bunnySubdivisions = level;
        auto s = makeBuiltinScene("bunny_box", p);
        if (!s)
            return s.error();
        scenes.push_back(std::move(*s));
    }
    return scenes;
}

std::vector<Job> scalingJobs(const Options& opt, const Axes& a) {
    std::vector<Job> jobs;
    for (const auto& t : opt.techniques) {
        for (uint32_t n : a.sizes)
            jobs.push_back({"pixels", t, t, "", 0, n, false});
        if (auto g = a.grids.find(t); g != a.grids.end())
            for (uint32_t n : g->second)
                jobs.push_back({"voxels", t, t, t + ".grid=" + std::to_string(n), 0, a.fixedSize, false});
        for (size_t l = 0; l < a.levels.size(); ++l)
            jobs.push_back({"triangles", t, t, "", 1 + l, a.fixedSize, false});
        if (t == "vct")
            for (size_t l = 0; l < a.levels.size(); ++l)
                jobs.push_back({"triangles", kRevoxelized, t, "", 1 + l, a.fixedSize, true});
    }
    return jobs;
}

// Times one job; the record's value is the job's axis value.
Result<gi::ScalingRecord> measureJob(Context& ctx, const Options& opt, const Job& job, const Scene& scene) {
    gi::GiSettings s;
    s.technique = *gi::parseTechnique(job.technique);
    if (!job.knobs.empty())
        if (auto ok = gi::applyKnob(s, job.knobs); !ok)
            return ok.error();
    std::function<Result<void>(gi::GiSystem&)> before;
    Scene relit = scene; // the light steps between two adjacent floats: a changed light, same image
    if (job.revoxelize || relit.lights.empty())
        before = [](gi::GiSystem& sys) -> Result<void> {
            sys.invalidate();
            return {};
        };
    else
        before = [&relit, base = relit.lights[0].intensity](gi::GiSystem& sys) {
            float& i = relit.lights[0].intensity;
            i = i == base ? std::nextafter(base, INFINITY) : base;
            return sys.updateScene(relit);
        };
    gi::FrameRequest request; // the composite only: readbacks are excluded from the times anyway
    auto t = measureTiming(ctx, scene, s, job.size, job.size, opt.repeat, request, before, kWarmup);
    if (!t)
        return makeError("--scaling " + job.axis + " " + job.series + " [" + job.knobs + "] " +
                         std::to_string(job.size) + "x" + std::to_string(job.size) + ": " + t.error().message);
    gi::ScalingRecord r;
    r.axis = job.axis;
    r.series = job.series;
    r.technique = job.technique;
    r.knobs = job.knobs;
    r.scene = scene.name;
    r.width = r.height = job.size;
    r.triangles = triangleCount(scene);
    if (job.axis == "pixels")
        r.value = double(job.size) * job.size;
    else if (job.axis == "voxels")
        r.value = std::pow(double(s.technique == gi::Technique::Vct ? s.vct.gridResolution : s.lpv.gridSize), 3.0);
    else
        r.value = double(r.triangles);
    r.totalMs = t->totalMs;
    r.wallMs = t->wallMs;
    r.passMs = t->passMs;
    for (const auto& [name, ms] : r.passMs)
        if (gi::isTechniquePass(name, job.technique))
            r.techniqueMs += ms;
    return r;
}

const std::vector<std::string> kAxes = {"pixels", "voxels", "triangles"};

Result<void> writeScalingFiles(const Options& opt, const std::vector<gi::ScalingRecord>& records) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::create_directories(opt.outDir, ec);
    if (ec)
        return makeError("--out " + opt.outDir + ": " + ec.message());
    Result<void> ok = writeFileAtomic(fs::path(opt.outDir) / "scaling.csv", gi::toScalingCsv(records));
    if (ok)
        ok = writeFileAtomic(fs::path(opt.outDir) / "scaling.json", gi::toScalingJson(records));
    for (const auto& axis : kAxes)
        if (ok)
            ok = writeFileAtomic(fs::path(opt.outDir) / ("scaling-" + axis + ".svg"), gi::toScalingSvgPlot(records, axis));
    return ok;
}

// The passes that make up >= 10% of the frame at the axis's largest value, indexed passes
// summed (gi.lpv.propagate[*]): which part is linear and which is fixed.
void printLargePassSlopes(const std::vector<gi::ScalingRecord>& records, const std::string& axis,
                          const std::string& name, const std::vector<double>& x, const std::vector<double>& total) {
    std::vector<std::string> groups;
    std::map<std::string, std::vector<double>> groupMs; // per point, same order as x
    size_t k = 0;
    for (const auto& r : records) {
        if (r.axis != axis || r.series != name)
            continue;
        for (const auto& [pass, ms] : r.passMs) {
            std::string g = pass.substr(0, pass.find('[')) + (pass.find('[') != std::string::npos ? "[*]" : "");
            auto& v = groupMs[g];
            if (v.empty())
                groups.push_back(g);
            v.resize(x.size(), 0.0);
            v[k] += ms;
        }
        ++k;
    }
    size_t largest = size_t(std::max_element(x.begin(), x.end()) - x.begin());
    for (const auto& g : groups)
        if (groupMs[g][largest] >= 0.1 * total[largest])
            std::printf("      %-24s slope %s (%.1f ms at %.0f)\n", g.c_str(),
                        slopeText(gi::fitLogLogSlope(x, groupMs[g])).c_str(), groupMs[g][largest], x[largest]);
}

// Slopes of log(ms) against log(axis value): 1 = linear, 0 = flat. "tech." counts only the
// technique's own passes (the G-buffer, shadow maps and direct light are the same for all).
void printSlopes(const std::vector<gi::ScalingRecord>& records) {
    std::printf("log-log slopes (1 = linear, 0 = flat): GPU total, technique passes, host wall time\n");
    for (const auto& axis : kAxes) {
        std::vector<std::string> series;
        for (const auto& r : records)
            if (r.axis == axis && std::find(series.begin(), series.end(), r.series) == series.end())
                series.push_back(r.series);
        for (const auto& name : series) {
            std::vector<double> x, total, tech, wall;
            for (const auto& r : records)
                if (r.axis == axis && r.series == name)
                    x.push_back(r.value), total.push_back(r.totalMs), tech.push_back(r.techniqueMs),
                        wall.push_back(r.wallMs);
            std::printf("  %s %s: slope %s (technique passes %s, frame wall time %s)\n", name.c_str(), axis.c_str(),
                        slopeText(gi::fitLogLogSlope(x, total)).c_str(), slopeText(gi::fitLogLogSlope(x, tech)).c_str(),
                        slopeText(gi::fitLogLogSlope(x, wall)).c_str());
            printLargePassSlopes(records, axis, name, x, total);
        }
    }
}

// Voxelization per frame: the gi.voxel.voxelize pass of the invalidated runs against the
// scene's triangles, and the same runs' extra host time over the relit runs of the same scene
// (on lavapipe the timestamps of short compute passes can miss work, the wall time cannot):
// the marginal cost per triangle is the least-squares slope of that extra time.
void printVoxelizeRate(const std::vector<gi::ScalingRecord>& records, const std::vector<Scene>& scenes, size_t levels) {
    std::vector<double> tris, voxMs, extraMs;
    for (size_t l = 0; l < levels; ++l) {
        const gi::ScalingRecord *revox = nullptr, *relit = nullptr;
        for (const auto& r : records)
            if (r.axis == "triangles" && r.triangles == triangleCount(scenes[1 + l])) {
                if (r.series == kRevoxelized)
                    revox = &r;
                else if (r.series == "vct")
                    relit = &r;
            }
        if (!revox || !relit)
            continue;
        double n = double(revox->triangles);
        double ms = voxelizeMs(*revox), extra = revox->wallMs - relit->wallMs;
        tris.push_back(n), voxMs.push_back(ms), extraMs.push_back(extra);
        std::printf(
            "  voxelize/frame: %6.0f triangles: gi.voxel.voxelize timestamp %8.3f ms (%8.3f M triangles/s); frame "
            "wall time %+8.2f ms over the relit frame\n",
            n, ms, ms > 0 ? n / (ms * 1e3) : 0.0, extra);
    }
    if (tris.size() < 2)
        return;
    double mt = 0, me = 0;
    for (size_t i = 0; i < tris.size(); ++i)
        mt += tris[i] / double(tris.size()), me += extraMs[i] / double(tris.size());
    double sxx = 0, sxy = 0;
    for (size_t i = 0; i < tris.size(); ++i)
        sxx += (tris[i] - mt) * (tris[i] - mt), sxy += (tris[i] - mt) * (extraMs[i] - me);
    double msPerTri = sxx > 0 ? sxy / sxx : NAN;
    std::printf("  voxelize/frame: pass ms against triangles slope %s; extra wall time %.3g ms per 1k triangles "
                "(%.3g M triangles/s marginal)\n",
                slopeText(gi::fitLogLogSlope(tris, voxMs)).c_str(), msPerTri * 1e3, msPerTri > 0 ? 1e-3 / msPerTri : NAN);
}

int failWith(const std::string& message) {
    std::fprintf(stderr, "vkgi-bench: %s\n", message.c_str());
    return 1;
}

} // namespace

int runScaling(Context& ctx, const Options& opt) {
    const Axes axes = axesFor(opt.quick);
    auto scenes = scalingScenes(axes.levels);
    if (!scenes)
        return failWith(scenes.error().message);
    const std::vector<Job> jobs = scalingJobs(opt, axes);
    std::vector<gi::ScalingRecord> records;
    Progress progress("vkgi-bench --scaling", jobs.size());
    for (const Job& job : jobs) {
        auto r = measureJob(ctx, opt, job, (*scenes)[job.scene]);
        if (!r)
            return failWith(r.error().message);
        records.push_back(std::move(*r));
        progress.add(1);
    }
    progress.finish();
    if (auto ok = writeScalingFiles(opt, records); !ok)
        return failWith(ok.error().message);

    std::printf("%-10s %10s %-20s %-14s %9s %9s %9s %9s\n", "axis", "value", "series", "knobs", "size", "total ms",
                "tech. ms", "wall ms");
    for (const auto& r : records)
        std::printf("%-10s %10.0f %-20s %-14s %4ux%-4u %9.2f %9.2f %9.2f\n", r.axis.c_str(), r.value, r.series.c_str(),
                    r.knobs.c_str(), r.width, r.height, r.totalMs, r.techniqueMs, r.wallMs);
    printSlopes(records);
    printVoxelizeRate(records, *scenes, axes.levels.size());
    std::printf("wrote %s/scaling.csv, scaling.json, scaling-{pixels,voxels,triangles}.svg\n", opt.outDir.c_str());
    return 0;
}

} // namespace vkgi::bench
