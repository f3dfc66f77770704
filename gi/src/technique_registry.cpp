// Technique names and module construction: the one place a new technique registers itself.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "lpv/lpv_technique.hpp"
#include "technique.hpp"
#include "vct/vct_technique.hpp"
#include "vpl/vpl_technique_module.hpp"

namespace vkgi::gi {

namespace {
struct TechniqueName {
    Technique technique;
    const char* name;
    int bounces; // reflections the technique models before its bounce knobs (see modelledBounces)
};
// vct: direct light plus VctSettings::bounces voxel bounces (added in modelledBounces); lpv: one
// indirect bounce, plus one when LpvSettings::bounces reflects at the voxel grid; vpl: one
// indirect bounce per VPL generation (VplSettings::bounces) of the punctual lights' light, and
// of the emitters' light their direct illumination plus one bounce fewer (docs/vpl.md).
constexpr std::array kTechniques = {TechniqueName{Technique::None, "none", 1}, TechniqueName{Technique::Lpv, "lpv", 2},
                                    TechniqueName{Technique::Vpl, "vpl", 2}, TechniqueName{Technique::Vct, "vct", 1}};
} // namespace

const char* toString(Technique technique) {
    for (const TechniqueName& t : kTechniques)
        if (t.technique == technique)
            return t.name;
    return "unknown";
}

int modelledBounces(const GiSettings& settings, const Scene* scene) {
    for (const TechniqueName& t : kTechniques) {
        if (t.technique != settings.technique)
            continue;
        switch (settings.technique) {
        case Technique::Vct: return t.bounces + int(settings.vct.bounces);
        case Technique::Lpv: return t.bounces + (settings.lpv.bounces ? 1 : 0);
        case Technique::Vpl: {
            const bool emission = scene && scene->hasEmission();
            const VplLighting lighting = scene ? vplLighting(scene->lights, emission) : VplLighting::Spots;
            const int generations = int(resolveVplSettings(settings.vpl, lighting).bounces);
            // Emitter VPLs carry the emitters' direct illumination (one reflection) and their
            // generations one more each: a scene lit by emission alone is modelled to B
            // reflections, one lit by punctual lights to B + 1 (the larger count when it has both).
            if (emission && scene->lights.empty())
                return generations;
            return t.bounces + generations - 1;
        }
        default: return t.bounces;
        }
    }
    return -1;
}

std::vector<std::string> techniqueNames() {
    std::vector<std::string> names;
    for (const TechniqueName& t : kTechniques)
        names.emplace_back(t.name);
    return names;
}

Result<Technique> parseTechnique(std::string_view name) {
    std::string valid;
    for (const TechniqueName& t : kTechniques) {
        if (name == t.name)
            return t.technique;
        valid += (valid.empty() ? "" : ", ") + std::string(t.name);
    }
    return makeError("unknown technique '" + std::string(name) + "' (valid: " + valid + ")");
}

namespace {

Result<void> checkSharedSettings(const GiSettings& s) {
    if (s.shadowMapSize < 16 || s.shadowMapSize > 8192)
        return makeError("GiSettings.shadowMapSize " + std::to_string(s.shadowMapSize) + " is outside 16..8192");
    if (s.maxShadowLayers < 1 || s.maxShadowLayers > 2048)
        return makeError("GiSettings.maxShadowLayers " + std::to_string(s.maxShadowLayers) + " is outside 1..2048");
    if (s.shadowCascades > kMaxShadowCascades)
        return makeError("GiSettings.shadowCascades " + std::to_string(s.shadowCascades) + " is outside 0.." +
                         std::to_string(kMaxShadowCascades) + " (cascades per directional light, 0 = off)");
    if (s.pcfRadius > 8)
        return makeError("GiSettings.pcfRadius " + std::to_string(s.pcfRadius) + " is above 8");
    for (float b : {s.shadowNormalOffset, s.shadowConstantBias})
        if (!std::isfinite(b) || b < 0.0f || b > 100.0f)
            return makeError("GiSettings shadow biases must be finite and in 0..100 texels");
    return {};
}

} // namespace

Result<void> validateSettings(const GiSettings& settings) {
    if (auto ok = checkSharedSettings(settings); !ok)
        return ok;
    switch (settings.technique) {
    case Technique::None: return {};
    case Technique::Lpv: return validate(settings.lpv);
    case Technique::Vpl: return validateVplSettings(settings.vpl);
    case Technique::Vct: return validateVctSettings(settings.vct);
    }
    return makeError("GiSettings.technique " + std::to_string(uint32_t(settings.technique)) + " is unknown");
}

Result<std::unique_ptr<TechniqueModule>> createTechnique(Context& ctx, const GiSettings& settings) {
    switch (settings.technique) {
    case Technique::None: return std::unique_ptr<TechniqueModule>();
    case Technique::Lpv: return createLpvTechnique(ctx, settings);
    case Technique::Vpl: return createVplTechniqueModule(ctx, settings);
    case Technique::Vct: return createVctTechnique(ctx, settings.vct);
    }
    return makeError(std::string("technique ") + toString(settings.technique) + " is not built into this library");
}

} // namespace vkgi::gi
