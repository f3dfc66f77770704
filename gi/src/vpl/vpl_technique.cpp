// The VPL technique as render-graph passes: upload of the per-light tables, VPL generation
// from the RSM, the deferred gather over the G-buffer, negative VPLs, and the low-resolution
// gather with discontinuity refinement. All synchronisation comes from the declared accesses.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <utility>

#include "vkgi/context.hpp"
#include "vkgi/pipeline.hpp"
#include "vkgi/resources.hpp"
#include "vkgi/rg/compute_pass.hpp"
#include "gi/vpl.h"
#include "vkgi/vpl.hpp"
#include "vk_dispatch.hpp"

namespace vkgi::gi {

namespace {

constexpr VkFormat kRadianceFormat = VK_FORMAT_R32G32B32A32_SFLOAT; // 32F: 1e9 cd stays finite
// vkCmdUpdateBuffer moves at most 65536 bytes per call.
constexpr VkDeviceSize kUpdateChunk = 65536;
// The share of a large sun window's selection weights spread by flux alone, whatever the frame
// shows (vpl_select.comp): every lit candidate keeps a chance, and a VPL's flux is divided by at
// most 1 / (this share's probability), which bounds the heaviest VPL.
constexpr float kVplCandidateFloor = 0.1f;

ImageDesc radianceImage(uint32_t width, uint32_t height) {
    ImageDesc d;
    d.format = kRadianceFormat;
    d.width = width;
    d.height = height;
    d.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    return d;
}

BufferDesc storageBuffer(VkDeviceSize bytes) {
    return {bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::GpuOnly};
}

void updateBuffer(VkCommandBuffer cmd, VkBuffer buffer, const void* data, VkDeviceSize bytes) {
    const auto* p = static_cast<const uint8_t*>(data);
    for (VkDeviceSize offset = 0; offset < bytes; offset += kUpdateChunk)
        vkCmdUpdateBuffer(cmd, buffer, offset, std::min(kUpdateChunk, bytes - offset), p + offset);
}

// What the generation pass reads per light: one VplLight each, and the local Halton directions
// (or window points, or the emitter source's surfel indices) of all sources, subset-major.
struct LightTables {
    std::vector<gpu::VplLight> lights;
    std::vector<glm::vec4> directions;
    uint32_t sources = 0; // generation-0 sources: the lights, then the emitters when the scene emits
    // Large sun windows with VplSettings::candidates > 0 (docs/vpl.md, "Candidates weighted by
    // the image"): per such sun `candidatesPerSun` entries of focusedWindowPoints (xy NDC, z area,
    // w the light's index), subset-major, and their world-fixed ids; vpl.select fills the sun's
    // slots from them.
    std::vector<glm::vec4> candidates;
    std::vector<uint32_t> candidateIds;
    uint32_t candidatesPerSun = 0;
};

struct LightTableHandles {
    rg::BufferHandle lights;
    rg::BufferHandle directions;
    rg::BufferHandle candidates;   // only with candidates
    rg::BufferHandle candidateIds;
};

// The gather's images at the gather resolution.
struct GatherImages {
    rg::ImageHandle indirect; // indirect radiance albedo/pi * E
    rg::ImageHandle incident; // VPL irradiance E
    rg::ImageHandle travel;   // luminance-weighted sum of the directions the light travels in
    rg::ImageHandle surface;  // interleaved: each pixel's packed surface (gi/vpl_surface.h)
};

Result<void> checkInputs(const VplInputs& in, const VplSettings& settings) {
    if (auto ok = validateVplSettings(settings); !ok)
        return ok.error();
    if (in.width == 0 || in.height == 0 || in.width > 65535 || in.height > 65535)
        return makeError("VplTechnique: image size " + std::to_string(in.width) + "x" + std::to_string(in.height) +
                         " is outside 1..65535 (refine list packs 16-bit coordinates)");
    if (in.emitterSurfels > 0 && (!in.emitterPosition.valid() || !in.emitterNormal.valid() ||
                                  !in.emitterFlux.valid() || in.emitterResolution == 0 ||
                                  uint64_t(in.emitterResolution) * in.emitterResolution < in.emitterSurfels))
        return makeError("VplTechnique: " + std::to_string(in.emitterSurfels) +
                         " emitter surfels but no surfel images large enough to hold them");
    if (in.spots.size() > kMaxVplLights)
        return makeError("VplTechnique: " + std::to_string(in.spots.size()) + " lights exceed the maximum " +
                         std::to_string(kMaxVplLights));
    if (settings.visibility != VplVisibilityMode::Off && (!in.occupancy.valid() || in.occupancyResolution == 0 || !(in.occupancyOriginSize.w > 0.0f)))
        return makeError("VplTechnique: visibility is on but the inputs carry no occupancy volume");
    if (settings.bounces > 1 && (!in.occupancy.valid() || !in.faces.valid() || in.occupancyResolution == 0 ||
                                 !(in.occupancyOriginSize.w > 0.0f)))
        return makeError("VplTechnique: bounces " + std::to_string(settings.bounces) +
                         " need the voxel grid's albedo and faces volumes, which the inputs do not carry");
    for (const VplSpot& spot : in.spots) {
        if (spot.layerCount != 1 && spot.layerCount != 6)
            return makeError("VplTechnique: a light's RSM layer count must be 1 or 6, got " +
                             std::to_string(spot.layerCount));
        if (spot.directional && spot.layerCount != 1)
            return makeError("VplTechnique: a directional light has one orthographic RSM layer, got " +
                             std::to_string(spot.layerCount));
    }
    return {};
}

// Documented fall-back: no spotlight, no VPL light. One clear keeps the output defined.
VplOutputs addClearPass(rg::RenderGraph& graph, uint32_t width, uint32_t height) {
    rg::ImageHandle indirect = graph.createImage("vpl.indirect", radianceImage(width, height));
    graph.addPass(
        "vpl.no_spot_clear", [&](rg::PassBuilder& b) { indirect = b.write(indirect, rg::Access::TransferWrite); },
        [indirect](rg::PassContext& pc) {
            VkClearColorValue zero{};
            VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
            vkCmdClearColorImage(pc.cmd(), pc.image(indirect).image, pc.layout(indirect), &zero, 1, &range);
        });
    VplOutputs out;
    out.indirect = indirect;
    return out;
}

LightTableHandles addUploadPass(rg::RenderGraph& graph, LightTables tables) {
    LightTableHandles handles;
    handles.lights = graph.createBuffer("vpl.lights", storageBuffer(tables.lights.size() * sizeof(gpu::VplLight)));
    handles.directions =
        graph.createBuffer("vpl.directions", storageBuffer(tables.directions.size() * sizeof(glm::vec4)));
    if (!tables.candidates.empty()) {
        handles.candidates =
            graph.createBuffer("vpl.candidate_table", storageBuffer(tables.candidates.size() * sizeof(glm::vec4)));
        handles.candidateIds =
            graph.createBuffer("vpl.candidate_ids", storageBuffer(tables.candidateIds.size() * sizeof(uint32_t)));
    }
    struct UploadData {
        LightTables tables;
        LightTableHandles handles;
    };
    graph.addPass<UploadData>(
        "vpl.upload",
        [&](rg::PassBuilder& b, UploadData& d) {
            d.tables = std::move(tables);
            handles.lights = b.write(handles.lights, rg::Access::TransferWrite);
            handles.directions = b.write(handles.directions, rg::Access::TransferWrite);
            if (handles.candidates.valid()) {
                handles.candidates = b.write(handles.candidates, rg::Access::TransferWrite);
                handles.candidateIds = b.write(handles.candidateIds, rg::Access::TransferWrite);
            }
            d.handles = handles;
        },
        [](const UploadData& d, rg::PassContext& pc) {
            updateBuffer(pc.cmd(), pc.buffer(d.handles.lights).buffer, d.tables.lights.data(),
                         d.tables.lights.size() * sizeof(gpu::VplLight));
            updateBuffer(pc.cmd(), pc.buffer(d.handles.directions).buffer, d.tables.directions.data(),
                         d.tables.directions.size() * sizeof(glm::vec4));
            if (d.handles.candidates.valid()) {
                updateBuffer(pc.cmd(), pc.buffer(d.handles.candidates).buffer, d.tables.candidates.data(),
                             d.tables.candidates.size() * sizeof(glm::vec4));
                updateBuffer(pc.cmd(), pc.buffer(d.handles.candidateIds).buffer, d.tables.candidateIds.data(),
                             d.tables.candidateIds.size() * sizeof(uint32_t));
            }
        });
    return handles;
}

// The refine list (gi/vpl_refine_list.h) with its header reset: no entry, and the refine pass's
// dispatch at 0 x 1 x 1 work groups (the entries are written before they are read).
rg::BufferHandle addRefineClearPass(rg::RenderGraph& graph, uint32_t width, uint32_t height) {
    const VkDeviceSize bytes = VPL_REFINE_LIST_HEADER_BYTES + VkDeviceSize(width) * height * sizeof(uint32_t);
    BufferDesc desc = storageBuffer(bytes);
    desc.usage |= VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;
    rg::BufferHandle list = graph.createBuffer("vpl.refine_list", desc);
    graph.addPass(
        "vpl.refine_clear", [&](rg::PassBuilder& b) { list = b.write(list, rg::Access::TransferWrite); },
        [list](rg::PassContext& pc) {
            const uint32_t header[4] = {0, 0, 1, 1};
            static_assert(sizeof(header) == VPL_REFINE_LIST_HEADER_BYTES);
            vkCmdUpdateBuffer(pc.cmd(), pc.buffer(list).buffer, 0, sizeof(header), header);
        });
    return list;
}

// The interleaved gather's dispatch: per axis, n sub-images of ceil(size / n) pixels, each a
// whole number of work groups (vpl_gather.comp derives pixel and subset from the group).
glm::uvec3 interleavedGrid(uint32_t width, uint32_t height, uint32_t n) {
    auto axis = [n](uint32_t size) {
        const uint32_t sub = (size + n - 1) / n;
        return n * ((sub + GI_VPL_LOCAL_SIZE_2D - 1) / GI_VPL_LOCAL_SIZE_2D) * GI_VPL_LOCAL_SIZE_2D;
    };
    return {axis(width), axis(height), 1};
}

// Push constants shared by the per-pixel passes. `sources` = lights x generations (gi/vpl.h).
gpu::VplPixelPush pixelPush(const VplInputs& in, const VplSettings& settings, uint32_t sources) {
    const uint32_t vplCount = sources * settings.vplCount;
    const uint32_t factor = settings.lowResFactor;
    const uint32_t lowResWidth = (in.width + factor - 1) / factor, lowResHeight = (in.height + factor - 1) / factor;
    gpu::VplPixelPush push{};
    push.size = glm::uvec4(lowResWidth, lowResHeight, factor, in.width * in.height);
    push.counts = glm::uvec4(vplCount, settings.negativeVplCount, in.width, in.height);
    push.camera = glm::vec4(in.camera.position, 0.0f);
    push.params = glm::vec4(settings.clampDistance * settings.clampDistance, settings.refineThreshold, settings.interleaveTolerance,
                            settings.negativeVplCount > 0 ? 1.0f : 0.0f);
    // With the half-voxel bits the visibility march sees a grid of twice the resolution
    // (gi/vpl_visibility.h).
    const uint32_t halves = in.occupancyHalves.valid() ? 2u : 1u;
    push.interleave = glm::uvec4(settings.interleave, sources, settings.vplCount,
                                 settings.visibility != VplVisibilityMode::Off ? halves * in.occupancyResolution : 0u);
    push.grid = settings.visibility != VplVisibilityMode::Off
                    ? glm::vec4(glm::vec3(in.occupancyOriginSize), in.occupancyOriginSize.w / float(halves))
                    : glm::vec4(0.0f);
    return push;
}

} // namespace

struct VplTechnique::Impl {
    Context& ctx;
    Pipeline generate, importance, importanceVisible, select, emitter, bounce, visibilityMap, gather, gatherVisible,
        gatherMaps, interleaveRows, interleaveColumns, negativeGenerate, negativeGather, upsample, refine, refineVisible, refineMaps;
    VkSampler pointSampler = VK_NULL_HANDLE; // texelFetch-only, but sampled bindings need one
    // Halton directions per (count, cosOuter bits): the CPU search is the only costly CPU step.
    std::map<std::pair<uint32_t, uint32_t>, std::vector<glm::vec3>> directionCache;

