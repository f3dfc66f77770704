#include "vkgi/context.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>

#include "engine/frame_constants.h"
#include "vkgi/resources.hpp"
#include "vk_check.hpp"
#include "vk_dispatch.hpp"

namespace vkgi {

void ValidationLog::add(VkDebugUtilsMessageSeverityFlagBitsEXT severity, const char* message) {
    const char* tag = severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning";
    std::fprintf(stderr, "vkgi: validation %s: %s\n", tag, message);
    std::lock_guard lock(m_mutex);
    m_messages.emplace_back(message);
}

uint32_t ValidationLog::count() const {
    std::lock_guard lock(m_mutex);
    return uint32_t(m_messages.size());
}

std::vector<std::string> ValidationLog::messages() const {
    std::lock_guard lock(m_mutex);
    return m_messages;
}

void ValidationLog::clear() {
    std::lock_guard lock(m_mutex);
    m_messages.clear();
}

namespace {

VKAPI_ATTR VkBool32 VKAPI_CALL debugCallback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                             VkDebugUtilsMessageTypeFlagsEXT, const VkDebugUtilsMessengerCallbackDataEXT* data,
                                             void* user) {
    // Warnings count too: synchronization hazards are reported as warnings or errors
    // depending on the layer version, and a clean run must show neither.
    if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT)
        static_cast<ValidationLog*>(user)->add(severity, data->pMessage);
    return VK_FALSE;
}

bool hasLayer(const char* name) {
    uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, nullptr);
    std::vector<VkLayerProperties> layers(n);
    vkEnumerateInstanceLayerProperties(&n, layers.data());
    for (const auto& l : layers)
        if (std::strcmp(l.layerName, name) == 0)
            return true;
    return false;
}

bool hasInstanceExtension(const char* name) {
    uint32_t n = 0;
    vkEnumerateInstanceExtensionProperties(nullptr, &n, nullptr);
    std::vector<VkExtensionProperties> exts(n);
    vkEnumerateInstanceExtensionProperties(nullptr, &n, exts.data());
    for (const auto& e : exts)
        if (std::strcmp(e.extensionName, name) == 0)
            return true;
    return false;
}

bool hasDeviceExtension(VkPhysicalDevice pd, const char* name) {
    uint32_t n = 0;
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, nullptr);
    std::vector<VkExtensionProperties> exts(n);
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, exts.data());
    for (const auto& e : exts)
        if (std::strcmp(e.extensionName, name) == 0)
            return true;
    return false;
}

int findQueueFamily(VkPhysicalDevice pd) {
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
    std::vector<VkQueueFamilyProperties> fams(n);
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, fams.data());
    for (uint32_t i = 0; i < n; ++i)
        if ((fams[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) && (fams[i].queueFlags & VK_QUEUE_COMPUTE_BIT))
            return int(i);
    return -1;
}

VkDebugUtilsMessengerCreateInfoEXT messengerInfo(ValidationLog* log) {
    VkDebugUtilsMessengerCreateInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    info.pfnUserCallback = debugCallback;
    info.pUserData = log;
    return info;
}

} // namespace

Context::~Context() {
    if (m_device) {
        vkDeviceWaitIdle(m_device);
        m_allocator.reset();
        if (m_fence)
            vkDestroyFence(m_device, m_fence, nullptr);
        if (m_frameSetLayout)
            vkDestroyDescriptorSetLayout(m_device, m_frameSetLayout, nullptr);
        if (m_commandPool)
            vkDestroyCommandPool(m_device, m_commandPool, nullptr);
    }
    if (!m_ownsDevice)
        return;
    if (m_device)
        vkDestroyDevice(m_device, nullptr);
    if (m_messenger) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(m_instance, "vkDestroyDebugUtilsMessengerEXT"));
        if (destroy)
            destroy(m_instance, m_messenger, nullptr);
    }
    if (m_instance)
        vkDestroyInstance(m_instance, nullptr);
}

