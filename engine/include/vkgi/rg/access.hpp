#pragma once
// Every way a pass can touch a resource, as one enum (THSVS / kajiya style). A single table
// maps each value to its synchronization2 stage + access, the image layout it needs and the
// usage flags it implies, so barriers, layouts and transient usage are all derived from it.
#include <cstdint>

#include <vulkan/vulkan.h>

namespace vkgi::rg {

enum class Access : uint8_t {
    None,                       // no access (initial state of external images, e.g. a fresh swapchain image)
    ComputeSampledRead,         // texture() in a compute shader
    ComputeStorageRead,         // imageLoad / readonly SSBO in a compute shader
    ComputeStorageWrite,        // imageStore / writeonly SSBO; previous contents preserved
    ComputeStorageReadWrite,    // read-modify-write, atomics
    ComputeStorageWriteDiscard, // full overwrite: previous contents may be dropped (UNDEFINED old layout)
    ComputeUniformRead,         // uniform buffer in a compute shader
    VertexShaderStorageRead,    // SSBO / storage image read in a vertex shader
    FragmentSampledRead,        // texture() in a fragment shader
    FragmentStorageRead,        // SSBO / storage image read in a fragment shader
    GraphicsUniformRead,        // uniform buffer in vertex or fragment shaders
    ColorAttachmentWrite,       // colour attachment, store only (blending off)
    ColorAttachmentReadWrite,   // colour attachment with blending or load
    DepthAttachmentWrite,       // depth test + write
    DepthAttachmentRead,        // depth test without write
    VertexBufferRead,
    IndexBufferRead,
    IndirectRead,  // draw or dispatch indirect arguments
    TransferRead,  // copy / blit source
    TransferWrite, // copy / blit / clear / fill destination
    HostRead,      // mapped readback after the submit finished
    Present,       // swapchain image handed to the presentation engine
    Count
};

// The single source of truth for one Access value.
struct AccessInfo {
    const char* name;
    VkPipelineStageFlags2 stages;
    VkAccessFlags2 access;
    VkImageLayout layout;           // layout an image must be in (UNDEFINED for buffer-only accesses)
    VkImageUsageFlags imageUsage;   // usage a transient image gets from this access
    VkBufferUsageFlags bufferUsage; // usage a transient buffer gets from this access
    bool write;                     // the access modifies the resource
    bool discard;                   // a write that does not preserve the previous contents
    bool image;                     // valid on images
    bool buffer;                    // valid on buffers
};

const AccessInfo& accessInfo(Access access);
const char* toString(Access access);

} // namespace vkgi::rg
