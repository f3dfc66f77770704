// vkgi calls Vulkan only through the vkGetInstanceProcAddr a host gives it
// (ExternalDevice::getInstanceProcAddr), and a failed Vulkan call inside a frame comes back as
// renderFrame's error instead of aborting the process. A wrapping vkGetInstanceProcAddr hands
// out vkAllocateMemory and vkQueueSubmit2 that fail on demand: out of device memory is
// transient (the next frame succeeds and matches a clean frame bit for bit), a lost device
// leaves a GiSystem that is destroyed without validation messages.
#include <atomic>
#include <cstring>
#include <string>

#include "vkgi/builtin_scenes.hpp"
#include "vkgi/gi.hpp"
#include "support/gi_render.hpp"
#include "support/gpu_fixture.hpp"

using namespace vkgi;
using namespace vkgi::gi;

namespace {

// The host's side of the fault injection; the real functions come from the Vulkan loader.
std::atomic<uint32_t> g_lookups{0};        // names the library looked up through the wrapper
std::atomic<bool> g_failAllocate{false};   // vkAllocateMemory returns VK_ERROR_OUT_OF_DEVICE_MEMORY
std::atomic<uint32_t> g_failedAllocations{0};
std::atomic<VkResult> g_submitResult{VK_SUCCESS}; // an error: vkQueueSubmit2 returns it, submitting nothing
std::atomic<int32_t> g_buffersBeforeFailure{-1}; // >= 0: vkCreateBuffer succeeds this many more times, then fails
PFN_vkAllocateMemory g_allocateMemory = nullptr;
PFN_vkCreateBuffer g_createBuffer = nullptr;
PFN_vkQueueSubmit2 g_queueSubmit2 = nullptr;

VKAPI_ATTR VkResult VKAPI_CALL faultyAllocateMemory(VkDevice device, const VkMemoryAllocateInfo* info,
                                                    const VkAllocationCallbacks* allocator, VkDeviceMemory* memory) {
    if (g_failAllocate) {
        ++g_failedAllocations;
        return VK_ERROR_OUT_OF_DEVICE_MEMORY;
    }
    return g_allocateMemory(device, info, allocator, memory);
}

VKAPI_ATTR VkResult VKAPI_CALL faultyQueueSubmit2(VkQueue queue, uint32_t count, const VkSubmitInfo2* submits,
                                                  VkFence fence) {
    if (VkResult r = g_submitResult; r != VK_SUCCESS)
        return r; // nothing reaches the driver: the frame never runs
    return g_queueSubmit2(queue, count, submits, fence);
}

VKAPI_ATTR VkResult VKAPI_CALL faultyCreateBuffer(VkDevice device, const VkBufferCreateInfo* info,
                                                  const VkAllocationCallbacks* allocator, VkBuffer* buffer) {
    int32_t left = g_buffersBeforeFailure.load();
    if (left == 0)
        return VK_ERROR_OUT_OF_DEVICE_MEMORY;
    if (left > 0)
        g_buffersBeforeFailure = left - 1;
    return g_createBuffer(device, info, allocator, buffer);
}

VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL hostGetInstanceProcAddr(VkInstance instance, const char* name) {
    ++g_lookups;
    PFN_vkVoidFunction real = vkGetInstanceProcAddr(instance, name);
    if (std::strcmp(name, "vkAllocateMemory") == 0) {
        g_allocateMemory = reinterpret_cast<PFN_vkAllocateMemory>(real);
        return reinterpret_cast<PFN_vkVoidFunction>(faultyAllocateMemory);
    }
    if (std::strcmp(name, "vkCreateBuffer") == 0) {
        g_createBuffer = reinterpret_cast<PFN_vkCreateBuffer>(real);
        return reinterpret_cast<PFN_vkVoidFunction>(faultyCreateBuffer);
    }
    if (std::strcmp(name, "vkQueueSubmit2") == 0) {
        g_queueSubmit2 = reinterpret_cast<PFN_vkQueueSubmit2>(real);
        return reinterpret_cast<PFN_vkVoidFunction>(faultyQueueSubmit2);
    }
    return real;
}

bool sameImage(const HdrImage& a, const HdrImage& b) {
    return a.width == b.width && a.height == b.height && a.pixels == b.pixels;
}

class VulkanLoaderTest : public test::GpuTest {
protected:
    void SetUp() override {
        test::GpuTest::SetUp();
        g_lookups = 0;
        g_failAllocate = false;
        g_failedAllocations = 0;
        g_submitResult = VK_SUCCESS;
        g_buffersBeforeFailure = -1;
    }
    void TearDown() override {
        g_failAllocate = false;
        g_submitResult = VK_SUCCESS;
        g_buffersBeforeFailure = -1;
        test::GpuTest::TearDown();
    }

