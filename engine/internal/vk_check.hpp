#pragma once
// VKGI_CHECK is always on (release builds too): a failed Vulkan call is a programming or
// device error the frame cannot recover from, so it prints file:line, the expression and the
// VkResult name, then aborts. Recoverable failures use Result<T> instead.
#include <vulkan/vulkan.h>

namespace vkgi {

// Name of a VkResult value ("VK_ERROR_DEVICE_LOST"); the 1.3.239 headers lack vk_enum_string_helper.h.
const char* toString(VkResult result);
[[noreturn]] void vkFatal(const char* file, int line, const char* expr, VkResult result);
[[noreturn]] void fatal(const char* file, int line, const char* message);

} // namespace vkgi

#define VKGI_CHECK(expr)                                                                                                 \
    do {                                                                                                               \
        VkResult vkgi_check_result_ = (expr);                                                                          \
        if (vkgi_check_result_ != VK_SUCCESS)                                                                          \
            ::vkgi::vkFatal(__FILE__, __LINE__, #expr, vkgi_check_result_);                                            \
    } while (0)

// Always-on invariant check for programming errors (misuse of an API), with a message.
#define VKGI_ASSERT(cond, msg)                                                                                           \
    do {                                                                                                               \
        if (!(cond))                                                                                                   \
            ::vkgi::fatal(__FILE__, __LINE__, msg);                                                                    \
    } while (0)
