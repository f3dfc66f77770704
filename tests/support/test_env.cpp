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

std::filesystem::path freshOutputDir(const std::filesystem::path& relative) {
    std::filesystem::path dir = outputDir() / relative;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

size_t countEntries(const std::filesystem::path& dir) {
    size_t n = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir))
        ++n;
    return n;
}

} // namespace vkgi::test
