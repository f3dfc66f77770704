#pragma once
// How an indirect-light technique plugs into GiSystem. Adding one takes: a Technique value and
// its name (gi.hpp, technique_registry.cpp), one TechniqueModule subclass in gi/src/<name>/, and
// one case in createTechnique. addPasses gets the shared handles of this frame (TechniqueInputs)
// and returns what it produced (IndirectOutputs); GiSystem publishes those, composites them and
// marks the requested ones as outputs, and the graph culls the passes no requested output needs.
// A technique writes no other technique's or GiSystem's data: the one image it may replace, the
// direct light, it returns (IndirectOutputs::direct).
//
// Pass selection (pass_selection.hpp): TechniqueInputs::selection holds the scene's features and
// the SceneChanges since the module's last addPasses. A module keeps results that
// only depend on the scene and lights (voxel grid, voxel light, propagated volumes) in
// persistent graph resources (importImage of an rg::PersistentImage) and registers the passes
// that produce them only when the changes dirty them; whatever it leaves out, or never needs for
// this scene, it records with PassSelection::leaveOut. GiSystem does not call addPasses at all
// when no requested output needs indirect light (the changes then keep accumulating).
#include <memory>
#include <vector>

#include "vkgi/gpu_scene.hpp"
#include "vkgi/rg/blackboard.hpp"
#include "vkgi/rg/render_graph.hpp"
#include "vkgi/frame_data.hpp"
#include "vkgi/gi.hpp"
#include "direct/direct_passes.hpp"
#include "pass_selection.hpp"

namespace vkgi::gi {

// This frame's shared handles, valid for the graph addPasses adds to.
struct TechniqueInputs {
    const FrameData& frame;
    const SceneHandles& scene;
    const GBufferData& gbuffer;
    const ShadowData& shadow; // the shadow atlas (its layers may be empty)
    const RsmData* rsm;       // present when the technique needsRsm() (or GiSettings::forceRsm)
    rg::ImageHandle direct;   // the deferred direct light (emission + punctual lights), read-only
    PassSelection& selection;
    // For handles a technique publishes beyond IndirectOutputs (its own types: VoxelGridData,
    // VctOutputs, VplOutputs) for tests and tools; never for the inputs above.
    rg::Blackboard& blackboard;
    // The shared passes' pipelines, for RSMs of sources that are not scene lights (the LPV's
    // emitter proxies: addPointSourceRsmPass).
    const DirectPipelines& pipelines;
};

// What a technique's passes produce, camera resolution, RGBA32F.
struct IndirectOutputs {
    rg::ImageHandle indirect; // indirect radiance (nits)
    rg::ImageHandle ao;       // alpha = AO visibility in [0, 1]; invalid when not produced
    rg::ImageHandle glossy;   // glossy cone radiance (nits); invalid when not produced
    // A re-shaded direct light that replaces TechniqueInputs::direct in the composite and the
    // direct output (VCT's cone-traced soft shadows); invalid when the technique keeps it.
    rg::ImageHandle direct;
};

class TechniqueModule {
public:
    virtual ~TechniqueModule() = default;
    // True when the technique reads RsmData: the light passes then also write the RSM targets.
    virtual bool needsRsm() const { return false; }
    // The part of the scene whose RSM texels this frame's passes read, when it is a window
    // inside the scene (planShadows then fits directional lights' RSMs to it); invalid = all.
    virtual Aabb rsmWindow(const FrameData& frame) const {
        (void)frame;
        return {};
    }
    // Boxes, finest first, whose points this frame's passes look up in the shadow atlas for every
    // directional light (VCT's clipmap levels). planShadows gives each light one depth-only
    // layer fitted to each leading box whose texels are finer than the light's whole-scene layer;
    // the shaders find them in GpuLightShadow::cascades (z first window layer, w count: box k is
    // layer z + k when k < w, else the light's own layer). Empty = none.
    virtual std::vector<Aabb> shadowWindows(const FrameData& frame) const {
        (void)frame;
        return {};
    }
    // After setScene (`uploaded` = new geometry) and updateScene (moved instances/lights).
    virtual Result<void> sceneChanged(Context& ctx, const Scene& scene, const GpuScene& gpu, bool uploaded) {
        (void)ctx, (void)scene, (void)gpu, (void)uploaded;
        return {};
    }
    // Adds this frame's passes.
    virtual IndirectOutputs addPasses(rg::RenderGraph& graph, const TechniqueInputs& inputs) = 0;
    // Device memory the technique keeps across frames (volumes, histories), in bytes.
    virtual uint64_t persistentBytes() const { return 0; }
};

// The module of `settings.technique`; null for Technique::None.
Result<std::unique_ptr<TechniqueModule>> createTechnique(Context& ctx, const GiSettings& settings);

} // namespace vkgi::gi
