// CPU side of the VPL placement: the Halton directions inside a spot cone and the spot frame, and
// the world-anchored points of a large sun window.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <string>

#include "gi/vpl.h"
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
    if (!std::isfinite(s.focusRadius) || s.focusRadius < 0.01f || s.focusRadius > 1e5f)
        return bad("focusRadius " + std::to_string(s.focusRadius) + " must be in [0.01, 1e5] metres");
    if (s.candidates > kMaxVplCandidates)
        return bad("candidates " + std::to_string(s.candidates) + " is outside 0.." +
                   std::to_string(kMaxVplCandidates));
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
    if (uint32_t(s.visibility) > uint32_t(VplVisibilityMode::Maps))
        return bad("visibility " + std::to_string(uint32_t(s.visibility)) + " is not off, on, auto or maps");
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

namespace {

// An orthographic window's x and y as coordinates on the plane across the light, in metres:
// NDC = scale * (axis . p) + offset, with axis a unit vector fixed by the light's direction, so
// that plane coordinates belong to the world and not to where the window lies.
struct WindowPlane {
    glm::dvec3 axis[2];
    double scale[2] = {1.0, 1.0};
    double offset[2] = {0.0, 0.0};
    double toPlane(int k, double ndc) const { return (ndc - offset[k]) / scale[k]; }
    double toNdc(int k, double metres) const { return scale[k] * metres + offset[k]; }
};

WindowPlane windowPlane(const glm::mat4& viewProj) {
    WindowPlane w;
    for (int k = 0; k < 2; ++k) {
        const glm::dvec3 row(viewProj[0][k], viewProj[1][k], viewProj[2][k]);
        w.scale[k] = std::max(glm::length(row), 1e-30);
        w.axis[k] = row / w.scale[k];
        w.offset[k] = viewProj[3][k];
    }
    return w;
}

// Radial CDF of the focus density p(r) = 1 / (pi R^2 (1 + r^2/R^2)^2).
double focusCdf(double r, double radius) {
    return r * r / (radius * radius + r * r);
}

// Ring k's inner radius: 0, R/2, R, 2R, 4R, ...
double ringRadius(uint32_t k, double radius) {
    return k == 0 ? 0.0 : radius * std::ldexp(1.0, int(k) - 2);
}

} // namespace

bool windowIsFocused(const glm::mat4& windowViewProj, float radius) {
    const WindowPlane w = windowPlane(windowViewProj);
    const double halfX = 1.0 / w.scale[0], halfY = 1.0 / w.scale[1];
    return std::sqrt(halfX * halfX + halfY * halfY) > 2.0 * double(radius);
}

