// vkgi-minimal: a host of the GI module alone (the package's core, no optional component). It
// creates a headless device with vkgi's DeviceBuilder, renders two frames of a built-in scene
// with a GI technique and prints the composite image's mean. It reads no file and writes none,
// and links only vkgi::gi (Vulkan and GLM), so tests/package builds it against a package found
// without any component to show that such a host needs nothing else.
//
//   vkgi-minimal [SCENE [TECHNIQUE [SIZE]]]     e.g. vkgi-minimal cornell vpl 32
#include <charconv>
#include <cstdio>
#include <string>
#include <string_view>

#include "vkgi/builtin_scenes.hpp"
#include "vkgi/context.hpp"
#include "vkgi/gi.hpp"

namespace {

int fail(const std::string& message) {
    std::fprintf(stderr, "vkgi-minimal: %s\n", message.c_str());
    return 1;
}

} // namespace

int main(int argc, char** argv) {
    std::string sceneName = argc > 1 ? argv[1] : "cornell";
    std::string techniqueName = argc > 2 ? argv[2] : "vpl";
    std::string_view sizeText = argc > 3 ? argv[3] : "32";
    uint32_t size = 0;
    auto [end, ec] = std::from_chars(sizeText.data(), sizeText.data() + sizeText.size(), size);
    if (ec != std::errc() || end != sizeText.data() + sizeText.size() || size < 1 || size > 4096)
        return fail("SIZE: expected 1..4096, got '" + std::string(sizeText) + "'");
    auto technique = vkgi::gi::parseTechnique(techniqueName);
    if (!technique)
        return fail("unknown technique '" + techniqueName + "'");
    auto scene = vkgi::makeBuiltinScene(sceneName);
    if (!scene)
        return fail(scene.error().message);

    auto ctx = vkgi::DeviceBuilder().setApplicationName("vkgi-minimal").build();
    if (!ctx)
        return fail(ctx.error().message);
    vkgi::gi::GiSettings settings;
    settings.technique = *technique;
    auto gi = vkgi::gi::GiSystem::create(**ctx, settings);
    if (!gi)
        return fail(gi.error().message);
    if (auto ok = (*gi)->setScene(*scene); !ok)
        return fail(ok.error().message);
    vkgi::Camera camera = scene->cameraOrDefault();
    vkgi::gi::FrameRequest request;
    // Two frames, as vkgi-render renders them.
    auto frame = (*gi)->renderFrame(camera, size, size, request);
    if (frame)
        frame = (*gi)->renderFrame(camera, size, size, request);
    if (!frame)
        return fail(frame.error().message);
    glm::dvec3 sum(0.0);
    for (const glm::vec3& p : frame->composite.pixels)
        sum += glm::dvec3(p);
    glm::dvec3 mean = sum / double(frame->composite.pixels.size());
    std::printf("%s %ux%u technique %s: composite mean %.6f %.6f %.6f nits\n", sceneName.c_str(), size, size,
                techniqueName.c_str(), mean.x, mean.y, mean.z);
    return 0;
}
