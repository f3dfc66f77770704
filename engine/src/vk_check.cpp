#include "vk_check.hpp"
#include "vk_dispatch.hpp"

#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

namespace vkgi {

const char* toString(VkResult r) {
    switch (r) {
#define GI_CASE(x)                                                                                                     \
    case x:                                                                                                            \
        return #x;
        GI_CASE(VK_SUCCESS)
        GI_CASE(VK_NOT_READY)
        GI_CASE(VK_TIMEOUT)
        GI_CASE(VK_EVENT_SET)
        GI_CASE(VK_EVENT_RESET)
        GI_CASE(VK_INCOMPLETE)
        GI_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
        GI_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        GI_CASE(VK_ERROR_INITIALIZATION_FAILED)
        GI_CASE(VK_ERROR_DEVICE_LOST)
        GI_CASE(VK_ERROR_MEMORY_MAP_FAILED)
        GI_CASE(VK_ERROR_LAYER_NOT_PRESENT)
        GI_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
        GI_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
        GI_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
        GI_CASE(VK_ERROR_TOO_MANY_OBJECTS)
        GI_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
        GI_CASE(VK_ERROR_FRAGMENTED_POOL)
        GI_CASE(VK_ERROR_UNKNOWN)
        GI_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
        GI_CASE(VK_ERROR_INVALID_EXTERNAL_HANDLE)
        GI_CASE(VK_ERROR_FRAGMENTATION)
        GI_CASE(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
        GI_CASE(VK_PIPELINE_COMPILE_REQUIRED)
        GI_CASE(VK_ERROR_SURFACE_LOST_KHR)
        GI_CASE(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR)
        GI_CASE(VK_SUBOPTIMAL_KHR)
        GI_CASE(VK_ERROR_OUT_OF_DATE_KHR)
        GI_CASE(VK_ERROR_VALIDATION_FAILED_EXT)
#undef GI_CASE
    default:
        return "VK_RESULT_UNKNOWN";
    }
}

namespace {

// "vkQueueSubmit2" from "vkQueueSubmit2(queue, 1, &submit, fence)"; "gi_system.cpp" from a path.
std::string vulkanErrorMessage(const char* file, int line, const char* expr, VkResult result) {
    std::string_view call(expr);
    call = call.substr(0, call.find('('));
    while (!call.empty() && call.back() == ' ')
        call.remove_suffix(1);
    std::string_view path(file);
    if (size_t slash = path.find_last_of('/'); slash != std::string_view::npos)
        path.remove_prefix(slash + 1);
    return std::string(call) + " failed: " + toString(result) + " (" + std::string(path) + ":" + std::to_string(line) +
           ")";
}

} // namespace

VulkanError::VulkanError(const char* file, int line, const char* expr, VkResult result)
    : std::runtime_error(vulkanErrorMessage(file, line, expr, result)), m_result(result) {}

void throwVulkanError(const char* file, int line, const char* expr, VkResult result) {
    throw VulkanError(file, line, expr, result);
}

void fatal(const char* file, int line, const char* message) {
    std::fprintf(stderr, "%s:%d: fatal: %s\n", file, line, message);
    std::fflush(stderr);
    std::abort();
}

} // namespace vkgi

namespace vkgi::rg::detail {

void missingBlackboardEntry(const char* typeName) {
    std::fprintf(stderr, "fatal: Blackboard::get: no entry of type %s (its producer pass did not run first)\n", typeName);
    std::abort();
}

} // namespace vkgi::rg::detail