Result<void> Context::initCommon() {
    vkGetPhysicalDeviceProperties(m_physicalDevice, &m_properties);
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(m_physicalDevice, &n, nullptr);
    std::vector<VkQueueFamilyProperties> fams(n);
    vkGetPhysicalDeviceQueueFamilyProperties(m_physicalDevice, &n, fams.data());
    if (m_queueFamily >= n)
        return makeError("queue family " + std::to_string(m_queueFamily) + " does not exist on this device");
    m_timestampValidBits = fams[m_queueFamily].timestampValidBits;

    m_fn.cmdPushDescriptorSet =
        reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(vkGetDeviceProcAddr(m_device, "vkCmdPushDescriptorSetKHR"));
    if (!m_fn.cmdPushDescriptorSet)
        return makeError("the device does not have VK_KHR_push_descriptor enabled (vkgi needs it)");
    m_fn.setObjectName = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
        vkGetInstanceProcAddr(m_instance, "vkSetDebugUtilsObjectNameEXT"));
    m_fn.cmdBeginLabel = reinterpret_cast<PFN_vkCmdBeginDebugUtilsLabelEXT>(
        vkGetInstanceProcAddr(m_instance, "vkCmdBeginDebugUtilsLabelEXT"));
    m_fn.cmdEndLabel =
        reinterpret_cast<PFN_vkCmdEndDebugUtilsLabelEXT>(vkGetInstanceProcAddr(m_instance, "vkCmdEndDebugUtilsLabelEXT"));
    m_debugUtils = m_fn.setObjectName && m_fn.cmdBeginLabel && m_fn.cmdEndLabel;

    VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = m_queueFamily;
    VKGI_CHECK(vkCreateCommandPool(m_device, &pool, nullptr, &m_commandPool));
    VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VKGI_CHECK(vkCreateFence(m_device, &fence, nullptr, &m_fence));
    VkDescriptorSetLayoutBinding frame{GI_FRAME_BINDING, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_ALL, nullptr};
    VkDescriptorSetLayoutCreateInfo layout{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    layout.bindingCount = 1;
    layout.pBindings = &frame;
    VKGI_CHECK(vkCreateDescriptorSetLayout(m_device, &layout, nullptr, &m_frameSetLayout));
    m_allocator = std::make_unique<Allocator>(*this);
    return {};
}

void Context::setName(VkObjectType type, uint64_t handle, const char* name) const {
    if (!m_debugUtils || !name)
        return;
    VkDebugUtilsObjectNameInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
    info.objectType = type;
    info.objectHandle = handle;
    info.pObjectName = name;
    m_fn.setObjectName(m_device, &info);
}

