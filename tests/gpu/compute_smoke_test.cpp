// The Vulkan core on a real device: exact compute readback, SPIR-V reflection, push-constant
// and specialization plumbing, timestamps, the allocator, and embedding on a device that
// vkgi did not create.
#include <cmath>
#include <cstring>

#include "vkgi/frame_constants.hpp"
#include "vkgi/pipeline.hpp"
#include "vkgi/rg/render_graph.hpp"
#include "vkgi/rg/transient_pool.hpp"
#include "vkgi/resources.hpp"
#include "engine/test_bindings.h"
#include "vk_check.hpp"
#include "support/gpu_fixture.hpp"
#include "support/gpu_util.hpp"

using namespace vkgi;

namespace {

struct SmokePush {
    uint32_t size[4];
    uint32_t offset[4];
};

constexpr uint32_t kW = 37, kH = 21; // not multiples of the 8x8 workgroup on purpose
constexpr uint32_t kScale = 7, kOffset = 1000;

// Runs smoke.comp on `ctx` and checks every element of both outputs exactly.
void runSmoke(Context& ctx, double* gpuMs = nullptr) {
    auto pipeline = createComputePipeline(ctx, {"engine/smoke.comp", {{0, kScale}}});
    ASSERT_TRUE(pipeline) << pipeline.error().message;
    Buffer buf = createBuffer(ctx, {kW * kH * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT}, "smoke.values");
    ImageDesc desc;
    desc.format = VK_FORMAT_R32_UINT;
    desc.width = kW;
    desc.height = kH;
    desc.usage = VK_IMAGE_USAGE_STORAGE_BIT;
    Image img = createImage(ctx, desc, "smoke.image");
    TimestampPool timestamps(ctx, 1);
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        timestamps.reset(cmd);
        test::toGeneral(cmd, {&img});
        uint32_t scope = timestamps.begin(cmd);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline->pipeline);
        SmokePush push{{kW, kH, 0, 0}, {kOffset, 0, 0, 0}};
        pushConstants(cmd, *pipeline, &push, sizeof(push));
        DescriptorItem items[2];
        items[0].binding = ENGINE_SMOKE_BINDING_VALUES;
        items[0].buffer = {buf.buffer, 0, VK_WHOLE_SIZE};
        items[1].binding = ENGINE_SMOKE_BINDING_IMAGE;
        items[1].image = {VK_NULL_HANDLE, img.view, VK_IMAGE_LAYOUT_GENERAL};
        pushDescriptors(ctx, cmd, *pipeline, items);
        vkCmdDispatch(cmd, groupCount(kW, 8), groupCount(kH, 8), 1);
        timestamps.end(cmd, scope);
    });
    auto values = readbackBuffer(ctx, buf);
    auto texels = readbackImage(ctx, img, VK_IMAGE_LAYOUT_GENERAL);
    ASSERT_EQ(values.size(), kW * kH * 4u);
    ASSERT_EQ(texels.size(), kW * kH * 4u);
    const auto* v = reinterpret_cast<const uint32_t*>(values.data());
    const auto* t = reinterpret_cast<const uint32_t*>(texels.data());
    uint32_t wrong = 0;
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            uint32_t i = y * kW + x;
            wrong += v[i] != i * kScale + kOffset;
            wrong += t[i] != x * 1000 + y;
        }
    EXPECT_EQ(wrong, 0u);
    auto ms = timestamps.resolveMs();
    ASSERT_EQ(ms.size(), 1u);
    EXPECT_TRUE(std::isfinite(ms[0]) && ms[0] >= 0.0 && ms[0] < 10000.0) << ms[0];
    if (gpuMs)
        *gpuMs = ms[0];
    destroyImage(ctx, img);
    destroyBuffer(ctx, buf);
    destroyPipeline(ctx, *pipeline);
}

class ComputeSmoke : public test::GpuTest {};

} // namespace

