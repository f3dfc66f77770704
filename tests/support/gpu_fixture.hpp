#pragma once
// Base fixture of every GPU test: a lavapipe device (VK_DRIVER_FILES is set by CTest) with the
// Khronos validation layer and synchronization validation on. Any validation message fails
// the test in TearDown, counted after the device is destroyed (which reports leaked objects).
// Without a usable device the test is skipped, unless GI_REQUIRE_GPU=1 (set by CI), where that
// is a failure.
#include <memory>

#include <gtest/gtest.h>

#include "vkgi/context.hpp"

namespace vkgi::test {

class GpuTest : public ::testing::Test {
protected:
    void SetUp() override;
    void TearDown() override;
    Context& ctx() { return *m_ctx; }

    // Validation messages so far (for tests that provoke one on purpose and then clear it).
    ValidationLog& validation() { return m_ctx->validation(); }

private:
    std::unique_ptr<Context> m_ctx;
};

// True when GI_REQUIRE_GPU=1: a missing device is then a failure, not a skip.
bool gpuRequired();

// The device every GPU test uses: lavapipe (unless VKGI_DEVICE names another) with validation
// and synchronization validation on.
Result<std::unique_ptr<Context>> buildTestContext();

} // namespace vkgi::test
