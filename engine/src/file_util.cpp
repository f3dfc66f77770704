#include "vkgi/file_util.hpp"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>
#include <system_error>

#include <unistd.h>

namespace vkgi {

namespace fs = std::filesystem;

namespace {

constexpr std::string_view kTempPrefix = ".vkgi-";
constexpr std::string_view kTempSuffix = ".tmp";

Error fileError(const fs::path& path, const std::string& what) {
    return makeError(path.string() + ": " + what);
}

// A symbolic link is written through: the final target of the chain (which may not exist yet,
// as cp creates the target of a dangling link).
Result<fs::path> resolveTarget(const fs::path& path) {
    if (path.filename().empty() || path.filename() == "." || path.filename() == "..")
        return fileError(path, "not a file name");
    std::error_code ec;
    fs::path p = path;
    for (int hops = 0; fs::is_symlink(fs::symlink_status(p, ec)); ++hops) {
        if (hops == 40)
            return fileError(path, "too many levels of symbolic links");
        fs::path next = fs::read_symlink(p, ec);
        if (ec)
            return fileError(path, "cannot read the symbolic link: " + ec.message());
        p = next.is_absolute() ? next : p.parent_path() / next;
    }
    if (p == path)
        return path;
    if (fs::is_directory(p, ec))
        return fileError(path, "the symbolic link points to a folder");
    fs::path resolved = fs::weakly_canonical(p, ec);
    return ec ? p : resolved;
}

bool processAlive(long pid) {
    return pid > 0 && (::kill(pid_t(pid), 0) == 0 || errno == EPERM);
}

// Removes ".vkgi-<pid>-<n>.tmp" files in `folder` whose process is gone.
void removeStaleTemporaries(const fs::path& folder) {
    std::error_code ec;
    fs::directory_iterator it(folder.empty() ? fs::path(".") : folder, ec), end;
    for (; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.size() <= kTempPrefix.size() + kTempSuffix.size() || name.rfind(kTempPrefix, 0) != 0 ||
            name.compare(name.size() - kTempSuffix.size(), kTempSuffix.size(), kTempSuffix) != 0)
            continue;
        char* endPid = nullptr;
        const long pid = std::strtol(name.c_str() + kTempPrefix.size(), &endPid, 10);
        if (!endPid || *endPid != '-' || pid == long(::getpid()) || processAlive(pid))
            continue;
        std::error_code rm;
        fs::remove(it->path(), rm);
    }
}

fs::path temporaryFor(const fs::path& target) {
    static std::atomic<uint64_t> counter{0};
    return target.parent_path() / (std::string(kTempPrefix) + std::to_string(::getpid()) + "-" +
                                   std::to_string(counter.fetch_add(1)) + std::string(kTempSuffix));
}

} // namespace

Result<AtomicFile> AtomicFile::begin(const fs::path& target) {
    Result<fs::path> resolved = resolveTarget(target);
    if (!resolved)
        return resolved.error();
    removeStaleTemporaries(resolved->parent_path());
    return AtomicFile(*resolved, temporaryFor(*resolved));
}

AtomicFile::AtomicFile(AtomicFile&& other) noexcept
    : m_target(std::move(other.m_target)), m_temporary(std::move(other.m_temporary)), m_done(other.m_done) {
    other.m_done = true;
}

AtomicFile::~AtomicFile() {
    if (!m_done) {
        std::error_code ec;
        fs::remove(m_temporary, ec);
    }
}

Result<void> AtomicFile::commit() {
    std::error_code ec;
    fs::rename(m_temporary, m_target, ec);
    m_done = !ec;
    if (ec)
        return fileError(m_target, "cannot move the finished file into place (" + ec.message() + ")");
    return {};
}

Result<void> writeFileAtomic(const fs::path& path, std::span<const uint8_t> contents) {
    Result<AtomicFile> file = AtomicFile::begin(path);
    if (!file)
        return file.error();
    std::FILE* f = std::fopen(file->temporary().c_str(), "wb");
    if (!f)
        return fileError(path, std::string("cannot write (") + std::strerror(errno) + ")");
    bool good = std::fwrite(contents.data(), 1, contents.size(), f) == contents.size();
    good = std::fflush(f) == 0 && good;
    const int err = errno;
    good = std::fclose(f) == 0 && good;
    if (!good)
        return fileError(path, std::string("write failed (") + std::strerror(err) + ")");
    return file->commit();
}

Result<void> writeFileAtomic(const fs::path& path, std::string_view contents) {
    return writeFileAtomic(path, std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(contents.data()),
                                                          contents.size()));
}

Result<OutputFolders> OutputFolders::create(const fs::path& file) {
    OutputFolders folders;
    std::error_code ec;
    const fs::path parent = file.parent_path();
    if (parent.empty() || fs::is_directory(parent, ec))
        return folders;
    // The missing ancestors, innermost first; created outermost first.
    std::vector<fs::path> missing;
    for (fs::path p = parent; !p.empty() && !fs::exists(p, ec); p = p.parent_path()) {
        missing.push_back(p);
        if (p == p.parent_path())
            break;
    }
    // Reverse iterators, not std::views::reverse: clang 14 cannot compile libstdc++ 12's ranges
    // (the sanitizer build).
    for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
        const fs::path& p = *it;
        if (!fs::create_directory(p, ec) && ec)
            return fileError(file, "cannot create folder " + p.string() + " (" + ec.message() + ")");
        folders.m_created.push_back(p);
    }
    if (!fs::is_directory(parent, ec))
        return fileError(file, "the parent " + parent.string() + " is not a folder");
    return folders;
}

OutputFolders::~OutputFolders() {
    for (auto it = m_created.rbegin(); it != m_created.rend(); ++it) {
        std::error_code ec;
        fs::remove(*it, ec); // removes only an empty folder
    }
}

} // namespace vkgi
