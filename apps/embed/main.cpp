// vkgi-embed: the minimal host of docs/embedding.md. It owns its Vulkan instance, device and
// queue (raw Vulkan, no vkgi helpers), wraps them for vkgi, renders one frame of a scene with a
// GI technique, prints the image mean and writes the image. It includes only vkgi's installed
// public headers, so the same file builds in the main tree and, through find_package(vkgi), in
// tests/package against the installed package.
//
//   vkgi-embed [--scene NAME|FILE] [--technique T] [--size WxH] [--out FILE.exr|.png] [--validate]
//              [--host-graph]
//
// --validate enables the Khronos validation layer with synchronization validation on the host's
// instance; any message makes the exit code 3. --host-graph adds vkgi's passes to the host's own
// render graph, recorded into the host's command buffer and submitted by the host, instead of
// GiSystem::renderFrame (the image is the same).
//
// Built with VKGI_EMBED_VOLK (tests/package's vkgi-embed-volk), the host loads Vulkan through
// volk, as many engines do, and hands volk's vkGetInstanceProcAddr to vkgi in ExternalDevice:
// vkgi then calls nothing of the Vulkan loader's that the host did not give it.
#include <algorithm>
#include <atomic>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <string>
#include <vector>

#ifdef VKGI_EMBED_VOLK
#include <volk.h> // before any Vulkan header: the vk* names are volk's function pointers
#else
#include <vulkan/vulkan.h>
#endif

#include "vkgi/context.hpp"
#include "vkgi/gltf_loader.hpp"
#include "vkgi/image_io.hpp"
#include "vkgi/resources.hpp"
#include "vkgi/rg/blackboard.hpp"
#include "vkgi/rg/transient_pool.hpp"
#include "vkgi/gi.hpp"

namespace {

struct Options {
    std::string scene = "cornell";
    std::string technique = "vpl";
    uint32_t width = 64;
    uint32_t height = 64;
    std::string out = "embed.exr";
    bool validate = false;
    bool hostGraph = false;
};

int fail(const std::string& message) {
    std::fprintf(stderr, "vkgi-embed: %s\n", message.c_str());
    return 1;
}

bool parseSide(std::string_view text, uint32_t& side) {
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), side);
    return ec == std::errc() && end == text.data() + text.size() && side >= 1 && side <= 16384;
}

// The errors read as the other apps' (apps/common/args.hpp), which this file cannot use: it
// includes only vkgi's installed headers.
vkgi::Result<Options> parseArgs(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        std::string arg = argv[i];
        if (arg == "--validate" || arg == "--host-graph") {
            (arg == "--validate" ? o.validate : o.hostGraph) = true;
            continue;
        }
        if (arg != "--scene" && arg != "--technique" && arg != "--size" && arg != "--out")
            return vkgi::makeError("unknown option '" + arg + "' (options: --scene --technique --size --out --validate --host-graph)");
        if (i + 1 == argc)
            return vkgi::makeError(arg + " needs a value");
        std::string value = argv[++i];
        if (arg == "--scene") {
            o.scene = value;
        } else if (arg == "--technique") {
            o.technique = value;
        } else if (arg == "--out") {
            if (!value.ends_with(".exr") && !value.ends_with(".png"))
                return vkgi::makeError("--out: expected a file name ending in .exr or .png, got '" + value + "'");
            o.out = value;
        } else {
            size_t x = value.find('x');
            if (x == std::string::npos || !parseSide(std::string_view(value).substr(0, x), o.width) ||
                !parseSide(std::string_view(value).substr(x + 1), o.height))
                return vkgi::makeError("--size: expected WxH with each side 1..16384, got '" + value + "'");
        }
    }
    return o;
}

// ---- The host's own Vulkan objects: everything vkgi needs is listed in docs/embedding.md. ----

std::atomic<uint32_t> g_validationMessages{0};

VKAPI_ATTR VkBool32 VKAPI_CALL onValidation(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                            VkDebugUtilsMessageTypeFlagsEXT, const VkDebugUtilsMessengerCallbackDataEXT* data,
                                            void*) {
    ++g_validationMessages;
    std::fprintf(stderr, "validation: %s\n", data->pMessage);
    return VK_FALSE;
}

struct HostVulkan {
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t queueFamily = 0;

