#pragma once
// GiSystem in one call for tests that render whole frames through the public API.
#include <memory>
#include <string>
#include <vector>

#include "vkgi/context.hpp"
#include "vkgi/scene.hpp"
#include "vkgi/gi.hpp"
#include "vkgi/reference.hpp"
#include "gi/vpl.h"

namespace vkgi::test {

// A built-in scene (vkgi/builtin_scenes.hpp); a scene that does not build fails the test here
// and gives an empty scene.
Scene builtinScene(const std::string& name);

// A GiSystem with `settings` and `scene` set.
Result<std::unique_ptr<gi::GiSystem>> systemWithScene(Context& ctx, const gi::GiSettings& settings, const Scene& scene);

// One frame of `scene` seen from `camera` by a new GiSystem with `settings`.
Result<gi::FrameResult> renderOnce(Context& ctx, const gi::GiSettings& settings, const Scene& scene,
                                   const Camera& camera, uint32_t width, uint32_t height,
                                   const gi::FrameRequest& request);

// The path tracer's image of `scene` from `camera` with at most `maxBounces` reflections (-1:
// unbounded), `spp` paths per pixel, through the reference cache, without progress output.
Result<gi::ReferenceImages> reference(const Scene& scene, const Camera& camera, uint32_t width, uint32_t height,
                                      uint32_t spp, int maxBounces);

// The "all bounces" reference: reference() with unbounded bounces.
Result<gi::ReferenceImages> allBounceReference(const Scene& scene, const Camera& camera, uint32_t width,
                                               uint32_t height, uint32_t spp = 256);

// The positive VPL records (VplOutputs::vpls, in gi/vpl.h's subset order) of one frame of `scene`
// with `settings` (Technique::Vpl) at size x size, through GiSystem::addPasses; empty, with a
// test failure, when the frame has no VPL.
std::vector<gpu::VplRecord> vplRecords(Context& ctx, const gi::GiSettings& settings, const Scene& scene, uint32_t size);

} // namespace vkgi::test