    explicit Impl(Context& c) : ctx(c) {}
    Result<const std::vector<glm::vec3>*> directions(uint32_t count, float cosOuter);
    Result<LightTables> lightTables(const std::vector<VplSpot>& spots, bool emitters, const VplSettings& settings,
                                    const Camera& camera);

    void addGeneratePass(rg::RenderGraph& graph, const std::string& name, const VplInputs& in, rg::BufferHandle lights,
                         rg::BufferHandle directions, uint32_t lightCount, uint32_t vplCount, rg::BufferHandle& vpls);
    void addEmitterPass(rg::RenderGraph& graph, const VplInputs& in, const VplSettings& settings,
                        const LightTableHandles& tables, uint32_t source, uint32_t vplCount, bool first,
                        rg::BufferHandle& vpls);
    rg::BufferHandle addSelectPasses(rg::RenderGraph& graph, const VplInputs& in, const VplSettings& settings,
                                     LightTableHandles& tables, uint32_t candidatesPerSun, uint32_t suns,
                                     uint32_t lightCount, rg::BufferHandle& vpls);
    void addBouncePasses(rg::RenderGraph& graph, const VplInputs& in, const VplSettings& settings,
                         const LightTableHandles& tables, uint32_t lightCount, uint32_t vplCount,
                         rg::BufferHandle& vpls);
    rg::BufferHandle addVisibilityMapPass(rg::RenderGraph& graph, const VplInputs& in, uint32_t vplCount,
                                          rg::BufferHandle vpls);
    GatherImages addGatherPass(rg::RenderGraph& graph, const VplInputs& in, rg::BufferHandle vpls,
                               rg::BufferHandle visibilityMaps, const gpu::VplPixelPush& push, const char* indirectName);
    GatherImages addInterleaveFilterPasses(rg::RenderGraph& graph, const VplInputs& in,
                                           const GatherImages& gathered, rg::BufferHandle& refineList,
                                           const gpu::VplPixelPush& push, const char* indirectName);
    rg::BufferHandle addNegativeGeneratePass(rg::RenderGraph& graph, const VplInputs& in, const GatherImages& gathered,
                                             const gpu::VplPixelPush& pixel);
    rg::ImageHandle addNegativeGatherPass(rg::RenderGraph& graph, const VplInputs& in, rg::BufferHandle negativeVpls,
                                          rg::ImageHandle positiveIndirect, const gpu::VplPixelPush& push,
                                          const char* indirectName);
    rg::ImageHandle addUpsamplePass(rg::RenderGraph& graph, const VplInputs& in, rg::ImageHandle lowResIndirect,
                                    rg::BufferHandle& refineList, const gpu::VplPixelPush& push);
    void addRefinePass(rg::RenderGraph& graph, const VplInputs& in, rg::BufferHandle vpls,
                       rg::BufferHandle visibilityMaps, rg::BufferHandle negativeVpls, rg::BufferHandle refineList,
                       rg::ImageHandle& indirect, const gpu::VplPixelPush& push);
};

Result<const std::vector<glm::vec3>*> VplTechnique::Impl::directions(uint32_t count, float cosOuter) {
    uint32_t bits;
    std::memcpy(&bits, &cosOuter, sizeof(bits));
    auto key = std::make_pair(count, bits);
    auto it = directionCache.find(key);
    if (it == directionCache.end()) {
        auto found = spotSampleDirections(count, cosOuter);
        if (!found)
            return found.error();
        if (directionCache.size() > 64) // settings sweeps: keep the cache bounded
            directionCache.clear();
        it = directionCache.emplace(key, std::move(found.value())).first;
    }
    return &it->second;
}

Result<LightTables> VplTechnique::Impl::lightTables(const std::vector<VplSpot>& spots, bool emitters,
                                                    const VplSettings& settings, const Camera& camera) {
    const uint32_t vplCount = settings.vplCount, interleave = settings.interleave;
    const uint32_t lightCount = uint32_t(spots.size()) + (emitters ? 1u : 0u);
    LightTables tables;
    std::vector<std::vector<glm::vec3>> samples; // per light, in Halton order
    // Per light, which bounce ray each sample's children take (empty: the sample's own index).
    std::vector<std::vector<uint32_t>> rayIds(spots.size() + (emitters ? 1u : 0u));
    for (uint32_t l = 0; l < spots.size(); ++l) {
        const VplSpot& spot = spots[l];
        gpu::VplLight light{};
        light.info = glm::uvec4(0, vplCount, spot.firstLayer, spot.layerCount);
        if (spot.directional) {
            // Halton points of the orthographic window; each VPL stands for 1/N of its area
            // (the shader turns that into flux with the layer's texel area, vpl_generate.comp).
            light.position = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f / float(vplCount));
            // A window much larger than the focus radius: points fixed to the world, denser
            // around the camera, each with the area it stands for. A camera that moves changes
            // only the few that cross a ring; points that followed the camera would all move
            // every frame and the image would shimmer.
            if (windowIsFocused(spot.window, settings.focusRadius) && settings.candidates > 0) {
                // Candidates: the same lattices, `candidates` times denser; vpl.select draws the
                // sun's N VPLs from them by their contribution to the frame. Until then its
                // slots hold points beyond the window (empty VPLs).
                const uint32_t m = vplCount * settings.candidates;
                FocusedWindowSamples focused = focusedWindowPoints(spot.window, camera.position, settings.focusRadius,
                                                                   m, interleave * interleave);
                for (uint32_t k = 0; k < m; ++k)
                    tables.candidates.emplace_back(focused.samples[k], float(l));
                tables.candidateIds.insert(tables.candidateIds.end(), focused.ids.begin(), focused.ids.end());
                tables.candidatesPerSun = m;
                samples.emplace_back(vplCount, glm::vec3(2.0f, 2.0f, 1.0f));
            } else if (windowIsFocused(spot.window, settings.focusRadius)) {
                FocusedWindowSamples focused = focusedWindowPoints(spot.window, camera.position,
                                                                   settings.focusRadius, vplCount, interleave * interleave);
                samples.push_back(std::move(focused.samples));
                rayIds[l] = std::move(focused.ids);
            } else {
                samples.push_back(windowSamplePoints(vplCount));
            }
        } else {
            auto local = directions(vplCount, spot.cosOuter);
            if (!local)
                return local.error();
            glm::mat3 frame = spotFrame(spot.direction);
            light.position = glm::vec4(spot.position, coneSolidAngle(spot.cosOuter) / float(vplCount));
            light.axisX = glm::vec4(frame[0], 0.0f);
            light.axisY = glm::vec4(frame[1], 0.0f);
            light.axisZ = glm::vec4(frame[2], 0.0f);
            samples.push_back(**local);
        }
        tables.lights.push_back(light);
    }
    // The emitters: one more source, whose N entries name the surfel each VPL takes
    // (vpl_emitter.comp). It needs no VplLight; an emission-only scene still binds a table of one.
    if (emitters)
        samples.push_back(emitterSampleOrder(vplCount));
    if (tables.lights.empty())
        tables.lights.push_back(gpu::VplLight{});
    tables.sources = lightCount;
    // Each bounced generation g >= 1 is L more sources g L + l, whose entries hold the local
    // cosine-lobe directions of the rays their parents trace (vpl_bounce.comp).
    for (uint32_t g = 1; g < settings.bounces; ++g) {
        std::vector<glm::vec3> rays = bounceSampleDirections(vplCount, g);
        for (uint32_t l = 0; l < lightCount; ++l) {
            if (rayIds[l].empty()) {
                samples.push_back(rays);
                continue;
            }
            std::vector<glm::vec3> own(vplCount);
            for (uint32_t k = 0; k < vplCount; ++k)
                own[k] = rays[rayIds[l][k] % vplCount];
            samples.push_back(std::move(own));
        }
    }
    // Subset-major order (gi/vpl.h): subset s holds each source's block of Halton samples
    // [s N / n^2, (s + 1) N / n^2). With interleave 1 this is source after source.
    const uint32_t subsets = interleave * interleave;
    for (uint32_t s = 0; s < subsets; ++s)
        for (uint32_t l = 0; l < samples.size(); ++l)
            for (uint32_t k = s * vplCount / subsets; k < (s + 1) * vplCount / subsets; ++k)
                tables.directions.emplace_back(samples[l][k], float(l));
    return tables;
}

