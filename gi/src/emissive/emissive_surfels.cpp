#include "emissive/emissive_surfels.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "vkgi/resources.hpp"
#include "vkgi/rg/compute_pass.hpp"
#include "vk_dispatch.hpp"

namespace vkgi::gi {

namespace {

struct EmittingSide {
    uint32_t instance = 0, triangle = 0, side = 0;
    double power = 0.0; // area x channel sum of the emission (the flux up to pi)
};

// The emitting triangle sides in instance order, as the path tracer sees them: a triangle emits
// from its front (counter-clockwise in object space), and from both sides when double-sided.
std::vector<EmittingSide> emittingSides(const Scene& scene) {
    std::vector<EmittingSide> sides;
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& inst = scene.instances[i];
        if (inst.mesh >= scene.meshes.size())
            continue;
        const Mesh& mesh = scene.meshes[inst.mesh];
        if (mesh.material >= scene.materials.size())
            continue;
        const Material& m = scene.materials[mesh.material];
        const double sum = double(m.emission.r) + double(m.emission.g) + double(m.emission.b);
        if (!(sum > 0.0) || !std::isfinite(sum))
            continue;
        for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
            glm::vec3 p[3];
            bool valid = true;
            for (int j = 0; j < 3; ++j) {
                const uint32_t index = mesh.indices[3 * t + j];
                valid = valid && index < mesh.positions.size();
                if (valid)
                    p[j] = glm::vec3(inst.transform * glm::vec4(mesh.positions[index], 1.0f));
            }
            if (!valid)
                continue;
            const double area = 0.5 * double(glm::length(glm::cross(p[1] - p[0], p[2] - p[0])));
            if (!(area > 0.0) || !std::isfinite(area))
                continue;
            for (uint32_t side = 0; side < (m.doubleSided ? 2u : 1u); ++side)
                sides.push_back({i, t, side, area * sum});
        }
    }
    return sides;
}

// Point i of n on the unit square: stratified in x, a golden-ratio sequence in y.
glm::vec2 stratified(uint32_t i, uint32_t n) {
    const double y = std::fmod(0.5 + double(i) * 0.6180339887498949, 1.0);
    return {float((double(i) + 0.5) / double(n)), float(y)};
}

gpu::GpuEmissiveSurfel surfel(const EmittingSide& s, glm::vec2 point, double weight) {
    gpu::GpuEmissiveSurfel out{};
    out.triangle = glm::uvec4(s.instance, s.triangle, s.side, 0u);
    out.point = glm::vec4(point, float(weight), 0.0f);
    return out;
}

} // namespace

std::vector<gpu::GpuEmissiveSurfel> planEmissiveSurfels(const Scene& scene, uint32_t count) {
    std::vector<gpu::GpuEmissiveSurfel> table;
    const std::vector<EmittingSide> sides = emittingSides(scene);
    if (sides.empty() || count == 0)
        return table;
    double total = 0.0;
    for (const EmittingSide& s : sides)
        total += s.power;
    table.reserve(count);
    if (sides.size() > count) {
        // Systematic sampling by power: surfel k takes the side whose cumulative power interval
        // holds (k + 1/2) total / count, at its relative place in that interval along x.
        const double step = total / double(count);
        double below = 0.0;
        size_t j = 0;
        for (uint32_t k = 0; k < count; ++k) {
            const double at = (double(k) + 0.5) * step;
            while (j + 1 < sides.size() && below + sides[j].power <= at)
                below += sides[j++].power;
            const double x = std::clamp((at - below) / sides[j].power, 0.0, 1.0);
            const glm::vec2 point(float(x), float(std::fmod(0.5 + double(k) * 0.6180339887498949, 1.0)));
            table.push_back(surfel(sides[j], point, step / sides[j].power));
        }
        return table;
    }
    // One surfel per side, the rest by power with the largest remainders.
    const uint32_t spare = count - uint32_t(sides.size());
    std::vector<uint32_t> n(sides.size(), 1u);
    std::vector<std::pair<double, size_t>> remainders;
    remainders.reserve(sides.size());
    uint32_t given = 0;
    for (size_t j = 0; j < sides.size(); ++j) {
        const double share = double(spare) * sides[j].power / total;
        const uint32_t whole = uint32_t(std::floor(share));
        n[j] += whole;
        given += whole;
        remainders.push_back({share - double(whole), j});
    }
    std::stable_sort(remainders.begin(), remainders.end(),
                     [](const auto& a, const auto& b) { return a.first > b.first; });
    for (size_t r = 0; given < spare && r < remainders.size(); ++r, ++given)
        ++n[remainders[r].second];
    for (size_t j = 0; j < sides.size(); ++j)
        for (uint32_t i = 0; i < n[j]; ++i)
            table.push_back(surfel(sides[j], stratified(i, n[j]), 1.0 / double(n[j])));
    return table;
}

