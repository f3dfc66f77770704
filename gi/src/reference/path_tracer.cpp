// The reference integrator: see vkgi/reference.hpp for the model and the estimator.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "engine/lights.h"
#include "vkgi/progress.hpp"
#include "vkgi/reference.hpp"
#include "reference/rt_scene.hpp"
#include "reference/sampling.hpp"

namespace vkgi::gi {

namespace {

using namespace ref;
using Clock = std::chrono::steady_clock;

// Largest image side accepted: beyond it a reference is a mistake (16384^2 x 3 images ~ 9 GiB).
constexpr uint32_t kMaxImageSide = 16384;
// Roulette keeps a path's throughput near this value instead of 1: the random tail then adds
// steps of 0.1 x the emission rather than 1 x, which measured ~30x more efficient (variance x
// time) on the albedo-0.99 furnace and ~13x at albedo 0.8, for ~2x longer paths.
constexpr float kRouletteThroughput = 0.1f;
// Shadow rays stop this fraction short of a sampled emitter point so they cannot hit it.
constexpr float kShadowShorten = 1e-4f;

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

Result<void> validate(const Scene& scene, const Camera& camera, uint32_t width, uint32_t height,
                      const ReferenceSettings& s) {
    if (width == 0 || height == 0 || width > kMaxImageSide || height > kMaxImageSide)
        return makeError("reference: image size " + std::to_string(width) + "x" + std::to_string(height) +
                         " out of range (1.." + std::to_string(kMaxImageSide) + " per side)");
    if (s.spp == 0)
        return makeError("reference: spp must be at least 1");
    if (s.maxBounces < -1)
        return makeError("reference: maxBounces must be -1 (unbounded) or >= 0, got " + std::to_string(s.maxBounces));
    if (!finite(camera.position) || !finite(camera.forward) || !finite(camera.up) || !std::isfinite(camera.yfov) ||
        !(camera.yfov > 0.0f) || !(camera.yfov < 3.14159f) || !(glm::length(camera.forward) > 0.0f))
        return makeError("reference: camera has a non-finite or degenerate position, direction or fov");
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        const Light& l = scene.lights[i];
        const std::string what = "reference: light " + (l.name.empty() ? "#" + std::to_string(i) : "'" + l.name + "'");
        if (!finite(l.position) || !finite(l.direction) || !finite(l.color) || !std::isfinite(l.intensity) ||
            !std::isfinite(l.range) || !std::isfinite(l.innerConeAngle) || !std::isfinite(l.outerConeAngle))
            return makeError(what + " has a NaN/Inf value");
        if (l.intensity < 0.0f || glm::any(glm::lessThan(l.color, glm::vec3(0.0f))))
            return makeError(what + " has a negative intensity or colour");
        if (l.type != LightType::Point && !(glm::length(l.direction) > 0.0f))
            return makeError(what + " has a zero direction");
        if (uint32_t(l.type) > uint32_t(LightType::Spot))
            return makeError(what + " has an unknown type");
    }
    return {};
}

// Per-light constants precomputed once.
struct PunctualLight {
    LightType type;
    glm::vec3 position;
    glm::vec3 direction; // unit, the way the light shines
    glm::vec3 radiantIntensity; // colour x intensity (cd, or lux for directional)
    float range;
    float cosInner, cosOuter;
};

class Integrator {
public:
    Integrator(const RtScene& rt, const Scene& scene, const ReferenceSettings& s) : m_rt(rt), m_settings(s) {
        for (const Light& l : scene.lights) {
            PunctualLight p;
            p.type = l.type;
            p.position = l.position;
            p.direction = l.type == LightType::Point ? glm::vec3(0.0f, -1.0f, 0.0f) : glm::normalize(l.direction);
            p.radiantIntensity = l.color * l.intensity;
            p.range = l.range;
            p.cosInner = std::cos(l.innerConeAngle);
            p.cosOuter = std::cos(l.outerConeAngle);
            if (glm::any(glm::greaterThan(p.radiantIntensity, glm::vec3(0.0f))))
                m_lights.push_back(p);
        }
    }