// vpl_generate.comp: `vplCount` VPL records from the RSM along the generation table `directions`
// (the VPLs themselves, "vpl.generate", or a large sun window's candidates, "vpl.candidates").
void VplTechnique::Impl::addGeneratePass(rg::RenderGraph& graph, const std::string& name, const VplInputs& in,
                                         rg::BufferHandle lights, rg::BufferHandle directions, uint32_t lightCount,
                                         uint32_t vplCount, rg::BufferHandle& vpls) {
    gpu::VplGeneratePush push{};
    push.info = glm::uvec4(lightCount, vplCount, 0, 0);
    rg::ComputePass(graph, name, generate)
        .push(push)
        .sample(VPL_GENERATE_BINDING_RSM_POSITION, in.rsmPosition, pointSampler)
        .sample(VPL_GENERATE_BINDING_RSM_NORMAL, in.rsmNormal, pointSampler)
        .sample(VPL_GENERATE_BINDING_RSM_FLUX, in.rsmFlux, pointSampler)
        .read(VPL_GENERATE_BINDING_SHADOW_VIEWS, in.shadowViews)
        .read(VPL_GENERATE_BINDING_LIGHTS, lights)
        .read(VPL_GENERATE_BINDING_DIRECTIONS, directions)
        .overwrite(VPL_GENERATE_BINDING_VPLS, vpls)
        .dispatch({vplCount, 1, 1});
}

