#pragma once
// The Vulkan context vkgi runs on: either a headless device it creates itself (DeviceBuilder)
// or a host engine's existing instance/device/queue that it wraps without owning
// (wrapExternalDevice). Everything else in engine/ takes a Context&.
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "vkgi/result.hpp"

namespace vkgi {

class Allocator;

// Validation-layer messages seen on this context. Tests fail when count() != 0.
class ValidationLog {
public:
    void add(VkDebugUtilsMessageSeverityFlagBitsEXT severity, const char* message);
    uint32_t count() const;
    std::vector<std::string> messages() const;
    void clear();

private:
    mutable std::mutex m_mutex;
    std::vector<std::string> m_messages;
};

// Device-level entry points that are extensions (or optional), loaded once per context.
struct DeviceFunctions {
    PFN_vkCmdPushDescriptorSetKHR cmdPushDescriptorSet = nullptr;
    PFN_vkSetDebugUtilsObjectNameEXT setObjectName = nullptr;
    PFN_vkCmdBeginDebugUtilsLabelEXT cmdBeginLabel = nullptr;
    PFN_vkCmdEndDebugUtilsLabelEXT cmdEndLabel = nullptr;
};

class Context {
public:
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    VkInstance instance() const { return m_instance; }
    VkPhysicalDevice physicalDevice() const { return m_physicalDevice; }
    VkDevice device() const { return m_device; }
    VkQueue queue() const { return m_queue; }
    uint32_t queueFamily() const { return m_queueFamily; }
    const VkPhysicalDeviceProperties& properties() const { return m_properties; }
    const DeviceFunctions& fn() const { return m_fn; }
    Allocator& allocator() { return *m_allocator; }
    ValidationLog& validation() { return *m_validation; }
    // The same log for a holder that outlives the context: vkDestroyDevice and vkDestroyInstance
    // report the objects still alive into it while ~Context runs.
    std::shared_ptr<const ValidationLog> sharedValidation() const { return m_validation; }
    bool ownsDevice() const { return m_ownsDevice; }
    // Nanoseconds per timestamp tick, and whether the queue supports timestamps.
    double timestampPeriodNs() const { return m_properties.limits.timestampPeriod; }
    bool timestampsSupported() const { return m_timestampValidBits != 0; }

    // Debug name of a Vulkan object (no-op without VK_EXT_debug_utils).
    void setName(VkObjectType type, uint64_t handle, const char* name) const;
    void beginLabel(VkCommandBuffer cmd, const char* name) const;
    void endLabel(VkCommandBuffer cmd) const;

    // Records `record` into a one-time command buffer, submits it and waits (uploads,
    // readbacks, tests). Not for per-frame work. Throws std::runtime_error when a Vulkan call fails.
    void submitAndWait(const std::function<void(VkCommandBuffer)>& record);
    // Submits one recorded command buffer to the queue, signalling `fence` (may be null). Throws
    // std::runtime_error when the submit fails.
    void submit(VkCommandBuffer cmd, VkFence fence) const;
    VkCommandPool commandPool() const { return m_commandPool; }
    // Set 0 of every pipeline layout: the per-frame constants (engine/frame_constants.h).
    VkDescriptorSetLayout frameSetLayout() const { return m_frameSetLayout; }

private:
    friend class DeviceBuilder;
    friend Result<std::unique_ptr<Context>> wrapExternalDevice(const struct ExternalDevice&);
    Context() = default;
    Result<void> initCommon();

