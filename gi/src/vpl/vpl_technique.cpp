// The VPL technique as render-graph passes: upload of the per-light tables, VPL generation
// from the RSM, the deferred gather over the G-buffer, negative VPLs, and the low-resolution
// gather with discontinuity refinement. All synchronisation comes from the declared accesses.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <utility>

#include "engine/context.hpp"
#include "engine/pipeline.hpp"
#include "engine/resources.hpp"
#include "engine/rg/compute_pass.hpp"
#include "gi/vpl.h"
#include "gi/vpl.hpp"

namespace vkgi::gi {

namespace {

constexpr VkFormat kRadianceFormat = VK_FORMAT_R32G32B32A32_SFLOAT; // 32F: 1e9 cd stays finite
// vkCmdUpdateBuffer moves at most 65536 bytes per call.
constexpr VkDeviceSize kUpdateChunk = 65536;

ImageDesc image2D(uint32_t w, uint32_t h) {
    ImageDesc d;
    d.format = kRadianceFormat;
    d.width = w;
    d.height = h;
    d.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    return d;
}

BufferDesc storageBuffer(VkDeviceSize bytes) {
    return {bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::GpuOnly};
}

void updateBuffer(VkCommandBuffer cmd, VkBuffer buffer, const void* data, VkDeviceSize bytes) {
    const auto* p = static_cast<const uint8_t*>(data);
    for (VkDeviceSize off = 0; off < bytes; off += kUpdateChunk)
        vkCmdUpdateBuffer(cmd, buffer, off, std::min(kUpdateChunk, bytes - off), p + off);
}

} // namespace

struct VplTechnique::Impl {
    Context& ctx;
    Pipeline generate, gather, negativeGenerate, negativeGather, upsample, refine;
    VkSampler pointSampler = VK_NULL_HANDLE; // texelFetch-only, but sampled bindings need one
    // Halton directions per (count, cosOuter bits): the CPU search is the only costly CPU step.
    std::map<std::pair<uint32_t, uint32_t>, std::vector<glm::vec3>> directionCache;

