// CPU side of the VPL placement: the Halton directions inside a spot cone and the spot frame.
#include <algorithm>
#include <cmath>
#include <string>

#include "gi/vpl.h"
#include "vkgi/scene.hpp"
#include "vkgi/vpl.hpp"

namespace vkgi::gi {

static_assert(kMaxVplsPerLight == GI_VPL_MAX_PER_LIGHT && kMaxNegativeVpls == GI_VPL_MAX_NEGATIVE &&
              kMaxVplLights == GI_VPL_MAX_LIGHTS && kMaxVplInterleave == GI_VPL_MAX_INTERLEAVE, "C++ limits must mirror gi/vpl.h");

Result<void> validateVplSettings(const VplSettings& s) {
    auto bad = [](const std::string& what) { return makeError("VplSettings: " + what); };
    if (s.vplCount == 0 || s.vplCount > kMaxVplsPerLight)
        return bad("vplCount " + std::to_string(s.vplCount) + " is outside 1.." + std::to_string(kMaxVplsPerLight));
    if (s.negativeVplCount > kMaxNegativeVpls)
        return bad("negativeVplCount " + std::to_string(s.negativeVplCount) + " is outside 0.." +
                   std::to_string(kMaxNegativeVpls));
    if (s.lowResFactor != 1 && s.lowResFactor != 2 && s.lowResFactor != 4)
        return bad("lowResFactor " + std::to_string(s.lowResFactor) + " must be 1, 2 or 4");
    if (!std::isfinite(s.refineThreshold) || s.refineThreshold < 0.0f)
        return bad("refineThreshold " + std::to_string(s.refineThreshold) + " must be finite and >= 0");
    if (!std::isfinite(s.focusRadius) || s.focusRadius <= 0.0f || s.focusRadius > 1e5f)
        return bad("focusRadius " + std::to_string(s.focusRadius) + " must be in (0, 1e5] metres");
    if (!std::isfinite(s.clampDistance) || s.clampDistance <= 0.0f || s.clampDistance > 16.0f)
        return bad("clampDistance " + std::to_string(s.clampDistance) + " must be in (0, 16]");
    if (s.interleave < 1 || s.interleave > kMaxVplInterleave)
        return bad("interleave " + std::to_string(s.interleave) + " is outside 1.." +
                   std::to_string(kMaxVplInterleave));
    if (s.visibilityGrid < 16 || s.visibilityGrid > 256 || (s.visibilityGrid & (s.visibilityGrid - 1)) != 0)
        return bad("visibilityGrid " + std::to_string(s.visibilityGrid) + " must be a power of two in 16..256");
    if (s.bounces > kMaxVplBounces)
        return bad("bounces " + std::to_string(s.bounces) + " is outside 0.." + std::to_string(kMaxVplBounces) +
                   " (0 = automatic)");
    if (uint32_t(s.visibility) > uint32_t(VplVisibilityMode::Auto))
        return bad("visibility " + std::to_string(uint32_t(s.visibility)) + " is not off, on or auto");
    if (uint32_t(s.visibilityPlacement) > uint32_t(VplGridPlacement::Camera))
        return bad("visibilityPlacement " + std::to_string(uint32_t(s.visibilityPlacement)) +
                   " is not auto, fitted or camera");
    if (!std::isfinite(s.interleaveTolerance) || s.interleaveTolerance <= 0.0f || s.interleaveTolerance > 1.0f)
        return bad("interleaveTolerance " + std::to_string(s.interleaveTolerance) + " must be in (0, 1]");
    return {};
}

Result<std::vector<glm::vec3>> spotSampleDirections(uint32_t count, float cosOuter) {
    if (count > kMaxVplsPerLight)
        return makeError("spotSampleDirections: " + std::to_string(count) + " VPLs exceed the maximum " +
                         std::to_string(kMaxVplsPerLight));
    if (!(cosOuter >= -1.0f && cosOuter < 1.0f))
        return makeError("spotSampleDirections: cone cosine " + std::to_string(cosOuter) + " is outside [-1, 1)");
    std::vector<glm::vec3> dirs;
    dirs.reserve(count);
    for (uint32_t i = 1; dirs.size() < count; ++i) {
        if (i > kMaxHaltonSearch)
            return makeError("spotSampleDirections: cone of cosine " + std::to_string(cosOuter) +
                             " too narrow: only " + std::to_string(dirs.size()) + " of " + std::to_string(count) +
                             " Halton points inside after " + std::to_string(kMaxHaltonSearch) + " indices");
        glm::vec3 d = gpu::vplHaltonSphere(i);
        if (d.z >= cosOuter)
            dirs.push_back(d);
    }
    return dirs;
}

std::vector<glm::vec3> windowSamplePoints(uint32_t count) {
    std::vector<glm::vec3> points;
    points.reserve(count);
    for (uint32_t i = 1; i <= count; ++i)
        points.emplace_back(2.0f * gpu::vplRadicalInverse(i, 2u) - 1.0f, 2.0f * gpu::vplRadicalInverse(i, 3u) - 1.0f,
                            0.0f);
    return points;
}

std::vector<glm::vec3> emitterSampleOrder(uint32_t count) {
    // Ranks of the van der Corput points of 1..count: a contiguous run of them is spread over
    // [0, 1), so its ranks are spread over the surfels (which the plan lists side after side).
    std::vector<uint32_t> byValue(count);
    for (uint32_t k = 0; k < count; ++k)
        byValue[k] = k;
    std::sort(byValue.begin(), byValue.end(), [](uint32_t a, uint32_t b) {
        return gpu::vplRadicalInverse(a + 1u, 2u) < gpu::vplRadicalInverse(b + 1u, 2u);
    });
    std::vector<glm::vec3> order(count);
    for (uint32_t rank = 0; rank < count; ++rank)
        order[byValue[rank]] = glm::vec3(float(rank), 0.0f, 0.0f);
    return order;
}

bool vplLightNeedsVisibility(LightType type) { return type == LightType::Directional || type == LightType::Point; }

VplSettings resolveVplSettings(const VplSettings& s, bool needsVisibility) {
    VplSettings r = s;
    if (r.visibility == VplVisibilityMode::Auto)
        r.visibility = needsVisibility ? VplVisibilityMode::On : VplVisibilityMode::Off;
    if (r.bounces == 0)
        r.bounces = r.visibility == VplVisibilityMode::On ? 2 : 1;
    return r;
}

std::vector<glm::vec3> bounceSampleDirections(uint32_t count, uint32_t generation) {
    // Primes the placement (2, 3) does not use, a new pair per generation: a VPL's bounce
    // direction must not repeat the pattern of where it sits.
    static constexpr uint32_t kBases[][2] = {{5, 7}, {11, 13}, {17, 19}};
    const uint32_t* bases = kBases[std::min<uint32_t>(std::max<uint32_t>(generation, 1u), 3u) - 1u];
    std::vector<glm::vec3> dirs;
    dirs.reserve(count);
    for (uint32_t i = 1; i <= count; ++i) {
        // Malley: uniform points of the unit disc lifted to the hemisphere have pdf cos / pi.
        const float u = gpu::vplRadicalInverse(i, bases[0]), v = gpu::vplRadicalInverse(i, bases[1]);
        const float r = std::sqrt(u), phi = 6.28318530718f * v;
        dirs.emplace_back(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - u)));
    }
    return dirs;
}

