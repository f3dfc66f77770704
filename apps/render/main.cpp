// vkgi-render: renders one frame of a scene headless with a GI technique (or the CPU path
// tracer), prints per-pass GPU times, optionally compares against the cached path-traced
// reference, and writes EXR/PNG images and a JSON report. `vkgi-render --help` lists options.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>

#include <unistd.h>

#include "../common/args.hpp"
#include "cli.hpp"
#include "vkgi/file_util.hpp"
#include "vkgi/gltf_loader.hpp"
#include "vkgi/image_io.hpp"
#include "vkgi/gi.hpp"
#include "vkgi/reference.hpp"

using namespace vkgi;

namespace {

// What one render produced: the final image, its direct part, and the timing report.
struct Rendered {
    HdrImage image;
    HdrImage direct;
    HdrImage indirect; // image - direct; the path tracer's own indirect paths
    HdrImage glossy, ao; // VCT only, when asked for (gi::FrameRequest)
    std::vector<rg::PassTiming> passes;
    double totalMs = 0.0;
    std::optional<double> unprofiledMs; // GI techniques: the same frame without pass timestamps
    std::vector<gi::LeftOutPass> leftOut;
    std::optional<render::MemoryUse> memory; // none for the path tracer
    // GPU times and passes of a third frame with nothing changed (GI techniques only): what a
    // static scene costs once the persistent volumes are valid.
    std::optional<render::StaticFrame> staticFrame;
    // The GPU context's validation log, read once the context is destroyed (none for the path tracer).
    std::shared_ptr<const ValidationLog> validation;
};

int fail(int code, const std::string& message) {
    std::fprintf(stderr, "vkgi-render: %s\n", message.c_str());
    return code;
}

gi::ReferenceSettings referenceSettings(const render::Options& o, int bounces) {
    gi::ReferenceSettings s;
    s.spp = o.spp;
    s.maxBounces = bounces;
    return s;
}

Result<gi::GiSettings> giSettings(const render::Options& o, gi::Technique t) {
    gi::GiSettings settings;
    settings.technique = t;
    if (auto ok = apps::applyKnobs(settings, o.knobs); !ok)
        return ok.error();
    return settings;
}

Result<Rendered> renderGi(const Scene& scene, const Camera& camera, const render::Options& o,
                          const gi::GiSettings& settings) {
    auto system = gi::GiSystem::createHeadless(settings);
    if (!system)
        return system.error();
    if (auto ok = (*system)->setScene(scene); !ok)
        return ok.error();
    gi::FrameRequest request;
    request.direct = true;
    request.glossy = !o.glossyOutputs.empty();
    request.ao = !o.aoOutputs.empty();
    // lavapipe JIT-compiles each shader at its first dispatch; a warm-up frame keeps that out of
    // the reported times (they are the second frame's, recomputing everything as a first frame
    // does: invalidate() keeps the warm-up's persistent volumes from being reused).
    auto frame = (*system)->renderFrame(camera, o.width, o.height, request);
    if (frame) {
        (*system)->invalidate();
        frame = (*system)->renderFrame(camera, o.width, o.height, request);
    }
    if (!frame)
        return frame.error();
    (*system)->invalidate();
    gi::FrameRequest unprofiled = request;
    unprofiled.passTimings = false;
    auto plain = (*system)->renderFrame(camera, o.width, o.height, unprofiled);
    if (!plain)
        return plain.error();
    auto still = (*system)->renderFrame(camera, o.width, o.height, request);
    if (!still)
        return still.error();
    auto indirect = subtract(frame->composite, frame->direct);
    if (!indirect)
        return indirect.error();
    return Rendered{std::move(frame->composite),
                    std::move(frame->direct),
                    std::move(*indirect),
                    std::move(frame->glossy),
                    std::move(frame->ao),
                    frame->passes,
                    frame->totalMs,
                    plain->totalMs,
                    frame->leftOut,
                    render::MemoryUse{frame->persistentByOwner, frame->transientBytes, frame->passMemory},
                    render::StaticFrame{still->passes, still->totalMs, still->leftOut},
                    (*system)->context().sharedValidation()};
}

Result<Rendered> renderPathTraced(const Scene& scene, const Camera& camera, const render::Options& o, int bounces) {
    auto ref = gi::renderReference(scene, camera, o.width, o.height, referenceSettings(o, bounces));
    if (!ref)
        return ref.error();
    double ms = ref->seconds * 1000.0;
    return Rendered{std::move(ref->full),
                    std::move(ref->direct),
                    std::move(ref->indirect),
                    {},
                    {},
                    {{"reference (CPU wall time)", ms}},
                    ms,
                    std::nullopt,
                    {},
                    std::nullopt,
                    {},
                    nullptr};
}

// Errors of the full image and of its indirect part (full - direct) against the reference.
Result<render::Errors> compare(const Scene& scene, const Camera& camera, const render::Options& o, int bounces,
                               const Rendered& r) {
    auto ref = gi::renderReferenceCached(scene, camera, o.width, o.height, referenceSettings(o, bounces));
    if (!ref)
        return ref.error();
    auto full = compareImages(r.image, ref->full);
    if (!full)
        return full.error();
    auto ind = compareImages(r.indirect, ref->indirect);
    if (!ind)
        return ind.error();
    return render::Errors{*full, *ind};
}

// Image format from the target's name (the temporary it is first written to has another).
Result<void> writeImage(const std::filesystem::path& target, const std::filesystem::path& file, const HdrImage& image,
                        const ToneMap& toneMap) {
    return target.extension() == ".exr" ? writeExr(file, image) : writePng(file, image, toneMap);
}

// Output folders made before rendering, so a bad --out fails before the device is created;
// they are removed again unless every output is written.
Result<std::vector<OutputFolders>> prepareOutputs(const render::Options& o) {
    std::vector<OutputFolders> folders;
    for (const auto& [flag, path] : render::outputFiles(o)) {
        auto made = OutputFolders::create(path);
        if (!made)
            return makeError(flag + ": " + made.error().message);
        folders.push_back(std::move(*made));
        const std::filesystem::path parent = path.has_parent_path() ? path.parent_path() : ".";
        if (::access(parent.c_str(), W_OK) != 0)
            return makeError(flag + ": " + path.string() + ": cannot write into folder " + parent.string());
    }
    return folders;
}

// Writes every output to a temporary beside it, then moves them all into place: a failure
// leaves none of them half-written and none of them new.
Result<void> writeOutputs(const render::Options& o, const Rendered& r, const std::optional<render::Errors>& errors) {
    std::vector<AtomicFile> staged;
    std::vector<std::string> names;
    // One exposure for every radiance part, so that they compare: given, or the frame's own.
    const float exposure = o.exposure ? *o.exposure : autoExposure(r.image);
    const std::pair<const std::vector<std::filesystem::path>*, const HdrImage*> parts[] = {
        {&o.outputs, &r.image},         {&o.directOutputs, &r.direct}, {&o.indirectOutputs, &r.indirect},
        {&o.glossyOutputs, &r.glossy}, {&o.aoOutputs, &r.ao}};
    for (const auto& [paths, image] : parts)
        for (const std::filesystem::path& out : *paths) {
            auto file = AtomicFile::begin(out);
            if (!file)
                return file.error();
            // AO is a visibility in [0, 1], not radiance: PNG stores it as is (no exposure, no curve).
            ToneMap toneMap = image == &r.ao ? ToneMap{1.0f, ToneMap::Curve::Clamp} : ToneMap{exposure, ToneMap::Curve::Aces};
            if (auto ok = writeImage(out, file->temporary(), *image, toneMap); !ok)
                return makeError(out.string() + ": " + ok.error().message);
            staged.push_back(std::move(*file));
            names.push_back(out.string());
        }
    if (o.json) {
        auto file = AtomicFile::begin(*o.json);
        if (!file)
            return file.error();
        if (auto ok = writeFileAtomic(file->temporary(), render::jsonReport(o, r.passes, r.totalMs, r.unprofiledMs,
                                                                           r.leftOut, r.staticFrame, r.memory, errors));
            !ok)
            return makeError(o.json->string() + ": " + ok.error().message);
        staged.push_back(std::move(*file));
        names.push_back(o.json->string());
    }
    for (size_t i = 0; i < staged.size(); ++i) {
        if (auto ok = staged[i].commit(); !ok)
            return ok;
        std::printf("wrote %s\n", names[i].c_str());
    }
    const bool png = std::any_of(names.begin(), names.end(), [](const std::string& name) {
        return std::filesystem::path(name).extension() == ".png";
    });
    if (png)
        std::printf("PNG exposure %.4g%s\n", exposure, o.exposure ? "" : " (auto: --exposure E sets it)");
    return {};
}

} // namespace