    explicit Impl(Context& c) : ctx(c) {}
    Result<const std::vector<glm::vec3>*> directions(uint32_t count, float cosOuter) {
        uint32_t bits;
        std::memcpy(&bits, &cosOuter, sizeof(bits));
        auto key = std::make_pair(count, bits);
        auto it = directionCache.find(key);
        if (it == directionCache.end()) {
            auto dirs = spotSampleDirections(count, cosOuter);
            if (!dirs)
                return dirs.error();
            if (directionCache.size() > 64) // settings sweeps: keep the cache bounded
                directionCache.clear();
            it = directionCache.emplace(key, std::move(dirs.value())).first;
        }
        return &it->second;
    }
};

VplTechnique::VplTechnique(std::unique_ptr<Impl> impl) : m(std::move(impl)) {}

VplTechnique::~VplTechnique() {
    Context& ctx = m->ctx;
    for (Pipeline* p : {&m->generate, &m->gather, &m->negativeGenerate, &m->negativeGather, &m->upsample, &m->refine})
        destroyPipeline(ctx, *p);
    if (m->pointSampler)
        vkDestroySampler(ctx.device(), m->pointSampler, nullptr);
}

Result<std::unique_ptr<VplTechnique>> VplTechnique::create(Context& ctx) {
    auto impl = std::make_unique<Impl>(ctx);
    std::unique_ptr<VplTechnique> r(new VplTechnique(std::move(impl)));
    const std::pair<Pipeline*, const char*> shaders[] = {
        {&r->m->generate, "gi/vpl/vpl_generate.comp"},
        {&r->m->gather, "gi/vpl/vpl_gather.comp"},
        {&r->m->negativeGenerate, "gi/vpl/vpl_negative_generate.comp"},
        {&r->m->negativeGather, "gi/vpl/vpl_negative_gather.comp"},
        {&r->m->upsample, "gi/vpl/vpl_upsample.comp"},
        {&r->m->refine, "gi/vpl/vpl_refine.comp"},
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
    r->m->pointSampler = createSampler(ctx, point);
    return r;
}

Result<VplOutputs> VplTechnique::addPasses(rg::RenderGraph& graph, const VplInputs& in, const VplSettings& s) {
    if (auto ok = validateVplSettings(s); !ok)
        return ok.error();
    if (in.width == 0 || in.height == 0 || in.width > 65535 || in.height > 65535)
        return makeError("VplTechnique: image size " + std::to_string(in.width) + "x" + std::to_string(in.height) +
                         " is outside 1..65535 (refine list packs 16-bit coordinates)");
    if (in.spots.size() > kMaxVplLights)
        return makeError("VplTechnique: " + std::to_string(in.spots.size()) + " lights exceed the maximum " +
                         std::to_string(kMaxVplLights));
    VplOutputs out;
    const ImageDesc fullDesc = image2D(in.width, in.height);

    if (in.spots.empty()) {
        // Documented fall-back: no spotlight, no VPL light. One clear keeps the output defined.
        struct ClearData {
            rg::ImageHandle indirect;
        };
        const auto& d = graph.addPass<ClearData>(
            "vpl.no_spot_clear",
            [&](rg::PassBuilder& b, ClearData& data) {
                data.indirect = b.write(b.create("vpl.indirect", fullDesc), rg::Access::TransferWrite);
            },
            [](const ClearData& data, rg::PassContext& pc) {
                VkClearColorValue zero{};
                VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
                vkCmdClearColorImage(pc.cmd(), pc.image(data.indirect).image, pc.layout(data.indirect), &zero, 1,
                                     &range);
            });
        out.indirect = d.indirect;
        return out;
    }

    // Per-light table and the concatenated local Halton directions.
    std::vector<gpu::VplLight> lights;
    std::vector<glm::vec4> dirs;
    for (const VplSpot& spot : in.spots) {
        if (spot.layerCount != 1 && spot.layerCount != 6)
            return makeError("VplTechnique: a light's RSM layer count must be 1 or 6, got " +
                             std::to_string(spot.layerCount));
        gpu::VplLight l{};
        l.info = glm::uvec4(uint32_t(dirs.size()), s.vplCount, spot.firstLayer, spot.layerCount);
        if (spot.directional) {
            // Halton points of the orthographic window; each VPL stands for 1/N of its area
            // (the shader turns that into flux with the layer's texel area, vpl_generate.comp).
            if (spot.layerCount != 1)
                return makeError("VplTechnique: a directional light has one orthographic RSM layer, got " +
                                 std::to_string(spot.layerCount));
            l.position = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f / float(s.vplCount));
            for (const glm::vec3& p : windowSamplePoints(s.vplCount))
                dirs.emplace_back(p, 0.0f);
        } else {
            auto local = m->directions(s.vplCount, spot.cosOuter);
            if (!local)
                return local.error();
            glm::mat3 frame = spotFrame(spot.direction);
            l.position = glm::vec4(spot.position, coneSolidAngle(spot.cosOuter) / float(s.vplCount));
            l.axisX = glm::vec4(frame[0], 0.0f);
            l.axisY = glm::vec4(frame[1], 0.0f);
            l.axisZ = glm::vec4(frame[2], 0.0f);
            for (const glm::vec3& d : **local)
                dirs.emplace_back(d, 0.0f);
        }
        lights.push_back(l);
    }
    const uint32_t vplTotal = uint32_t(dirs.size());
    out.vplCount = vplTotal;

    struct UploadData {
        rg::BufferHandle lights, directions;
        std::vector<gpu::VplLight> lightData;
        std::vector<glm::vec4> directionData;
    };
    const auto& uploaded = graph.addPass<UploadData>(
        "vpl.upload",
        [&](rg::PassBuilder& b, UploadData& d) {
            d.lightData = lights;
            d.directionData = dirs;
            d.lights = b.write(b.create("vpl.lights", storageBuffer(lights.size() * sizeof(gpu::VplLight))),
                               rg::Access::TransferWrite);
            d.directions = b.write(b.create("vpl.directions", storageBuffer(dirs.size() * sizeof(glm::vec4))),
                                   rg::Access::TransferWrite);
        },
        [](const UploadData& d, rg::PassContext& pc) {
            updateBuffer(pc.cmd(), pc.buffer(d.lights).buffer, d.lightData.data(),
                         d.lightData.size() * sizeof(gpu::VplLight));
            updateBuffer(pc.cmd(), pc.buffer(d.directions).buffer, d.directionData.data(),
                         d.directionData.size() * sizeof(glm::vec4));
        });

    rg::BufferHandle vpls =
        graph.createBuffer("vpl.vpls", storageBuffer(VkDeviceSize(vplTotal) * sizeof(gpu::VplRecord)));
    gpu::VplGeneratePush generatePush{};
    generatePush.info = glm::uvec4(uint32_t(lights.size()), vplTotal, 0, 0);
    rg::ComputePass(graph, "vpl.generate", m->generate)
        .push(generatePush)
        .sample(VPL_GENERATE_BINDING_RSM_POSITION, in.rsmPosition, m->pointSampler)
        .sample(VPL_GENERATE_BINDING_RSM_NORMAL, in.rsmNormal, m->pointSampler)
        .sample(VPL_GENERATE_BINDING_RSM_FLUX, in.rsmFlux, m->pointSampler)
        .read(VPL_GENERATE_BINDING_SHADOW_VIEWS, in.shadowViews)
        .read(VPL_GENERATE_BINDING_LIGHTS, uploaded.lights)
        .read(VPL_GENERATE_BINDING_DIRECTIONS, uploaded.directions)
        .overwrite(VPL_GENERATE_BINDING_VPLS, vpls)
        .dispatch({vplTotal, 1, 1});
    out.vpls = vpls;

    // Gather resolution and the shared push constants of the per-pixel passes.
    const uint32_t f = s.lowResFactor;
    const uint32_t lowW = (in.width + f - 1) / f, lowH = (in.height + f - 1) / f;
    const float clampDist = s.clampDistance * std::max(in.sceneDiagonal, 1e-6f);
    const float tanHalf = std::tan(0.5f * in.camera.yfov);
    gpu::VplPixelPush pixelPush{};
    pixelPush.size = glm::uvec4(lowW, lowH, f, in.width * in.height);
    pixelPush.counts = glm::uvec4(vplTotal, s.negativeVplCount, in.width, in.height);
    pixelPush.camera = glm::vec4(in.camera.position, 0.0f);
    pixelPush.params = glm::vec4(clampDist * clampDist, s.refineThreshold, 0.0f, 0.0f);

    rg::ImageHandle lowIndirect = graph.createImage(
        f == 1 && s.negativeVplCount == 0 ? "vpl.indirect" : "vpl.gather_indirect", image2D(lowW, lowH));
    rg::ImageHandle incident = graph.createImage("vpl.incident", image2D(lowW, lowH));
    rg::ImageHandle travel = graph.createImage("vpl.travel", image2D(lowW, lowH));
    rg::ComputePass(graph, "vpl.gather", m->gather)
        .push(pixelPush)
        .sample(VPL_GATHER_BINDING_POSITION, in.gPosition, m->pointSampler)
        .sample(VPL_GATHER_BINDING_NORMAL, in.gNormal, m->pointSampler)
        .sample(VPL_GATHER_BINDING_ALBEDO, in.gAlbedo, m->pointSampler)
        .read(VPL_GATHER_BINDING_VPLS, vpls)
        .overwrite(VPL_GATHER_BINDING_INDIRECT, lowIndirect)
        .overwrite(VPL_GATHER_BINDING_INCIDENT, incident)
        .overwrite(VPL_GATHER_BINDING_TRAVEL, travel)
        .dispatch({lowW, lowH, 1});
    rg::BufferHandle negativeVpls = vpls; // bound (with count 0) when negative VPLs are off

    if (s.negativeVplCount > 0) {
        negativeVpls = graph.createBuffer("vpl.negative_vpls",
                                          storageBuffer(VkDeviceSize(s.negativeVplCount) * sizeof(gpu::VplRecord)));
        gpu::VplGeneratePush negativePush{};
        negativePush.info = glm::uvec4(s.negativeVplCount, s.negativeVplCount, f, 0);
        negativePush.size = glm::uvec4(lowW, lowH, in.width, in.height);
        negativePush.camera = glm::vec4(in.camera.position, tanHalf);
        rg::ComputePass(graph, "vpl.negative_generate", m->negativeGenerate)
            .push(negativePush)
            .sample(VPL_NEGATIVE_GENERATE_BINDING_POSITION, in.gPosition, m->pointSampler)
            .sample(VPL_NEGATIVE_GENERATE_BINDING_NORMAL, in.gNormal, m->pointSampler)
            .sample(VPL_NEGATIVE_GENERATE_BINDING_INCIDENT, incident, m->pointSampler)
            .sample(VPL_NEGATIVE_GENERATE_BINDING_TRAVEL, travel, m->pointSampler)
            .overwrite(VPL_NEGATIVE_GENERATE_BINDING_NEGATIVE_VPLS, negativeVpls)
            .dispatch({s.negativeVplCount, 1, 1});
        out.negativeVpls = negativeVpls;

        rg::ImageHandle positiveIndirect = lowIndirect;
        lowIndirect = graph.createImage(f == 1 ? "vpl.indirect" : "vpl.negative_indirect", image2D(lowW, lowH));
        rg::ComputePass(graph, "vpl.negative_gather", m->negativeGather)
            .push(pixelPush)
            .sample(VPL_NEGATIVE_GATHER_BINDING_POSITION, in.gPosition, m->pointSampler)
            .sample(VPL_NEGATIVE_GATHER_BINDING_NORMAL, in.gNormal, m->pointSampler)
            .sample(VPL_NEGATIVE_GATHER_BINDING_ALBEDO, in.gAlbedo, m->pointSampler)
            .read(VPL_NEGATIVE_GATHER_BINDING_NEGATIVE_VPLS, negativeVpls)
            .sample(VPL_NEGATIVE_GATHER_BINDING_POSITIVE_INDIRECT, positiveIndirect, m->pointSampler)
            .overwrite(VPL_NEGATIVE_GATHER_BINDING_INDIRECT, lowIndirect)
            .dispatch({lowW, lowH, 1});
    }

    if (f == 1) {
        out.indirect = lowIndirect;
        return out;
    }

    struct ClearListData {
        rg::BufferHandle list;
    };
    const auto& cleared = graph.addPass<ClearListData>(
        "vpl.refine_clear",
        [&](rg::PassBuilder& b, ClearListData& d) {
            VkDeviceSize bytes = VPL_REFINE_LIST_HEADER_BYTES + VkDeviceSize(in.width) * in.height * 4;
            d.list = b.write(b.create("vpl.refine_list", storageBuffer(bytes)), rg::Access::TransferWrite);
        },
        [](const ClearListData& d, rg::PassContext& pc) {
            vkCmdFillBuffer(pc.cmd(), pc.buffer(d.list).buffer, 0, VPL_REFINE_LIST_HEADER_BYTES, 0);
        });
    rg::BufferHandle refineList = cleared.list;

    rg::ImageHandle indirect = graph.createImage("vpl.indirect", fullDesc);
    rg::ComputePass(graph, "vpl.upsample", m->upsample)
        .push(pixelPush)
        .sample(VPL_UPSAMPLE_BINDING_POSITION, in.gPosition, m->pointSampler)
        .sample(VPL_UPSAMPLE_BINDING_NORMAL, in.gNormal, m->pointSampler)
        .sample(VPL_UPSAMPLE_BINDING_LOW_RES_INDIRECT, lowIndirect, m->pointSampler)
        .overwrite(VPL_UPSAMPLE_BINDING_INDIRECT, indirect)
        .write(VPL_UPSAMPLE_BINDING_REFINE_LIST, refineList)
        .dispatch({in.width, in.height, 1});

    rg::ComputePass(graph, "vpl.refine", m->refine)
        .push(pixelPush)
        .sample(VPL_REFINE_BINDING_POSITION, in.gPosition, m->pointSampler)
        .sample(VPL_REFINE_BINDING_NORMAL, in.gNormal, m->pointSampler)
        .sample(VPL_REFINE_BINDING_ALBEDO, in.gAlbedo, m->pointSampler)
        .read(VPL_REFINE_BINDING_VPLS, vpls)
        .read(VPL_REFINE_BINDING_NEGATIVE_VPLS, negativeVpls)
        .read(VPL_REFINE_BINDING_REFINE_LIST, refineList)
        .write(VPL_REFINE_BINDING_INDIRECT, indirect)
        .dispatch({in.width * in.height, 1, 1});
    out.indirect = indirect;
    out.refineList = refineList;
    return out;
}

} // namespace vkgi::gi
