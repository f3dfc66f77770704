// Technique::Vpl inside GiSystem: every light of the scene with RSM layers becomes a VplSpot
// (spotlights as in the paper; point lights as spots with the whole sphere for a cone;
// directional lights sample their orthographic RSM window), and emissive surfaces one more
// source whose VPLs sit on the emissive surfels (docs/vpl.md, "Emitter VPLs").
#include "vpl/vpl_technique_module.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "vk_check.hpp"
#include "emissive/emissive_surfels.hpp"
#include "vkgi/vpl.hpp"
#include "voxel/scene_voxel_grid.hpp"

namespace vkgi::gi {

namespace {

// The VplSpot of every light that owns layers of the shadow atlas, in scene order (a light past
// the atlas's layer limit has none and gets no VPLs, as it gets no shadow).
std::vector<VplSpot> spotsWithRsmLayers(const Scene& scene, const RsmData& rsm) {
    std::vector<VplSpot> spots;
    for (uint32_t i = 0; i < scene.lights.size(); ++i) {
        const Light& light = scene.lights[i];
        uint32_t firstLayer = ~0u, layerCount = 0;
        for (uint32_t k = 0; k < rsm.layers.size(); ++k)
            if (rsm.layers[k].light == i) {
                firstLayer = std::min(firstLayer, k);
                ++layerCount;
            }
        if (layerCount == 0)
            continue;
        switch (light.type) {
        case LightType::Spot:
            spots.push_back({light.position, glm::normalize(light.direction), std::cos(light.outerConeAngle),
                             firstLayer, layerCount});
            break;
        case LightType::Point: // a spot whose cone is the whole sphere, on the cube's six layers
            spots.push_back({light.position, glm::vec3(0.0f, -1.0f, 0.0f), -1.0f, firstLayer, layerCount});
            break;
        case LightType::Directional: {
            VplSpot sun;
            sun.firstLayer = firstLayer;
            sun.layerCount = layerCount;
            sun.directional = true;
            sun.window = rsm.layers[firstLayer].viewProj;
            spots.push_back(sun);
            break;
        }
        }
    }
    return spots;
}

SharedGridPlacement sharedGridPlacement(const VplSettings& s) {
    switch (s.visibilityPlacement) {
    case VplGridPlacement::Fitted:
        return SharedGridPlacement::Fitted;
    case VplGridPlacement::Camera:
        return SharedGridPlacement::Camera;
    case VplGridPlacement::Auto:
        break;
    }
    return SharedGridPlacement::Auto;
}

VplInputs vplInputs(const TechniqueInputs& inputs, const RsmData* rsm) {
    const FrameData& frame = inputs.frame;
    VplInputs in;
    in.gPosition = inputs.gbuffer.position;
    in.gNormal = inputs.gbuffer.normal;
    in.gAlbedo = inputs.gbuffer.albedo;
    in.width = frame.width;
    in.height = frame.height;
    in.camera = frame.camera;
    if (rsm) {
        in.rsmPosition = rsm->position;
        in.rsmNormal = rsm->normal;
        in.rsmFlux = rsm->flux;
        in.shadowViews = inputs.shadow.views;
        in.spots = spotsWithRsmLayers(*frame.scene, *rsm);
    }
    return in;
}

class VplTechniqueModule final : public TechniqueModule {
public:
    VplTechniqueModule(std::unique_ptr<VplTechnique> technique, const VplSettings& settings)
        : m_technique(std::move(technique)), m_settings(settings), m_resolved(resolveVplSettings(settings, VplLighting::Spots)) {}

    // Without a light there is nothing to bounce: the light passes then leave the RSM out.
    bool needsRsm() const override { return m_lights > 0; }

    // Everything addPasses could reject is checked here, where errors can still be returned.
    Result<void> sceneChanged(Context& ctx, const Scene& scene, const GpuScene& gpu, bool uploaded) override {
        uint32_t lights = 0;
        for (const Light& l : scene.lights) {
            ++lights;
            if (l.type != LightType::Spot)
                continue;
            auto dirs = spotSampleDirections(m_settings.vplCount, std::cos(l.outerConeAngle));
            if (!dirs)
                return makeError("scene '" + scene.name + "', spot '" + l.name + "': " + dirs.error().message);
        }
        if (lights > kMaxVplLights)
            return makeError("scene '" + scene.name + "': " + std::to_string(lights) +
                             " lights exceed the VPL technique's maximum of " + std::to_string(kMaxVplLights));
        m_lights = lights;
        // The emitters' surfels: one per emitter VPL (the emitter source has N VPLs like a light).
        if (auto ok = m_emissive.sceneChanged(ctx, scene, m_settings.vplCount); !ok)
            return ok.error();
        const VplLighting lighting = vplLighting(scene.lights, m_emissive.exists());
        const bool sunOrEmission = lighting == VplLighting::SunOrEmission;
        m_resolved = resolveVplSettings(m_settings, lighting);
        // The grid exists only while visibility or bounces need it (leave out what a scene does
        // not need).
        if (m_resolved.visibility != VplVisibilityMode::Off || m_resolved.bounces > 1)
            return m_voxels.sceneChanged(ctx, gpu, uploaded, m_resolved.visibilityGrid,
                                         scene.cameraOrDefault().position, sharedGridPlacement(m_resolved),
                                         /*halfVoxels=*/true, sunOrEmission ? kSharedGridSpan : kSharedGridLampSpan);
        m_voxels.reset(); // a new scene that needs no grid keeps none
        return {};
    }

