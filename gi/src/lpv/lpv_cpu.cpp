#include "lpv/lpv_cpu.hpp"

#include "gi/lpv.h"

namespace vkgi::gi::lpv {

using gpu::lpvAxisStep;

ShVolume::ShVolume(glm::ivec3 cells) : size(cells) {
    for (auto& c : channel)
        c.assign(cellCount(), glm::vec4(0.0f));
}

bool ShVolume::contains(glm::ivec3 p) const {
    return glm::all(glm::greaterThanEqual(p, glm::ivec3(0))) && glm::all(glm::lessThan(p, size));
}

namespace {

// Blocking SH interpolated at the centre of the face destination p shares with its source
// for gather direction i: the mean of the GV values at the face's 4 corners.
glm::vec4 faceBlocking(const GeometryVolume& geometryVolume, glm::ivec3 p, int i) {
    glm::ivec3 c = gpu::lpvSharedFaceCorner(p, i);
    glm::ivec3 eb = gpu::lpvUnitAxis(((i >> 1) + 1) % 3), ec = gpu::lpvUnitAxis(((i >> 1) + 2) % 3);
    glm::vec4 sum(0.0f);
    for (glm::ivec3 q : {c, c + eb, c + ec, c + eb + ec})
        sum += geometryVolume.blocking[size_t(q.x) + size_t(geometryVolume.size.x) *
                                                         (size_t(q.y) + size_t(geometryVolume.size.y) * size_t(q.z))];
    return 0.25f * sum;
}

float transmittance(const GeometryVolume& geometryVolume, glm::ivec3 p, int i, int f) {
    if (geometryVolume.empty())
        return 1.0f;
    return gpu::lpvTransmittance(faceBlocking(geometryVolume, p, i), gpu::lpvFaceDirection(i, f));
}

} // namespace

void propagateStep(const ShVolume& source, ShVolume& target, ShVolume* accumulation,
                   const GeometryVolume& geometryVolume) {
    if (target.size != source.size)
        target = ShVolume(source.size);
    for (int z = 0; z < source.size.z; ++z)
        for (int y = 0; y < source.size.y; ++y)
            for (int x = 0; x < source.size.x; ++x) {
                glm::ivec3 p(x, y, z);
                glm::vec4 sum[3] = {glm::vec4(0.0f), glm::vec4(0.0f), glm::vec4(0.0f)};
                for (int i = 0; i < 6; ++i) {
                    glm::ivec3 q = p - lpvAxisStep(i);
                    if (!source.contains(q))
                        continue;
                    for (int f = 0; f < 5; ++f) {
                        float t = transmittance(geometryVolume, p, i, f);
                        glm::vec4 w = t * gpu::lpvFaceWeight(i, f);
                        glm::vec4 r = gpu::lpvFaceReprojection(i, f);
                        for (int c = 0; c < 3; ++c)
                            sum[c] += glm::dot(source.channel[c][source.index(q)], w) * r;
                    }
                }
                size_t k = target.index(p);
                for (int c = 0; c < 3; ++c) {
                    target.channel[c][k] = sum[c];
                    if (accumulation)
                        accumulation->channel[c][k] += sum[c];
                }
            }
}

double totalFlux(const ShVolume& v, int channel) {
    double sum = 0.0;
    for (const glm::vec4& c : v.channel[channel])
        sum += double(gpu::shIntegral(c));
    return sum;
}

double boundaryOutflow(const ShVolume& v, int channel, const GeometryVolume& geometryVolume) {
    // What a cell q sends to a destination p outside the grid, with that destination's own
    // shared-face occlusion (the GV covers the boundary faces too).
    double sum = 0.0;
    for (int z = 0; z < v.size.z; ++z)
        for (int y = 0; y < v.size.y; ++y)
            for (int x = 0; x < v.size.x; ++x) {
                glm::ivec3 q(x, y, z);
                for (int i = 0; i < 6; ++i) {
                    glm::ivec3 p = q + lpvAxisStep(i);
                    if (v.contains(p))
                        continue;
                    for (int f = 0; f < 5; ++f)
                        sum += double(transmittance(geometryVolume, p, i, f) *
                                      glm::dot(v.channel[channel][v.index(q)], gpu::lpvFaceWeight(i, f)));
                }
            }
    return sum;
}

} // namespace vkgi::gi::lpv
