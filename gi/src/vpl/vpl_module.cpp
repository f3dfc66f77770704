// Technique::Vpl inside GiSystem: every light of the scene with RSM layers becomes a VplSpot
// (spotlights as in the paper; point lights as spots with the whole sphere for a cone;
// directional lights sample their orthographic RSM window).
#include "vpl/vpl_module.hpp"

#include <cmath>
#include <string>

#include "engine/vk_check.hpp"
#include "gi/vpl.hpp"

namespace vkgi::gi {

namespace {

class VplModule final : public TechniqueModule {
public:
    VplModule(std::unique_ptr<VplRenderer> renderer, const VplSettings& settings)
        : m_renderer(std::move(renderer)), m_settings(settings) {}

    // Without a light there is nothing to bounce: the light passes then leave the RSM out.
    bool needsRsm() const override { return m_lights > 0; }

    // Everything addPasses could reject is checked here, where errors can still be returned.
    Result<void> sceneChanged(Context&, const Scene& scene, const GpuScene&, bool) override {
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
        return {};
    }

    IndirectOutputs addPasses(rg::RenderGraph& graph, const TechniqueInputs& inputs) override {
        const FrameData& frame = inputs.frame;
        const GBufferData& gbuffer = inputs.gbuffer;
        const ShadowData& shadow = inputs.shadow;
        const RsmData* rsmData = inputs.rsm;
        if (!rsmData) {
            inputs.selection.leaveOut("vpl.*", LeftOutReason::NotNeeded, "no light in the scene");
            return {};
        }
        const RsmData& rsm = *rsmData;
        VplInputs in;
        in.gPosition = gbuffer.position;
        in.gNormal = gbuffer.normal;
        in.gAlbedo = gbuffer.albedo;
        in.width = frame.width;
        in.height = frame.height;
        in.camera = frame.camera;
        in.rsmPosition = rsm.position;
        in.rsmNormal = rsm.normal;
        in.rsmFlux = rsm.flux;
        in.shadowViews = shadow.views;
        const Scene& scene = *frame.scene;
        Aabb bounds = scene.bounds();
        in.sceneDiagonal = bounds.valid() ? glm::length(bounds.extent()) : 1.0f;
        for (uint32_t i = 0; i < scene.lights.size(); ++i) {
            const Light& l = scene.lights[i];
            // The light's layers in the atlas (a light past the atlas's layer limit has none and
            // gets no VPLs, as it gets no shadow).
            uint32_t first = ~0u, count = 0;
            for (uint32_t k = 0; k < rsm.layers.size(); ++k)
                if (rsm.layers[k].light == i) {
                    first = std::min(first, k);
                    ++count;
                }
            if (count == 0)
                continue;
            switch (l.type) {
            case LightType::Spot:
                in.spots.push_back({l.position, glm::normalize(l.direction), std::cos(l.outerConeAngle), first, count});
                break;
            case LightType::Point: // a spot whose cone is the whole sphere, on the cube's six layers
                in.spots.push_back({l.position, glm::vec3(0.0f, -1.0f, 0.0f), -1.0f, first, count});
                break;
            case LightType::Directional: {
                VplSpot sun;
                sun.firstLayer = first;
                sun.layerCount = count;
                sun.directional = true;
                in.spots.push_back(sun);
                break;
            }
            }
        }
        if (in.spots.empty()) {
            // No light with an RSM: nothing to bounce, so the technique adds no pass and no
            // indirect image; GiSystem then composites nothing (the frame is the direct image).
            inputs.selection.leaveOut("vpl.*", LeftOutReason::NotNeeded,
                                      "no light has shadow-atlas layers (past maxShadowLayers)");
            return {};
        }
        auto out = m_renderer->addPasses(graph, in, m_settings);
        GI_ASSERT(out.ok(), "VplModule::addPasses: inputs were validated in sceneChanged");
        inputs.blackboard.add(*out);
        return {out->indirect, {}, {}, {}};
    }

private:
    std::unique_ptr<VplRenderer> m_renderer;
    VplSettings m_settings;
    uint32_t m_lights = 0; // lights of the current scene
};

} // namespace

Result<std::unique_ptr<TechniqueModule>> createVplModule(Context& ctx, const GiSettings& settings) {
    if (auto ok = validateVplSettings(settings.vpl); !ok)
        return ok.error();
    auto renderer = VplRenderer::create(ctx);
    if (!renderer)
        return renderer.error();
    return std::unique_ptr<TechniqueModule>(new VplModule(std::move(renderer.value()), settings.vpl));
}

} // namespace vkgi::gi