void Context::beginLabel(VkCommandBuffer cmd, const char* name) const {
    if (!m_debugUtils)
        return;
    VkDebugUtilsLabelEXT label{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
    label.pLabelName = name;
    m_fn.cmdBeginLabel(cmd, &label);
}

void Context::endLabel(VkCommandBuffer cmd) const {
    if (m_debugUtils)
        m_fn.cmdEndLabel(cmd);
}

void Context::submit(VkCommandBuffer cmd, VkFence fence) const {
    VkCommandBufferSubmitInfo cmdInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cmdInfo.commandBuffer = cmd;
    VkSubmitInfo2 info{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    info.commandBufferInfoCount = 1;
    info.pCommandBufferInfos = &cmdInfo;
    VKGI_CHECK(vkQueueSubmit2(m_queue, 1, &info, fence));
}

void Context::submitAndWait(const std::function<void(VkCommandBuffer)>& record) {
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = m_commandPool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cmd;
    VKGI_CHECK(vkAllocateCommandBuffers(m_device, &alloc, &cmd));
    try {
        VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        VKGI_CHECK(vkBeginCommandBuffer(cmd, &begin));
        record(cmd);
        VKGI_CHECK(vkEndCommandBuffer(cmd));
        submit(cmd, m_fence);
    } catch (...) {
        vkFreeCommandBuffers(m_device, m_commandPool, 1, &cmd); // never submitted
        throw;
    }
    VKGI_CHECK(vkWaitForFences(m_device, 1, &m_fence, VK_TRUE, UINT64_MAX));
    VKGI_CHECK(vkResetFences(m_device, 1, &m_fence));
    vkFreeCommandBuffers(m_device, m_commandPool, 1, &cmd);
}

DeviceBuilder& DeviceBuilder::preferDeviceName(std::string s) {
    m_deviceName = std::move(s);
    return *this;
}
DeviceBuilder& DeviceBuilder::preferDeviceType(VkPhysicalDeviceType t) {
    m_deviceType = t;
    return *this;
}
DeviceBuilder& DeviceBuilder::enableValidation(bool enable, bool synchronization) {
    m_validation = enable;
    m_syncValidation = enable && synchronization;
    return *this;
}
DeviceBuilder& DeviceBuilder::addInstanceExtension(const char* name) {
    m_instanceExtensions.push_back(name);
    return *this;
}
DeviceBuilder& DeviceBuilder::addDeviceExtension(const char* name) {
    m_deviceExtensions.push_back(name);
    return *this;
}
DeviceBuilder& DeviceBuilder::setApplicationName(std::string name) {
    m_appName = std::move(name);
    return *this;
}

namespace {

Result<VkPhysicalDevice> choosePhysicalDevice(VkInstance instance, const std::string& name, VkPhysicalDeviceType type) {
    uint32_t n = 0;
    vkEnumeratePhysicalDevices(instance, &n, nullptr);
    std::vector<VkPhysicalDevice> devices(n);
    vkEnumeratePhysicalDevices(instance, &n, devices.data());
    VkPhysicalDevice best = VK_NULL_HANDLE;
    int bestScore = -1;
    std::string seen;
    for (VkPhysicalDevice pd : devices) {
        VkPhysicalDeviceProperties props;
        vkGetPhysicalDeviceProperties(pd, &props);
        seen += std::string(seen.empty() ? "" : ", ") + props.deviceName;
        if (props.apiVersion < VK_API_VERSION_1_3 || findQueueFamily(pd) < 0 ||
            !std::all_of(std::begin(kRequiredDeviceExtensions), std::end(kRequiredDeviceExtensions),
                         [pd](const char* e) { return hasDeviceExtension(pd, e); }))
            continue;
        if (!name.empty() && std::strstr(props.deviceName, name.c_str()) == nullptr)
            continue;
        int score = 1;
        if (props.deviceType == type)
            score += 100;
        else if (props.deviceType == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU)
            score += 10;
        else if (props.deviceType == VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU)
            score += 5;
        if (score > bestScore) {
            best = pd;
            bestScore = score;
        }
    }
    if (!best)
        return makeError("no Vulkan 1.3 device with graphics+compute and VK_KHR_push_descriptor" +
                         (name.empty() ? std::string() : " whose name contains '" + name + "'") +
                         " (found: " + (seen.empty() ? "none" : seen) + ")");
    return best;
}

} // namespace

Result<std::unique_ptr<Context>> DeviceBuilder::build() {
    try {
        return buildContext();
    } catch (const VulkanError& e) {
        return makeError(e.what()); // ~Context has destroyed what was created
    }
}

Result<std::unique_ptr<Context>> DeviceBuilder::buildContext() {
    PFN_vkGetInstanceProcAddr gipa = nullptr;
    if (auto ok = loaderGetInstanceProcAddr(gipa); !ok)
        return ok.error();
    if (auto ok = loadGlobalFunctions(gipa); !ok)
        return ok.error();
    std::unique_ptr<Context> ctx(new Context());
    bool validation = m_validation && hasLayer("VK_LAYER_KHRONOS_validation");
    if (m_validation && !validation)
        return makeError("validation requested but VK_LAYER_KHRONOS_validation is not installed "
                         "(Debian package vulkan-validationlayers)");
    std::vector<const char*> exts = m_instanceExtensions;
    bool debugUtils = hasInstanceExtension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    if (debugUtils)
        exts.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);

    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = m_appName.c_str();
    app.pEngineName = "vkgi";
    app.apiVersion = VK_API_VERSION_1_3;
    VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ici.pApplicationInfo = &app;
    const char* layer = "VK_LAYER_KHRONOS_validation";
    VkValidationFeatureEnableEXT syncFeature = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
    VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    VkDebugUtilsMessengerCreateInfoEXT messenger = messengerInfo(ctx->m_validation.get());
    if (validation) {
        ici.enabledLayerCount = 1;
        ici.ppEnabledLayerNames = &layer;
        if (m_syncValidation) {
            features.enabledValidationFeatureCount = 1;
            features.pEnabledValidationFeatures = &syncFeature;
            messenger.pNext = &features;
        }
        if (debugUtils)
            ici.pNext = &messenger; // also catches messages from instance creation itself
    }
    ici.enabledExtensionCount = uint32_t(exts.size());
    ici.ppEnabledExtensionNames = exts.data();
    VkResult r = vkCreateInstance(&ici, nullptr, &ctx->m_instance);
    if (r != VK_SUCCESS)
        return makeError(std::string("vkCreateInstance failed: ") + toString(r));
    if (auto ok = loadInstanceFunctions(gipa, ctx->m_instance); !ok)
        return ok.error();
    if (validation && debugUtils) {
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(ctx->m_instance, "vkCreateDebugUtilsMessengerEXT"));
        messenger.pNext = nullptr;
        VKGI_CHECK(create(ctx->m_instance, &messenger, nullptr, &ctx->m_messenger));
    }

    auto pd = choosePhysicalDevice(ctx->m_instance, m_deviceName, m_deviceType);
    if (!pd)
        return pd.error();
    ctx->m_physicalDevice = *pd;
    ctx->m_queueFamily = uint32_t(findQueueFamily(*pd));

    float priority = 1.0f;
    VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qci.queueFamilyIndex = ctx->m_queueFamily;
    qci.queueCount = 1;
    qci.pQueuePriorities = &priority;

    VkPhysicalDeviceFeatures2 supported{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    vkGetPhysicalDeviceFeatures2(*pd, &supported);
    const DeviceFeatureChain enabled(supported.features);

    std::vector<const char*> devExts = m_deviceExtensions;
    devExts.insert(devExts.end(), std::begin(kRequiredDeviceExtensions), std::end(kRequiredDeviceExtensions));
    for (const char* e : devExts)
        if (!hasDeviceExtension(*pd, e))
            return makeError(std::string("device lacks required extension ") + e);
    VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    dci.pNext = &enabled.features;
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    dci.enabledExtensionCount = uint32_t(devExts.size());
    dci.ppEnabledExtensionNames = devExts.data();
    r = vkCreateDevice(*pd, &dci, nullptr, &ctx->m_device);
    if (r != VK_SUCCESS)
        return makeError(std::string("vkCreateDevice failed: ") + toString(r));
    vkGetDeviceQueue(ctx->m_device, ctx->m_queueFamily, 0, &ctx->m_queue);
    ctx->m_ownsDevice = true;
    if (auto ok = ctx->initCommon(); !ok)
        return ok.error();
    return ctx;
}

DeviceFeatureChain::DeviceFeatureChain(const VkPhysicalDeviceFeatures& supported) {
    features.pNext = &v13;
    v13.pNext = &v12;
    v12.pNext = &v11;
    v13.synchronization2 = VK_TRUE;
    v13.dynamicRendering = VK_TRUE;
    v13.maintenance4 = VK_TRUE;
    v12.hostQueryReset = VK_TRUE;
    v12.scalarBlockLayout = VK_TRUE;
    v11.multiview = VK_TRUE;
    // Optional: stores and atomics outside compute, layered rendering through a geometry shader,
    // storage-image formats, anisotropic sampling and depth clamping are used where present.
    VkPhysicalDeviceFeatures& f = features.features;
    f.fragmentStoresAndAtomics = supported.fragmentStoresAndAtomics;
    f.vertexPipelineStoresAndAtomics = supported.vertexPipelineStoresAndAtomics;
    f.geometryShader = supported.geometryShader;
    f.shaderStorageImageExtendedFormats = supported.shaderStorageImageExtendedFormats;
    f.samplerAnisotropy = supported.samplerAnisotropy;
    f.depthClamp = supported.depthClamp;
}

Result<std::unique_ptr<Context>> wrapExternalDevice(const ExternalDevice& ext) {
    if (!ext.instance || !ext.physicalDevice || !ext.device || !ext.queue)
        return makeError("wrapExternalDevice: instance, physicalDevice, device and queue must all be set");
    PFN_vkGetInstanceProcAddr gipa = ext.getInstanceProcAddr;
    if (!gipa)
        if (auto ok = loaderGetInstanceProcAddr(gipa); !ok)
            return makeError("wrapExternalDevice: " + ok.error().message);
    if (auto ok = loadInstanceFunctions(gipa, ext.instance); !ok)
        return makeError("wrapExternalDevice: " + ok.error().message);
    std::unique_ptr<Context> ctx(new Context());
    ctx->m_instance = ext.instance;
    ctx->m_physicalDevice = ext.physicalDevice;
    ctx->m_device = ext.device;
    ctx->m_queue = ext.queue;
    ctx->m_queueFamily = ext.queueFamily;
    ctx->m_ownsDevice = false;
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(ext.physicalDevice, &props);
    if (props.apiVersion < VK_API_VERSION_1_3)
        return makeError(std::string("wrapExternalDevice: ") + props.deviceName + " is not a Vulkan 1.3 device");
    try {
        if (auto ok = ctx->initCommon(); !ok)
            return makeError("wrapExternalDevice: " + ok.error().message);
    } catch (const VulkanError& e) {
        return makeError(std::string("wrapExternalDevice: ") + e.what());
    }
    return ctx;
}

DeviceBuilder defaultDeviceBuilder() {
    DeviceBuilder b;
    if (const char* name = std::getenv("VKGI_DEVICE"))
        b.preferDeviceName(name);
    if (const char* v = std::getenv("VKGI_VALIDATION"); v && std::strcmp(v, "0") != 0)
        b.enableValidation(true, true);
    return b;
}

} // namespace vkgi