int main(int argc, char** argv) {
    auto options = render::parseArgs(argc, argv);
    if (!options)
        return fail(2, options.error().message);
    const render::Options& o = *options;
    if (o.help) {
        std::fputs(render::helpText().c_str(), stdout);
        return 0;
    }
    bool pathTraced = o.technique == "reference"; // parseArgs checked the name
    auto technique = gi::parseTechnique(pathTraced ? "none" : o.technique);
    auto folders = prepareOutputs(o);
    if (!folders)
        return fail(2, folders.error().message);

    std::vector<std::string> warnings;
    GltfLoadOptions loadOptions;
    loadOptions.allowOutsideFolder = o.allowOutsideFolder;
    auto scene = loadScene(o.scene, {}, &warnings, loadOptions);
    for (const std::string& w : warnings) {
        // The loader's warning about a scene without light names what this app can do about it.
        const bool unlit = w.find("no punctual lights") != std::string::npos;
        std::fprintf(stderr, "vkgi-render: warning: %s%s\n", w.c_str(),
                     !unlit              ? ""
                     : o.lights.empty() ? " (add one with --light)"
                                         : " (--light adds one)");
    }
    if (!scene)
        return fail(1, scene.error().message);
    scene->lights.insert(scene->lights.end(), o.lights.begin(), o.lights.end());
    if (auto ok = validateScene(*scene); !ok) // e.g. more lights than a scene may have
        return fail(1, ok.error().message);
    Camera camera = o.camera ? apps::makeCamera(*o.camera, scene->bounds()) : scene->cameraOrDefault();
    auto settings = giSettings(o, *technique);
    if (!settings)
        return fail(2, settings.error().message);
    int bounces = o.bounces.value_or(pathTraced ? -1 : gi::modelledBounces(*settings, &*scene));

    if (pathTraced && !(o.glossyOutputs.empty() && o.aoOutputs.empty()))
        return fail(2, std::string(o.glossyOutputs.empty() ? "--out-ao" : "--out-glossy") +
                           ": the path tracer has no glossy or ambient-occlusion image (technique vct has)");
    auto rendered = pathTraced ? renderPathTraced(*scene, camera, o, bounces) : renderGi(*scene, camera, o, *settings);
    if (!rendered)
        return fail(1, rendered.error().message);
    // With VKGI_VALIDATION=1 any message (printed as it came) fails the run before a file is written;
    // the log is complete: the context, destroyed by now, reported the objects it still held.
    if (rendered->validation && rendered->validation->count() > 0)
        return fail(3, std::to_string(rendered->validation->count()) + " validation message(s) (printed above)");
    // Before any file is written: an asked-for part the technique did not produce.
    if (!o.glossyOutputs.empty() && rendered->glossy.pixels.empty())
        return fail(1, "--out-glossy: technique " + o.technique + " produces no glossy image (vct does)");
    if (!o.aoOutputs.empty() && rendered->ao.pixels.empty())
        return fail(1, o.technique == "vct" ? std::string("--out-ao: ambient occlusion is off (--vct.ao off)")
                                            : "--out-ao: technique " + o.technique +
                                                  " produces no ambient occlusion (vct does)");
    std::printf("%s %ux%u, technique %s\n", o.scene.c_str(), o.width, o.height, o.technique.c_str());
    std::fputs(render::timingTable(rendered->passes, rendered->totalMs, rendered->unprofiledMs, rendered->leftOut,
                                   rendered->memory, rendered->staticFrame)
                   .c_str(),
               stdout);

    std::optional<render::Errors> errors;
    if (o.compare) {
        auto e = compare(*scene, camera, o, bounces, *rendered);
        if (!e)
            return fail(1, "--compare: " + e.error().message);
        errors = *e;
        std::printf("error vs reference (%d bounces, %u spp): relMSE %.6g  RMSE %.6g nits  |  indirect: relMSE "
                    "%.6g  RMSE %.6g nits\n",
                    bounces, o.spp, e->full.relMse, e->full.rmse, e->indirect.relMse, e->indirect.rmse);
    }
    if (auto ok = writeOutputs(o, *rendered, errors); !ok)
        return fail(1, ok.error().message);
    for (OutputFolders& f : *folders)
        f.release();
    return 0;
}
