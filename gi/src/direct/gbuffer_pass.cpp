// G-buffer: one draw per instance into position/normal/albedo/emission + depth at the camera's
// pixel centres (Camera::projection, no jitter), so it lines up with the path tracer.
#include "direct/direct_passes.hpp"

#include "vkgi/context.hpp"
#include "vk_dispatch.hpp"

namespace vkgi::gi {

void drawScene(VkCommandBuffer cmd, const Pipeline& pipeline, const GpuScene& scene, VkBuffer indices,
               gpu::RasterPush push) {
    vkCmdBindIndexBuffer(cmd, indices, 0, VK_INDEX_TYPE_UINT32);
    for (const GpuDraw& d : scene.draws) {
        push.info.x = d.instance;
        pushConstants(cmd, pipeline, &push, sizeof(push));
        vkCmdDrawIndexed(cmd, d.indexCount, 1, d.firstIndex, d.vertexOffset, 0);
    }
}

namespace {
struct GBufferPass {
    GBufferData g;
    SceneHandles s;
    const Pipeline* pipeline = nullptr;
    const GpuScene* scene = nullptr;
    gpu::RasterPush push{};
    VkExtent2D extent{};
};
} // namespace

GBufferData addGBufferPass(rg::RenderGraph& graph, const DirectPipelines& p, const FrameData& frame,
                           const SceneHandles& scene) {
    using rg::Access;
    const GBufferPass& pass = graph.addPass<GBufferPass>(
        "gi.gbuffer",
        [&](rg::PassBuilder& b, GBufferPass& d) {
            auto target = [&](const char* name, VkFormat format) {
                ImageDesc desc;
                desc.format = format;
                desc.width = frame.width;
                desc.height = frame.height;
                return b.create(name, desc);
            };
            d.g.depth = b.write(target("gbuffer.depth", kDepthFormat), Access::DepthAttachmentWrite);
            d.g.position = b.write(target("gbuffer.position", kPositionFormat), Access::ColorAttachmentWrite);
            d.g.normal = b.write(target("gbuffer.normal", kNormalFormat), Access::ColorAttachmentWrite);
            d.g.albedo = b.write(target("gbuffer.albedo", kAlbedoFormat), Access::ColorAttachmentWrite);
            d.g.emission = b.write(target("gbuffer.emission", kEmissionFormat), Access::ColorAttachmentWrite);
            b.read(scene.vertices, Access::VertexShaderStorageRead);
            b.read(scene.instances, Access::VertexShaderStorageRead);
            b.read(scene.indices, Access::IndexBufferRead);
            b.read(scene.materials, Access::VertexShaderStorageRead);
            b.read(scene.textures, Access::FragmentSampledRead);
            d.s = scene;
            d.pipeline = frame.scene->textures.empty() ? &p.gbufferUntextured : &p.gbuffer;
            d.scene = frame.gpuScene;
            d.push = {frame.viewProj, glm::vec4(frame.camera.position, 0.0f), glm::vec4(0.0f), glm::uvec4(0u)};
            d.extent = {frame.width, frame.height};
        },
        [](const GBufferPass& d, rg::PassContext& pc) {
            VkCommandBuffer cmd = pc.cmd();
            const GBufferData& g = d.g;
            beginRendering(cmd, d.extent,
                           {pc.view(g.position), pc.view(g.normal), pc.view(g.albedo), pc.view(g.emission)},
                           pc.view(g.depth));
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, d.pipeline->pipeline);
            DescriptorItem items[4] = {
                pc.buffer(DIRECT_RASTER_BINDING_VERTICES, d.s.vertices),
                pc.buffer(DIRECT_RASTER_BINDING_INSTANCES, d.s.instances),
                pc.buffer(DIRECT_RASTER_BINDING_MATERIALS, d.s.materials),
                pc.sampled(DIRECT_RASTER_BINDING_TEXTURES, d.s.textures, d.scene->textureSampler)};
            pushDescriptors(pc.context(), cmd, *d.pipeline, items);
            drawScene(cmd, *d.pipeline, *d.scene, pc.buffer(d.s.indices).buffer, d.push);
            vkCmdEndRendering(cmd);
        });
    return pass.g;
}

} // namespace vkgi::gi
