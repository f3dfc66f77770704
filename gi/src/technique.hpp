#pragma once
// How an indirect-light technique plugs into GiSystem. Adding one takes: a Technique value and
// its name (gi.hpp, technique_registry.cpp), one TechniqueModule subclass in gi/src/<name>/, and
// one case in createTechnique. The module reads the shared handles from the blackboard
// (FrameData, SceneHandles, GBufferData, ShadowData, and RsmData when needsRsm()) and must add
// IndirectData; the graph culls its passes when no requested output needs them.
#include <memory>

#include "engine/gpu_scene.hpp"
#include "engine/rg/blackboard.hpp"
#include "engine/rg/render_graph.hpp"
#include "gi/frame_data.hpp"
#include "gi/gi.hpp"

namespace vkgi::gi {

class TechniqueModule {
public:
    virtual ~TechniqueModule() = default;
    // True when the technique reads RsmData: the light passes then also write the RSM targets.
    virtual bool needsRsm() const { return false; }
    // After setScene (`uploaded` = new geometry) and updateScene (moved instances/lights).
    virtual Result<void> sceneChanged(Context& ctx, const Scene& scene, const GpuScene& gpu, bool uploaded) {
        (void)ctx, (void)scene, (void)gpu, (void)uploaded;
        return {};
    }
    // Adds this frame's passes; must add IndirectData to `blackboard`.
    virtual void addPasses(rg::RenderGraph& graph, rg::Blackboard& blackboard) = 0;
    // Device memory the technique keeps across frames (volumes, histories), in bytes.
    virtual uint64_t persistentBytes() const { return 0; }
};

// The module of `settings.technique`; null for Technique::None.
Result<std::unique_ptr<TechniqueModule>> createTechnique(Context& ctx, const GiSettings& settings);

} // namespace vkgi::gi