    ~HostVulkan() {
        if (device)
            vkDestroyDevice(device, nullptr);
        if (messenger) {
            auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
            destroy(instance, messenger, nullptr);
        }
        if (instance)
            vkDestroyInstance(instance, nullptr);
    }
};

vkgi::Result<void> createInstance(HostVulkan& host, bool validate) {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "vkgi-embed";
    app.apiVersion = VK_API_VERSION_1_3; // vkgi needs Vulkan 1.3
    const char* layer = "VK_LAYER_KHRONOS_validation";
    const char* debugUtils = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
    VkValidationFeatureEnableEXT sync = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
    VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = &sync;
    VkDebugUtilsMessengerCreateInfoEXT messenger{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    messenger.messageSeverity =
        VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                            VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                            VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    messenger.pfnUserCallback = onValidation;
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
#ifdef VKGI_EMBED_VOLK
    if (volkInitialize() != VK_SUCCESS)
        return vkgi::makeError("volkInitialize failed: no Vulkan loader");
#endif
    if (validate) {
        features.pNext = &messenger;
        info.pNext = &features;
        info.enabledLayerCount = 1;
        info.ppEnabledLayerNames = &layer;
        info.enabledExtensionCount = 1;
        info.ppEnabledExtensionNames = &debugUtils;
    }
    if (VkResult r = vkCreateInstance(&info, nullptr, &host.instance); r != VK_SUCCESS)
        return vkgi::makeError("vkCreateInstance failed (" + std::to_string(int(r)) +
                               (validate ? "); is the Khronos validation layer installed?" : ")"));
#ifdef VKGI_EMBED_VOLK
    volkLoadInstance(host.instance);
#endif
    if (validate) {
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(host.instance, "vkCreateDebugUtilsMessengerEXT"));
        if (!create || create(host.instance, &messenger, nullptr, &host.messenger) != VK_SUCCESS)
            return vkgi::makeError("cannot create the debug messenger");
    }
    return {};
}

bool hasExtension(VkPhysicalDevice pd, const char* name) {
    uint32_t n = 0;
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, nullptr);
    std::vector<VkExtensionProperties> exts(n);
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, exts.data());
    for (const auto& e : exts)
        if (std::strcmp(e.extensionName, name) == 0)
            return true;
    return false;
}

