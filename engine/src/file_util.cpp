#include "engine/file_util.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

#include <unistd.h>

namespace vkgi {

Result<void> writeFileAtomic(const std::filesystem::path& path, std::string_view contents) {
    std::filesystem::path tmp = path;
    tmp += ".tmp" + std::to_string(::getpid());
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out)
            return makeError(path.string() + ": cannot write (" + std::strerror(errno) + ")");
        out.write(contents.data(), std::streamsize(contents.size()));
        out.flush();
        if (!out) {
            std::error_code ec;
            std::filesystem::remove(tmp, ec);
            return makeError(path.string() + ": write failed");
        }
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        return makeError(path.string() + ": cannot move the finished file into place (" + ec.message() + ")");
    }
    return {};
}

} // namespace vkgi
