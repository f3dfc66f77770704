#include "support/gpu_fixture.hpp"

#include <cstdlib>
#include <cstring>

namespace vkgi::test {

bool gpuRequired() {
    const char* v = std::getenv("GI_REQUIRE_GPU");
    return v && std::strcmp(v, "1") == 0;
}

void GpuTest::SetUp() {
    DeviceBuilder builder = defaultDeviceBuilder();
    builder.enableValidation(true, true);
    if (!std::getenv("VKGI_DEVICE"))
        builder.preferDeviceName("llvmpipe");
    auto ctx = builder.build();
    if (!ctx) {
        if (gpuRequired())
            FAIL() << "no Vulkan device: " << ctx.error().message;
        GTEST_SKIP() << "no Vulkan device: " << ctx.error().message;
    }
    m_ctx = std::move(*ctx);
}

void GpuTest::TearDown() {
    if (!m_ctx)
        return;
    vkDeviceWaitIdle(m_ctx->device());
    uint32_t count = m_ctx->validation().count();
    EXPECT_EQ(count, 0u) << "validation messages:\n" << [&] {
        std::string all;
        for (const auto& m : m_ctx->validation().messages())
            all += "  " + m + "\n";
        return all;
    }();
    m_ctx.reset();
}

} // namespace vkgi::test