// Large sun windows' candidates (docs/vpl.md, "Candidates weighted by the image"): their VPL
// records (vpl_generate.comp over the candidate table), their estimated contribution to the
// frame (vpl_importance.comp, through the visibility grid when there is one), and the sun's N
// VPLs drawn from them by priority sampling (vpl_select.comp), which also writes the bounce rays
// of their children into the generation table.
rg::BufferHandle VplTechnique::Impl::addSelectPasses(rg::RenderGraph& graph, const VplInputs& in,
                                                     const VplSettings& settings, LightTableHandles& tables,
                                                     uint32_t candidatesPerSun, uint32_t suns, uint32_t lightCount,
                                                     rg::BufferHandle& vpls) {
    const uint32_t total = candidatesPerSun * suns;
    rg::BufferHandle candidates =
        graph.createBuffer("vpl.candidates", storageBuffer(VkDeviceSize(total) * sizeof(gpu::VplRecord)));
    addGeneratePass(graph, "vpl.candidates", in, tables.lights, tables.candidates, lightCount, total, candidates);

    rg::BufferHandle weights =
        graph.createBuffer("vpl.candidate_weights", storageBuffer(VkDeviceSize(total) * sizeof(float)));
    const bool visible = settings.visibility != VplVisibilityMode::Off && in.occupancy.valid();
    gpu::VplImportancePush importancePush{};
    importancePush.info = glm::uvec4(total, GI_VPL_IMPORTANCE_PIXELS, in.width, in.height);
    importancePush.params = glm::vec4(settings.clampDistance * settings.clampDistance, 0.0f, 0.0f, 0.0f);
    if (visible) {
        const uint32_t halves = in.occupancyHalves.valid() ? 2u : 1u;
        importancePush.interleave = glm::uvec4(0u, 0u, 0u, halves * in.occupancyResolution);
        importancePush.grid = glm::vec4(glm::vec3(in.occupancyOriginSize), in.occupancyOriginSize.w / float(halves));
    }
    rg::ComputePass importancePass(graph, "vpl.importance", visible ? importanceVisible : importance);
    importancePass.push(importancePush)
        .sample(VPL_IMPORTANCE_BINDING_POSITION, in.gPosition, pointSampler)
        .sample(VPL_IMPORTANCE_BINDING_NORMAL, in.gNormal, pointSampler)
        .sample(VPL_IMPORTANCE_BINDING_ALBEDO, in.gAlbedo, pointSampler)
        .read(VPL_IMPORTANCE_BINDING_CANDIDATES, candidates)
        .overwrite(VPL_IMPORTANCE_BINDING_WEIGHTS, weights);
    if (visible)
        importancePass.sample(VPL_IMPORTANCE_BINDING_OCCUPANCY,
                              in.occupancyHalves.valid() ? in.occupancyHalves : in.occupancy, pointSampler);
    importancePass.dispatch({total, 1, 1});

    gpu::VplSelectPush selectPush{};
    selectPush.info = glm::uvec4(candidatesPerSun, settings.vplCount, settings.interleave, lightCount);
    selectPush.shape = glm::uvec4(lightCount * settings.bounces, settings.bounces, 0u, 0u);
    selectPush.params = glm::vec4(kVplCandidateFloor, 0.0f, 0.0f, 0.0f);
    rg::ComputePass(graph, "vpl.select", select)
        .push(selectPush)
        .read(VPL_SELECT_BINDING_TABLE, tables.candidates)
        .read(VPL_SELECT_BINDING_IDS, tables.candidateIds)
        .read(VPL_SELECT_BINDING_CANDIDATES, candidates)
        .read(VPL_SELECT_BINDING_WEIGHTS, weights)
        .write(VPL_SELECT_BINDING_VPLS, vpls)
        .write(VPL_SELECT_BINDING_DIRECTIONS, tables.directions)
        .dispatch({suns * GI_VPL_SELECT_LOCAL_SIZE, 1, 1});
    return candidates;
}

