#include "flight.hpp"

#include <algorithm>

#include <glm/glm.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include "vkgi/file_util.hpp"
#include "vkgi/gltf_loader.hpp"
#include "vkgi/knobs.hpp"
#include "vkgi/progress.hpp"

namespace vkgi::bench {

namespace {

// Metres per frame: a fifth of the finest clipmap voxel of the automatic clipmap (0.25 m), so
// frames that move no level, the finest level only, or several alternate along the flight, and
// 48 frames (2.4 m) keep the built-in scenes' cameras clear of their walls and objects.
constexpr float kFlightStep = 0.05f;
// --path orbit: degrees per frame about the vertical axis through the point the camera looks at
// (a slow orbit, the temporal-stability case of issue #15).
constexpr float kOrbitDegrees = 0.5f;

// The camera of frame `f` along the path.
Camera pathCamera(const Camera& start, const Aabb& bounds, bool orbit, uint32_t f) {
    Camera camera = start;
    const glm::vec3 forward = glm::normalize(start.forward);
    if (!orbit) {
        camera.position += forward * (kFlightStep * float(f));
        return camera;
    }
    // Pivot at the depth of the bounds' centre along the view, kept between 0.5 and 10 m ahead
    // so that inside a large world the orbit stays around what the camera sees.
    const glm::vec3 centre = bounds.valid() ? bounds.centre() : start.position + forward;
    const float depth = std::clamp(glm::dot(centre - start.position, forward), 0.5f, 10.0f);
    const glm::vec3 pivot = start.position + forward * depth;
    const float a = glm::radians(kOrbitDegrees * float(f));
    const glm::mat3 turn(glm::vec3(std::cos(a), 0.0f, -std::sin(a)), glm::vec3(0.0f, 1.0f, 0.0f),
                         glm::vec3(std::sin(a), 0.0f, std::cos(a)));
    camera.position = pivot + turn * (start.position - pivot);
    camera.forward = turn * start.forward;
    camera.up = turn * start.up;
    return camera;
}

// Mean |a - b| over the mean of a and b, summed over channels: how much an image changed.
double relativeChange(const HdrImage& a, const HdrImage& b) {
    double diff = 0.0, mass = 0.0;
    for (size_t i = 0; i < a.pixels.size() && i < b.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            diff += std::abs(double(a.pixels[i][c]) - double(b.pixels[i][c]));
            mass += 0.5 * (double(a.pixels[i][c]) + double(b.pixels[i][c]));
        }
    return mass > 0.0 ? diff / mass : 0.0;
}

uint32_t countPasses(const gi::FrameResult& f, const std::string& prefix) {
    uint32_t n = 0;
    for (const rg::PassTiming& p : f.passes)
        n += p.name.rfind(prefix, 0) == 0 ? 1 : 0;
    return n;
}

double median(std::vector<double> v) {
    if (v.empty())
        return 0.0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

struct Row {
    std::string scene, technique;
    uint32_t frame = 0;
    float distance = 0.0f;
    double ms = 0.0;
    uint32_t levels = 0;   // VCT clipmap levels (or the one grid) re-voxelized
    uint32_t cascades = 0; // shadow cascades re-rendered
    double indirectChange = 0.0, directChange = 0.0;
};

} // namespace

int runFlight(Context& ctx, const Options& opt) {
    std::vector<Row> rows;
    Progress progress("vkgi-bench --flight", uint64_t(opt.scenes.size() * opt.techniques.size() * opt.flightFrames));
    for (const std::string& sceneName : opt.scenes) {
        auto scene = loadScene(sceneName);
        if (!scene) {
            std::fprintf(stderr, "vkgi-bench: %s\n", scene.error().message.c_str());
            return 1;
        }
        const Camera start = scene->cameraOrDefault();
        for (const std::string& tech : opt.techniques) {
            gi::GiSettings s;
            s.technique = *gi::parseTechnique(tech);
            if (opt.set && tech != "none") {
                std::stringstream in(*opt.set);
                for (std::string kv; in >> kv;)
                    if (auto ok = gi::applyKnob(s, kv); !ok) {
                        std::fprintf(stderr, "vkgi-bench: %s\n", ok.error().message.c_str());
                        return 2;
                    }
            }
            auto sys = gi::GiSystem::create(ctx, s);
            if (!sys || !(*sys)->setScene(*scene)) {
                std::fprintf(stderr, "vkgi-bench: %s %s: cannot create the system or set the scene\n",
                             sceneName.c_str(), tech.c_str());
                return 1;
            }
            gi::FrameRequest request;
            request.composite = false;
            request.direct = true;
            request.indirect = s.technique != gi::Technique::None;
            request.passTimings = true;
            // A warm-up frame (lavapipe compiles each shader at its first dispatch), then the
            // scene is set again so the flight's first frame rebuilds everything with warm
            // shaders: the full update the others are compared with.
            if (!(*sys)->renderFrame(start, opt.width, opt.height, request) || !(*sys)->setScene(*scene)) {
                std::fprintf(stderr, "vkgi-bench: %s %s: the warm-up frame failed\n", sceneName.c_str(), tech.c_str());
                return 1;
            }
            gi::FrameResult previous;
            for (uint32_t f = 0; f < opt.flightFrames; ++f) {
                progress.add(1);
                const Camera camera = pathCamera(start, scene->bounds(), opt.flightOrbit, f);
                auto frame = (*sys)->renderFrame(camera, opt.width, opt.height, request);
                if (!frame) {
                    std::fprintf(stderr, "vkgi-bench: %s %s frame %u: %s\n", sceneName.c_str(), tech.c_str(), f,
                                 frame.error().message.c_str());
                    return 1;
                }
                Row r{sceneName, tech, f, opt.flightOrbit ? kOrbitDegrees * float(f) : kFlightStep * float(f),
                      frame->totalMs,
                      countPasses(*frame, "gi.voxel.voxelize"), countPasses(*frame, "gi.light[")};
                if (f > 0) {
                    r.directChange = relativeChange(frame->direct, previous.direct);
                    r.indirectChange = relativeChange(frame->indirect, previous.indirect);
                }
                rows.push_back(r);
                previous = std::move(*frame);
            }
        }
    }
    progress.finish();
    std::ostringstream csv;
    csv << "scene,technique,frame," << (opt.flightOrbit ? "angle_deg" : "distance_m") << ",gpu_ms,voxelized_levels,light_passes,indirect_change,direct_change\n";
    for (const Row& r : rows)
        csv << r.scene << ',' << r.technique << ',' << r.frame << ',' << r.distance << ',' << r.ms << ',' << r.levels
            << ',' << r.cascades << ',' << r.indirectChange << ',' << r.directChange << '\n';
    std::filesystem::create_directories(opt.outDir);
    if (auto ok = writeFileAtomic(std::filesystem::path(opt.outDir) / "flight.csv", csv.str()); !ok) {
        std::fprintf(stderr, "vkgi-bench: %s\n", ok.error().message.c_str());
        return 1;
    }
    // Per scene and technique: the first frame (everything rebuilt), the median ms of the
    // others by the number of re-voxelized levels, the ratio of a frame re-voxelizing one level
    // to the full one, and the largest indirect change over the direct change of the same step.
    std::map<std::pair<std::string, std::string>, std::map<uint32_t, std::vector<double>>> byLevels;
    std::map<std::pair<std::string, std::string>, std::vector<double>> ratios;
    std::map<std::pair<std::string, std::string>, double> full;
    for (const Row& r : rows) {
        if (r.frame == 0) {
            full[{r.scene, r.technique}] = r.ms;
            continue;
        }
        byLevels[{r.scene, r.technique}][r.levels].push_back(r.ms);
        if (r.directChange > 0.0)
            ratios[{r.scene, r.technique}].push_back(r.indirectChange / r.directChange);
    }
    // The change ratio's usual value depends on the scene (how much of the image is direct
    // light); a pop is a frame far above the scene's median.
    std::printf("%-12s %-5s %9s  %-44s %12s  %s\n", "scene", "tech", "full ms",
                "median ms by re-voxelized levels (frames)", "1 level/full",
                "indirect/direct change: median, max");
    for (const auto& [key, levels] : byLevels) {
        std::string cells;
        for (const auto& [n, ms] : levels) {
            char cell[64];
            std::snprintf(cell, sizeof cell, " %u: %.2f (%zu)", n, median(ms), ms.size());
            cells += cell;
        }
        const double one = levels.count(1) ? median(levels.at(1)) : 0.0;
        const std::vector<double>& r = ratios[key];
        std::printf("%-12s %-5s %9.2f  %-44s %12.3f  %.3g, %.3g\n", key.first.c_str(), key.second.c_str(), full[key],
                    cells.c_str(), full[key] > 0.0 && one > 0.0 ? one / full[key] : 0.0, median(r),
                    r.empty() ? 0.0 : *std::max_element(r.begin(), r.end()));
    }
    std::printf("wrote %s/flight.csv\n", opt.outDir.c_str());
    return 0;
}

} // namespace vkgi::bench
