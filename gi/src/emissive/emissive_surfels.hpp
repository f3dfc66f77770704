#pragma once
// Emissive surfaces as light sources of the RSM-based techniques: a fixed number of surfels
// spread over the scene's emitting triangles by power, written each frame into images in the
// RSM's formats (gi/emissive.h) by `<prefix>.emissive.surfels`. The VPL technique places its
// emitter VPLs on them (docs/vpl.md, "Emitter VPLs"); the LPV places its emitter proxies on the
// same table's surfels, on the CPU (emitterPointSources; docs/lpv.md, "Emissive surfaces"). The table of which triangle, side and
// point each surfel takes is built on the CPU when the scene is set; the pass transforms the
// points and areas with this frame's instances, so moving emitters are followed.
#include <string>
#include <vector>

#include "vkgi/context.hpp"
#include "vkgi/frame_data.hpp"
#include "vkgi/pipeline.hpp"
#include "vkgi/rg/render_graph.hpp"
#include "vkgi/scene.hpp"
#include "direct/direct_passes.hpp"
#include "gi/emissive.h"

namespace vkgi::gi {

// The surfel table of `scene` (empty without emission): every emitting triangle side gets at
// least one surfel and the rest go by power (area x the emission's channel sum, largest
// remainders), each carrying 1 / (its side's count) of the side's flux, its points stratified
// over the triangle. With more sides than `count`, sides are picked systematically by power and
// every surfel carries count-th of the total power (weight = total / (count x side power)).
std::vector<gpu::GpuEmissiveSurfel> planEmissiveSurfels(const Scene& scene, uint32_t count);

// A Lambertian point source standing for part of the scene's emission: radiant intensity
// (flux / pi) max(0, normal.w), flux pi Le A w of the surfel it is placed on. The LPV renders an
// RSM for each (docs/lpv.md, "Emissive surfaces").
struct EmitterPointSource {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 0.0f, 1.0f}; // unit normal of the emitting side
    glm::vec3 flux{0.0f};
};

// One point source per surfel of planEmissiveSurfels(scene, count), placed where surfels.comp
// places that surfel with the scene's current instance transforms (empty without emission). With
// at most `count` emitting sides their fluxes sum to pi Le A over every side, per channel.
std::vector<EmitterPointSource> emitterPointSources(const Scene& scene, uint32_t count);

// The images (createRsmImages: 2D arrays, layer 0 used; gi/emissive.h) and their side.
struct EmissiveSurfelImages : RsmImages {
    uint32_t resolution = 0; // texels per side
};

class EmissiveSurfels {
public:
    EmissiveSurfels() = default;
    EmissiveSurfels(const EmissiveSurfels&) = delete;
    EmissiveSurfels& operator=(const EmissiveSurfels&) = delete;
    ~EmissiveSurfels() { reset(); }

    // Rebuilds the table of `count` surfels from the scene's emissive materials; without any,
    // exists() is false and nothing is allocated.
    Result<void> sceneChanged(Context& ctx, const Scene& scene, uint32_t count);
    bool exists() const { return m_count > 0; }
    uint32_t count() const { return m_count; }
    uint64_t bytes() const { return m_table.buffer.buffer ? m_table.buffer.alloc.size : 0; }

    // The surfels of this frame, as transients named `<prefix>.emissive.*`. Requires exists().
    EmissiveSurfelImages addPasses(rg::RenderGraph& graph, const SceneHandles& scene,
                                   const std::string& prefix = "gi");

    void reset();

private:
    Context* m_ctx = nullptr;
    Pipeline m_pipeline{};
    rg::PersistentBuffer m_table;
    uint32_t m_count = 0;
    uint32_t m_resolution = 0;
    std::vector<gpu::GpuEmissiveSurfel> m_plan; // what m_table holds
};

} // namespace vkgi::gi
