// vkgi-view: a GLFW window showing a scene lit by a vkgi GI technique, with an ImGui panel for
// the technique, its knobs, the lights and a dynamic object, per-pass GPU times, and
// screenshots (EXR + PNG). Scripted runs (--frames/--camera-script/--screenshot/--exit) are
// what CI runs under xvfb-run. `vkgi-view --help` lists everything.
#include <cstdio>

#include "../common/args.hpp"
#include "vkgi/context.hpp"
#include "vkgi/gltf_loader.hpp"
#include "vkgi/gi.hpp"
#include "options.hpp"
#include "viewer.hpp"
#include "window.hpp"

using namespace vkgi;

namespace {

int fail(int code, const std::string& message) {
    std::fprintf(stderr, "vkgi-view: %s\n", message.c_str());
    return code;
}

} // namespace

int main(int argc, char** argv) {
    auto options = view::parseArgs(argc, argv);
    if (!options)
        return fail(2, options.error().message);
    const view::Options& o = *options;
    if (o.help) {
        std::fputs(view::helpText().c_str(), stdout);
        return 0;
    }
    gi::GiSettings settings;
    settings.technique = *gi::parseTechnique(o.technique);
    if (auto ok = apps::applyKnobs(settings, o.knobs); !ok)
        return fail(2, ok.error().message);

    std::vector<std::string> warnings;
    auto scene = loadScene(o.scene, {}, &warnings);
    for (const std::string& w : warnings)
        std::fprintf(stderr, "vkgi-view: warning: %s\n", w.c_str());
    if (!scene)
        return fail(1, scene.error().message);
    scene->lights.insert(scene->lights.end(), o.lights.begin(), o.lights.end());
    if (o.camera)
        scene->camera = apps::makeCamera(*o.camera, scene->bounds());
    if (auto ok = validateScene(*scene); !ok)
        return fail(1, ok.error().message);

    auto window = view::Window::create("vkgi-view: " + o.scene, o.width, o.height);
    if (!window)
        return fail(1, window.error().message);
    DeviceBuilder builder = defaultDeviceBuilder();
    for (const char* ext : view::Window::requiredInstanceExtensions())
        builder.addInstanceExtension(ext);
    builder.addDeviceExtension(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    builder.setApplicationName("vkgi-view");
    if (o.validation)
        builder.enableValidation(true, true);
    auto ctx = builder.build();
    if (!ctx)
        return fail(1, ctx.error().message);

    int code = 0;
    {
        auto viewer = view::Viewer::create(o, **window, **ctx, std::move(*scene), settings);
        if (!viewer)
            return fail(1, viewer.error().message);
        code = (*viewer)->run();
    }
    // Counted once the device is destroyed too, which reports every Vulkan object left alive.
    const std::shared_ptr<const ValidationLog> log = (*ctx)->sharedValidation();
    ctx->reset();
    if (uint32_t n = log->count(); n > 0)
        return fail(3, std::to_string(n) + " validation message(s) (printed above)");
    return code;
}
