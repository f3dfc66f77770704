#pragma once
namespace vkgi::gi {
// The library version, "MAJOR.MINOR.PATCH", as configured by CMake.
const char* version();
} // namespace vkgi::gi