    // One path through the pixel centre; adds radiance to `direct` (<= 1 reflection) or
    // `indirect` (>= 2 reflections). Returns the number of rays traced.
    uint64_t tracePath(const glm::vec3& origin, const glm::vec3& dir, Rng& rng, glm::dvec3& direct,
                       glm::dvec3& indirect) const {
        uint64_t rays = 0;
        auto add = [&](int reflections, const glm::vec3& c) {
            (reflections <= 1 ? direct : indirect) += glm::dvec3(c);
        };
        glm::vec3 beta(1.0f);
        glm::vec3 rayOrg = origin, rayDir = dir;
        glm::vec3 prevPosition = origin; // the exact point the ray left (rayOrg is offset from it)
        float pdfBsdfPrev = 0.0f;        // solid-angle pdf of the direction that reached this vertex
        for (int k = 0;; ++k) {   // k = reflections so far
            RTCRayHit rh = makeRay(rayOrg, rayDir, std::numeric_limits<float>::infinity());
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            rtcIntersect1(m_rt.embree(), &ctx, &rh);
            ++rays;
            if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID)
                break; // no environment light
            const SurfaceHit s = m_rt.surface(rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v);
            const float cosOut = glm::dot(s.ng, -rayDir); // > 0: the ray arrives on the front face
            if ((cosOut > 0.0f || s.doubleSided) && glm::any(glm::greaterThan(s.emission, glm::vec3(0.0f)))) {
                float w = 1.0f;
                if (k > 0) { // a BSDF-sampled hit that NEE could also have produced
                    // The distance NEE's pdf uses: between the exact points, not from the offset origin.
                    float t = glm::length(s.position - prevPosition);
                    float pdfLight = s.lightPdfPerArea * t * t / std::max(std::abs(cosOut), 1e-12f);
                    w = powerHeuristic(pdfBsdfPrev, pdfLight);
                }
                add(k, beta * s.emission * w);
            }
            if ((m_settings.maxBounces >= 0 && k >= m_settings.maxBounces) || k >= kMaxReflections)
                break;
            if (!glm::any(glm::greaterThan(s.albedo, glm::vec3(0.0f))))
                break;

            // Shade on the side the ray came from (two-sided reflection).
            const glm::vec3 ng = cosOut >= 0.0f ? s.ng : -s.ng;
            const glm::vec3 ns = glm::dot(s.ns, ng) >= 0.0f ? s.ns : -s.ns;
            // Geometry terms use the exact hit point; only rays leave from the offset origin `o`,
            // so the offset can never bias the inverse-square falloff.
            const glm::vec3 p = s.position;
            const glm::vec3 o = cosOut >= 0.0f ? s.spawnAbove : s.spawnBelow;
            const glm::vec3 f = s.albedo * kInvPi; // Lambert

            for (const PunctualLight& l : m_lights) {
                glm::vec3 wi;
                glm::vec3 li;
                if (l.type == LightType::Directional) {
                    wi = -l.direction;
                    li = l.radiantIntensity; // lux on a surface facing the light
                } else {
                    glm::vec3 d = l.position - p;
                    float dist2 = glm::dot(d, d);
                    if (!(dist2 > 0.0f))
                        continue;
                    float dist = std::sqrt(dist2);
                    wi = d / dist;
                    float atten = gpu::lightRangeWindow(dist, l.range) / dist2;
                    if (l.type == LightType::Spot)
                        atten *= gpu::spotConeAttenuation(glm::dot(l.direction, -wi), l.cosInner, l.cosOuter);
                    li = l.radiantIntensity * atten;
                }
                if (glm::dot(wi, ng) <= 0.0f)
                    continue;
                float cosS = std::max(0.0f, glm::dot(ns, wi));
                glm::vec3 c = beta * f * li * cosS;
                if (!glm::any(glm::greaterThan(c, glm::vec3(0.0f))))
                    continue;
                ++rays;
                bool blocked = l.type == LightType::Directional
                                   ? occluded(o, wi, std::numeric_limits<float>::infinity())
                                   : occludedSegment(o, l.position, 0.0f);
                if (!blocked)
                    add(k + 1, c);
            }

            if (m_rt.hasAreaLights()) {
                float uPick = rng.next(), u1 = rng.next(), u2 = rng.next();
                const LightSample ls = m_rt.sampleAreaLight(uPick, u1, u2);
                glm::vec3 d = ls.position - p;
                float dist2 = glm::dot(d, d);
                float dist = std::sqrt(dist2);
                glm::vec3 wi = d / dist;
                float cosL = glm::dot(ls.ng, -wi);
                if (ls.doubleSided)
                    cosL = std::abs(cosL);
                float cosS = glm::dot(ns, wi);
                if (dist2 > 0.0f && cosL > 0.0f && glm::dot(wi, ng) > 0.0f && cosS > 0.0f) {
                    float pdfLight = ls.pdfArea * dist2 / cosL;
                    float w = powerHeuristic(pdfLight, cosS * kInvPi);
                    glm::vec3 c = beta * f * ls.emission * (cosS * w / pdfLight);
                    if (glm::any(glm::greaterThan(c, glm::vec3(0.0f))) && std::isfinite(pdfLight)) {
                        ++rays;
                        if (!occludedSegment(o, ls.position, kShadowShorten))
                            add(k + 1, c);
                    }
                }
            }

            // Continue by cosine sampling about the shading normal; f cos / pdf = albedo.
            const float u1 = rng.next(), u2 = rng.next();
            glm::vec3 wi = sampleCosine(ns, u1, u2);
            float cosS = glm::dot(ns, wi);
            if (glm::dot(wi, ng) <= 0.0f || !(cosS > 0.0f))
                break; // below the true surface: would leak through it
            pdfBsdfPrev = cosS * kInvPi;
            beta *= s.albedo;
            if (k + 1 > 3) { // Russian roulette once 3 reflections are taken
                float q = std::min(1.0f, maxComponent(beta) / kRouletteThroughput);
                if (rng.next() >= q)
                    break;
                beta /= q;
            }
            rayOrg = o;
            prevPosition = p;
            rayDir = wi;
        }
        return rays;
    }

private:
    static RTCRayHit makeRay(const glm::vec3& o, const glm::vec3& d, float tFar) {
        RTCRayHit rh{};
        rh.ray.org_x = o.x;
        rh.ray.org_y = o.y;
        rh.ray.org_z = o.z;
        rh.ray.tnear = 0.0f;
        rh.ray.dir_x = d.x;
        rh.ray.dir_y = d.y;
        rh.ray.dir_z = d.z;
        rh.ray.tfar = tFar;
        rh.ray.mask = ~0u;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        return rh;
    }