FocusedWindowSamples focusedWindowPoints(const glm::mat4& windowViewProj, const glm::vec3& camera, float radius,
                                         uint32_t count, uint32_t subsets) {
    const WindowPlane w = windowPlane(windowViewProj);
    const double R = radius;
    double lo[2], hi[2], centre[2];
    for (int k = 0; k < 2; ++k) {
        const double a = w.toPlane(k, -1.0), b = w.toPlane(k, 1.0);
        lo[k] = std::min(a, b);
        hi[k] = std::max(a, b);
        const double cell = 0.25 * R;
        centre[k] = std::floor(glm::dot(w.axis[k], glm::dvec3(camera)) / cell + 0.5) * cell;
    }
    double farthest = 0.0; // from the camera's place to the window's farthest corner
    for (double x : {lo[0], hi[0]})
        for (double y : {lo[1], hi[1]})
            farthest = std::max(farthest, std::hypot(x - centre[0], y - centre[1]));

    // Subset s owns the slots [s N / n^2, (s + 1) N / n^2) of gi/vpl.h's order (blocks differ
    // by one, or are empty, when N is not a multiple of the subsets). The lattices fill kFill of
    // the slots on average; the rest absorbs how many lattice points happen to fall into a ring.
    auto blockStart = [&](uint32_t subset) { return uint32_t(uint64_t(subset) * count / subsets); };
    const uint32_t slots = count;
    constexpr double kFill = 0.97;
    struct Point {
        double u, v, share;
        uint32_t ring;
        int64_t i, j;
    };
    std::vector<Point> points;
    for (uint32_t ring = 0; ringRadius(ring, R) < farthest && points.size() < slots; ++ring) {
        const double inner = ringRadius(ring, R), outer = ringRadius(ring + 1, R);
        const double expected = kFill * double(count) * (focusCdf(outer, R) - focusCdf(inner, R));
        const double area = 3.14159265358979 * (outer * outer - inner * inner);
        const double spacing = std::sqrt(area / expected);
        // A fixed offset per ring (the R2 sequence), so that the rings' lattices do not line up.
        const double offset[2] = {spacing * std::fmod(0.5 + 0.7548776662466927 * ring, 1.0),
                                  spacing * std::fmod(0.5 + 0.5698402909980532 * ring, 1.0)};
        // Lattice indices of the ring's box within the window. Beyond 2^52 a double no longer
        // holds every lattice point (a focus radius far below the coordinates): no points.
        double first[2], last[2];
        bool representable = true;
        for (int k = 0; k < 2; ++k) {
            first[k] = std::ceil((std::max(centre[k] - outer, lo[k]) - offset[k]) / spacing);
            last[k] = std::floor((std::min(centre[k] + outer, hi[k]) - offset[k]) / spacing);
            representable = representable && std::abs(first[k]) < 0x1p52 && std::abs(last[k]) < 0x1p52;
        }
        if (!representable)
            continue;
        for (int64_t j = int64_t(first[1]); j <= int64_t(last[1]); ++j)
            for (int64_t i = int64_t(first[0]); i <= int64_t(last[0]); ++i) {
                const double u = double(i) * spacing + offset[0], v = double(j) * spacing + offset[1];
                const double r2 = (u - centre[0]) * (u - centre[0]) + (v - centre[1]) * (v - centre[1]);
                if (r2 >= inner * inner && r2 < outer * outer)
                    points.push_back({u, v, spacing * spacing, ring, i, j});
            }
    }
    // Rings are added from the camera outwards: an overfull set drops the farthest ring's points.
    if (points.size() > slots)
        points.resize(slots);

    // Subsets: a point's subset is its lattice class (i mod n, j mod n), so that each subset is
    // a coarser lattice of every ring and a point keeps its subset while the camera moves. A
    // subset that is full passes its remaining points to the subsets with room, in order.
    const uint32_t n = uint32_t(std::lround(std::sqrt(double(subsets))));
    auto mod = [](int64_t x, uint32_t m) { return uint32_t(((x % int64_t(m)) + int64_t(m)) % int64_t(m)); };
    std::vector<uint32_t> filled(subsets, 0);
    FocusedWindowSamples out;
    out.samples.assign(count, glm::vec3(2.0f, 2.0f, 1.0f)); // beyond the window: an empty VPL
    out.ids.assign(count, 0u);
    auto room = [&](uint32_t subset) { return filled[subset] < blockStart(subset + 1) - blockStart(subset); };
    auto place = [&](const Point& p, uint32_t subset) {
        const uint32_t index = blockStart(subset) + filled[subset]++;
        out.samples[index] = glm::vec3(float(w.toNdc(0, p.u)), float(w.toNdc(1, p.v)), float(p.share));
        // Which bounce ray the point's children take: fixed by the point, not by its slot.
        out.ids[index] = uint32_t((uint64_t(p.i) * 73856093u) ^ (uint64_t(p.j) * 19349663u) ^ (uint64_t(p.ring) * 83492791u));
    };
    std::vector<const Point*> spilled;
    for (const Point& p : points) {
        const uint32_t subset = n * n == subsets ? mod(p.i, n) + n * mod(p.j, n) : 0u;
        if (room(subset))
            place(p, subset);
        else
            spilled.push_back(&p);
    }
    uint32_t subset = 0;
    for (const Point* p : spilled) {
        while (!room(subset))
            ++subset;
        place(*p, subset);
    }
    return out;
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

VplSettings resolveVplSettings(const VplSettings& s, VplLighting lighting) {
    VplSettings r = s;
    if (r.visibility == VplVisibilityMode::Auto)
        r.visibility = lighting == VplLighting::SunOrEmission ? VplVisibilityMode::On
                       : lighting == VplLighting::PointLights ? VplVisibilityMode::Maps
                                                              : VplVisibilityMode::Off;
    if (r.bounces == 0)
        r.bounces = r.visibility != VplVisibilityMode::Off ? 2 : 1;
    return r;
}

std::vector<glm::vec3> bounceSampleDirections(uint32_t count, uint32_t generation) {
    std::vector<glm::vec3> dirs;
    dirs.reserve(count);
    for (uint32_t i = 1; i <= count; ++i)
        dirs.push_back(gpu::vplBounceDirection(i, generation));
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
