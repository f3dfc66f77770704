#include "sweep.hpp"

#include <algorithm>
#include <chrono>
#include <map>
#include <memory>

#include "vkgi/image_metrics.hpp"

namespace vkgi::bench {

namespace {
// relMSE's epsilon for the dark-weighted column (the usual one is compareImages' 0.01).
constexpr float kDarkEpsilon = 0.001f;

std::vector<std::string> product(const std::string& a, const std::vector<std::string>& av, const std::string& b,
                                 const std::vector<std::string>& bv) {
    std::vector<std::string> out;
    for (const auto& x : av)
        for (const auto& y : bv)
            out.push_back(a + "=" + x + " " + b + "=" + y);
    return out;
}
double median(std::vector<double> v) {
    if (v.empty())
        return 0.0;
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}
} // namespace

std::vector<std::string> sweepFor(const std::string& technique, bool quick) {
    // The grids the issues ask for: the main quality axes crossed, then one-at-a-time toggles
    // around the defaults.
    std::vector<std::string> s;
    if (technique == "none") {
        s = {""};
    } else if (technique == "lpv") {
        s = product("lpv.grid", {"16", "32", "64"}, "lpv.iterations", {"4", "8", "16", "32", "64"});
        for (const char* t : {"lpv.occlusion=off", "lpv.bounces=on", "lpv.damping=0", "lpv.cascades=2", "lpv.cascades=3",
                              "lpv.rsm_reduce=1", "lpv.rsm_reduce=4"})
            s.push_back(std::string("lpv.grid=32 lpv.iterations=8 ") + t);
        // The defaults (16^3 x 20) and their step count with the former RSM reduction and with
        // multi-bounce (docs/lpv.md "Defaults").
        for (const char* t : {"", " lpv.rsm_reduce=4", " lpv.bounces=on"})
            s.push_back(std::string("lpv.grid=16 lpv.iterations=20") + t);
    } else if (technique == "vct") {
        s = product("vct.grid", {"32", "64", "128"}, "vct.cones", {"4", "6", "16"});
        for (const char* t :
             {"vct.step=0.5", "vct.step=2", "vct.bounces=1", "vct.lowres=1", "vct.lowres=2", "vct.filter=1"})
            s.push_back(std::string("vct.grid=64 vct.cones=6 ") + t);
    } else if (technique == "vpl") {
        // The count at every interleave tile side, then the other knobs beside the defaults.
        s = product("vpl.interleave", {"1", "2", "4"}, "vpl.count", {"128", "256", "512"});
        for (const char* t : {"vpl.interleave=3", "vpl.negative=100", "vpl.negative=200", "vpl.lowres=2",
                              "vpl.lowres=2 vpl.interleave=1", "vpl.lowres=4 vpl.interleave=1",
                              "vpl.lowres=2 vpl.interleave=1 vpl.threshold=0.05", "vpl.interleave_tolerance=0.05",
                              "vpl.visibility=off vpl.bounces=1", "vpl.visibility=on vpl.bounces=1",
                              "vpl.visibility=on vpl.visibility_grid=32", "vpl.visibility=off vpl.bounces=2",
                              "vpl.visibility=on vpl.bounces=2", "vpl.visibility=on vpl.bounces=3"})
            s.push_back(std::string("vpl.count=256 ") + t);
    }
    if (quick && s.size() > 1)
        s.resize(1);
    return s;
}

Result<Timing> measureTiming(Context& ctx, const Scene& scene, const gi::GiSettings& settings, uint32_t width,
                             uint32_t height, uint32_t repeat, const gi::FrameRequest& request,
                             const std::function<Result<void>(gi::GiSystem&)>& beforeFrame, uint32_t warmup,
                             bool alternateDirect) {
    auto sys = gi::GiSystem::create(ctx, settings);
    if (!sys)
        return sys.error();
    if (auto ok = (*sys)->setScene(scene); !ok)
        return ok.error();
    Camera cam = scene.cameraOrDefault();
    std::map<std::string, std::vector<double>> passMs;
    std::vector<std::string> order;
    std::vector<double> totals, profiledTotals, readbacks, walls;
    std::vector<double> directTotals, directReadbacks; // the alternating direct-only frames
    Timing out;
    // Each measured frame is rendered twice: with a timestamp scope per pass (the per-pass split)
    // and with the frame's scope only (the frame time: pass scopes cost ~0.06 ms each on lavapipe,
    // rg::TimestampScopes). The first frames warm up lavapipe's JIT.
    gi::FrameRequest profiled = request, unprofiled = request;
    profiled.passTimings = true;
    unprofiled.passTimings = false;
    // The direct-only frame: a second system with technique none (what its rows render).
    std::unique_ptr<gi::GiSystem> directSys;
    if (alternateDirect) {
        gi::GiSettings none = settings;
        none.technique = gi::Technique::None;
        auto created = gi::GiSystem::create(ctx, none);
        if (!created)
            return created.error();
        directSys = std::move(*created);
        if (auto ok = directSys->setScene(scene); !ok)
            return ok.error();
    }
    gi::FrameRequest directProfiled = profiled, directUnprofiled = unprofiled;
    for (gi::FrameRequest* d : {&directProfiled, &directUnprofiled})
        d->indirect = d->glossy = d->ao = false;
    std::vector<const gi::FrameRequest*> requests = {&profiled, &unprofiled};
    if (alternateDirect)
        requests.insert(requests.end(), {&directProfiled, &directUnprofiled});
    for (uint32_t frame = 0; frame < warmup + repeat; ++frame) {
        for (const gi::FrameRequest* req : requests) {
            if (frame < warmup && (req == &unprofiled || req == &directUnprofiled))
                continue;
            const bool direct = req == &directProfiled || req == &directUnprofiled;
            gi::GiSystem& system = direct ? *directSys : **sys;
            if (beforeFrame)
                if (auto ok = beforeFrame(system); !ok)
                    return ok.error();
            auto t0 = std::chrono::steady_clock::now();
            auto r = system.renderFrame(cam, width, height, *req);
            if (!r)
                return r.error();
            double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            if (frame < warmup)
                continue;
            if (direct) {
                double readback = 0.0;
                for (const auto& p : r->passes)
                    if (p.name.find(".readback") != std::string::npos)
                        readback += p.ms;
                (req == &directUnprofiled ? directTotals : directReadbacks)
                    .push_back(req == &directUnprofiled ? r->totalMs : readback);
                continue;
            }
            if (req == &unprofiled) {
                totals.push_back(r->totalMs);
                walls.push_back(wall);
                continue;
            }
            // Copying results to the host is the bench's cost, not the technique's: the readback
            // passes' time is taken out of both totals (the unprofiled frame's by this frame's).
            double total = r->totalMs, readback = 0.0;
            for (const auto& p : r->passes) {
                if (p.name.find(".readback") != std::string::npos) {
                    readback += p.ms;
                    continue;
                }
                if (!passMs.count(p.name))
                    order.push_back(p.name);
                passMs[p.name].push_back(p.ms);
            }
            profiledTotals.push_back(total - readback);
            readbacks.push_back(readback);
            out.last = std::move(*r);
        }
    }
    for (const auto& name : order)
        out.passMs.push_back({name, median(passMs[name])});
    out.totalMs = median(totals) - median(readbacks);
    out.profiledMs = median(profiledTotals);
    out.wallMs = median(walls);
    if (alternateDirect)
        out.directMs = median(directTotals) - median(directReadbacks);
    return out;
}

namespace {

// The record's errors: `full` and `indirect` against the reference with the technique's bounce
// count, `fullAll` and `indirectAll` against the unbounded one (the same images for a
// technique; the ambient baseline fits one constant to each reference).
Result<void> fillErrors(gi::BenchRecord& rec, const HdrImage& full, const HdrImage& fullAll, const HdrImage& indirect,
                        const HdrImage& indirectAll, const References& refs) {
    auto f = compareImages(full, *refs.full);
    auto ind = compareImages(indirect, *refs.indirect);
    auto fAll = compareImages(fullAll, *refs.fullAll);
    auto indAll = compareImages(indirectAll, *refs.indirectAll);
    auto fDark = compareImages(full, *refs.full, kDarkEpsilon);
    auto fAllDark = compareImages(fullAll, *refs.fullAll, kDarkEpsilon);
    for (const auto* e : {&f, &ind, &fAll, &indAll, &fDark, &fAllDark})
        if (!*e)
            return e->error();
    rec.relMse = f->relMse;
    rec.rmse = f->rmse;
    rec.relMseIndirect = ind->relMse;
    rec.rmseIndirect = ind->rmse;
    rec.referenceBounces = refs.bounces;
    rec.relMseAll = fAll->relMse;
    rec.rmseAll = fAll->rmse;
    rec.relMseIndirectAll = indAll->relMse;
    rec.rmseIndirectAll = indAll->rmse;
    rec.relMseDark = fDark->relMse;
    rec.relMseAllDark = fAllDark->relMse;
    const std::vector<bool> surface = surfacePixels(full, *refs.full);
    const double truth = laplacianEnergy(*refs.indirect, surface);
    rec.hfRatio = truth > 0.0 ? laplacianEnergy(indirect, surface) / truth : 0.0;
    return {};
}

} // namespace

Result<Measured> measure(Context& ctx, const Scene& scene, const std::string& sceneName, const gi::GiSettings& settings,
                         const std::string& knobs, const Options& opt, const References& refs) {
    gi::FrameRequest request;
    request.indirect = settings.technique != gi::Technique::None;
    // Every measured frame recomputes everything, as for a scene where everything moves:
    // otherwise a static scene would reuse the persistent volumes and time only the lookups.
    auto invalidate = [](gi::GiSystem& sys) -> Result<void> {
        sys.invalidate();
        return {};
    };
    auto timing = measureTiming(ctx, scene, settings, opt.width, opt.height, opt.repeat, request, invalidate, 1, true);
    if (!timing)
        return timing.error();
    const gi::FrameResult& last = timing->last;
    gi::BenchRecord rec;
    rec.scene = sceneName;
    rec.technique = gi::toString(settings.technique);
    rec.knobs = knobs;
    rec.passMs = timing->passMs;
    rec.totalMs = timing->totalMs;
    rec.profiledMs = timing->profiledMs;
    rec.directMs = timing->directMs;
    rec.deviceMiB = double(last.persistentBytes + last.transientBytes) / (1024.0 * 1024.0);
    rec.triangles = scene.triangleCount();
    for (const auto& pass : rec.passMs)
        for (const rg::PassMemory& m : last.passMemory)
            if (m.name == pass.first) {
                rec.passBytes.push_back({pass.first, double(m.accessedBytes)});
                break;
            }
    // Without a technique the indirect estimate is zero: its error is that of "no GI".
    HdrImage indirect = last.indirect.empty() ? HdrImage(opt.width, opt.height) : last.indirect;
    if (auto ok = fillErrors(rec, last.composite, last.composite, indirect, indirect, refs); !ok)
        return ok.error();
    Measured out{std::move(rec), {}, {}};
    if (settings.technique == gi::Technique::None) {
        // The best constant for each reference, on the pixels that show a surface.
        gi::BenchRecord ambient = out.record;
        ambient.technique = "ambient";
        ambient.knobs = "(best constant)";
        const std::vector<bool> surface = surfacePixels(last.composite, *refs.full);
        const HdrImage matched = bestAmbient(last.composite, *refs.full, surface);
        const HdrImage all = bestAmbient(last.composite, *refs.fullAll, surface);
        auto matchedIndirect = subtract(matched, last.composite), allIndirect = subtract(all, last.composite);
        if (!matchedIndirect || !allIndirect)
            return (matchedIndirect ? allIndirect : matchedIndirect).error();
        if (auto ok = fillErrors(ambient, matched, all, *matchedIndirect, *allIndirect, refs); !ok)
            return ok.error();
        out.ambient = std::move(ambient);
    }

    // A technique whose passes were all left out as not needed names itself "gi.<t>.*" or "<t>.*".
    const std::string t = out.record.technique;
    for (const gi::LeftOutPass& p : last.leftOut)
        if (p.reason == gi::LeftOutReason::NotNeeded && (p.name == t + ".*" || p.name == "gi." + t + ".*"))
            out.notApplicable = p.detail;
    return out;
}

} // namespace vkgi::bench