// The emitter source's VPLs on this frame's emissive surfels (vpl_emitter.comp): after
// vpl.generate, which leaves their slots empty, or as the buffer's first writer in a scene
// without punctual lights.
void VplTechnique::Impl::addEmitterPass(rg::RenderGraph& graph, const VplInputs& in, const VplSettings& settings,
                                        const LightTableHandles& tables, uint32_t source, uint32_t vplCount,
                                        bool first, rg::BufferHandle& vpls) {
    gpu::VplEmitterPush push{};
    push.info = glm::uvec4(source, vplCount, first ? 1u : 0u, 0u);
    push.surfels = glm::uvec4(in.emitterSurfels, in.emitterResolution, 0u, 0u);
    push.scale = glm::vec4(float(in.emitterSurfels) / float(settings.vplCount), 0.0f, 0.0f, 0.0f);
    rg::ComputePass pass(graph, "vpl.emitter", emitter);
    pass.push(push)
        .sample(VPL_EMITTER_BINDING_POSITION, in.emitterPosition, pointSampler)
        .sample(VPL_EMITTER_BINDING_NORMAL, in.emitterNormal, pointSampler)
        .sample(VPL_EMITTER_BINDING_FLUX, in.emitterFlux, pointSampler)
        .read(VPL_EMITTER_BINDING_DIRECTIONS, tables.directions);
    if (first)
        pass.overwrite(VPL_EMITTER_BINDING_VPLS, vpls);
    else
        pass.write(VPL_EMITTER_BINDING_VPLS, vpls);
    pass.dispatch({vplCount, 1, 1});
}

// One pass per bounced generation: each VPL of generation g - 1 traces its ray and writes its
// child of generation g (vpl_bounce.comp); the graph orders them and derives the barriers.
void VplTechnique::Impl::addBouncePasses(rg::RenderGraph& graph, const VplInputs& in, const VplSettings& settings,
                                         const LightTableHandles& tables, uint32_t lightCount, uint32_t vplCount,
                                         rg::BufferHandle& vpls) {
    for (uint32_t g = 1; g < settings.bounces; ++g) {
        gpu::VplBouncePush push{};
        push.info = glm::uvec4(vplCount, lightCount, g, settings.interleave);
        // With the half-voxel bits the rays walk half voxels, as the visibility march does.
        const uint32_t halves = in.occupancyHalves.valid() ? 2u : 1u;
        push.grid = glm::uvec4(settings.vplCount, halves * in.occupancyResolution, lightCount * settings.bounces, 0);
        push.origin = glm::vec4(glm::vec3(in.occupancyOriginSize), in.occupancyOriginSize.w / float(halves));
        const std::string name = "vpl.bounce[" + std::to_string(g) + "]";
        rg::ComputePass(graph, name.c_str(), bounce)
            .push(push)
            .read(VPL_BOUNCE_BINDING_DIRECTIONS, tables.directions)
            .sample(VPL_BOUNCE_BINDING_ALBEDO, in.occupancy, pointSampler)
            .sample(VPL_BOUNCE_BINDING_HALVES, in.occupancyHalves.valid() ? in.occupancyHalves : in.occupancy,
                    pointSampler)
            .read(VPL_BOUNCE_BINDING_FACES, in.faces)
            .write(VPL_BOUNCE_BINDING_VPLS, vpls)
            .dispatch({vplCount, 1, 1});
    }
}

// With visibility: every VPL's visibility map (gi/vpl_visibility.h), once all generations are
// written; the gather and refine passes look their VPLs' light up in it.
rg::BufferHandle VplTechnique::Impl::addVisibilityMapPass(rg::RenderGraph& graph, const VplInputs& in,
                                                          uint32_t vplCount, rg::BufferHandle vpls) {
    const uint32_t texels = GI_VPL_VISIBILITY_MAP_SIDE * GI_VPL_VISIBILITY_MAP_SIDE;
    rg::BufferHandle maps =
        graph.createBuffer("vpl.visibility_maps", storageBuffer(VkDeviceSize(vplCount) * texels * sizeof(float)));
    gpu::VplBouncePush push{};
    push.info = glm::uvec4(vplCount, 0, 0, 0);
    // With the half-voxel bits the rays walk half voxels, as the bounce rays do.
    const uint32_t halves = in.occupancyHalves.valid() ? 2u : 1u;
    push.grid = glm::uvec4(0, halves * in.occupancyResolution, 0, 0);
    push.origin = glm::vec4(glm::vec3(in.occupancyOriginSize), in.occupancyOriginSize.w / float(halves));
    rg::ComputePass(graph, "vpl.visibility_maps", visibilityMap)
        .push(push)
        .read(VPL_VISIBILITY_MAP_BINDING_VPLS, vpls)
        .sample(VPL_VISIBILITY_MAP_BINDING_ALBEDO, in.occupancy, pointSampler)
        .sample(VPL_VISIBILITY_MAP_BINDING_HALVES, in.occupancyHalves.valid() ? in.occupancyHalves : in.occupancy,
                pointSampler)
        .overwrite(VPL_VISIBILITY_MAP_BINDING_MAP, maps)
        .dispatch({vplCount * texels, 1, 1});
    return maps;
}

