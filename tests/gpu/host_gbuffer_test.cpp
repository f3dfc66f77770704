// Host G-buffer path (GiSystem::renderIndirect, GiSystem::addPasses with a HostGBuffer): the
// host's images, filled here with vkgi's own G-buffer of the same view by a host graph, must
// give the internal path's indirect light: bit for bit when the host also gives positions,
// within float rounding when positions are reconstructed from depth. The host's output image
// receives the same numbers; bad input gives one-line errors naming the field.
#include <algorithm>
#include <cmath>
#include <string>

#include "direct/direct_passes.hpp"
#include "vkgi/builtin_scenes.hpp"
#include "vkgi/resources.hpp"
#include "vkgi/rg/blackboard.hpp"
#include "vkgi/rg/transient_pool.hpp"
#include "vkgi/frame_data.hpp"
#include "vkgi/gi.hpp"
#include "support/gi_render.hpp"
#include "support/gpu_fixture.hpp"
#include "support/image_stats.hpp"

using namespace vkgi;
using namespace vkgi::gi;

namespace {

constexpr uint32_t kSize = 64;
constexpr VkImageUsageFlags kReadUsage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT;

struct CopyPass {
    rg::ImageHandle src, dst;
};

// Copies a G-buffer image into a host image and leaves it in ComputeSampledRead.
void addCopy(rg::RenderGraph& graph, const std::string& name, rg::ImageHandle src, const Image& dst) {
    rg::ImageHandle imported = graph.importImage(name, dst, rg::Access::None);
    const CopyPass& pass = graph.addPass<CopyPass>(
        name,
        [&](rg::PassBuilder& b, CopyPass& d) {
            b.read(src, rg::Access::TransferRead);
            d.src = src;
            d.dst = b.write(imported, rg::Access::TransferWrite);
        },
        [](const CopyPass& d, rg::PassContext& pc) {
            const Image& s = pc.image(d.src);
            const Image& t = pc.image(d.dst);
            VkImageCopy region{};
            region.srcSubresource = {aspectOf(s.desc.format), 0, 0, 1};
            region.dstSubresource = region.srcSubresource;
            region.extent = {s.desc.width, s.desc.height, 1};
            vkCmdCopyImage(pc.cmd(), s.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, t.image,
                           VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
        });
    graph.exportImage(pass.dst, rg::Access::ComputeSampledRead);
}

HostImage hostImage(const Image& image, rg::Access access) {
    return {image.image, image.view, image.desc.format, image.desc.width, image.desc.height,
            image.desc.usage | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, access};
}

double maxDifference(const HdrImage& a, const HdrImage& b) {
    double d = 0.0;
    for (size_t i = 0; i < a.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c)
            d = std::max(d, double(std::abs(a.pixels[i][c] - b.pixels[i][c])));
    return d;
}

using test::meanRgb;

class HostGBufferTest : public test::GpuTest {
protected:
    void SetUp() override {
        test::GpuTest::SetUp();
        if (IsSkipped() || HasFatalFailure())
            return;
        auto s = makeBuiltinScene("cornell");
        ASSERT_TRUE(s) << s.error().message;
        scene = std::move(*s);
        camera = scene.cameraOrDefault();
        auto image = [&](VkFormat format, VkImageUsageFlags usage, const char* name) {
            ImageDesc d;
            d.format = format;
            d.width = kSize;
            d.height = kSize;
            d.usage = usage;
            return createImage(ctx(), d, name);
        };
        depth = image(kDepthFormat, VK_IMAGE_USAGE_SAMPLED_BIT, "host.depth");
        position = image(kPositionFormat, kReadUsage, "host.position");
        normal = image(kNormalFormat, kReadUsage, "host.normal");
        albedo = image(kAlbedoFormat, kReadUsage, "host.albedo");
        output32 = image(VK_FORMAT_R32G32B32A32_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT, "host.indirect32");
        output16 = image(VK_FORMAT_R16G16B16A16_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT, "host.indirect16");
        fillHostGBuffer();
    }
    void TearDown() override {
        for (Image* i : {&depth, &position, &normal, &albedo, &output32, &output16})
            if (*i)
                destroyImage(ctx(), *i);
        test::GpuTest::TearDown();
    }

    std::unique_ptr<GiSystem> system(Technique t) {
        GiSettings s;
        s.technique = t;
        auto sys = test::systemWithScene(ctx(), s, scene);
        EXPECT_TRUE(sys) << sys.error().message;
        return sys ? std::move(*sys) : nullptr;
    }

    // The host's G-buffer: vkgi's own G-buffer of the camera, copied by a host graph.
    void fillHostGBuffer() {
        auto sys = system(Technique::None);
        ASSERT_TRUE(sys);
        rg::RenderGraph graph;
        rg::Blackboard bb;
        FrameRequest none{false, false, false};
        auto out = sys->addPasses(graph, bb, camera, kSize, kSize, none);
        ASSERT_TRUE(out) << out.error().message;
        const GBufferData& g = bb.get<GBufferData>();
        addCopy(graph, "copy.depth", g.depth, depth);
        addCopy(graph, "copy.position", g.position, position);
        addCopy(graph, "copy.normal", g.normal, normal);
        addCopy(graph, "copy.albedo", g.albedo, albedo);
        auto ok = graph.compile();
        ASSERT_TRUE(ok) << ok.error().message;
        rg::TransientPool pool(ctx());
        ctx().submitAndWait([&](VkCommandBuffer cmd) { graph.execute(cmd, ctx(), pool); });
    }

    HostGBuffer gbuffer(bool withPosition) const {
        HostGBuffer g;
        g.depth = hostImage(depth, rg::Access::ComputeSampledRead);
        g.normal = hostImage(normal, rg::Access::ComputeSampledRead);
        g.albedo = hostImage(albedo, rg::Access::ComputeSampledRead);
        if (withPosition)
            g.position = hostImage(position, rg::Access::ComputeSampledRead);
        return g;
    }

    // Reads a host RGBA32F image (in ComputeSampledRead) back to the CPU.
    HdrImage readHostImage(const Image& image) {
        Buffer buffer = createBuffer(ctx(), {VkDeviceSize(kSize) * kSize * 16, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                             MemoryUsage::GpuToCpu},
                                     "test.readback");
        rg::RenderGraph graph;
        rg::ImageHandle h = graph.importImage("host.output", image, rg::Access::FragmentSampledRead);
        addReadbackPass(graph, "readback", h, buffer);
        EXPECT_TRUE(graph.compile());
        rg::TransientPool pool(ctx());
        ctx().submitAndWait([&](VkCommandBuffer cmd) { graph.execute(cmd, ctx(), pool); });
        HdrImage out = readbackToImage(buffer, kSize, kSize);
        destroyBuffer(ctx(), buffer);
        return out;
    }

    HdrImage internalIndirect(Technique t) {
        auto sys = system(t);
        EXPECT_TRUE(sys);
        if (!sys)
            return {};
        FrameRequest request;
        request.indirect = true;
        auto frame = sys->renderFrame(camera, kSize, kSize, request);
        EXPECT_TRUE(frame) << frame.error().message;
        return frame ? frame->indirect : HdrImage{};
    }

    Scene scene;
    Camera camera;
    Image depth, position, normal, albedo, output32, output16;
};

} // namespace

// Same positions, normals and albedo as the G-buffer pass: the same indirect light, bit for bit,
// both in FrameResult::indirect and in the host's RGBA32F output image.
TEST_F(HostGBufferTest, HostPositionsGiveTheInternalIndirectExactly) {
    HdrImage internal = internalIndirect(Technique::Vpl);
    ASSERT_FALSE(internal.empty());
    ASSERT_GT(meanRgb(internal), 0.01); // the Cornell box has visible indirect light

    auto sys = system(Technique::Vpl);
    ASSERT_TRUE(sys);
    HostFrame frame;
    frame.gbuffer = gbuffer(true);
    frame.indirect = hostImage(output32, rg::Access::None);
    frame.indirectFinalAccess = rg::Access::FragmentSampledRead;
    frame.readback = true;
    auto r = sys->renderIndirect(camera, frame);
    ASSERT_TRUE(r) << r.error().message;
    ASSERT_EQ(r->indirect.width, kSize);
    EXPECT_TRUE(r->composite.empty());
    EXPECT_TRUE(r->direct.empty());
    EXPECT_EQ(maxDifference(r->indirect, internal), 0.0);
    // No G-buffer pass and no direct light on this path.
    for (const rg::PassTiming& p : r->passes) {
        EXPECT_NE(p.name, "gi.gbuffer");
        EXPECT_NE(p.name, "gi.direct");
    }
    EXPECT_EQ(maxDifference(readHostImage(output32), internal), 0.0);

    // The next frame states the final accesses of this one (a wrong layout would be a
    // validation error) and gives the same light.
    frame.gbufferFinalAccess = rg::Access::TransferRead;
    frame.indirectFinalAccess = rg::Access::ComputeSampledRead;
    auto second = sys->renderIndirect(camera, frame);
    ASSERT_TRUE(second) << second.error().message;
    frame.gbuffer = gbuffer(true);
    for (HostImage* im : {&frame.gbuffer.normal, &frame.gbuffer.albedo, &frame.gbuffer.position})
        im->access = rg::Access::TransferRead;
    frame.indirect.access = rg::Access::ComputeSampledRead;
    frame.indirectFinalAccess = rg::Access::FragmentSampledRead;
    auto third = sys->renderIndirect(camera, frame);
    ASSERT_TRUE(third) << third.error().message;
    EXPECT_EQ(maxDifference(third->indirect, internal), 0.0);
    EXPECT_EQ(maxDifference(readHostImage(output32), internal), 0.0);
}

// Positions reconstructed from D32 depth differ from the rasterised ones by float rounding. On
// lavapipe the image mean moves by 1.1e-5 relative and the largest pixel by 1.1e-3 nits (0.7% of
// the mean, at silhouettes); the bounds leave about 4x margin. Also blits into an RGBA16F output.
TEST_F(HostGBufferTest, DepthOnlyGBufferMatchesWithinRounding) {
    HdrImage internal = internalIndirect(Technique::Vpl);
    ASSERT_FALSE(internal.empty());
    auto sys = system(Technique::Vpl);
    ASSERT_TRUE(sys);
    HostFrame frame;
    frame.gbuffer = gbuffer(false);
    frame.indirect = hostImage(output16, rg::Access::None);
    frame.readback = true;
    auto r = sys->renderIndirect(camera, frame);
    ASSERT_TRUE(r) << r.error().message;
    bool ranPositionPass = false;
    for (const rg::PassTiming& p : r->passes)
        ranPositionPass = ranPositionPass || p.name == "gi.host.position";
    EXPECT_TRUE(ranPositionPass);
    double m = meanRgb(internal);
    EXPECT_NEAR(meanRgb(r->indirect), m, 1e-4 * m);
    EXPECT_LT(maxDifference(r->indirect, internal), 3e-2 * m);
    std::printf("depth-only host G-buffer: mean %.7f vs %.7f, max pixel difference %.3g nits\n", meanRgb(r->indirect), m,
                maxDifference(r->indirect, internal));
}

// The same passes in a host graph: only the indirect image comes back, marked as output.
TEST_F(HostGBufferTest, AddPassesIntoAHostGraph) {
    auto sys = system(Technique::Vpl);
    ASSERT_TRUE(sys);
    rg::RenderGraph graph;
    rg::Blackboard bb;
    auto out = sys->addPasses(graph, bb, camera, gbuffer(true));
    ASSERT_TRUE(out) << out.error().message;
    EXPECT_TRUE(out->indirect.valid());
    EXPECT_FALSE(out->composite.valid());
    EXPECT_FALSE(out->direct.valid());
    EXPECT_FALSE(bb.has<DirectData>() && bb.get<DirectData>().direct.valid());
    auto ok = graph.compile();
    ASSERT_TRUE(ok) << ok.error().message;
    rg::TransientPool pool(ctx());
    ctx().submitAndWait([&](VkCommandBuffer cmd) { graph.execute(cmd, ctx(), pool); });
}

TEST_F(HostGBufferTest, BadInputNamesTheField) {
    auto vpl = system(Technique::Vpl);
    auto none = system(Technique::None);
    ASSERT_TRUE(vpl && none);
    HostFrame frame;
    frame.gbuffer = gbuffer(true);
    frame.readback = true;
    auto expectError = [&](GiSystem& sys, const HostFrame& f, const std::string& needle) {
        auto r = sys.renderIndirect(camera, f);
        ASSERT_FALSE(r);
        EXPECT_NE(r.error().message.find(needle), std::string::npos) << r.error().message;
    };
    expectError(*none, frame, "technique none");
    HostFrame bad = frame;
    bad.gbuffer.normal.format = VK_FORMAT_R8G8B8A8_UNORM;
    expectError(*vpl, bad, "HostGBuffer.normal: format");
    bad = frame;
    bad.gbuffer.albedo.width = kSize / 2;
    expectError(*vpl, bad, "HostGBuffer.albedo: size");
    bad = frame;
    bad.gbuffer.position.usage = VK_IMAGE_USAGE_SAMPLED_BIT;
    expectError(*vpl, bad, "HostGBuffer.position: usage");
    bad = frame;
    bad.gbuffer.position = {};
    bad.gbuffer.depth = {};
    expectError(*vpl, bad, "HostGBuffer.depth");
    bad = frame;
    bad.gbuffer.normal.access = rg::Access::None;
    expectError(*vpl, bad, "HostGBuffer.normal: access None");
    bad = frame;
    bad.readback = false;
    expectError(*vpl, bad, "nothing to do");
    bad = frame;
    bad.indirect = hostImage(normal, rg::Access::None);
    bad.indirect.format = VK_FORMAT_R8G8B8A8_UNORM;
    expectError(*vpl, bad, "HostFrame.indirect: format");
    bad = frame;
    bad.indirectFinalAccess = rg::Access::TransferWrite;
    expectError(*vpl, bad, "HostFrame.indirectFinalAccess");
}

// GiSystem::record into the host's own command buffers, two frames in flight (both recorded and
// submitted before either is waited for), each into its own output image: both receive exactly
// the internal path's indirect light. The host submits; vkgi neither submits nor waits.
TEST_F(HostGBufferTest, RecordIntoHostCommandBuffersTwoFramesInFlight) {
    HdrImage internal = internalIndirect(Technique::Vpl);
    ASSERT_GT(meanRgb(internal), 0.01);
    auto sys = system(Technique::Vpl);
    ASSERT_TRUE(sys);
    ImageDesc d;
    d.format = VK_FORMAT_R32G32B32A32_SFLOAT;
    d.width = kSize;
    d.height = kSize;
    d.usage = VK_IMAGE_USAGE_SAMPLED_BIT;
    Image second = createImage(ctx(), d, "host.indirect.second");

    VkDevice device = ctx().device();
    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.queueFamilyIndex = ctx().queueFamily();
    VkCommandPool pool = VK_NULL_HANDLE;
    ASSERT_EQ(vkCreateCommandPool(device, &poolInfo, nullptr, &pool), VK_SUCCESS);
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 2;
    VkCommandBuffer cmds[2] = {};
    ASSERT_EQ(vkAllocateCommandBuffers(device, &alloc, cmds), VK_SUCCESS);

    const Image* outputs[2] = {&output32, &second};
    for (uint32_t i = 0; i < 2; ++i) {
        VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        ASSERT_EQ(vkBeginCommandBuffer(cmds[i], &begin), VK_SUCCESS);
        HostFrame frame;
        frame.gbuffer = gbuffer(true);
        frame.indirect = hostImage(*outputs[i], rg::Access::None);
        frame.indirectFinalAccess = rg::Access::FragmentSampledRead;
        auto ok = sys->record(cmds[i], camera, frame);
        ASSERT_TRUE(ok) << ok.error().message;
        ASSERT_EQ(vkEndCommandBuffer(cmds[i]), VK_SUCCESS);
        VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        submit.commandBufferCount = 1;
        submit.pCommandBuffers = &cmds[i];
        ASSERT_EQ(vkQueueSubmit(ctx().queue(), 1, &submit, VK_NULL_HANDLE), VK_SUCCESS);
    }
    ASSERT_EQ(vkQueueWaitIdle(ctx().queue()), VK_SUCCESS);
    EXPECT_EQ(maxDifference(readHostImage(output32), internal), 0.0);
    EXPECT_EQ(maxDifference(readHostImage(second), internal), 0.0);

    // What record cannot do names the field.
    HostFrame frame;
    frame.gbuffer = gbuffer(true);
    frame.readback = true;
    frame.indirect = hostImage(output32, rg::Access::FragmentSampledRead);
    auto readback = sys->record(cmds[0], camera, frame);
    ASSERT_FALSE(readback);
    EXPECT_NE(readback.error().message.find("readback"), std::string::npos) << readback.error().message;
    frame.readback = false;
    frame.indirect = {};
    auto noOutput = sys->record(cmds[0], camera, frame);
    ASSERT_FALSE(noOutput);
    EXPECT_NE(noOutput.error().message.find("HostFrame.indirect"), std::string::npos) << noOutput.error().message;

    vkDestroyCommandPool(device, pool, nullptr);
    destroyImage(ctx(), second);
}
