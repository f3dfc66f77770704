#pragma once
// LPV propagation as render-graph passes: one rg::ComputePass per iteration
// ("gi.lpv.propagate[k]"), ping-ponging two wavefront volumes and adding the new wavefronts to
// the accumulation volume. The graph derives every barrier; nothing here records one.
#include <array>
#include <cstdint>
#include <string>

#include <glm/glm.hpp>

#include "vkgi/rg/render_graph.hpp"
#include "lpv/lpv_volume.hpp"

namespace vkgi::gi::lpv {

// Graph handles of one SH volume (R, G, B channel images).
struct ShHandles {
    std::array<rg::ImageHandle, 3> channel;
};

// Description of one channel image of an SH volume.
ImageDesc shImageDesc(glm::ivec3 cells, VkFormat format);

// Transient SH volume (e.g. the second ping-pong wavefront) named "<name>.r/g/b".
ShHandles createShVolume(rg::RenderGraph& graph, const char* name, glm::ivec3 cells, VkFormat format);

struct PropagationVolumes {
    ShHandles wavefront;    // in: the injected light; out: the last wavefront
    ShHandles scratch;      // second ping-pong volume, fully overwritten (may be transient)
    ShHandles accumulation; // in: holds the injected light; out: plus every propagated wavefront
};

// The shared voxel grid (gi/voxel_grid.h) for multi-bounce: albedo and normal volumes (RGBA8,
// a = occupancy) and where they sit.
struct VoxelInput {
    rg::ImageHandle albedo, normal;
    glm::vec4 originSize{0.0f}; // xyz world min corner, w voxel edge length
    uint32_t resolution = 0;
};

// Adds `iterations` propagation passes. `geometryVolume` (cells + 1 texels per axis, RGBA16F)
// enables occlusion when valid; `voxels` (valid albedo) enables reflection at occupied voxels,
// which needs `lpvOrigin` (xyz world min corner, w cell size). Returns the updated handles.
PropagationVolumes addPropagationPasses(rg::RenderGraph& graph, const Propagator& propagator, glm::ivec3 cells,
                                        VkFormat format, PropagationVolumes volumes, rg::ImageHandle geometryVolume,
                                        uint32_t iterations, const VoxelInput& voxels = {},
                                        glm::vec4 lpvOrigin = glm::vec4(0.0f), const std::string& prefix = "gi.lpv");

} // namespace vkgi::gi::lpv
