#pragma once
// vkgi-bench's command line: the option table (apps/common/cli.hpp), the checks between
// options, and the help text. Errors are one line naming the option (exit code 2).
#include <string>

#include "vkgi/result.hpp"
#include "sweep.hpp"

namespace vkgi::bench {

// Parses argv; Options::techniques is filled with every technique when none is named.
Result<Options> parseArgs(int argc, const char* const* argv);
std::string helpText();

} // namespace vkgi::bench