glm::mat3 spotFrame(const glm::vec3& direction) {
    // Double precision: the rotation loses ~1/(1 + c) of its accuracy as d approaches +Y.
    const glm::dvec3 a(0.0, -1.0, 0.0);
    glm::dvec3 d = glm::normalize(glm::dvec3(direction));
    glm::dvec3 v = glm::cross(a, d);
    double c = glm::dot(a, d);
    // Rodrigues' rotation a -> d: R = I + [v]x + [v]x^2 / (1 + c); singular only at d = -a.
    glm::dmat3 vx(0.0, v.z, -v.y, -v.z, 0.0, v.x, v.y, -v.x, 0.0); // columns of the cross-product matrix
    glm::dmat3 r = c > -1.0 + 1e-12 ? glm::dmat3(1.0) + vx + vx * vx * (1.0 / (1.0 + c))
                                    : glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, -1));
    glm::dvec3 x = r * glm::dvec3(1.0, 0.0, 0.0);
    // Re-orthonormalise against the exact axis so the frame is orthonormal to float precision.
    x = glm::normalize(x - glm::dot(x, d) * d);
    glm::dvec3 y = glm::cross(d, x);
    return glm::mat3(glm::vec3(x), glm::vec3(y), glm::vec3(d));
}

} // namespace vkgi::gi
