#include "vk_dispatch.hpp"

#include <dlfcn.h>

#include <mutex>
#include <string>

namespace vkgi::vkfn {

#define VKGI_VK_DEFINE(name) PFN_##name name = nullptr;
PFN_vkGetInstanceProcAddr vkGetInstanceProcAddr = nullptr;
VKGI_VK_GLOBAL_FUNCTIONS(VKGI_VK_DEFINE)
VKGI_VK_INSTANCE_FUNCTIONS(VKGI_VK_DEFINE)
#undef VKGI_VK_DEFINE

} // namespace vkgi::vkfn

namespace vkgi {

namespace {

std::mutex g_loadMutex;
// What the table was last filled from: a second Context on the same loader and instance does not
// rewrite pointers other threads may be calling through.
PFN_vkGetInstanceProcAddr g_globalsFrom = nullptr;
PFN_vkGetInstanceProcAddr g_instanceFrom = nullptr;
VkInstance g_instance = VK_NULL_HANDLE;

template <typename Pfn> Result<void> load(PFN_vkGetInstanceProcAddr gipa, VkInstance instance, const char* name, Pfn& out) {
    out = reinterpret_cast<Pfn>(gipa(instance, name));
    if (!out)
        return makeError(std::string("vkGetInstanceProcAddr returned no ") + name +
                         " (vkgi needs a Vulkan 1.3 instance and device)");
    return {};
}

Result<void> loadGlobalsLocked(PFN_vkGetInstanceProcAddr gipa) {
    if (g_globalsFrom == gipa)
        return {};
    vkfn::vkGetInstanceProcAddr = gipa;
#define VKGI_VK_LOAD(name)                                                                                             \
    if (auto ok = load(gipa, VK_NULL_HANDLE, #name, vkfn::name); !ok)                                                  \
        return ok;
    VKGI_VK_GLOBAL_FUNCTIONS(VKGI_VK_LOAD)
#undef VKGI_VK_LOAD
    g_globalsFrom = gipa;
    g_instanceFrom = nullptr;
    return {};
}

} // namespace

Result<void> loaderGetInstanceProcAddr(PFN_vkGetInstanceProcAddr& gipa) {
    // Never closed: the table points into the loader for the rest of the process.
    static void* library = dlopen("libvulkan.so.1", RTLD_NOW | RTLD_LOCAL);
    if (!library)
        return makeError("cannot load the Vulkan loader libvulkan.so.1 (Debian package libvulkan1)");
    gipa = reinterpret_cast<PFN_vkGetInstanceProcAddr>(dlsym(library, "vkGetInstanceProcAddr"));
    if (!gipa)
        return makeError("libvulkan.so.1 has no vkGetInstanceProcAddr");
    return {};
}

Result<void> loadGlobalFunctions(PFN_vkGetInstanceProcAddr gipa) {
    std::lock_guard lock(g_loadMutex);
    return loadGlobalsLocked(gipa);
}

Result<void> loadInstanceFunctions(PFN_vkGetInstanceProcAddr gipa, VkInstance instance) {
    std::lock_guard lock(g_loadMutex);
    if (auto ok = loadGlobalsLocked(gipa); !ok)
        return ok;
    if (g_instanceFrom == gipa && g_instance == instance)
        return {};
#define VKGI_VK_LOAD(name)                                                                                             \
    if (auto ok = load(gipa, instance, #name, vkfn::name); !ok)                                                        \
        return ok;
    VKGI_VK_INSTANCE_FUNCTIONS(VKGI_VK_LOAD)
#undef VKGI_VK_LOAD
    g_instanceFrom = gipa;
    g_instance = instance;
    return {};
}

} // namespace vkgi
