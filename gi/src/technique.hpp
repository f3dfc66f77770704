#pragma once
// How an indirect-light technique plugs into GiSystem. Adding one takes: a Technique value and
// its name (gi.hpp, technique_registry.cpp), one TechniqueModule subclass in gi/src/<name>/, and
// one case in createTechnique. The module reads the shared handles from the blackboard
// (FrameData, SceneHandles, GBufferData, ShadowData, and RsmData when needsRsm()) and must add
// IndirectData; the graph culls its passes when no requested output needs them.
//
// Pass selection (pipeline.hpp): the blackboard also holds PassSelection, with the scene's
// features and the SceneChanges since the module's last addPasses. A module keeps results that
// only depend on the scene and lights (voxel grid, voxel light, propagated volumes) in
// persistent graph resources (importImage of an rg::PersistentImage) and registers the passes
// that produce them only when the changes dirty them; whatever it leaves out, or never needs for
// this scene, it records with PassSelection::leaveOut. GiSystem does not call addPasses at all
// when no requested output needs indirect light (the changes then keep accumulating).
#include <memory>

#include "engine/gpu_scene.hpp"
#include "engine/rg/blackboard.hpp"
#include "engine/rg/render_graph.hpp"
#include "gi/frame_data.hpp"
#include "gi/gi.hpp"
#include "pipeline.hpp"

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
