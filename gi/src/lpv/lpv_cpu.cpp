#include "lpv/lpv_cpu.hpp"

#include "gi/lpv.h"

namespace vkgi::gi::lpv {

using gpu::lpvAxisStep;

ShVolume::ShVolume(glm::ivec3 cells, int shBands) : size(cells), bands(shBands) {
    for (int c = 0; c < 3; ++c) {
        channel[c].assign(cellCount(), glm::vec4(0.0f));
        if (bands == 3) {
            band2[c].assign(cellCount(), glm::vec4(0.0f));
            band2Last[c].assign(cellCount(), 0.0f);
        }
    }
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
    const bool three = source.bands == 3;
    if (target.size != source.size || target.bands != source.bands)
        target = ShVolume(source.size, source.bands);
    for (int z = 0; z < source.size.z; ++z)
        for (int y = 0; y < source.size.y; ++y)
            for (int x = 0; x < source.size.x; ++x) {
                glm::ivec3 p(x, y, z);
                glm::vec4 sum[3] = {glm::vec4(0.0f), glm::vec4(0.0f), glm::vec4(0.0f)};
                glm::vec4 sum2[3] = {glm::vec4(0.0f), glm::vec4(0.0f), glm::vec4(0.0f)};
                float sum2Last[3] = {0.0f, 0.0f, 0.0f};
                for (int i = 0; i < 6; ++i) {
                    glm::ivec3 q = p - lpvAxisStep(i);
                    if (!source.contains(q))
                        continue;
                    size_t k = source.index(q);
                    for (int f = 0; f < 5; ++f) {
                        float t = transmittance(geometryVolume, p, i, f);
                        glm::vec4 w = t * gpu::lpvFaceWeight(i, f);
                        glm::vec4 r = gpu::lpvFaceReprojection(i, f);
                        if (!three) {
                            for (int c = 0; c < 3; ++c)
                                sum[c] += glm::dot(source.channel[c][k], w) * r;
                            continue;
                        }
                        glm::vec4 w2 = t * gpu::lpvFaceWeightBand2(i, f);
                        glm::vec4 r2 = gpu::lpvFaceReprojectionBand2(i, f);
                        float w2l = t * gpu::lpvFaceWeightBand2Last(i, f);
                        float r2l = gpu::lpvFaceReprojectionBand2Last(i, f);
                        for (int c = 0; c < 3; ++c) {
                            float flux = glm::dot(source.channel[c][k], w) + glm::dot(source.band2[c][k], w2) +
                                         source.band2Last[c][k] * w2l;
                            sum[c] += flux * r;
                            sum2[c] += flux * r2;
                            sum2Last[c] += flux * r2l;
                        }
                    }
                }
                size_t k = target.index(p);
                for (int c = 0; c < 3; ++c) {
                    target.channel[c][k] = sum[c];
                    if (accumulation)
                        accumulation->channel[c][k] += sum[c];
                    if (three) {
                        target.band2[c][k] = sum2[c];
                        target.band2Last[c][k] = sum2Last[c];
                        if (accumulation) {
                            accumulation->band2[c][k] += sum2[c];
                            accumulation->band2Last[c][k] += sum2Last[c];
                        }
                    }
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
                    size_t k = v.index(q);
                    for (int f = 0; f < 5; ++f) {
                        float flux = glm::dot(v.channel[channel][k], gpu::lpvFaceWeight(i, f));
                        if (v.bands == 3)
                            flux += glm::dot(v.band2[channel][k], gpu::lpvFaceWeightBand2(i, f)) +
                                    v.band2Last[channel][k] * gpu::lpvFaceWeightBand2Last(i, f);
                        sum += double(transmittance(geometryVolume, p, i, f) * flux);
                    }
                }
            }
    return sum;
}

} // namespace vkgi::gi::lpv
