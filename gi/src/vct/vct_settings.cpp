#include <cmath>
#include <algorithm>
#include <string>

#include "vkgi/vct.hpp"
#include "gi/vct_passes.h"

namespace vkgi::gi {

namespace {
constexpr uint32_t kVctMaxClipmapLayers = 2048;

bool isPowerOfTwo(uint32_t v) {
    return v != 0 && (v & (v - 1)) == 0;
}
} // namespace

Result<void> validateVctSettings(const VctSettings& s) {
    if (!isPowerOfTwo(s.gridResolution) || s.gridResolution < GI_VOXEL_MIN_RESOLUTION ||
        s.gridResolution > GI_VOXEL_MAX_RESOLUTION)
        return makeError("vct: gridResolution " + std::to_string(s.gridResolution) +
                         " must be a power of two in [16, 256]");
    if (s.diffuseCones == 0 || s.diffuseCones > 32)
        return makeError("vct: diffuseCones " + std::to_string(s.diffuseCones) + " must be in [1, 32]");
    // Wider half-angles would read exactly the texels kVctMaxDiffuseAperture reads (the level cap).
    if (!std::isfinite(s.diffuseAperture) || s.diffuseAperture <= 0.0f || s.diffuseAperture > kVctMaxDiffuseAperture)
        return makeError("vct: diffuseAperture " + std::to_string(s.diffuseAperture) +
                         " must be a finite half-angle in (0, " + std::to_string(kVctMaxDiffuseAperture) +
                         "] radians: the level cap keeps a wider cone to the texels atan(1/3) reads");
    if (!std::isfinite(s.stepFactor) || s.stepFactor <= 0.0f || s.stepFactor > 4.0f)
        return makeError("vct: stepFactor must be finite and in (0, 4]");
    if (s.lowResFactor != 1 && s.lowResFactor != 2 && s.lowResFactor != 4)
        return makeError("vct: lowResFactor " + std::to_string(s.lowResFactor) + " must be 1, 2 or 4");
    if (s.filter < 1 || s.filter > kVctMaxFilter)
        return makeError("vct: filter " + std::to_string(s.filter) + " must be in [1, " +
                         std::to_string(kVctMaxFilter) + "] (1 = off)");
    if (!std::isfinite(s.refineThreshold) || s.refineThreshold < 0.0f)
        return makeError("vct: refineThreshold must be finite and >= 0");
    if (s.bounces < 1 || s.bounces > 3)
        return makeError("vct: bounces " + std::to_string(s.bounces) + " must be 1, 2 or 3");
    if (!std::isfinite(s.aoDistance) || s.aoDistance < 0.0f)
        return makeError("vct: aoDistance must be finite and >= 0");
    if (!std::isfinite(s.shadowAperture) || s.shadowAperture <= 0.0f || s.shadowAperture > 1.0f)
        return makeError("vct: shadowAperture must be a finite half-angle in (0, 1] radians");
    if (uint32_t(s.occlusion) > uint32_t(VctOcclusion::ShadowMap))
        return makeError("vct: occlusion " + std::to_string(uint32_t(s.occlusion)) + " is not a VctOcclusion");
    if (uint32_t(s.prefilter) > uint32_t(VctPrefilter::On))
        return makeError("vct: prefilter " + std::to_string(uint32_t(s.prefilter)) + " is not a VctPrefilter");
    if (s.gridBox && (!s.gridBox->valid() || !std::isfinite(s.gridBox->min.x + s.gridBox->min.y + s.gridBox->min.z +
                                                            s.gridBox->max.x + s.gridBox->max.y + s.gridBox->max.z)))
        return makeError("vct: gridBox must be a finite, non-empty box");
    if (s.levels > kVctMaxLevels)
        return makeError("vct: levels " + std::to_string(s.levels) + " must be in [0, " +
                         std::to_string(kVctMaxLevels) + "] (0 = automatic)");
    if (!std::isfinite(s.voxel) || s.voxel < 0.0f)
        return makeError("vct: voxel must be a finite edge length >= 0 metres (0 = automatic)");
    // The clipmap volume stacks the levels' six views of N slices along the layers of one array
    // image; 2048 layers is what lavapipe allows (maxImageArrayLayers).
    if (s.levels > 1 && GI_VCT_DIRECTIONS * s.gridResolution * s.levels > kVctMaxClipmapLayers)
        return makeError("vct: levels " + std::to_string(s.levels) + " of " + std::to_string(s.gridResolution) +
                         "^3 need " + std::to_string(GI_VCT_DIRECTIONS * s.gridResolution * s.levels) +
                         " array layers; at most " + std::to_string(kVctMaxClipmapLayers) +
                         " (6 * grid * levels): use fewer levels or a smaller grid");
    if (s.levels > 1 && s.softShadows)
        return makeError("vct: soft_shadows need levels = 1 (the shadow cones read a single grid)");
    if (s.levels > 1 && s.voxel > 0.0f && (s.voxel < 1e-4f || s.voxel > 1e4f))
        return makeError("vct: voxel " + std::to_string(s.voxel) + " m is outside [1e-4, 1e4] metres");
    return {};
}

VctSettings resolveVctLevels(const VctSettings& s, const Aabb& bounds, const Camera& camera) {
    if (s.levels != 0)
        return s;
    VctSettings fitted = s, clip = s;
    fitted.levels = 1;
    clip.levels = kVctAutoLevels;
    clip.gridResolution = kVctAutoLevelResolution;
    // Soft shadows and an explicit grid box need the one grid.
    if (s.softShadows || s.gridBox || !bounds.valid())
        return fitted;
    const glm::vec3 eye = camera.position;
    const bool inside = glm::all(glm::greaterThanEqual(eye, bounds.min)) && glm::all(glm::lessThanEqual(eye, bounds.max));
    const glm::vec3 e = bounds.extent();
    // fitVoxelGrid: the longest side spans resolution - 1 voxels.
    const float fittedVoxel = std::max({e.x, e.y, e.z}) / float(s.gridResolution - 1);
    const float coarsest = vctFinestVoxel(clip) * float(1u << (kVctAutoLevels - 1));
    // The bounds only select here; the clipmap's voxels are set in metres.
    return inside && fittedVoxel > coarsest ? clip : fitted;
}

float vctFinestVoxel(const VctSettings& s) {
    return s.voxel > 0.0f ? s.voxel : kVctAutoFinestSpan / float(s.gridResolution);
}

} // namespace vkgi::gi
