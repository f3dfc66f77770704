// Render graph logic without a Vulkan device: culling, versioning, validation messages, state
// round trips of imports, and barriers checked against the Khronos synchronization examples.
#include <algorithm>
#include <sstream>

#include <gtest/gtest.h>

#include "vkgi/rg/blackboard.hpp"
#include "vkgi/rg/render_graph.hpp"

namespace vkgi::rg {
namespace {

using Names = std::vector<std::string>;

ImageDesc image2d(uint32_t size, uint32_t mips = 1, VkFormat format = VK_FORMAT_R32_UINT) {
    ImageDesc d;
    d.format = format;
    d.width = d.height = size;
    d.mipLevels = mips;
    return d;
}

BufferDesc buffer(VkDeviceSize size) {
    BufferDesc d;
    d.size = size;
    return d;
}

// Pass that writes a fresh version of `h` and nothing else.
ImageHandle writer(RenderGraph& g, const std::string& name, ImageHandle h,
                   Access access = Access::ComputeStorageWrite) {
    ImageHandle out;
    g.addPass(
        name, [&](PassBuilder& b) { out = b.write(h, access); }, [](PassContext&) {});
    return out;
}

BufferHandle writer(RenderGraph& g, const std::string& name, BufferHandle h) {
    BufferHandle out;
    g.addPass(
        name, [&](PassBuilder& b) { out = b.write(h, Access::ComputeStorageWrite); }, [](PassContext&) {});
    return out;
}

// Pass that reads `h` (the mips/layers of `range`) and is kept for its side effect.
template <typename Handle>
void reader(RenderGraph& g, const std::string& name, Handle h, Access access, SubresourceRange range = {}) {
    g.addPass(
        name,
        [&](PassBuilder& b) {
            if constexpr (std::is_same_v<Handle, ImageHandle>)
                b.read(h, access, range);
            else
                b.read(h, access);
            b.sideEffect();
        },
        [](PassContext&) {});
}

// Barriers before `pass` without the first-use placeholders of transients (those only carry
// the previous frame's pool state at execute time).
std::vector<BarrierInfo> barriers(const RenderGraph& g, const std::string& pass) {
    const std::vector<BarrierInfo>* list = g.barriersBefore(pass);
    EXPECT_NE(list, nullptr) << pass;
    std::vector<BarrierInfo> out;
    if (list)
        std::copy_if(list->begin(), list->end(), std::back_inserter(out), [](auto& b) { return !b.firstUse; });
    return out;
}

std::string compileError(RenderGraph& g) {
    Result<void> r = g.compile();
    return r ? std::string("<compiled>") : r.error().message;
}

TEST(RenderGraphCull, UnusedPassIsCulled) {
    RenderGraph g;
    ImageHandle a = writer(g, "used", g.createImage("a", image2d(8)));
    writer(g, "unused", g.createImage("b", image2d(8)));
    g.markOutput(a);
    ASSERT_TRUE(g.compile());
    EXPECT_EQ(g.orderedPassNames(), Names{"used"});
    EXPECT_EQ(g.culledPassNames(), Names{"unused"});
}

TEST(RenderGraphCull, SideEffectKeepsPass) {
    RenderGraph g;
    ImageHandle t = g.createImage("t", image2d(8));
    g.addPass(
        "debug",
        [&](PassBuilder& b) {
            (void)b.write(t, Access::ComputeStorageWrite);
            b.sideEffect();
        },
        [](PassContext&) {});
    writer(g, "dropped", g.createImage("u", image2d(8)));
    ASSERT_TRUE(g.compile());
    EXPECT_EQ(g.orderedPassNames(), Names{"debug"});
    EXPECT_EQ(g.culledPassNames(), Names{"dropped"});
}

TEST(RenderGraphCull, ExportAndImportedWritesKeepPasses) {
    RenderGraph g;
    Image host;
    host.desc = image2d(8);
    ImageHandle external = g.importImage("host", host, Access::None);
    writer(g, "writes_import", external); // no reader, but the import outlives the graph
    ImageHandle t = writer(g, "writes_export", g.createImage("t", image2d(8)));
    g.exportImage(t, Access::FragmentSampledRead);
    ASSERT_TRUE(g.compile());
    EXPECT_EQ(g.orderedPassNames(), (Names{"writes_import", "writes_export"}));
    EXPECT_TRUE(g.culledPassNames().empty());
}

TEST(RenderGraphCull, ChainIsCulledTransitivelyButSharedProducerKept) {
    RenderGraph g;
    ImageHandle x = writer(g, "a", g.createImage("x", image2d(8)));
    ImageHandle y, z, out;
    g.addPass(
        "b",
        [&](PassBuilder& b) {
            b.read(x, Access::ComputeStorageRead);
            y = b.write(b.create("y", image2d(8)), Access::ComputeStorageWrite);
        },
        [](PassContext&) {});
    g.addPass(
        "c",
        [&](PassBuilder& b) {
            b.read(y, Access::ComputeStorageRead);
            z = b.write(b.create("z", image2d(8)), Access::ComputeStorageWrite);
        },
        [](PassContext&) {});
    ASSERT_TRUE(g.compile());
    EXPECT_EQ(g.culledPassNames(), (Names{"a", "b", "c"})) << "nothing reads z, so the whole chain dies";

    g.addPass(
        "d",
        [&](PassBuilder& b) {
            b.read(x, Access::ComputeStorageRead);
            out = b.write(b.create("out", image2d(8)), Access::ComputeStorageWrite);
        },
        [](PassContext&) {});
    g.markOutput(out);
    ASSERT_TRUE(g.compile());
    EXPECT_EQ(g.orderedPassNames(), (Names{"a", "d"}));
    EXPECT_EQ(g.culledPassNames(), (Names{"b", "c"}));
}

TEST(RenderGraphCull, PartialWriteKeepsPreviousVersionProducer) {
    // Mip 1 written after mip 0: the output version still holds mip 0, so its writer stays.
    RenderGraph g;
    ImageHandle h = g.createImage("chain", image2d(8, 2));
    ImageHandle v1, v2;
    g.addPass(
        "mip0", [&](PassBuilder& b) { v1 = b.write(h, Access::ComputeStorageWrite, SubresourceRange::mip(0)); },
        [](PassContext&) {});
    g.addPass(
        "mip1", [&](PassBuilder& b) { v2 = b.write(v1, Access::ComputeStorageWrite, SubresourceRange::mip(1)); },
        [](PassContext&) {});
    g.markOutput(v2);
    ASSERT_TRUE(g.compile());
    EXPECT_EQ(g.orderedPassNames(), (Names{"mip0", "mip1"}));
}

TEST(RenderGraphVersions, WriteReturnsNewVersion) {
    RenderGraph g;
    ImageHandle h0 = g.createImage("img", image2d(8));
    ImageHandle h1 = writer(g, "first", h0);
    ImageHandle h2 = writer(g, "second", h1);
    EXPECT_EQ(h0.version, 0u);
    EXPECT_EQ(h1.version, 1u);
    EXPECT_EQ(h2.version, 2u);
    EXPECT_EQ(h1.index, h0.index);
    g.markOutput(h2);
    EXPECT_TRUE(g.compile());
}

TEST(RenderGraphVersions, TwoWritersOfOneVersionNameBothPasses) {
    RenderGraph g;
    ImageHandle h0 = g.createImage("albedo", image2d(8));
    g.markOutput(writer(g, "writer_a", h0));
    writer(g, "writer_b", h0);
    std::string error = compileError(g);
    EXPECT_NE(error.find("'writer_a'"), std::string::npos) << error;
    EXPECT_NE(error.find("'writer_b'"), std::string::npos) << error;
    EXPECT_NE(error.find("'albedo'"), std::string::npos) << error;
}

TEST(RenderGraphValidation, ReadOfNeverWrittenResourceNamesPassAndResource) {
    RenderGraph g;
    ImageHandle h = g.createImage("radiance", image2d(8));
    reader(g, "consumer", h, Access::ComputeSampledRead);
    std::string error = compileError(g);
    EXPECT_NE(error.find("'consumer'"), std::string::npos) << error;
    EXPECT_NE(error.find("'radiance'"), std::string::npos) << error;
    EXPECT_NE(error.find("no pass wrote"), std::string::npos) << error;
}

TEST(RenderGraphValidation, ReadOfUnwrittenMipIsAnError) {
    RenderGraph g;
    ImageHandle h = g.createImage("pyramid", image2d(8, 2));
    ImageHandle v1;
    g.addPass(
        "mip0", [&](PassBuilder& b) { v1 = b.write(h, Access::ComputeStorageWrite, SubresourceRange::mip(0)); },
        [](PassContext&) {});
    reader(g, "reads_mip1", v1, Access::ComputeStorageRead, SubresourceRange::mip(1));
    std::string error = compileError(g);
    EXPECT_NE(error.find("'reads_mip1' reads mip 1 layer 0 of 'pyramid'"), std::string::npos) << error;
}

TEST(RenderGraphValidation, StaleAndFutureVersionsAreErrors) {
    RenderGraph g;
    ImageHandle h0 = g.createImage("img", image2d(8));
    ImageHandle h1 = writer(g, "w1", h0);
    ImageHandle h2 = writer(g, "w2", h1);
    g.markOutput(h2);
    reader(g, "late_reader", h1, Access::ComputeStorageRead);
    std::string error = compileError(g);
    EXPECT_NE(error.find("'late_reader' reads 'img' v1, but pass 'w2' already wrote v2"), std::string::npos) << error;

    RenderGraph g2;
    ImageHandle future{g2.createImage("img", image2d(8)).index, 5};
    reader(g2, "time_traveller", future, Access::ComputeStorageRead);
    error = compileError(g2);
    EXPECT_NE(error.find("'time_traveller' reads 'img' v5, a version that is only written later"), std::string::npos)
        << error;
}

TEST(RenderGraphValidation, AccessInvalidForResourceKind) {
    RenderGraph g;
    BufferHandle buf = g.createBuffer("counts", buffer(64));
    g.addPass(
        "raster", [&](PassBuilder& b) { (void)b.write(buf, Access::ColorAttachmentWrite); }, [](PassContext&) {});
    std::string error = compileError(g);
    EXPECT_NE(error.find("ColorAttachmentWrite is not valid on buffer 'counts'"), std::string::npos) << error;

    RenderGraph g2;
    ImageHandle colour = g2.createImage("colour", image2d(8, 1, VK_FORMAT_R8G8B8A8_UNORM));
    g2.addPass(
        "depth", [&](PassBuilder& b) { (void)b.write(colour, Access::DepthAttachmentWrite); }, [](PassContext&) {});
    error = compileError(g2);
    EXPECT_NE(error.find("depth attachment access on colour image 'colour'"), std::string::npos) << error;
}

TEST(RenderGraphValidation, ConflictingLayoutsInOnePass) {
    RenderGraph g;
    ImageHandle h = writer(g, "w", g.createImage("img", image2d(8)));
    g.addPass(
        "both",
        [&](PassBuilder& b) {
            b.read(h, Access::ComputeSampledRead);
            b.read(h, Access::ComputeStorageRead);
            b.sideEffect();
        },
        [](PassContext&) {});
    std::string error = compileError(g);
    EXPECT_NE(error.find("'both' uses mip 0 layer 0 of 'img' as both ComputeSampledRead and ComputeStorageRead"),
              std::string::npos)
        << error;
}

TEST(RenderGraphValidation, ImportedImageMissingUsage) {
    RenderGraph g;
    PersistentImage grid;
    grid.image.desc = image2d(8);
    grid.image.desc.usage = VK_IMAGE_USAGE_SAMPLED_BIT;
    writer(g, "store", g.importImage("grid", grid));
    std::string error = compileError(g);
    EXPECT_NE(error.find("'store' uses imported 'grid' as ComputeStorageWrite"), std::string::npos) << error;
}

TEST(RenderGraphUsage, TransientUsageAccumulatesFromLiveAccesses) {
    RenderGraph g;
    ImageHandle h = writer(g, "w", g.createImage("img", image2d(8)));
    reader(g, "r", h, Access::FragmentSampledRead);
    ImageHandle unusedCopy = g.createImage("other", image2d(8));
    writer(g, "culled", unusedCopy, Access::TransferWrite);
    ASSERT_TRUE(g.compile());
    EXPECT_EQ(g.imageDesc(h).usage, VkImageUsageFlags(VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT));
    EXPECT_EQ(g.imageDesc(unusedCopy).usage, 0u) << "culled passes add no usage";
}

// Khronos synchronization examples: "Compute write to storage buffer, compute read".
TEST(RenderGraphBarriers, ComputeWriteThenComputeReadStorageBuffer) {
    RenderGraph g;
    BufferHandle b1 = writer(g, "producer", g.createBuffer("ssbo", buffer(256)));
    reader(g, "consumer", b1, Access::ComputeStorageRead);
    ASSERT_TRUE(g.compile());
    EXPECT_TRUE(barriers(g, "producer").empty()) << "a transient's first write waits on nothing in this graph";
    auto list = barriers(g, "consumer");
    ASSERT_EQ(list.size(), 1u);
    EXPECT_FALSE(list[0].image);
    EXPECT_EQ(list[0].resourceName, "ssbo");
    EXPECT_EQ(list[0].srcStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(list[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(list[0].dstStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(list[0].dstAccess, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
}

// "Compute write to storage image, graphics fragment read as sampled image", then a second
// fragment read (read-after-read: nothing) and a compute sampled read (new stage: from the write).
TEST(RenderGraphBarriers, StorageImageToFragmentSampledAndReadAfterRead) {
    RenderGraph g;
    ImageHandle h = writer(g, "write", g.createImage("img", image2d(8)));
    for (const char* name : {"frag1", "frag2"})
        reader(g, name, h, Access::FragmentSampledRead);
    reader(g, "compute", h, Access::ComputeSampledRead);
    ASSERT_TRUE(g.compile());
    auto first = barriers(g, "frag1");
    ASSERT_EQ(first.size(), 1u);
    EXPECT_EQ(first[0].srcStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(first[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(first[0].dstStages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
    EXPECT_EQ(first[0].dstAccess, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    EXPECT_EQ(first[0].oldLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(first[0].newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_TRUE(barriers(g, "frag2").empty());
    auto third = barriers(g, "compute");
    ASSERT_EQ(third.size(), 1u);
    EXPECT_EQ(third[0].dstStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(third[0].oldLayout, third[0].newLayout);
}

// "Graphics write to colour attachment, compute read as sampled image".
TEST(RenderGraphBarriers, ColorAttachmentToComputeSampled) {
    RenderGraph g;
    ImageHandle h = g.createImage("colour", image2d(8, 1, VK_FORMAT_R8G8B8A8_UNORM));
    h = writer(g, "raster", h, Access::ColorAttachmentWrite);
    reader(g, "post", h, Access::ComputeSampledRead);
    ASSERT_TRUE(g.compile());
    auto list = barriers(g, "post");
    ASSERT_EQ(list.size(), 1u);
    EXPECT_EQ(list[0].srcStages, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
    EXPECT_EQ(list[0].srcAccess, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    EXPECT_EQ(list[0].dstStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(list[0].dstAccess, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    EXPECT_EQ(list[0].oldLayout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    EXPECT_EQ(list[0].newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}

// Write-after-read: an execution dependency on the reader, no memory access in the source.
TEST(RenderGraphBarriers, WriteAfterReadIsExecutionDependency) {
    RenderGraph g;
    BufferHandle b1 = writer(g, "w1", g.createBuffer("buf", buffer(64)));
    reader(g, "read", b1, Access::ComputeStorageRead);
    g.markOutput(writer(g, "w2", b1));
    ASSERT_TRUE(g.compile());
    auto list = barriers(g, "w2");
    ASSERT_EQ(list.size(), 1u);
    EXPECT_EQ(list[0].srcStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(list[0].srcAccess, VK_ACCESS_2_NONE);
    EXPECT_EQ(list[0].dstAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

// Mip chain, one pass per level: barriers only on the mips each pass touches, then a sampled
// read of the whole chain merges the equal mips into one barrier.
TEST(RenderGraphBarriers, MipChainTouchesOnlyItsMips) {
    constexpr uint32_t kMips = 4;
    RenderGraph g;
    ImageHandle h = g.createImage("pyramid", image2d(16, kMips));
    g.addPass(
        "mip[0]", [&](PassBuilder& b) { h = b.write(h, Access::ComputeStorageWrite, SubresourceRange::mip(0)); },
        [](PassContext&) {});
    for (uint32_t k = 1; k < kMips; ++k)
        g.addPass(
            "mip[" + std::to_string(k) + "]",
            [&](PassBuilder& b) {
                b.read(h, Access::ComputeStorageRead, SubresourceRange::mip(k - 1));
                h = b.write(h, Access::ComputeStorageWrite, SubresourceRange::mip(k));
            },
            [](PassContext&) {});
    reader(g, "consume", h, Access::ComputeSampledRead);
    ASSERT_TRUE(g.compile());
    EXPECT_EQ(h.version, kMips);
    for (uint32_t k = 1; k < kMips; ++k) {
        const auto* all = g.barriersBefore("mip[" + std::to_string(k) + "]");
        ASSERT_NE(all, nullptr);
        ASSERT_EQ(all->size(), 2u) << "read-after-write on mip k-1 and first use of mip k";
        const BarrierInfo& raw = (*all)[0].firstUse ? (*all)[1] : (*all)[0];
        const BarrierInfo& init = (*all)[0].firstUse ? (*all)[0] : (*all)[1];
        EXPECT_EQ(raw.range, (SubresourceRange{k - 1, 1, 0, 1}));
        EXPECT_EQ(raw.srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
        EXPECT_EQ(raw.dstAccess, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
        EXPECT_EQ(raw.oldLayout, VK_IMAGE_LAYOUT_GENERAL);
        EXPECT_EQ(init.range, (SubresourceRange{k, 1, 0, 1}));
        EXPECT_EQ(init.oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
        EXPECT_EQ(init.newLayout, VK_IMAGE_LAYOUT_GENERAL);
    }
    auto last = barriers(g, "consume");
    ASSERT_EQ(last.size(), 2u);
    EXPECT_EQ(last[0].range, (SubresourceRange{0, kMips - 1, 0, 1})) << "mips that were last read";
    EXPECT_EQ(last[0].srcAccess, VK_ACCESS_2_NONE);
    EXPECT_EQ(last[1].range, (SubresourceRange{kMips - 1, 1, 0, 1})) << "the last mip was last written";
    EXPECT_EQ(last[1].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    for (const BarrierInfo& b : last)
        EXPECT_EQ(b.newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}

TEST(RenderGraphBarriers, DiscardWriteUsesUndefinedOldLayout) {
    RenderGraph g;
    PersistentImage img;
    img.image.desc = image2d(8);
    img.state.assign(1, stateAfter(Access::ComputeStorageWrite));
    ImageHandle h = g.importImage("history", img);
    writer(g, "overwrite", h, Access::ComputeStorageWriteDiscard);
    ASSERT_TRUE(g.compile());
    auto list = barriers(g, "overwrite");
    ASSERT_EQ(list.size(), 1u);
    EXPECT_EQ(list[0].oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
    EXPECT_EQ(list[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT) << "still ordered after the old write";
}

TEST(RenderGraphImport, PersistentStateRoundTripsAcrossFrames) {
    PersistentImage volume;
    volume.image.desc = image2d(8);
    {
        RenderGraph frame1;
        writer(frame1, "inject", frame1.importImage("lpv", volume));
        ASSERT_TRUE(frame1.compile());
        frame1.storeFinalStates();
    }
    ASSERT_EQ(volume.state.size(), 1u);
    EXPECT_EQ(volume.state[0].layout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(volume.state[0].writeStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    {
        RenderGraph frame2;
        ImageHandle h = frame2.importImage("lpv", volume);
        reader(frame2, "shade", h, Access::FragmentSampledRead);
        ASSERT_TRUE(frame2.compile());
        auto list = barriers(frame2, "shade");
        ASSERT_EQ(list.size(), 1u) << "the previous frame's write is waited on";
        EXPECT_EQ(list[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
        EXPECT_EQ(list[0].oldLayout, VK_IMAGE_LAYOUT_GENERAL);
        EXPECT_EQ(list[0].newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        frame2.storeFinalStates();
    }
    EXPECT_EQ(volume.state[0].layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    {
        RenderGraph frame3;
        writer(frame3, "inject", frame3.importImage("lpv", volume));
        ASSERT_TRUE(frame3.compile());
        auto list = barriers(frame3, "inject");
        ASSERT_EQ(list.size(), 1u);
        EXPECT_EQ(list[0].srcStages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT) << "write after the last frame's read";
        EXPECT_EQ(list[0].srcAccess, VK_ACCESS_2_NONE);
        EXPECT_EQ(list[0].oldLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }
}

TEST(RenderGraphImport, ExportToPresentAddsFinalBarrier) {
    RenderGraph g;
    Image swap;
    swap.desc = image2d(8, 1, VK_FORMAT_B8G8R8A8_UNORM);
    ImageHandle h = g.importImage("swapchain", swap, Access::Present);
    h = writer(g, "draw", h, Access::ColorAttachmentWrite);
    g.exportImage(h, Access::Present);
    ASSERT_TRUE(g.compile());
    auto first = barriers(g, "draw");
    ASSERT_EQ(first.size(), 1u);
    EXPECT_EQ(first[0].oldLayout, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
    EXPECT_EQ(first[0].newLayout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    const auto& fin = g.compiled().finalBarriers;
    ASSERT_EQ(fin.size(), 1u);
    EXPECT_EQ(fin[0].srcStages, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
    EXPECT_EQ(fin[0].srcAccess, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    EXPECT_EQ(fin[0].dstStages, VK_PIPELINE_STAGE_2_NONE);
    EXPECT_EQ(fin[0].newLayout, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
}

TEST(RenderGraphBarriers, OnePassBatchesAllItsBarriers) {
    RenderGraph g;
    ImageHandle a = writer(g, "wa", g.createImage("a", image2d(8)));
    ImageHandle b2 = writer(g, "wb", g.createImage("b", image2d(8)));
    BufferHandle c = writer(g, "wc", g.createBuffer("c", buffer(64)));
    g.addPass(
        "gather",
        [&](PassBuilder& b) {
            b.read(a, Access::ComputeSampledRead);
            b.read(b2, Access::ComputeStorageRead);
            b.read(c, Access::ComputeStorageRead);
            b.sideEffect();
        },
        [](PassContext&) {});
    ASSERT_TRUE(g.compile());
    auto list = barriers(g, "gather");
    ASSERT_EQ(list.size(), 3u);
    EXPECT_EQ(list[0].resourceName, "a");
    EXPECT_EQ(list[1].resourceName, "b");
    EXPECT_EQ(list[2].resourceName, "c");
}

TEST(RenderGraphApi, TypedPassAndBlackboard) {
    struct GBufferData {
        ImageHandle albedo;
    };
    RenderGraph g;
    Blackboard bb;
    int executed = 0;
    const GBufferData& gb = g.addPass<GBufferData>(
        "gbuffer",
        [&](PassBuilder& b, GBufferData& d) {
            d.albedo =
                b.write(b.create("albedo", image2d(8, 1, VK_FORMAT_R8G8B8A8_UNORM)), Access::ColorAttachmentWrite);
        },
        [&executed](const GBufferData&, PassContext&) { ++executed; });
    bb.add(gb);
    EXPECT_TRUE(bb.has<GBufferData>());
    EXPECT_FALSE(bb.has<int>());
    g.markOutput(bb.get<GBufferData>().albedo);
    ASSERT_TRUE(g.compile());
    EXPECT_EQ(g.orderedPassNames(), Names{"gbuffer"});
    EXPECT_EQ(bb.get<GBufferData>().albedo.version, 1u);
}

TEST(RenderGraphDot, CulledPassIsGreyed) {
    RenderGraph g;
    g.markOutput(writer(g, "kept", g.createImage("a", image2d(8))));
    writer(g, "culled_pass", g.createImage("b", image2d(8)));
    ASSERT_TRUE(g.compile());
    std::ostringstream dot;
    g.writeDot(dot);
    std::string text = dot.str();
    EXPECT_EQ(text.rfind("digraph", 0), 0u);
    std::istringstream lines(text);
    std::string line, culledLine, keptLine;
    while (std::getline(lines, line)) {
        if (line.find("\"culled_pass\"") != std::string::npos)
            culledLine = line;
        if (line.find("\"kept\"") != std::string::npos)
            keptLine = line;
    }
    EXPECT_NE(culledLine.find("fillcolor=lightgrey"), std::string::npos) << text;
    EXPECT_EQ(keptLine.find("lightgrey"), std::string::npos) << text;
    EXPECT_NE(text.find("\"a\\nv1\""), std::string::npos) << "resource versions are labelled";
}

} // namespace
} // namespace vkgi::rg