GatherImages VplTechnique::Impl::addGatherPass(rg::RenderGraph& graph, const VplInputs& in, rg::BufferHandle vpls,
                                               rg::BufferHandle visibilityMaps, const gpu::VplPixelPush& push,
                                               const char* indirectName) {
    const uint32_t width = push.size.x, height = push.size.y;
    GatherImages out;
    out.indirect = graph.createImage(indirectName, radianceImage(width, height));
    out.incident = graph.createImage("vpl.incident", radianceImage(width, height));
    out.travel = graph.createImage("vpl.travel", radianceImage(width, height));
    ImageDesc surface = radianceImage(width, height);
    surface.format = VK_FORMAT_R32G32B32A32_UINT;
    out.surface = graph.createImage("vpl.surface", surface);
    rg::ComputePass pass(graph, "vpl.gather", visibilityMaps.valid() ? gatherMaps : push.interleave.w > 0 ? gatherVisible : gather);
    pass.push(push)
        .sample(VPL_GATHER_BINDING_POSITION, in.gPosition, pointSampler)
        .sample(VPL_GATHER_BINDING_NORMAL, in.gNormal, pointSampler)
        .sample(VPL_GATHER_BINDING_ALBEDO, in.gAlbedo, pointSampler)
        .read(VPL_GATHER_BINDING_VPLS, vpls)
        .overwrite(VPL_GATHER_BINDING_INDIRECT, out.indirect)
        .overwrite(VPL_GATHER_BINDING_INCIDENT, out.incident)
        .overwrite(VPL_GATHER_BINDING_TRAVEL, out.travel)
        .overwrite(VPL_GATHER_BINDING_SURFACE, out.surface);
    if (visibilityMaps.valid())
        pass.read(VPL_GATHER_BINDING_VISIBILITY_MAP, visibilityMaps);
    else if (push.interleave.w > 0)
        pass.sample(VPL_GATHER_BINDING_OCCUPANCY, in.occupancyHalves.valid() ? in.occupancyHalves : in.occupancy,
                    pointSampler);
    pass.dispatch(interleavedGrid(width, height, push.interleave.x));
    return out;
}

GatherImages VplTechnique::Impl::addInterleaveFilterPasses(rg::RenderGraph& graph, const VplInputs& in,
                                                           const GatherImages& gathered, rg::BufferHandle& refineList,
                                                           const gpu::VplPixelPush& push, const char* indirectName) {
    const uint32_t width = push.size.x, height = push.size.y;
    rg::ImageHandle rowsIncident = graph.createImage("vpl.rows_incident", radianceImage(width, height));
    rg::ImageHandle rowsTravel = graph.createImage("vpl.rows_travel", radianceImage(width, height));
    rg::ComputePass(graph, "vpl.interleave_rows", interleaveRows)
        .push(push)
        .sample(VPL_INTERLEAVE_ROWS_BINDING_SURFACE, gathered.surface, pointSampler)
        .sample(VPL_INTERLEAVE_ROWS_BINDING_GATHER_INCIDENT, gathered.incident, pointSampler)
        .sample(VPL_INTERLEAVE_ROWS_BINDING_GATHER_TRAVEL, gathered.travel, pointSampler)
        .overwrite(VPL_INTERLEAVE_ROWS_BINDING_INCIDENT, rowsIncident)
        .overwrite(VPL_INTERLEAVE_ROWS_BINDING_TRAVEL, rowsTravel)
        .dispatch({width, height, 1});
    GatherImages out;
    out.indirect = graph.createImage(indirectName, radianceImage(width, height));
    out.incident = graph.createImage("vpl.filtered_incident", radianceImage(width, height));
    out.travel = graph.createImage("vpl.filtered_travel", radianceImage(width, height));
    rg::ComputePass(graph, "vpl.interleave_columns", interleaveColumns)
        .push(push)
        .sample(VPL_INTERLEAVE_COLUMNS_BINDING_SURFACE, gathered.surface, pointSampler)
        .sample(VPL_INTERLEAVE_COLUMNS_BINDING_ALBEDO, in.gAlbedo, pointSampler)
        .sample(VPL_INTERLEAVE_COLUMNS_BINDING_ROWS_INCIDENT, rowsIncident, pointSampler)
        .sample(VPL_INTERLEAVE_COLUMNS_BINDING_ROWS_TRAVEL, rowsTravel, pointSampler)
        .overwrite(VPL_INTERLEAVE_COLUMNS_BINDING_INDIRECT, out.indirect)
        .overwrite(VPL_INTERLEAVE_COLUMNS_BINDING_INCIDENT, out.incident)
        .overwrite(VPL_INTERLEAVE_COLUMNS_BINDING_TRAVEL, out.travel)
        .write(VPL_INTERLEAVE_COLUMNS_BINDING_REFINE_LIST, refineList)
        .dispatch({width, height, 1});
    return out;
}

rg::BufferHandle VplTechnique::Impl::addNegativeGeneratePass(rg::RenderGraph& graph, const VplInputs& in,
                                                             const GatherImages& gathered,
                                                             const gpu::VplPixelPush& pixel) {
    const uint32_t count = pixel.counts.y;
    rg::BufferHandle negativeVpls =
        graph.createBuffer("vpl.negative_vpls", storageBuffer(VkDeviceSize(count) * sizeof(gpu::VplRecord)));
    gpu::VplGeneratePush push{};
    push.info = glm::uvec4(count, count, pixel.size.z, 0);
    push.size = glm::uvec4(pixel.size.x, pixel.size.y, in.width, in.height);
    push.camera = glm::vec4(in.camera.position, std::tan(0.5f * in.camera.yfov));
    rg::ComputePass(graph, "vpl.negative_generate", negativeGenerate)
        .push(push)
        .sample(VPL_NEGATIVE_GENERATE_BINDING_POSITION, in.gPosition, pointSampler)
        .sample(VPL_NEGATIVE_GENERATE_BINDING_NORMAL, in.gNormal, pointSampler)
        .sample(VPL_NEGATIVE_GENERATE_BINDING_INCIDENT, gathered.incident, pointSampler)
        .sample(VPL_NEGATIVE_GENERATE_BINDING_TRAVEL, gathered.travel, pointSampler)
        .overwrite(VPL_NEGATIVE_GENERATE_BINDING_NEGATIVE_VPLS, negativeVpls)
        .dispatch({count, 1, 1});
    return negativeVpls;
}

