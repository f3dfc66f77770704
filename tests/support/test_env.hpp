#pragma once
// Paths the test harness hands to tests through the environment (set by tests/CMakeLists.txt).
#include <filesystem>

namespace vkgi::test {
// Folder for artefacts a test writes (actual/diff images, DOT dumps); created on demand.
std::filesystem::path outputDir();
// The repository root (for tests/assets and golden data).
std::filesystem::path sourceDir();
} // namespace vkgi::test
