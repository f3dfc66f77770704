#pragma once
// CPU reference of LPV propagation: the same shared formulas (gi/lpv.h) as lpv/propagate.comp,
// evaluated on the host. Tests use it as the expected result of the GPU passes and to check the
// energy bookkeeping; it is not used at run time.
#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

namespace vkgi::gi::lpv {

// One SH per cell and colour channel; x varies fastest, then y, then z. Bands 0 and 1 (vec4) in
// `channel`. With 3 bands, band 2 in `band2` (Y2-2..Y21) and `band2Last` (Y22), the layout of
// gi/sh.h; empty with 2 bands. 3 bands exist only on the CPU, as a measured comparison
// (docs/lpv.md, "Alternatives measured and rejected").
struct ShVolume {
    glm::ivec3 size{0};
    int bands = 2;
    std::vector<glm::vec4> channel[3];
    std::vector<glm::vec4> band2[3];
    std::vector<float> band2Last[3];

    ShVolume() = default;
    explicit ShVolume(glm::ivec3 cells, int shBands = 2);
    size_t index(glm::ivec3 p) const {
        return size_t(p.x) + size_t(size.x) * (size_t(p.y) + size_t(size.y) * size_t(p.z));
    }
    bool contains(glm::ivec3 p) const;
    size_t cellCount() const { return size_t(size.x) * size_t(size.y) * size_t(size.z); }
};

// Geometry volume: blocking-potential SH on the (size + 1)^3 cell corners; empty = no occlusion.
struct GeometryVolume {
    glm::ivec3 size{0}; // = LPV size + 1
    std::vector<glm::vec4> blocking;
    bool empty() const { return blocking.empty(); }
};

// One gather step: target = propagate(source); accumulation += target when accumulation is given.
// The source's band count decides the propagation's (the geometry volume stays 2-band).
void propagateStep(const ShVolume& source, ShVolume& target, ShVolume* accumulation,
                   const GeometryVolume& geometryVolume);

// Sum over cells of the integral of the intensity SH (total flux in flight) of one channel.
double totalFlux(const ShVolume& v, int channel);

// Flux of one channel that the next propagation step sends out of the grid (through its
// boundary faces), which is all it loses in empty space.
double boundaryOutflow(const ShVolume& v, int channel, const GeometryVolume& geometryVolume);

} // namespace vkgi::gi::lpv
