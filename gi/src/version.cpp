#include "vkgi/version.hpp"
namespace vkgi::gi {
const char* version() { return GI_VERSION_STRING; }
} // namespace vkgi::gi
