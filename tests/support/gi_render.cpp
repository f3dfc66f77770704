#include "support/gi_render.hpp"

#include <gtest/gtest.h>

#include "vkgi/builtin_scenes.hpp"
#include "vkgi/rg/blackboard.hpp"
#include "vkgi/vpl.hpp"
#include "support/gpu_util.hpp"

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

std::vector<gpu::VplRecord> vplRecords(Context& ctx, const gi::GiSettings& settings, const Scene& scene, uint32_t size) {
    auto sys = systemWithScene(ctx, settings, scene);
    EXPECT_TRUE(sys) << (sys ? "" : sys.error().message);
    if (!sys)
        return {};
    rg::RenderGraph graph;
    rg::Blackboard bb;
    auto outputs = (*sys)->addPasses(graph, bb, scene.cameraOrDefault(), size, size, gi::FrameRequest{});
    EXPECT_TRUE(outputs) << (outputs ? "" : outputs.error().message);
    const gi::VplOutputs* vo = bb.tryGet<gi::VplOutputs>();
    EXPECT_TRUE(vo && vo->vplCount > 0) << scene.name << ": the frame has no VPL";
    if (!outputs || !vo || vo->vplCount == 0)
        return {};
    const VkDeviceSize bytes = VkDeviceSize(vo->vplCount) * sizeof(gpu::VplRecord);
    return asArray<gpu::VplRecord>(runAndReadBuffer(ctx, graph, vo->vpls, bytes));
}

Result<gi::ReferenceImages> reference(const Scene& scene, const Camera& camera, uint32_t width, uint32_t height,
                                      uint32_t spp, int maxBounces) {
    gi::ReferenceSettings rs;
    rs.spp = spp;
    rs.maxBounces = maxBounces;
    rs.progress = false;
    return gi::renderReferenceCached(scene, camera, width, height, rs);
}

Result<gi::ReferenceImages> allBounceReference(const Scene& scene, const Camera& camera, uint32_t width,
                                               uint32_t height, uint32_t spp) {
    return reference(scene, camera, width, height, spp, -1);
}

} // namespace vkgi::test