    bool occluded(const glm::vec3& o, const glm::vec3& d, float tFar) const {
        RTCRayHit rh = makeRay(o, d, tFar);
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        rtcOccluded1(m_rt.embree(), &ctx, &rh.ray);
        return rh.ray.tfar < 0.0f; // Embree sets tfar = -inf on a hit
    }

    // Is anything between `from` and `to`, stopping `shorten` (a fraction) short of `to`?
    bool occludedSegment(const glm::vec3& from, const glm::vec3& to, float shorten) const {
        glm::vec3 d = to - from;
        float len = glm::length(d);
        if (!(len > 0.0f))
            return false;
        return occluded(from, d / len, len * (1.0f - shorten));
    }

    const RtScene& m_rt;
    ReferenceSettings m_settings;
    std::vector<PunctualLight> m_lights;
};

} // namespace

Result<ReferenceImages> renderReference(const Scene& scene, const Camera& camera, uint32_t width, uint32_t height,
                                        const ReferenceSettings& settings) {
    if (auto ok = validate(scene, camera, width, height, settings); !ok)
        return ok.error();
    const auto start = Clock::now();
    auto built = RtScene::build(scene);
    if (!built)
        return makeError("reference: " + built.error().message);
    const RtScene& rt = **built;
    const Integrator integrator(rt, scene, settings);

    ReferenceImages out;
    out.full = HdrImage(width, height);
    out.direct = HdrImage(width, height);
    out.indirect = HdrImage(width, height);
    std::atomic<uint64_t> rays{0};
    Progress progress("reference", uint64_t(width) * height, settings.progress);
    const double invSpp = 1.0 / double(settings.spp);

    // Each pixel is owned by one task and sums its samples in order: thread-count independent.
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, height, 1), [&](const tbb::blocked_range<uint32_t>& rows) {
        uint64_t localRays = 0;
        for (uint32_t y = rows.begin(); y != rows.end(); ++y) {
            for (uint32_t x = 0; x < width; ++x) {
                const glm::vec3 dir = camera.pixelRayDirection(x, y, width, height);
                const uint64_t pixel = uint64_t(y) * width + x;
                glm::dvec3 direct(0.0), indirect(0.0);
                for (uint32_t s = 0; s < settings.spp; ++s) {
                    Rng rng(settings.seed, pixel, s);
                    localRays += integrator.tracePath(camera.position, dir, rng, direct, indirect);
                }
                out.direct.at(x, y) = glm::vec3(direct * invSpp);
                out.indirect.at(x, y) = glm::vec3(indirect * invSpp);
                out.full.at(x, y) = glm::vec3((direct + indirect) * invSpp);
            }
            progress.add(width);
        }
        rays.fetch_add(localRays);
    });
    progress.finish();
    out.rays = rays.load();
    out.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return out;
}

} // namespace vkgi::gi
