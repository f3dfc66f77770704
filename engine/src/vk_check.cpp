#include "vk_check.hpp"

#include <cstdio>
#include <cstdlib>

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

void vkFatal(const char* file, int line, const char* expr, VkResult result) {
    std::fprintf(stderr, "%s:%d: %s -> %s\n", file, line, expr, toString(result));
    std::fflush(stderr);
    std::abort();
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
