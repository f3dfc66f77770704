#pragma once
// The library's own Vulkan entry points. vkgi_engine and vkgi_gi compile with VK_NO_PROTOTYPES
// and reach Vulkan only through these pointers, loaded from a vkGetInstanceProcAddr: the host's
// (ExternalDevice::getInstanceProcAddr) or the Vulkan loader's, opened with dlopen. The library
// therefore references no global vk* symbol, which a volk host defines as variables of the same
// names (calling one of those as a function crashes).
//
// Include this header from library .cpp files only. Tests and apps compile with the global
// prototypes and include some engine/src and gi/src headers: none of those may include this one,
// or the using-directive below would make every vk* call there ambiguous.
#include <vulkan/vulkan.h>

#include "vkgi/result.hpp"

// Global commands: loaded through vkGetInstanceProcAddr(VK_NULL_HANDLE, ...).
#define VKGI_VK_GLOBAL_FUNCTIONS(X)                                                                                    \
    X(vkCreateInstance)                                                                                                \
    X(vkEnumerateInstanceExtensionProperties)                                                                          \
    X(vkEnumerateInstanceLayerProperties)

// Instance and device commands: loaded through vkGetInstanceProcAddr(instance, ...), so device
// commands are the loader's dispatching entry points and serve any device of the instance.
#define VKGI_VK_INSTANCE_FUNCTIONS(X)                                                                                  \
    X(vkAllocateCommandBuffers)                                                                                        \
    X(vkAllocateDescriptorSets)                                                                                        \
    X(vkAllocateMemory)                                                                                                \
    X(vkBeginCommandBuffer)                                                                                            \
    X(vkBindBufferMemory)                                                                                              \
    X(vkBindImageMemory)                                                                                               \
    X(vkCmdBeginRendering)                                                                                             \
    X(vkCmdBindDescriptorSets)                                                                                         \
    X(vkCmdBindIndexBuffer)                                                                                            \
    X(vkCmdBindPipeline)                                                                                               \
    X(vkCmdBlitImage)                                                                                                  \
    X(vkCmdClearColorImage)                                                                                            \
    X(vkCmdClearDepthStencilImage)                                                                                     \
    X(vkCmdCopyBuffer)                                                                                                 \
    X(vkCmdCopyBufferToImage)                                                                                          \
    X(vkCmdCopyImage)                                                                                                  \
    X(vkCmdCopyImageToBuffer)                                                                                          \
    X(vkCmdDispatch)                                                                                                   \
    X(vkCmdDispatchIndirect)                                                                                           \
    X(vkCmdDrawIndexed)                                                                                                \
    X(vkCmdEndRendering)                                                                                               \
    X(vkCmdFillBuffer)                                                                                                 \
    X(vkCmdPipelineBarrier2)                                                                                           \
    X(vkCmdPushConstants)                                                                                              \
    X(vkCmdResetQueryPool)                                                                                             \
    X(vkCmdSetScissor)                                                                                                 \
    X(vkCmdSetViewport)                                                                                                \
    X(vkCmdUpdateBuffer)                                                                                               \
    X(vkCmdWriteTimestamp2)                                                                                            \
    X(vkCreateBuffer)                                                                                                  \
    X(vkCreateBufferView)                                                                                              \
    X(vkCreateCommandPool)                                                                                             \
    X(vkCreateComputePipelines)                                                                                        \
    X(vkCreateDescriptorPool)                                                                                          \
    X(vkCreateDescriptorSetLayout)                                                                                     \
    X(vkCreateDevice)                                                                                                  \
    X(vkCreateFence)                                                                                                   \
    X(vkCreateGraphicsPipelines)                                                                                       \
    X(vkCreateImage)                                                                                                   \
    X(vkCreateImageView)                                                                                               \
    X(vkCreatePipelineLayout)                                                                                          \
    X(vkCreateQueryPool)                                                                                               \
    X(vkCreateSampler)                                                                                                 \
    X(vkCreateShaderModule)                                                                                            \
    X(vkDestroyBuffer)                                                                                                 \
    X(vkDestroyBufferView)                                                                                             \
    X(vkDestroyCommandPool)                                                                                            \
    X(vkDestroyDescriptorPool)                                                                                         \
    X(vkDestroyDescriptorSetLayout)                                                                                    \
    X(vkDestroyDevice)                                                                                                 \
    X(vkDestroyFence)                                                                                                  \
    X(vkDestroyImage)                                                                                                  \
    X(vkDestroyImageView)                                                                                              \
    X(vkDestroyInstance)                                                                                               \
    X(vkDestroyPipeline)                                                                                               \
    X(vkDestroyPipelineLayout)                                                                                         \
    X(vkDestroyQueryPool)                                                                                              \
    X(vkDestroySampler)                                                                                                \
    X(vkDestroyShaderModule)                                                                                           \
    X(vkDeviceWaitIdle)                                                                                                \
    X(vkEndCommandBuffer)                                                                                              \
    X(vkEnumerateDeviceExtensionProperties)                                                                            \
    X(vkEnumeratePhysicalDevices)                                                                                      \
    X(vkFreeCommandBuffers)                                                                                            \
    X(vkFreeMemory)                                                                                                    \
    X(vkGetBufferMemoryRequirements)                                                                                   \
    X(vkGetDeviceProcAddr)                                                                                             \
    X(vkGetDeviceQueue)                                                                                                \
    X(vkGetImageMemoryRequirements)                                                                                    \
    X(vkGetPhysicalDeviceFeatures2)                                                                                    \
    X(vkGetPhysicalDeviceMemoryProperties)                                                                             \
    X(vkGetPhysicalDeviceProperties)                                                                                   \
    X(vkGetPhysicalDeviceQueueFamilyProperties)                                                                        \
    X(vkGetQueryPoolResults)                                                                                           \
    X(vkMapMemory)                                                                                                     \
    X(vkQueueSubmit2)                                                                                                  \
    X(vkResetCommandBuffer)                                                                                            \
    X(vkResetFences)                                                                                                   \
    X(vkUpdateDescriptorSets)                                                                                          \
    X(vkWaitForFences)

namespace vkgi::vkfn {

#define VKGI_VK_DECLARE(name) extern PFN_##name name;
extern PFN_vkGetInstanceProcAddr vkGetInstanceProcAddr;
VKGI_VK_GLOBAL_FUNCTIONS(VKGI_VK_DECLARE)
VKGI_VK_INSTANCE_FUNCTIONS(VKGI_VK_DECLARE)
#undef VKGI_VK_DECLARE

} // namespace vkgi::vkfn

// Existing call sites (vkCmdDispatch(...)) compile unchanged and call the table.
using namespace vkgi::vkfn;

namespace vkgi {

// Sets `gipa` to the Vulkan loader's vkGetInstanceProcAddr (libvulkan.so.1, opened once and kept
// open), or returns an error saying the loader is missing.
Result<void> loaderGetInstanceProcAddr(PFN_vkGetInstanceProcAddr& gipa);
// Fills the global commands from `gipa` (before vkCreateInstance).
Result<void> loadGlobalFunctions(PFN_vkGetInstanceProcAddr gipa);
// Fills the whole table from `gipa` and `instance`. One table serves the process: every Context
// loads it, and the entries of two loaders' gipa are interchangeable, since each dispatches on
// the handle it is given. The last Context created with a different gipa wins.
Result<void> loadInstanceFunctions(PFN_vkGetInstanceProcAddr gipa, VkInstance instance);

} // namespace vkgi
