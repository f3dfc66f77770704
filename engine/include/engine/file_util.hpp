#pragma once
// Whole-file text writes that never leave a half-written file: the data goes to a temporary
// file in the same folder, which is then renamed over the target.
#include <filesystem>
#include <string_view>

#include "engine/result.hpp"

namespace vkgi {

Result<void> writeFileAtomic(const std::filesystem::path& path, std::string_view contents);

} // namespace vkgi
