// rg::ComputePass without a Vulkan device: the access of every binding follows from the
// pipeline's reflected descriptor (type and readonly/writeonly), writes rename the caller's
// handle, and every misuse is a compile() error naming the pass and the binding.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "vkgi/rg/compute_pass.hpp"
#include "engine/test_bindings.h"

namespace vkgi::rg {
namespace {

ReflectedBinding binding(uint32_t n, VkDescriptorType type, bool readable, bool writable, const char* name) {
    ReflectedBinding b;
    b.set = 1;
    b.binding = n;
    b.type = type;
    b.readable = readable;
    b.writable = writable;
    b.name = name;
    return b;
}

// What a shader with these set-1 bindings reflects to: 0 readonly image, 1 writeonly image,
// 2 read-write image, 3 sampled image, 4 readonly buffer, 5 read-write buffer, 6 uniform buffer.
Pipeline fakePipeline() {
    Pipeline p;
    p.name = "test.comp";
    p.bindPoint = VK_PIPELINE_BIND_POINT_COMPUTE;
    p.localSize[0] = p.localSize[1] = 8;
    p.pushConstantSize = 16;
    p.bindings = {binding(0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, true, false, "src"),
                  binding(1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, false, true, "dst"),
                  binding(2, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, true, true, "acc"),
                  binding(3, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, true, false, "tex"),
                  binding(4, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, true, false, "inBuf"),
                  binding(5, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, true, true, "ioBuf"),
                  binding(6, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, true, false, "params")};
    return p;
}

ImageDesc image2d(uint32_t size, uint32_t mips = 1) {
    ImageDesc d;
    d.format = VK_FORMAT_R32_UINT;
    d.width = d.height = size;
    d.mipLevels = mips;
    return d;
}

struct Push {
    uint32_t v[4];
};

struct Fixture {
    RenderGraph g;
    Pipeline p = fakePipeline();
    ImageHandle src, dst, acc, tex;
    BufferHandle in, io, params;
    Fixture() {
        src = g.createImage("src", image2d(16, 2));
        dst = g.createImage("dst", image2d(16, 2));
        acc = g.createImage("acc", image2d(16));
        tex = g.createImage("tex", image2d(16));
        in = g.createBuffer("in", {256});
        io = g.createBuffer("io", {256});
        params = g.createBuffer("params", {256});
    }
    // A producer for every input (reading a never-written transient is an error).
    void produceInputs() {
        for (ImageHandle* h : {&src, &acc, &tex})
            g.addPass(
                "make." + g.resourceName(h->index), [&](PassBuilder& b) { *h = b.write(*h, Access::TransferWrite); },
                [](PassContext&) {});
        for (BufferHandle* h : {&in, &io, &params})
            g.addPass(
                "make." + g.resourceName(h->index), [&](PassBuilder& b) { *h = b.write(*h, Access::TransferWrite); },
                [](PassContext&) {});
    }
    std::string compileError() {
        Result<void> r = g.compile();
        return r ? std::string("<compiled>") : r.error().message;
    }
};

// The barrier into `pass` for resource `name` (the first one, whatever its range).
const BarrierInfo* barrierFor(const RenderGraph& g, const char* pass, const std::string& name) {
    const std::vector<BarrierInfo>* list = g.barriersBefore(pass);
    if (!list)
        return nullptr;
    for (const BarrierInfo& b : *list)
        if (b.resourceName == name && !b.firstUse)
            return &b;
    return nullptr;
}

TEST(ComputePass, AccessesFollowTheReflectedBindings) {
    Fixture f;
    f.produceInputs();
    const ImageHandle dstBefore = f.dst, accBefore = f.acc;
    const BufferHandle ioBefore = f.io;
    ComputePass(f.g, "pass", f.p)
        .push(Push{})
        .read(0, f.src, SubresourceRange::mip(1))
        .write(1, f.dst, SubresourceRange::mip(0))
        .write(2, f.acc)
        .sample(3, f.tex, VK_NULL_HANDLE)
        .read(4, f.in)
        .write(5, f.io)
        .read(6, f.params)
        .dispatch({16, 16, 1});
    // Writes renamed the caller's handles.
    EXPECT_EQ(f.dst.index, dstBefore.index);
    EXPECT_EQ(f.dst.version, dstBefore.version + 1);
    EXPECT_EQ(f.acc.version, accBefore.version + 1);
    EXPECT_EQ(f.io.version, ioBefore.version + 1);
    f.g.markOutput(f.dst);
    f.g.markOutput(f.acc);
    f.g.markOutput(f.io);
    ASSERT_EQ(f.compileError(), "<compiled>");

    struct Expect {
        const char* resource;
        VkAccessFlags2 access;
        VkImageLayout layout;
    } expected[] = {
        {"src", VK_ACCESS_2_SHADER_STORAGE_READ_BIT, VK_IMAGE_LAYOUT_GENERAL},
        {"acc", VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_IMAGE_LAYOUT_GENERAL},
        {"tex", VK_ACCESS_2_SHADER_SAMPLED_READ_BIT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL},
        {"in", VK_ACCESS_2_SHADER_STORAGE_READ_BIT, VK_IMAGE_LAYOUT_UNDEFINED},
        {"io", VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_IMAGE_LAYOUT_UNDEFINED},
        {"params", VK_ACCESS_2_UNIFORM_READ_BIT, VK_IMAGE_LAYOUT_UNDEFINED},
    };
    for (const Expect& e : expected) {
        const BarrierInfo* b = barrierFor(f.g, "pass", e.resource);
        ASSERT_NE(b, nullptr) << e.resource;
        EXPECT_EQ(b->dstAccess, e.access) << e.resource;
        EXPECT_EQ(b->dstStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT) << e.resource;
        if (b->image) {
            EXPECT_EQ(b->newLayout, e.layout) << e.resource;
        }
    }
    // src: only the mip the pass declared is transitioned.
    const BarrierInfo* src = barrierFor(f.g, "pass", "src");
    EXPECT_EQ(src->range.baseMip, 1u);
    EXPECT_EQ(src->range.mipCount, 1u);
    // dst is writeonly and never written before: a write-only access, no read bits.
    const BarrierInfo* dst = barrierFor(f.g, "pass", "dst");
    if (dst) {
        EXPECT_EQ(dst->dstAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    }
}

TEST(ComputePass, IndirectArgumentsAreReadAsIndirect) {
    Fixture f;
    f.produceInputs();
    ComputePass(f.g, "pass", f.p)
        .push(Push{})
        .read(0, f.src)
        .write(1, f.dst)
        .write(2, f.acc)
        .sample(3, f.tex, VK_NULL_HANDLE)
        .read(4, f.in)
        .write(5, f.io)
        .read(6, f.params)
        .dispatchIndirect(f.in, 16);
    f.g.markOutput(f.dst);
    ASSERT_EQ(f.compileError(), "<compiled>");
    const BarrierInfo* in = barrierFor(f.g, "pass", "in");
    ASSERT_NE(in, nullptr);
    EXPECT_EQ(in->dstAccess, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
    EXPECT_EQ(in->dstStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT);
}

TEST(ComputePass, OverwriteDropsThePreviousContents) {
    Fixture f;
    f.produceInputs();
    f.g.addPass(
        "make.dst", [&](PassBuilder& b) { f.dst = b.write(f.dst, Access::ComputeStorageReadWrite); },
        [](PassContext&) {});
    ComputePass(f.g, "pass", f.p)
        .push(Push{})
        .read(0, f.src)
        .overwrite(1, f.dst)
        .write(2, f.acc)
        .sample(3, f.tex, VK_NULL_HANDLE)
        .read(4, f.in)
        .write(5, f.io)
        .read(6, f.params)
        .dispatch({1, 1, 1});
    f.g.markOutput(f.dst);
    ASSERT_EQ(f.compileError(), "<compiled>");
    // Nothing needs what make.dst wrote: the overwrite does not read it.
    const std::vector<std::string> culled = f.g.culledPassNames();
    EXPECT_NE(std::find(culled.begin(), culled.end(), "make.dst"), culled.end());
    const std::vector<BarrierInfo>* list = f.g.barriersBefore("pass");
    ASSERT_NE(list, nullptr);
    bool sawDst = false;
    for (const BarrierInfo& b : *list)
        if (b.resourceName == "dst") {
            sawDst = true;
            EXPECT_EQ(b.oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
            EXPECT_EQ(b.newLayout, VK_IMAGE_LAYOUT_GENERAL);
        }
    EXPECT_TRUE(sawDst);
}

// Each misuse names the pass, the shader and the binding.
TEST(ComputePass, MisuseIsACompileErrorNamingPassAndBinding) {
    struct Case {
        const char* what;
        void (*declare)(Fixture&);
        const char* message;
    } cases[] = {
        {"read of a writable image",
         [](Fixture& f) {
             ComputePass(f.g, "p", f.p).push(Push{}).read(2, f.acc).dispatch({1, 1, 1});
         },
         "binding 2 ('acc') is read with read() but the shader may write it"},
        {"write of a readonly image",
         [](Fixture& f) {
             ComputePass(f.g, "p", f.p).push(Push{}).write(0, f.src).dispatch({1, 1, 1});
         },
         "binding 0 ('src') is readonly in the shader but bound with write()"},
        {"unknown binding",
         [](Fixture& f) { ComputePass(f.g, "p", f.p).push(Push{}).read(9, f.src).dispatch({1, 1, 1}); },
         "test.comp binding 9 is not in the shader's set 1"},
        {"binding twice",
         [](Fixture& f) {
             ComputePass(f.g, "p", f.p).push(Push{}).read(0, f.src).read(0, f.src).dispatch({1, 1, 1});
         },
         "binding 0 is bound twice"},
        {"buffer for an image",
         [](Fixture& f) { ComputePass(f.g, "p", f.p).push(Push{}).read(0, f.in).dispatch({1, 1, 1}); },
         "binding 0 ('src') is an image, given a buffer"},
        {"sampled binding as storage",
         [](Fixture& f) { ComputePass(f.g, "p", f.p).push(Push{}).read(3, f.tex).dispatch({1, 1, 1}); },
         "binding 3 ('tex') is sampled: bind it with sample()"},
        {"missing binding",
         [](Fixture& f) { ComputePass(f.g, "p", f.p).push(Push{}).read(0, f.src).dispatch({1, 1, 1}); },
         "binding 1 ('dst') is not bound"},
        {"wrong push size",
         [](Fixture& f) { ComputePass(f.g, "p", f.p).push(uint32_t(0)).read(0, f.src).dispatch({1, 1, 1}); },
         "test.comp expects 16 bytes of push constants, given 4"},
        {"never dispatched", [](Fixture& f) { ComputePass(f.g, "p", f.p).push(Push{}); },
         "pass 'p': declared but never dispatched"},
        {"uniform written",
         [](Fixture& f) { ComputePass(f.g, "p", f.p).push(Push{}).write(6, f.params).dispatch({1, 1, 1}); },
         "binding 6 ('params') is a uniform binding and cannot be written"},
    };
    for (const Case& c : cases) {
        Fixture f;
        f.produceInputs();
        c.declare(f);
        const std::string error = f.compileError();
        EXPECT_NE(error.find(c.message), std::string::npos) << c.what << ": " << error;
        EXPECT_NE(error.find("'p'"), std::string::npos) << c.what << ": " << error;
    }
}

} // namespace
} // namespace vkgi::rg

namespace vkgi {
namespace {

const ReflectedBinding* findSet1(const ShaderReflection& r, uint32_t binding) {
    for (const ReflectedBinding& b : r.bindings)
        if (b.set == 1 && b.binding == binding)
            return &b;
    return nullptr;
}

// GLSL's readonly / writeonly reach the reflection: on image variables (mip_sum.comp: readonly
// src, writeonly dst) and on buffer blocks, whose qualifiers glslang puts on every member
// (reduce.comp: writeonly buffer; tiny.comp: a buffer with neither).
TEST(SpirvReflection, ReadonlyAndWriteonlyQualifiers) {
    struct Expect {
        const char* shader;
        uint32_t binding;
        bool readable, writable;
    } cases[] = {{"engine/test/mip_sum.comp", ENGINE_MIP_SUM_BINDING_SOURCE, true, false},
                 {"engine/test/mip_sum.comp", ENGINE_MIP_SUM_BINDING_TARGET, false, true},
                 {"engine/test/reduce.comp", ENGINE_REDUCE_BINDING_LEVEL, true, false},
                 {"engine/test/reduce.comp", ENGINE_REDUCE_BINDING_VALUES, false, true},
                 {"engine/test/tiny.comp", ENGINE_TINY_BINDING_COUNTER, true, true}};
    for (const Expect& e : cases) {
        Result<std::vector<uint32_t>> code = loadSpirv(e.shader);
        ASSERT_TRUE(code) << code.error().message;
        Result<ShaderReflection> r = reflectSpirv(*code);
        ASSERT_TRUE(r) << r.error().message;
        const ReflectedBinding* b = findSet1(*r, e.binding);
        ASSERT_NE(b, nullptr) << e.shader << " binding " << e.binding;
        EXPECT_EQ(b->readable, e.readable) << e.shader << " binding " << e.binding;
        EXPECT_EQ(b->writable, e.writable) << e.shader << " binding " << e.binding;
    }
}

} // namespace
} // namespace vkgi