rg::ImageHandle VplTechnique::Impl::addNegativeGatherPass(rg::RenderGraph& graph, const VplInputs& in,
                                                          rg::BufferHandle negativeVpls,
                                                          rg::ImageHandle positiveIndirect,
                                                          const gpu::VplPixelPush& push, const char* indirectName) {
    const uint32_t width = push.size.x, height = push.size.y;
    rg::ImageHandle indirect = graph.createImage(indirectName, radianceImage(width, height));
    rg::ComputePass(graph, "vpl.negative_gather", negativeGather)
        .push(push)
        .sample(VPL_NEGATIVE_GATHER_BINDING_POSITION, in.gPosition, pointSampler)
        .sample(VPL_NEGATIVE_GATHER_BINDING_NORMAL, in.gNormal, pointSampler)
        .sample(VPL_NEGATIVE_GATHER_BINDING_ALBEDO, in.gAlbedo, pointSampler)
        .read(VPL_NEGATIVE_GATHER_BINDING_NEGATIVE_VPLS, negativeVpls)
        .sample(VPL_NEGATIVE_GATHER_BINDING_POSITIVE_INDIRECT, positiveIndirect, pointSampler)
        .overwrite(VPL_NEGATIVE_GATHER_BINDING_INDIRECT, indirect)
        .dispatch({width, height, 1});
    return indirect;
}

rg::ImageHandle VplTechnique::Impl::addUpsamplePass(rg::RenderGraph& graph, const VplInputs& in,
                                                    rg::ImageHandle lowResIndirect, rg::BufferHandle& refineList,
                                                    const gpu::VplPixelPush& push) {
    rg::ImageHandle indirect = graph.createImage("vpl.indirect", radianceImage(in.width, in.height));
    rg::ComputePass(graph, "vpl.upsample", upsample)
        .push(push)
        .sample(VPL_UPSAMPLE_BINDING_POSITION, in.gPosition, pointSampler)
        .sample(VPL_UPSAMPLE_BINDING_NORMAL, in.gNormal, pointSampler)
        .sample(VPL_UPSAMPLE_BINDING_LOW_RES_INDIRECT, lowResIndirect, pointSampler)
        .overwrite(VPL_UPSAMPLE_BINDING_INDIRECT, indirect)
        .write(VPL_UPSAMPLE_BINDING_REFINE_LIST, refineList)
        .dispatch({in.width, in.height, 1});
    return indirect;
}

void VplTechnique::Impl::addRefinePass(rg::RenderGraph& graph, const VplInputs& in, rg::BufferHandle vpls,
                                       rg::BufferHandle visibilityMaps, rg::BufferHandle negativeVpls,
                                       rg::BufferHandle refineList, rg::ImageHandle& indirect,
                                       const gpu::VplPixelPush& push) {
    rg::ComputePass pass(graph, "vpl.refine", visibilityMaps.valid() ? refineMaps : push.interleave.w > 0 ? refineVisible : refine);
    pass.push(push)
        .sample(VPL_REFINE_BINDING_POSITION, in.gPosition, pointSampler)
        .sample(VPL_REFINE_BINDING_NORMAL, in.gNormal, pointSampler)
        .sample(VPL_REFINE_BINDING_ALBEDO, in.gAlbedo, pointSampler)
        .read(VPL_REFINE_BINDING_VPLS, vpls)
        .read(VPL_REFINE_BINDING_NEGATIVE_VPLS, negativeVpls)
        .read(VPL_REFINE_BINDING_REFINE_LIST, refineList)
        .write(VPL_REFINE_BINDING_INDIRECT, indirect);
    if (visibilityMaps.valid())
        pass.read(VPL_REFINE_BINDING_VISIBILITY_MAP, visibilityMaps);
    else if (push.interleave.w > 0)
        pass.sample(VPL_REFINE_BINDING_OCCUPANCY, in.occupancyHalves.valid() ? in.occupancyHalves : in.occupancy,
                    pointSampler);
    pass.dispatchIndirect(refineList, sizeof(uint32_t)); // one thread per entry (the header's command)
}

VplTechnique::VplTechnique(std::unique_ptr<Impl> impl) : m(std::move(impl)) {}

VplTechnique::~VplTechnique() {
    Context& ctx = m->ctx;
    for (Pipeline* p : {&m->generate, &m->importance, &m->importanceVisible, &m->select, &m->emitter, &m->bounce, &m->visibilityMap, &m->gather, &m->interleaveRows, &m->interleaveColumns, &m->negativeGenerate,
                        &m->negativeGather, &m->upsample, &m->refine, &m->gatherVisible, &m->refineVisible, &m->gatherMaps,
                        &m->refineMaps})
        destroyPipeline(ctx, *p);
    if (m->pointSampler)
        vkDestroySampler(ctx.device(), m->pointSampler, nullptr);
}

Result<std::unique_ptr<VplTechnique>> VplTechnique::create(Context& ctx) {
    auto impl = std::make_unique<Impl>(ctx);
    std::unique_ptr<VplTechnique> technique(new VplTechnique(std::move(impl)));
    Impl& m = *technique->m;
    const std::pair<Pipeline*, const char*> shaders[] = {
        {&m.generate, "gi/vpl/vpl_generate.comp"},
        {&m.importance, "gi/vpl/vpl_importance.comp"},
        {&m.importanceVisible, "gi/vpl/vpl_importance_visible.comp"},
        {&m.select, "gi/vpl/vpl_select.comp"},
        {&m.emitter, "gi/vpl/vpl_emitter.comp"},
        {&m.bounce, "gi/vpl/vpl_bounce.comp"},
        {&m.visibilityMap, "gi/vpl/vpl_visibility_map.comp"},
        {&m.gather, "gi/vpl/vpl_gather.comp"},
        {&m.interleaveRows, "gi/vpl/vpl_interleave_rows.comp"},
        {&m.interleaveColumns, "gi/vpl/vpl_interleave_columns.comp"},
        {&m.negativeGenerate, "gi/vpl/vpl_negative_generate.comp"},
        {&m.negativeGather, "gi/vpl/vpl_negative_gather.comp"},
        {&m.upsample, "gi/vpl/vpl_upsample.comp"},
        {&m.refine, "gi/vpl/vpl_refine.comp"},
        {&m.gatherVisible, "gi/vpl/vpl_gather_visible.comp"},
        {&m.refineVisible, "gi/vpl/vpl_refine_visible.comp"},
        {&m.gatherMaps, "gi/vpl/vpl_gather_maps.comp"},
        {&m.refineMaps, "gi/vpl/vpl_refine_maps.comp"},
    };
    for (const auto& [pipeline, name] : shaders) {
        auto p = createComputePipeline(ctx, {name, {}});
        if (!p)
            return p.error();
        *pipeline = std::move(p.value());
    }
    SamplerDesc point;
    point.filter = VK_FILTER_NEAREST;
    point.mipmap = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    m.pointSampler = createSampler(ctx, point);
    return technique;
}