    // The fixture's device seen as a host's: every Vulkan function vkgi calls on it comes
    // through hostGetInstanceProcAddr.
    std::unique_ptr<Context> wrapWithHostLoader() {
        ExternalDevice device{ctx().instance(), ctx().physicalDevice(), ctx().device(), ctx().queue(),
                              ctx().queueFamily()};
        device.getInstanceProcAddr = hostGetInstanceProcAddr;
        auto wrapped = wrapExternalDevice(device);
        EXPECT_TRUE(wrapped) << (wrapped ? "" : wrapped.error().message);
        return wrapped ? std::move(*wrapped) : nullptr;
    }

    Scene scene() {
        auto s = makeBuiltinScene("cornell");
        EXPECT_TRUE(s) << (s ? "" : s.error().message);
        return s ? *s : Scene{};
    }
};

GiSettings smallVct() {
    GiSettings s;
    s.technique = Technique::Vct;
    s.shadowMapSize = 64;
    s.vct.gridResolution = 16;
    return s;
}

TEST_F(VulkanLoaderTest, HostGetInstanceProcAddrGivesTheDefaultLoadersImage) {
    Scene cornell = scene();
    FrameRequest request;
    request.indirect = true;
    // Rendered before any Context loads vkgi's table from the host's function.
    auto reference = test::renderOnce(ctx(), smallVct(), cornell, cornell.cameraOrDefault(), 32, 32, request);
    ASSERT_TRUE(reference) << reference.error().message;

    auto hostCtx = wrapWithHostLoader();
    ASSERT_TRUE(hostCtx);
    EXPECT_GT(g_lookups.load(), 50u) << "vkgi loads its functions through the host's vkGetInstanceProcAddr";
    auto frame = test::renderOnce(*hostCtx, smallVct(), cornell, cornell.cameraOrDefault(), 32, 32, request);
    ASSERT_TRUE(frame) << frame.error().message;
    EXPECT_GT(reference->composite.pixels.size(), 0u);
    EXPECT_TRUE(sameImage(frame->composite, reference->composite));
    EXPECT_TRUE(sameImage(frame->indirect, reference->indirect));
}

// The frame is large enough that its transients do not fit in the memory the system allocated
// while it was created and given its scene (resources.cpp's block size): the frame must allocate.
TEST_F(VulkanLoaderTest, OutOfDeviceMemoryIsReturnedAndTheNextFrameMatchesACleanOne) {
    constexpr uint32_t kWidth = 1024, kHeight = 1024;
    Scene cornell = scene();
    GiSettings settings;
    settings.shadowMapSize = 64;
    auto clean = test::renderOnce(ctx(), settings, cornell, cornell.cameraOrDefault(), kWidth, kHeight, {});
    ASSERT_TRUE(clean) << clean.error().message;

    auto hostCtx = wrapWithHostLoader();
    ASSERT_TRUE(hostCtx);
    auto system = test::systemWithScene(*hostCtx, settings, cornell);
    ASSERT_TRUE(system) << system.error().message;
    g_failAllocate = true;
    auto failed = (*system)->renderFrame(cornell.cameraOrDefault(), kWidth, kHeight);
    g_failAllocate = false;
    ASSERT_FALSE(failed) << "the frame allocated no device memory";
    EXPECT_GT(g_failedAllocations.load(), 0u);
    const std::string& message = failed.error().message;
    EXPECT_EQ(message.rfind("vkAllocateMemory failed: VK_ERROR_OUT_OF_DEVICE_MEMORY (resources.cpp:", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << "one line";

    auto recovered = (*system)->renderFrame(cornell.cameraOrDefault(), kWidth, kHeight);
    ASSERT_TRUE(recovered) << recovered.error().message;
    EXPECT_TRUE(sameImage(recovered->composite, clean->composite)) << "the failed frame left nothing stale";
}

TEST_F(VulkanLoaderTest, DeviceLostAtSubmitIsReturnedAndTheSystemIsDestroyedCleanly) {
    Scene cornell = scene();
    auto hostCtx = wrapWithHostLoader();
    ASSERT_TRUE(hostCtx);
    auto system = test::systemWithScene(*hostCtx, smallVct(), cornell);
    ASSERT_TRUE(system) << system.error().message;
    g_submitResult = VK_ERROR_DEVICE_LOST;
    auto failed = (*system)->renderFrame(cornell.cameraOrDefault(), 32, 32);
    ASSERT_FALSE(failed);
    const std::string& message = failed.error().message;
    EXPECT_EQ(message.rfind("vkQueueSubmit2 failed: VK_ERROR_DEVICE_LOST (context.cpp:", 0), 0u) << message;
    system->reset(); // destroys everything with the device "lost": no abort, no throw
    hostCtx.reset();
}

// A submit that fails transiently: the recorded frame never ran, so the resources' tracked states
// and the skipped-as-clean work must be those of before it (validation checks the layouts).
TEST_F(VulkanLoaderTest, FailedSubmitLeavesNoStaleStateForTheNextFrame) {
    Scene cornell = scene();
    FrameRequest request;
    request.indirect = true;
    auto clean = test::renderOnce(ctx(), smallVct(), cornell, cornell.cameraOrDefault(), 32, 32, request);
    ASSERT_TRUE(clean) << clean.error().message;

    auto hostCtx = wrapWithHostLoader();
    ASSERT_TRUE(hostCtx);
    auto system = test::systemWithScene(*hostCtx, smallVct(), cornell);
    ASSERT_TRUE(system) << system.error().message;
    g_submitResult = VK_ERROR_OUT_OF_DEVICE_MEMORY;
    auto failed = (*system)->renderFrame(cornell.cameraOrDefault(), 32, 32, request);
    g_submitResult = VK_SUCCESS;
    ASSERT_FALSE(failed);
    EXPECT_EQ(failed.error().message.rfind("vkQueueSubmit2 failed: VK_ERROR_OUT_OF_DEVICE_MEMORY (", 0), 0u)
        << failed.error().message;
    auto recovered = (*system)->renderFrame(cornell.cameraOrDefault(), 32, 32, request);
    ASSERT_TRUE(recovered) << recovered.error().message;
    EXPECT_TRUE(sameImage(recovered->composite, clean->composite));
    EXPECT_TRUE(sameImage(recovered->indirect, clean->indirect));
}

// setScene fails part-way through the upload (a buffer of the scene or a staging buffer cannot be
// created): the error names the call, the buffers already made are freed, the system keeps no
// scene, and a later setScene renders as a clean system does.
TEST_F(VulkanLoaderTest, FailedSceneUploadFreesWhatItMadeAndTheNextUploadRenders) {
    Scene cornell = scene();
    auto clean = test::renderOnce(ctx(), smallVct(), cornell, cornell.cameraOrDefault(), 32, 32, {});
    ASSERT_TRUE(clean) << clean.error().message;

    auto hostCtx = wrapWithHostLoader();
    ASSERT_TRUE(hostCtx);
    auto system = GiSystem::create(*hostCtx, smallVct());
    ASSERT_TRUE(system) << system.error().message;
    const VkDeviceSize live = hostCtx->allocator().liveBytes();
    // Buffers are made in pairs (the table, then its staging buffer): every point of failure.
    for (int32_t before : {0, 1, 2, 3, 8, 9}) {
        g_buffersBeforeFailure = before;
        auto failed = (*system)->setScene(cornell);
        g_buffersBeforeFailure = -1;
        ASSERT_FALSE(failed) << before;
        EXPECT_EQ(failed.error().message.rfind("vkCreateBuffer failed: VK_ERROR_OUT_OF_DEVICE_MEMORY (", 0), 0u)
            << failed.error().message;
        EXPECT_EQ(hostCtx->allocator().liveBytes(), live) << "the half-uploaded scene is freed, failing after "
                                                          << before << " buffers";
    }
    auto noScene = (*system)->renderFrame(cornell.cameraOrDefault(), 32, 32);
    ASSERT_FALSE(noScene);
    EXPECT_NE(noScene.error().message.find("no scene"), std::string::npos) << noScene.error().message;

    ASSERT_TRUE((*system)->setScene(cornell));
    auto frame = (*system)->renderFrame(cornell.cameraOrDefault(), 32, 32);
    ASSERT_TRUE(frame) << frame.error().message;
    EXPECT_TRUE(sameImage(frame->composite, clean->composite));
}

} // namespace