    VkInstance m_instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT m_messenger = VK_NULL_HANDLE;
    VkPhysicalDevice m_physicalDevice = VK_NULL_HANDLE;
    VkDevice m_device = VK_NULL_HANDLE;
    VkQueue m_queue = VK_NULL_HANDLE;
    uint32_t m_queueFamily = 0;
    uint32_t m_timestampValidBits = 0;
    VkPhysicalDeviceProperties m_properties{};
    VkCommandPool m_commandPool = VK_NULL_HANDLE;
    VkFence m_fence = VK_NULL_HANDLE;
    VkDescriptorSetLayout m_frameSetLayout = VK_NULL_HANDLE;
    DeviceFunctions m_fn;
    std::unique_ptr<Allocator> m_allocator;
    std::shared_ptr<ValidationLog> m_validation = std::make_shared<ValidationLog>();
    bool m_ownsDevice = true;
    bool m_debugUtils = false;
};

// Creates a headless instance + device (no surface) with the features vkgi needs:
// Vulkan 1.3, synchronization2, dynamic rendering, VK_KHR_push_descriptor.
class DeviceBuilder {
public:
    // Pick the first device whose name contains `substring` (e.g. "llvmpipe"); error if none does.
    DeviceBuilder& preferDeviceName(std::string substring);
    DeviceBuilder& preferDeviceType(VkPhysicalDeviceType type);
    // Validation layer; `synchronization` also enables synchronization validation.
    DeviceBuilder& enableValidation(bool enable, bool synchronization = true);
    // Extra instance extensions (e.g. from glfwGetRequiredInstanceExtensions) and device
    // extensions (VK_KHR_swapchain) for windowed apps.
    DeviceBuilder& addInstanceExtension(const char* name);
    DeviceBuilder& addDeviceExtension(const char* name);
    DeviceBuilder& setApplicationName(std::string name);
    // Loads Vulkan from libvulkan.so.1; a failed Vulkan call comes back as the error.
    Result<std::unique_ptr<Context>> build();

private:
    Result<std::unique_ptr<Context>> buildContext(); // build() without catching VulkanError
    std::string m_deviceName;
    VkPhysicalDeviceType m_deviceType = VK_PHYSICAL_DEVICE_TYPE_MAX_ENUM;
    bool m_validation = false;
    bool m_syncValidation = false;
    std::vector<const char*> m_instanceExtensions;
    std::vector<const char*> m_deviceExtensions;
    std::string m_appName = "vkgi";
};

// The device extensions vkgi needs.
inline constexpr const char* kRequiredDeviceExtensions[] = {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};

// The features a device must enable for vkgi (docs/embedding.md "The device vkgi needs"), as a
// VkDeviceCreateInfo::pNext chain starting at `features`: the required Vulkan 1.1-1.3 features,
// and the optional core features vkgi uses where `supported` (from vkGetPhysicalDeviceFeatures2)
// has them. DeviceBuilder creates its device with it, and a host creating its own device can
// too: it may enable more features in these structures or chain its own after `v11`. The
// chain points into the object, so it is neither copied nor moved. No Vulkan call is made.
struct DeviceFeatureChain {
    explicit DeviceFeatureChain(const VkPhysicalDeviceFeatures& supported);
    DeviceFeatureChain(const DeviceFeatureChain&) = delete;
    DeviceFeatureChain& operator=(const DeviceFeatureChain&) = delete;

    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    VkPhysicalDeviceVulkan13Features v13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceVulkan11Features v11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES};
};

// A host application's device, which vkgi uses but never destroys. The host must have
// created it with Vulkan 1.3, kRequiredDeviceExtensions and the features of DeviceFeatureChain;
// `queue` must support compute and graphics.
struct ExternalDevice {
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t queueFamily = 0;
    // The host's vkGetInstanceProcAddr (volk: the global `vkGetInstanceProcAddr` after
    // volkInitialize), through which vkgi loads every Vulkan function it calls. Null: the Vulkan
    // loader's, from libvulkan.so.1. vkgi never calls a global vk* symbol either way. One function
    // table serves the process, so every Context should come from the same loader.
    PFN_vkGetInstanceProcAddr getInstanceProcAddr = nullptr;
};
// A failed Vulkan call while wrapping comes back as the error ("vkCreateFence failed: ...").
Result<std::unique_ptr<Context>> wrapExternalDevice(const ExternalDevice& external);

// Environment defaults for tools and tests: VKGI_DEVICE selects by name substring,
// VKGI_VALIDATION=1 turns validation on.
DeviceBuilder defaultDeviceBuilder();

} // namespace vkgi