TEST_F(ComputeSmoke, ExactReadbackOfBufferAndImage) {
    double ms = -1.0;
    runSmoke(ctx(), &ms);
    EXPECT_GE(ms, 0.0);
}

TEST_F(ComputeSmoke, ReflectionMatchesTheShader) {
    auto p = createComputePipeline(ctx(), {"engine/smoke.comp", {}});
    ASSERT_TRUE(p) << p.error().message;
    ASSERT_EQ(p->bindings.size(), 2u);
    EXPECT_EQ(p->bindings[0].set, 1u);
    EXPECT_EQ(p->bindings[0].binding, uint32_t(ENGINE_SMOKE_BINDING_VALUES));
    EXPECT_EQ(p->bindings[0].type, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    EXPECT_EQ(p->bindings[1].binding, uint32_t(ENGINE_SMOKE_BINDING_IMAGE));
    EXPECT_EQ(p->bindings[1].type, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
    EXPECT_EQ(p->bindings[1].name, "img");
    EXPECT_EQ(p->pushConstantSize, sizeof(SmokePush));
    EXPECT_EQ(p->localSize[0], 8u);
    EXPECT_EQ(p->localSize[1], 8u);
    EXPECT_EQ(p->localSize[2], 1u);
    destroyPipeline(ctx(), *p);
}

TEST_F(ComputeSmoke, MissingShaderIsAReadableError) {
    auto p = createComputePipeline(ctx(), {"engine/does_not_exist.comp", {}});
    ASSERT_FALSE(p);
    EXPECT_NE(p.error().message.find("engine/does_not_exist.comp"), std::string::npos) << p.error().message;
}

TEST_F(ComputeSmoke, AllocatorReusesAndReturnsMemory) {
    Allocator& a = ctx().allocator();
    VkDeviceSize before = a.liveBytes();
    std::vector<Buffer> bufs;
    for (uint32_t i = 0; i < 64; ++i)
        bufs.push_back(createBuffer(ctx(), {4096 + i * 512, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT}, "alloc.test"));
    EXPECT_GE(a.liveBytes() - before, 64u * 4096u);
    VkDeviceSize reserved = a.reservedBytes();
    for (size_t i = 0; i < bufs.size(); i += 2) // free every other one, then refill the holes
        destroyBuffer(ctx(), bufs[i]);
    for (size_t i = 0; i < bufs.size(); i += 2)
        bufs[i] = createBuffer(ctx(), {4096, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT}, "alloc.refill");
    EXPECT_EQ(a.reservedBytes(), reserved) << "holes should be reused, not new blocks";
    for (Buffer& b : bufs)
        destroyBuffer(ctx(), b);
    EXPECT_EQ(a.liveBytes(), before);
}

// Embedding: the host creates instance and device itself; vkgi wraps them without owning them.
TEST(Embedding, RunsOnAHostCreatedDevice) {
    uint32_t validationMessages = 0;
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.apiVersion = VK_API_VERSION_1_3;
    const char* layer = "VK_LAYER_KHRONOS_validation";
    const char* ext = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
    VkDebugUtilsMessengerCreateInfoEXT dbg{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    dbg.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    dbg.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
    dbg.pfnUserCallback = [](VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
                             const VkDebugUtilsMessengerCallbackDataEXT* d, void* user) -> VkBool32 {
        ADD_FAILURE() << "validation: " << d->pMessage;
        ++*static_cast<uint32_t*>(user);
        return VK_FALSE;
    };
    dbg.pUserData = &validationMessages;
    VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ici.pNext = &dbg;
    ici.pApplicationInfo = &app;
    ici.enabledLayerCount = 1;
    ici.ppEnabledLayerNames = &layer;
    ici.enabledExtensionCount = 1;
    ici.ppEnabledExtensionNames = &ext;
    VkInstance instance;
    if (vkCreateInstance(&ici, nullptr, &instance) != VK_SUCCESS) {
        if (test::gpuRequired())
            FAIL() << "cannot create a Vulkan instance";
        GTEST_SKIP() << "no Vulkan";
    }
    uint32_t n = 1;
    VkPhysicalDevice pd;
    VkResult r = vkEnumeratePhysicalDevices(instance, &n, &pd);
    ASSERT_TRUE((r == VK_SUCCESS || r == VK_INCOMPLETE) && n >= 1);
    float prio = 1.0f;
    VkDeviceQueueCreateInfo q{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    q.queueFamilyIndex = 0; // lavapipe: one graphics+compute family
    q.queueCount = 1;
    q.pQueuePriorities = &prio;
    VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    f13.synchronization2 = VK_TRUE;
    f13.dynamicRendering = VK_TRUE;
    const char* devExt = VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME;
    VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    dci.pNext = &f13;
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &q;
    dci.enabledExtensionCount = 1;
    dci.ppEnabledExtensionNames = &devExt;
    VkDevice device;
    VKGI_CHECK(vkCreateDevice(pd, &dci, nullptr, &device));
    VkQueue queue;
    vkGetDeviceQueue(device, 0, 0, &queue);
    {
        auto ctx = wrapExternalDevice({instance, pd, device, queue, 0});
        ASSERT_TRUE(ctx) << ctx.error().message;
        EXPECT_FALSE((*ctx)->ownsDevice());
        runSmoke(**ctx);
    } // vkgi's context is gone; the host's device must still work
    VKGI_CHECK(vkDeviceWaitIdle(device));
    vkDestroyDevice(device, nullptr);
    vkDestroyInstance(instance, nullptr);
    EXPECT_EQ(validationMessages, 0u);
}

TEST(Embedding, RejectsAnIncompleteHostDevice) {
    auto ctx = wrapExternalDevice({});
    ASSERT_FALSE(ctx);
    EXPECT_NE(ctx.error().message.find("must all be set"), std::string::npos);
}

// The harness itself: a deliberate API misuse must reach the validation log (otherwise a
// silent log would prove nothing in every other GPU test). The log is cleared afterwards.
TEST_F(ComputeSmoke, ValidationLayerReportsMisuse) {
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = 0; // invalid: size must be > 0
    info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    VkBuffer buffer = VK_NULL_HANDLE;
    vkCreateBuffer(ctx().device(), &info, nullptr, &buffer);
    EXPECT_GE(validation().count(), 1u);
    if (buffer)
        vkDestroyBuffer(ctx().device(), buffer, nullptr);
    validation().clear();
}

// The fixture checks the log after the device is destroyed, because only vkDestroyDevice reports
// an object the test left alive. This test leaks a sampler on its own context on purpose: the
// log held past the context must name it.
TEST(ValidationLog, HearsTheObjectALeakLeavesWhenTheDeviceIsDestroyed) {
    auto ctx = test::buildTestContext();
    if (!ctx) {
        if (test::gpuRequired())
            FAIL() << "no Vulkan device: " << ctx.error().message;
        GTEST_SKIP() << "no Vulkan device: " << ctx.error().message;
    }
    VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    VkSampler sampler = VK_NULL_HANDLE;
    VKGI_CHECK(vkCreateSampler((*ctx)->device(), &info, nullptr, &sampler));
    const std::shared_ptr<const ValidationLog> log = (*ctx)->sharedValidation();
    EXPECT_EQ(log->count(), 0u);
    ctx->reset();
    ASSERT_GE(log->count(), 1u);
    bool named = false;
    for (const std::string& m : log->messages())
        named = named || m.find("VkSampler") != std::string::npos;
    EXPECT_TRUE(named) << log->messages().front();
}

// Set 0: the per-frame constants reach a shader through the shared frame layout, and the
// ring hands out a different set per frame in flight.
TEST_F(ComputeSmoke, FrameConstantsReachTheShader) {
    auto pipeline = createComputePipeline(ctx(), {"engine/frame_smoke.comp", {}});
    ASSERT_TRUE(pipeline) << pipeline.error().message;
    EXPECT_EQ(pipeline->setLayouts[0], ctx().frameSetLayout());
    FrameConstantsRing ring(ctx(), 2);
    gpu::FrameConstants fc{};
    fc.viewProj = glm::mat4(1.0f);
    fc.viewProj[3] = glm::vec4(1.5f, -2.0f, 3.25f, 1.0f);
    fc.cameraPosition = glm::vec4(0.278f, 0.273f, -0.8f, 0.686f);
    fc.resolution = glm::uvec4(256, 128, 7, 3);
    fc.sceneMax = glm::vec4(0.5592f, 0.5488f, 0.5592f, 0.0f);
    VkDescriptorSet first = ring.next(gpu::FrameConstants{});
    VkDescriptorSet set = ring.next(fc);
    EXPECT_NE(first, set);
    Buffer out = createBuffer(ctx(), {4 * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT}, "frame.out");
    ctx().submitAndWait([&](VkCommandBuffer cmd) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline->pipeline);
        bindFrameSet(cmd, *pipeline, set);
        DescriptorItem item;
        item.binding = ENGINE_FRAME_SMOKE_BINDING_VALUES;
        item.buffer = {out.buffer, 0, VK_WHOLE_SIZE};
        pushDescriptors(ctx(), cmd, *pipeline, {&item, 1});
        vkCmdDispatch(cmd, 1, 1, 1);
    });
    auto bytes = readbackBuffer(ctx(), out);
    const auto* v = reinterpret_cast<const glm::vec4*>(bytes.data());
    EXPECT_EQ(v[0], fc.viewProj[3]);
    EXPECT_EQ(v[1], fc.cameraPosition);
    EXPECT_EQ(v[2], glm::vec4(256, 128, 7, 3));
    EXPECT_EQ(v[3], fc.sceneMax);
    destroyBuffer(ctx(), out);
    destroyPipeline(ctx(), *pipeline);
}

// Inside the render graph, dispatch() binds the frame set by itself for shaders that read it.
TEST_F(ComputeSmoke, GraphDispatchBindsTheFrameSet) {
    auto pipeline = createComputePipeline(ctx(), {"engine/frame_smoke.comp", {}});
    ASSERT_TRUE(pipeline) << pipeline.error().message;
    FrameConstantsRing ring(ctx(), 1);
    gpu::FrameConstants fc{};
    fc.cameraPosition = glm::vec4(1.0f, 2.0f, 3.0f, 4.0f);
    fc.resolution = glm::uvec4(64, 32, 1, 0);
    rg::TransientPool pool(ctx());
    rg::RenderGraph graph;
    graph.setFrameSet(ring.next(fc));
    Buffer out = createBuffer(ctx(), {4 * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT}, "frame.graph.out");
    rg::BufferHandle h = graph.importBuffer("out", out, rg::Access::None);
    graph.addPass(
        "frame.copy", [&](rg::PassBuilder& b) { h = b.write(h, rg::Access::ComputeStorageWrite); },
        [h, p = &*pipeline](rg::PassContext& pc) { pc.dispatch(*p, {1, 1, 1}, {pc.buffer(ENGINE_FRAME_SMOKE_BINDING_VALUES, h)}); });
    graph.exportBuffer(h, rg::Access::HostRead);
    ASSERT_TRUE(graph.compile());
    ctx().submitAndWait([&](VkCommandBuffer cmd) { graph.execute(cmd, ctx(), pool); });
    auto bytes = readbackBuffer(ctx(), out);
    const auto* v = reinterpret_cast<const glm::vec4*>(bytes.data());
    EXPECT_EQ(v[1], fc.cameraPosition);
    EXPECT_EQ(v[2], glm::vec4(64, 32, 1, 0));
    destroyBuffer(ctx(), out);
    destroyPipeline(ctx(), *pipeline);
}
