#include "support/test_env.hpp"

#include <cstdlib>

namespace vkgi::test {

namespace {
// Runs before main(), so the Vulkan loader sees VK_DRIVER_FILES on its first call. A value
// already in the environment wins (VKGI_DEVICE / a real GPU, a CI-provided cache folder).
struct DefaultEnvironment {
    DefaultEnvironment() {
        setenv("VK_DRIVER_FILES", VKGI_TEST_ICD, 0);
        setenv("MESA_SHADER_CACHE_DIR", VKGI_TEST_SHADER_CACHE, 0);
        setenv("VKGI_TEST_OUTPUT_DIR", VKGI_TEST_OUTPUT, 0);
        setenv("VKGI_SOURCE_DIR", VKGI_TEST_SOURCE, 0);
    }
} const kDefaultEnvironment;
} // namespace

std::filesystem::path outputDir() {
    const char* env = std::getenv("VKGI_TEST_OUTPUT_DIR");
    std::filesystem::path dir = env ? env : std::filesystem::temp_directory_path() / "vkgi-test-output";
    std::filesystem::create_directories(dir);
    return dir;
}

std::filesystem::path sourceDir() {
    const char* env = std::getenv("VKGI_SOURCE_DIR");
    return env ? std::filesystem::path(env) : std::filesystem::current_path();
}

} // namespace vkgi::test
