#pragma once
// Whole-file writes that never leave a half-written file, and output folders that are removed
// again when the write they were made for fails.
//
// The data goes to a hidden temporary file in the target's folder, ".vkgi-<pid>-<n>.tmp" (short,
// so a target name of up to 255 bytes stays valid), which is then renamed over the target. A
// target that is a symbolic link is written through, as cp does: the link stays and the file it
// points to is replaced. Temporaries left by a process that no longer exists (killed during a
// write) are removed by the next write into the same folder.
#include <filesystem>
#include <span>
#include <string_view>
#include <vector>

#include "vkgi/result.hpp"

namespace vkgi {

Result<void> writeFileAtomic(const std::filesystem::path& path, std::string_view contents);
Result<void> writeFileAtomic(const std::filesystem::path& path, std::span<const uint8_t> contents);

// For writers that need a file name (OpenEXR): begin() gives the temporary to write, commit()
// renames it over the target, and the destructor removes it when commit() was not reached.
class AtomicFile {
public:
    static Result<AtomicFile> begin(const std::filesystem::path& target);
    AtomicFile(AtomicFile&& other) noexcept;
    AtomicFile& operator=(AtomicFile&&) = delete;
    AtomicFile(const AtomicFile&) = delete;
    ~AtomicFile();
    const std::filesystem::path& temporary() const { return m_temporary; }
    Result<void> commit();

private:
    AtomicFile(std::filesystem::path target, std::filesystem::path temporary)
        : m_target(std::move(target)), m_temporary(std::move(temporary)) {}
    std::filesystem::path m_target; // the file written (a symbolic link's target, resolved)
    std::filesystem::path m_temporary;
    bool m_done = false;
};

// Creates the missing folders above `file` and remembers them; release() keeps them,
// otherwise the destructor removes the ones it created (deepest first) when they are empty,
// so a failed write leaves no folder chain behind.
class OutputFolders {
public:
    static Result<OutputFolders> create(const std::filesystem::path& file);
    OutputFolders(OutputFolders&& other) noexcept : m_created(std::move(other.m_created)) { other.m_created.clear(); }
    OutputFolders& operator=(OutputFolders&&) = delete;
    OutputFolders(const OutputFolders&) = delete;
    ~OutputFolders();
    void release() { m_created.clear(); }

private:
    OutputFolders() = default;
    std::vector<std::filesystem::path> m_created; // outermost first
};

} // namespace vkgi