std::vector<EmitterPointSource> emitterPointSources(const Scene& scene, uint32_t count) {
    std::vector<EmitterPointSource> out;
    for (const gpu::GpuEmissiveSurfel& s : planEmissiveSurfels(scene, count)) {
        // The same placement as surfels.comp (which does it on the GPU for this frame's instances).
        const Instance& inst = scene.instances[s.triangle.x];
        const Mesh& mesh = scene.meshes[inst.mesh];
        glm::vec3 v[3];
        for (int j = 0; j < 3; ++j)
            v[j] = glm::vec3(inst.transform * glm::vec4(mesh.positions[mesh.indices[3 * s.triangle.y + j]], 1.0f));
        const glm::vec3 c = glm::cross(v[1] - v[0], v[2] - v[0]);
        const float twiceArea = glm::length(c);
        const float mirrored = glm::determinant(glm::mat3(inst.transform)) < 0.0f ? -1.0f : 1.0f;
        const float facing = s.triangle.z == 0u ? mirrored : -mirrored;
        const float su = std::sqrt(s.point.x);
        EmitterPointSource p;
        p.position = v[0] * (1.0f - su) + v[1] * (s.point.y * su) + v[2] * (su - s.point.y * su);
        p.normal = c * (facing / twiceArea);
        const float area = 0.5f * twiceArea * s.point.z;
        p.flux = 3.14159265358979f * scene.materials[mesh.material].emission * area;
        out.push_back(p);
    }
    return out;
}

Result<void> EmissiveSurfels::sceneChanged(Context& ctx, const Scene& scene, uint32_t count) {
    const std::vector<gpu::GpuEmissiveSurfel> table = planEmissiveSurfels(scene, count);
    if (table.empty()) {
        reset();
        return {};
    }
    // A rigid move keeps the plan (the pass follows the instances): no upload, no device wait.
    if (table.size() == m_plan.size() &&
        std::memcmp(table.data(), m_plan.data(), table.size() * sizeof(gpu::GpuEmissiveSurfel)) == 0)
        return {};
    m_ctx = &ctx;
    if (m_pipeline.pipeline == VK_NULL_HANDLE) {
        auto pipeline = createComputePipeline(ctx, {"gi/emissive/surfels.comp", {}});
        if (!pipeline)
            return pipeline.error();
        m_pipeline = *pipeline;
    }
    const VkDeviceSize bytes = VkDeviceSize(table.size() * sizeof(gpu::GpuEmissiveSurfel));
    if (!m_table.buffer.buffer || m_table.buffer.desc.size < bytes) {
        if (m_table.buffer.buffer) {
            vkDeviceWaitIdle(ctx.device()); // the last frame may still read it
            destroyBuffer(ctx, m_table.buffer);
        }
        m_table = {};
        m_table.buffer = createBuffer(
            ctx, {bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT}, "gi.emissive.table");
    } else {
        vkDeviceWaitIdle(ctx.device());
    }
    uploadBuffer(ctx, m_table.buffer, table.data(), bytes);
    m_count = uint32_t(table.size());
    m_plan = table;
    m_resolution = uint32_t(std::ceil(std::sqrt(double(m_count))));
    return {};
}

EmissiveSurfelImages EmissiveSurfels::addPasses(rg::RenderGraph& graph, const SceneHandles& scene,
                                                const std::string& prefix) {
    EmissiveSurfelImages out{createRsmImages(graph, prefix + ".emissive", m_resolution, 1), m_resolution};
    gpu::EmissiveSurfelPush push{};
    push.info = glm::uvec4(m_count, m_resolution, 0u, 0u);
    rg::BufferHandle table = graph.importBuffer(prefix + ".emissive.table", m_table);
    rg::ComputePass(graph, prefix + ".emissive.surfels", m_pipeline)
        .push(push)
        .read(EMISSIVE_BINDING_VERTICES, scene.vertices)
        .read(EMISSIVE_BINDING_INDICES, scene.indices)
        .read(EMISSIVE_BINDING_INSTANCES, scene.instances)
        .read(EMISSIVE_BINDING_MATERIALS, scene.materials)
        .read(EMISSIVE_BINDING_SURFELS, table)
        .overwrite(EMISSIVE_BINDING_POSITION, out.position)
        .overwrite(EMISSIVE_BINDING_NORMAL, out.normal)
        .overwrite(EMISSIVE_BINDING_FLUX, out.flux)
        .dispatch({m_resolution, m_resolution, 1u});
    return out;
}

void EmissiveSurfels::reset() {
    if (!m_ctx)
        return;
    if (m_table.buffer.buffer || m_pipeline.pipeline != VK_NULL_HANDLE)
        vkDeviceWaitIdle(m_ctx->device());
    if (m_table.buffer.buffer)
        destroyBuffer(*m_ctx, m_table.buffer);
    if (m_pipeline.pipeline != VK_NULL_HANDLE)
        destroyPipeline(*m_ctx, m_pipeline);
    m_table = {};
    m_pipeline = {};
    m_count = 0;
    m_resolution = 0;
    m_plan.clear();
}

} // namespace vkgi::gi
