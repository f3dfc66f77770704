#include "support/gi_render.hpp"

#include <gtest/gtest.h>

#include "vkgi/builtin_scenes.hpp"

namespace vkgi::test {

Scene builtinScene(const std::string& name) {
    auto s = makeBuiltinScene(name);
    if (!s) {
        ADD_FAILURE() << "built-in scene " << name << ": " << s.error().message;
        return {};
    }
    return std::move(*s);
}

Result<std::unique_ptr<gi::GiSystem>> systemWithScene(Context& ctx, const gi::GiSettings& settings,
                                                      const Scene& scene) {
    auto system = gi::GiSystem::create(ctx, settings);
    if (!system)
        return system.error();
    if (auto ok = (*system)->setScene(scene); !ok)
        return ok.error();
    return system;
}

Result<gi::FrameResult> renderOnce(Context& ctx, const gi::GiSettings& settings, const Scene& scene,
                                   const Camera& camera, uint32_t width, uint32_t height,
                                   const gi::FrameRequest& request) {
    auto system = systemWithScene(ctx, settings, scene);
    if (!system)
        return system.error();
    return (*system)->renderFrame(camera, width, height, request);
}

} // namespace vkgi::test