    uint64_t persistentBytes() const override { return m_voxels.bytes() + m_emissive.bytes(); }

    IndirectOutputs addPasses(rg::RenderGraph& graph, const TechniqueInputs& inputs) override {
        if (!inputs.rsm && !m_emissive.exists()) {
            inputs.selection.leaveOut("vpl.*", LeftOutReason::NotNeeded, "no light and no emission in the scene");
            return {};
        }
        VplInputs in = vplInputs(inputs, inputs.rsm);
        if (in.spots.empty() && !m_emissive.exists()) {
            // No light with an RSM: nothing to bounce, so the technique adds no pass and no
            // indirect image; GiSystem then composites nothing (the frame is the direct image).
            inputs.selection.leaveOut("vpl.*", LeftOutReason::NotNeeded,
                                      "no light has shadow-atlas layers (past maxShadowLayers)");
            return {};
        }
        if (m_emissive.exists()) {
            EmissiveSurfelImages surfels = m_emissive.addPasses(graph, inputs.scene, "vpl");
            in.emitterPosition = surfels.position;
            in.emitterNormal = surfels.normal;
            in.emitterFlux = surfels.flux;
            in.emitterSurfels = m_emissive.count();
            in.emitterResolution = surfels.resolution;
        }
        VplSettings settings = m_resolved;
        if (m_voxels.exists()) {
            VoxelGridData grid =
                m_voxels.addPasses(graph, inputs.scene, inputs.selection.changes, inputs.frame.camera.position);
            in.occupancy = grid.albedo;
            in.faces = grid.faces;
            in.occupancyOriginSize = grid.params.originSize;
            in.occupancyResolution = grid.params.dims.x;
            if (grid.params.dims.z != 0)
                in.occupancyHalves = grid.normal; // the camera-centred grid's half-voxel bits (its alpha)
        } else {
            settings.visibility = VplVisibilityMode::Off; // no geometry, no grid: nothing can occlude
            settings.bounces = 1;        // nor reflect a bounced ray
        }
        auto out = m_technique->addPasses(graph, in, settings);
        VKGI_ASSERT(out.ok(), "VplTechniqueModule::addPasses: inputs were validated in sceneChanged");
        inputs.blackboard.add(*out);
        return {out->indirect, {}, {}, {}};
    }

private:
    std::unique_ptr<VplTechnique> m_technique;
    VplSettings m_settings; // as requested (automatic values unresolved)
    VplSettings m_resolved; // resolved for the current scene (resolveVplSettings)
    uint32_t m_lights = 0; // lights of the current scene
    SceneVoxelGrid m_voxels; // the visibility and bounce grid (vpl.visibility on or vpl.bounces > 1)
    EmissiveSurfels m_emissive; // the emitter VPLs' surfels (exists() only in scenes with emission)
};

} // namespace

VplLighting vplLighting(const std::vector<Light>& lights, bool emission) {
    const auto has = [&lights](LightType type) {
        return std::any_of(lights.begin(), lights.end(), [type](const Light& l) { return l.type == type; });
    };
    if (emission || has(LightType::Directional))
        return VplLighting::SunOrEmission;
    return has(LightType::Point) ? VplLighting::PointLights : VplLighting::Spots;
}

Result<std::unique_ptr<TechniqueModule>> createVplTechniqueModule(Context& ctx, const GiSettings& settings) {
    if (auto ok = validateVplSettings(settings.vpl); !ok)
        return ok.error();
    auto technique = VplTechnique::create(ctx);
    if (!technique)
        return technique.error();
    return std::unique_ptr<TechniqueModule>(new VplTechniqueModule(std::move(technique.value()), settings.vpl));
}

} // namespace vkgi::gi
