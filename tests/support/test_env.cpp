#include "support/test_env.hpp"

#include <cstdlib>

namespace vkgi::test {

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