Result<VplOutputs> VplTechnique::addPasses(rg::RenderGraph& graph, const VplInputs& in, const VplSettings& requested) {
    if (auto ok = validateVplSettings(requested); !ok)
        return ok.error();
    const bool directional =
        std::any_of(in.spots.begin(), in.spots.end(), [](const VplSpot& spot) { return spot.directional; });
    // A point light is a spot whose cone is the whole sphere.
    const bool point = std::any_of(in.spots.begin(), in.spots.end(),
                                   [](const VplSpot& spot) { return !spot.directional && spot.cosOuter <= -1.0f; });
    VplSettings settings = resolveVplSettings(requested, directional || in.emitterSurfels > 0 ? VplLighting::SunOrEmission
                                                         : point ? VplLighting::PointLights
                                                                 : VplLighting::Spots);
    // Called without a voxel grid (the renderer's direct use), a lamp-lit scene's automatic
    // visibility maps fall back to the paper's setting, as a scene without geometry does in
    // VplTechniqueModule: no grid, nothing to occlude or reflect a ray.
    if (requested.visibility == VplVisibilityMode::Auto && settings.visibility == VplVisibilityMode::Maps &&
        !in.occupancy.valid()) {
        settings.visibility = VplVisibilityMode::Off;
        if (requested.bounces == 0)
            settings.bounces = 1;
    }
    if (auto ok = checkInputs(in, settings); !ok)
        return ok.error();
    const bool emitters = in.emitterSurfels > 0;
    if (in.spots.empty() && !emitters)
        return addClearPass(graph, in.width, in.height);
    auto tables = m->lightTables(in.spots, emitters, settings, in.camera);
    if (!tables)
        return tables.error();

    VplOutputs out;
    // Generation-0 sources: the spots, then the emitters (gi/vpl.h); the bounces and the
    // per-pixel passes count the emitters as one more light.
    const uint32_t spotCount = uint32_t(in.spots.size());
    const uint32_t lightCount = tables->sources;
    out.vplCount = uint32_t(tables->directions.size());
    const uint32_t candidatesPerSun = tables->candidatesPerSun;
    const uint32_t suns = candidatesPerSun > 0 ? uint32_t(tables->candidates.size()) / candidatesPerSun : 0u;
    LightTableHandles uploaded = addUploadPass(graph, std::move(tables.value()));
    out.vpls = graph.createBuffer("vpl.vpls", storageBuffer(VkDeviceSize(out.vplCount) * sizeof(gpu::VplRecord)));
    if (spotCount > 0)
        m->addGeneratePass(graph, "vpl.generate", in, uploaded.lights, uploaded.directions, spotCount, out.vplCount,
                           out.vpls);
    if (emitters)
        m->addEmitterPass(graph, in, settings, uploaded, spotCount, out.vplCount, spotCount == 0, out.vpls);
    if (suns > 0) {
        out.candidates =
            m->addSelectPasses(graph, in, settings, uploaded, candidatesPerSun, suns, lightCount, out.vpls);
        out.candidateCount = candidatesPerSun * suns;
    }
    if (settings.bounces > 1)
        m->addBouncePasses(graph, in, settings, uploaded, lightCount, out.vplCount, out.vpls);

    // Each step's image carries the output's name when it is the last to create one.
    const bool lowRes = settings.lowResFactor > 1;
    const bool negative = settings.negativeVplCount > 0;
    const bool interleaved = settings.interleave > 1;
    const gpu::VplPixelPush push = pixelPush(in, settings, lightCount * settings.bounces);
    // Pixels gathered again with every VPL: the upsample's discontinuities (low resolution) or
    // the pixels the interleave filter could not give every subset (full resolution).
    if (lowRes || interleaved)
        out.refineList = addRefineClearPass(graph, in.width, in.height);
    auto name = [](bool last, const char* intermediate) { return last ? "vpl.indirect" : intermediate; };
    // Only with vpl.visibility maps (invalid otherwise).
    const rg::BufferHandle visibilityMaps = settings.visibility == VplVisibilityMode::Maps
                                                ? m->addVisibilityMapPass(graph, in, out.vplCount, out.vpls)
                                                : rg::BufferHandle{};
    GatherImages gathered = m->addGatherPass(graph, in, out.vpls, visibilityMaps, push,
                                             name(!lowRes && !negative && !interleaved, "vpl.gather_indirect"));
    if (interleaved)
        gathered = m->addInterleaveFilterPasses(graph, in, gathered, out.refineList, push,
                                                name(!lowRes && !negative, "vpl.filtered_indirect"));
    rg::ImageHandle indirect = gathered.indirect;
    rg::BufferHandle negativeVpls = out.vpls; // bound (with count 0) when negative VPLs are off
    if (negative) {
        negativeVpls = m->addNegativeGeneratePass(graph, in, gathered, push);
        out.negativeVpls = negativeVpls;
        indirect = m->addNegativeGatherPass(graph, in, negativeVpls, gathered.indirect, push,
                                            name(!lowRes, "vpl.negative_indirect"));
    }
    if (lowRes)
        indirect = m->addUpsamplePass(graph, in, indirect, out.refineList, push);
    if (out.refineList.valid())
        m->addRefinePass(graph, in, out.vpls, visibilityMaps, negativeVpls, out.refineList, indirect, push);
    out.indirect = indirect;
    return out;
}

} // namespace vkgi::gi
