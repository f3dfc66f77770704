#pragma once
// VKGI_CHECK is always on (release builds too). A failed Vulkan call throws VulkanError; every
// public entry point of GiSystem, DeviceBuilder::build and wrapExternalDevice catch it and return
// the message as Result's error, so a device loss or an exhausted heap never aborts the host.
// Lower-level engine functions (resources.hpp, pipeline.hpp, the render graph) let it through to
// their caller. VKGI_ASSERT is for programming errors (misuse of an API) and still aborts.
#include <stdexcept>

#include <vulkan/vulkan.h>

namespace vkgi {

// Name of a VkResult value ("VK_ERROR_DEVICE_LOST"); the 1.3.239 headers lack vk_enum_string_helper.h.
const char* toString(VkResult result);

// A failed Vulkan call: what() is one line, "vkQueueSubmit2 failed: VK_ERROR_DEVICE_LOST (context.cpp:123)".
class VulkanError : public std::runtime_error {
public:
    VulkanError(const char* file, int line, const char* expr, VkResult result);
    VkResult result() const { return m_result; }

private:
    VkResult m_result;
};

[[noreturn]] void throwVulkanError(const char* file, int line, const char* expr, VkResult result);
[[noreturn]] void fatal(const char* file, int line, const char* message);

} // namespace vkgi

#define VKGI_CHECK(expr)                                                                                                 \
    do {                                                                                                               \
        VkResult vkgi_check_result_ = (expr);                                                                          \
        if (vkgi_check_result_ != VK_SUCCESS)                                                                          \
            ::vkgi::throwVulkanError(__FILE__, __LINE__, #expr, vkgi_check_result_);                                   \
    } while (0)

// Always-on invariant check for programming errors (misuse of an API), with a message; aborts.
#define VKGI_ASSERT(cond, msg)                                                                                           \
    do {                                                                                                               \
        if (!(cond))                                                                                                   \
            ::vkgi::fatal(__FILE__, __LINE__, msg);                                                                    \
    } while (0)
