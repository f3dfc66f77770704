#include "support/gpu_fixture.hpp"

#include <cstdlib>
#include <cstring>

namespace vkgi::test {

bool gpuRequired() {
    const char* v = std::getenv("GI_REQUIRE_GPU");
    return v && std::strcmp(v, "1") == 0;
}

Result<std::unique_ptr<Context>> buildTestContext() {
    DeviceBuilder builder = defaultDeviceBuilder();
    builder.enableValidation(true, true);
    if (!std::getenv("VKGI_DEVICE"))
        builder.preferDeviceName("llvmpipe");
    return builder.build();
}

void GpuTest::SetUp() {
    auto ctx = buildTestContext();
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
    // Checked after the device is gone: destroying it reports every object the test leaked.
    const std::shared_ptr<const ValidationLog> log = m_ctx->sharedValidation();
    m_ctx.reset();
    EXPECT_EQ(log->count(), 0u) << "validation messages:\n" << [&] {
        std::string all;
        for (const auto& m : log->messages())
            all += "  " + m + "\n";
        return all;
    }();
}

} // namespace vkgi::test