// First Vulkan 1.3 device with vkgi's extensions and a graphics+compute queue.
vkgi::Result<void> createDevice(HostVulkan& host) {
    uint32_t n = 0;
    vkEnumeratePhysicalDevices(host.instance, &n, nullptr);
    std::vector<VkPhysicalDevice> devices(n);
    vkEnumeratePhysicalDevices(host.instance, &n, devices.data());
    for (VkPhysicalDevice pd : devices) {
        VkPhysicalDeviceProperties props;
        vkGetPhysicalDeviceProperties(pd, &props);
        if (props.apiVersion < VK_API_VERSION_1_3 ||
            !std::all_of(std::begin(vkgi::kRequiredDeviceExtensions), std::end(vkgi::kRequiredDeviceExtensions),
                         [pd](const char* e) { return hasExtension(pd, e); }))
            continue;
        uint32_t familyCount = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(pd, &familyCount, nullptr);
        std::vector<VkQueueFamilyProperties> families(familyCount);
        vkGetPhysicalDeviceQueueFamilyProperties(pd, &familyCount, families.data());
        for (uint32_t f = 0; f < familyCount; ++f) {
            VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
            if ((families[f].queueFlags & need) != need)
                continue;
            host.physicalDevice = pd;
            host.queueFamily = f;
            break;
        }
        if (host.physicalDevice)
            break;
    }
    if (!host.physicalDevice)
        return vkgi::makeError("no Vulkan 1.3 device with VK_KHR_push_descriptor and a graphics+compute queue");

    // The features vkgi needs (docs/embedding.md); the optional core ones only when supported.
    VkPhysicalDeviceFeatures2 supported{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    vkGetPhysicalDeviceFeatures2(host.physicalDevice, &supported);
    const vkgi::DeviceFeatureChain enabled(supported.features);

    float priority = 1.0f;
    VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queue.queueFamilyIndex = host.queueFamily;
    queue.queueCount = 1;
    queue.pQueuePriorities = &priority;
    VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    info.pNext = &enabled.features;
    info.queueCreateInfoCount = 1;
    info.pQueueCreateInfos = &queue;
    info.enabledExtensionCount = uint32_t(std::size(vkgi::kRequiredDeviceExtensions));
    info.ppEnabledExtensionNames = vkgi::kRequiredDeviceExtensions;
    if (VkResult r = vkCreateDevice(host.physicalDevice, &info, nullptr, &host.device); r != VK_SUCCESS)
        return vkgi::makeError("vkCreateDevice failed (" + std::to_string(int(r)) + ")");
#ifdef VKGI_EMBED_VOLK
    volkLoadDevice(host.device); // the host's own device calls skip the loader's dispatch
#endif
    vkGetDeviceQueue(host.device, host.queueFamily, 0, &host.queue);
    return {};
}

// ---- Host-graph mode: the host records and submits; vkgi only adds passes. ----

struct ReadbackPass {
    vkgi::rg::ImageHandle image;
    vkgi::rg::BufferHandle buffer;
};

// One frame of vkgi's passes plus the host's own readback pass in a host graph, executed into the
// host's command buffer and submitted to the host's queue. Returns the composite image.
vkgi::Result<vkgi::HdrImage> renderInHostGraph(const HostVulkan& host, vkgi::Context& ctx, vkgi::gi::GiSystem& gi,
                                               const vkgi::Camera& camera, uint32_t width, uint32_t height) {
    namespace rg = vkgi::rg;
    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT; // one command buffer, re-recorded each frame
    poolInfo.queueFamilyIndex = host.queueFamily;
    VkCommandPool pool = VK_NULL_HANDLE;
    if (vkCreateCommandPool(host.device, &poolInfo, nullptr, &pool) != VK_SUCCESS)
        return vkgi::makeError("vkCreateCommandPool failed");
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    vkAllocateCommandBuffers(host.device, &alloc, &cmd);
    VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence = VK_NULL_HANDLE;
    vkCreateFence(host.device, &fenceInfo, nullptr, &fence);
    vkgi::Buffer readback = vkgi::createBuffer(
        ctx, {VkDeviceSize(width) * height * 16, VK_BUFFER_USAGE_TRANSFER_DST_BIT, vkgi::MemoryUsage::GpuToCpu},
        "embed.readback");
    vkgi::Result<vkgi::HdrImage> result = vkgi::HdrImage{};
    {
        rg::TransientPool transients(ctx); // graph transients, reused across frames; outlives the GPU work
        // Two frames, as vkgi-render renders them; each must finish before the next addPasses.
        for (int frame = 0; frame < 2 && result; ++frame) {
            rg::RenderGraph graph;
            rg::Blackboard blackboard;
            vkgi::gi::FrameRequest request; // composite only
            auto outputs = gi.addPasses(graph, blackboard, camera, width, height, request);
            if (!outputs) {
                result = outputs.error();
                break;
            }
            rg::BufferHandle buffer = graph.importBuffer("embed.readback", readback, rg::Access::HostRead);
            const ReadbackPass& copy = graph.addPass<ReadbackPass>(
                "embed.readback",
                [&](rg::PassBuilder& b, ReadbackPass& d) {
                    b.read(outputs->composite, rg::Access::TransferRead);
                    d.image = outputs->composite;
                    d.buffer = b.write(buffer, rg::Access::TransferWrite);
                },
                [](const ReadbackPass& d, rg::PassContext& pc) {
                    const vkgi::Image& image = pc.image(d.image);
                    VkBufferImageCopy region{};
                    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
                    region.imageExtent = {image.desc.width, image.desc.height, 1};
                    vkCmdCopyImageToBuffer(pc.cmd(), image.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                           pc.buffer(d.buffer).buffer, 1, &region);
                });
            graph.exportBuffer(copy.buffer, rg::Access::HostRead); // barriers make it visible to the host
            if (auto ok = graph.compile(); !ok) {
                result = ok.error();
                break;
            }
            vkResetCommandBuffer(cmd, 0);
            VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
            begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
            vkBeginCommandBuffer(cmd, &begin);
            graph.execute(cmd, ctx, transients); // the host's own passes could be recorded around it
            vkEndCommandBuffer(cmd);
            VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
            submit.commandBufferCount = 1;
            submit.pCommandBuffers = &cmd;
            vkResetFences(host.device, 1, &fence);
            vkQueueSubmit(host.queue, 1, &submit, fence);
            vkWaitForFences(host.device, 1, &fence, VK_TRUE, UINT64_MAX);
        }
        if (result) {
            vkgi::HdrImage image(width, height);
            const auto* texels = static_cast<const glm::vec4*>(readback.mapped());
            for (size_t i = 0; i < image.pixels.size(); ++i)
                image.pixels[i] = glm::vec3(texels[i]);
            result = std::move(image);
        }
    }
    vkgi::destroyBuffer(ctx, readback);
    vkDestroyFence(host.device, fence, nullptr);
    vkDestroyCommandPool(host.device, pool, nullptr);
    return result;
}

glm::dvec3 mean(const vkgi::HdrImage& image) {
    glm::dvec3 sum(0.0);
    for (const glm::vec3& p : image.pixels)
        sum += glm::dvec3(p);
    return sum / double(image.pixels.size());
}

// Exit code once vkgi is done: 3 when the validation layer reported anything.
int finish() {
    if (uint32_t n = g_validationMessages.load(); n != 0) {
        std::fprintf(stderr, "vkgi-embed: %u validation message(s)\n", n);
        return 3;
    }
    return 0;
}

int run(const Options& o) {
    auto technique = vkgi::gi::parseTechnique(o.technique);
    if (!technique) {
        std::string names;
        for (const std::string& n : vkgi::gi::techniqueNames())
            names += (names.empty() ? "" : ", ") + n;
        return fail("--technique: expected one of " + names + ", got '" + o.technique + "'");
    }
    auto scene = vkgi::loadScene(o.scene);
    if (!scene)
        return fail(scene.error().message);

    HostVulkan host;
    if (auto ok = createInstance(host, o.validate); !ok)
        return fail(ok.error().message);
    if (auto ok = createDevice(host); !ok)
        return fail(ok.error().message);
    {
        // vkgi uses the host's objects and never destroys them; the Context and the GiSystem
        // must be destroyed before the device (this scope).
        vkgi::ExternalDevice device{host.instance, host.physicalDevice, host.device, host.queue, host.queueFamily};
        // The loader the host uses (with volk, its vkGetInstanceProcAddr variable); null would
        // mean libvulkan.so.1's.
        device.getInstanceProcAddr = vkGetInstanceProcAddr;
        auto ctx = vkgi::wrapExternalDevice(device);
        if (!ctx)
            return fail(ctx.error().message);
        vkgi::gi::GiSettings settings;
        settings.technique = *technique;
        auto gi = vkgi::gi::GiSystem::create(**ctx, settings);
        if (!gi)
            return fail(gi.error().message);
        if (auto ok = (*gi)->setScene(*scene); !ok)
            return fail(ok.error().message);
        vkgi::Camera camera = scene->cameraOrDefault();
        vkgi::HdrImage composite;
        if (o.hostGraph) {
            auto image = renderInHostGraph(host, **ctx, **gi, camera, o.width, o.height);
            if (!image)
                return fail(image.error().message);
            composite = std::move(*image);
        } else {
            vkgi::gi::FrameRequest request;
            request.indirect = *technique != vkgi::gi::Technique::None;
            // Two frames, as vkgi-render renders them: the first one JIT-compiles the shaders.
            auto frame = (*gi)->renderFrame(camera, o.width, o.height, request);
            if (frame)
                frame = (*gi)->renderFrame(camera, o.width, o.height, request);
            if (!frame)
                return fail(frame.error().message);
            composite = std::move(frame->composite);
            std::printf("%.2f ms GPU\n", frame->totalMs);
            if (!frame->indirect.empty()) {
                glm::dvec3 mi = mean(frame->indirect);
                std::printf("indirect mean %.6f %.6f %.6f nits\n", mi.x, mi.y, mi.z);
            }
        }
        glm::dvec3 m = mean(composite);
        std::printf("%s %ux%u technique %s%s: composite mean %.6f %.6f %.6f nits\n", o.scene.c_str(), o.width,
                    o.height, o.technique.c_str(), o.hostGraph ? " (host graph)" : "", m.x, m.y, m.z);
        auto written = o.out.ends_with(".exr") ? vkgi::writeExr(o.out, composite) : vkgi::writePng(o.out, composite);
        if (!written)
            return fail(written.error().message);
        std::printf("wrote %s\n", o.out.c_str());
    }
    return finish();
}

} // namespace

int main(int argc, char** argv) {
    auto options = parseArgs(argc, argv);
    if (!options)
        return std::fprintf(stderr, "vkgi-embed: %s\n", options.error().message.c_str()), 2;
    return run(*options);
}
