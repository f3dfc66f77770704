#pragma once
// Paths the test harness hands to tests through the environment (set by tests/CMakeLists.txt).
#include <filesystem>

namespace vkgi::test {
// Folder for artefacts a test writes (actual/diff images, DOT dumps); created on demand.
std::filesystem::path outputDir();
// The repository root (for tests/assets and golden data).
std::filesystem::path sourceDir();
// outputDir() / `relative`, emptied (created when missing): a test's own scratch folder.
std::filesystem::path freshOutputDir(const std::filesystem::path& relative);
// Number of entries in `dir` (to prove a failed write left no temporary or partial file).
size_t countEntries(const std::filesystem::path& dir);
} // namespace vkgi::test
