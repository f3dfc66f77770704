#pragma once
// Host G-buffer path of GiSystem (gi.hpp HostGBuffer/HostFrame, docs/embedding.md): checks the
// host's images, imports them into the frame graph in place of the G-buffer pass, and copies
// the indirect light into the host's output image. Private to gi/.
#include "direct/direct_passes.hpp"

namespace vkgi::gi {

// Formats, sizes, handles, usage and access of every given image; one-line errors naming the field.
Result<void> checkHostGBuffer(const HostGBuffer& g);
Result<void> checkHostIndirect(const HostImage& target, const HostGBuffer& g);
// The final accesses of HostFrame must be image read accesses (render-graph exports).
Result<void> checkFinalAccess(const char* name, rg::Access access);

// Leaves the host's G-buffer images (not the reconstructed position) in `finalAccess`.
void exportHostGBuffer(rg::RenderGraph& graph, const GBufferData& imported, const HostGBuffer& g,
                       rg::Access finalAccess);

// GBufferData over the host's images (emission stays invalid: no technique reads it); the
// position comes from HostGBuffer::position or a "gi.host.position" pass over the depth.
GBufferData importHostGBuffer(rg::RenderGraph& graph, const DirectPipelines& p, const FrameData& frame,
                              const HostGBuffer& g);

// "gi.host.indirect": copies (or, between RGBA32F and RGBA16F, blits) `indirect` into the
// host's image and leaves it in `finalAccess`.
void addHostIndirectCopy(rg::RenderGraph& graph, rg::ImageHandle indirect, const HostImage& target,
                         rg::Access finalAccess);

} // namespace vkgi::gi
