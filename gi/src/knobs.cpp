#include "vkgi/knobs.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <type_traits>

namespace vkgi::gi {

namespace {

std::string fmt(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

// Accessor-based constructors: `field` returns a reference to the member inside GiSettings.
template <typename Field>
Knob uintKnob(const char* name, double lo, double hi, std::optional<Technique> t, const char* help, Field field) {
    return {name, help, Knob::Kind::Uint, lo, hi, t,
            [field](const GiSettings& s) { return std::to_string(field(const_cast<GiSettings&>(s))); },
            [field](GiSettings& s, double v) { field(s) = uint32_t(v); }};
}
template <typename Field>
Knob floatKnob(const char* name, double lo, double hi, std::optional<Technique> t, const char* help, Field field) {
    return {name, help, Knob::Kind::Float, lo, hi, t,
            [field](const GiSettings& s) { return fmt(field(const_cast<GiSettings&>(s))); },
            [field](GiSettings& s, double v) { field(s) = float(v); }};
}
template <typename Field>
Knob boolKnob(const char* name, std::optional<Technique> t, const char* help, Field field) {
    return {name, help, Knob::Kind::Bool, 0, 1, t,
            [field](const GiSettings& s) { return std::string(field(const_cast<GiSettings&>(s)) ? "on" : "off"); },
            [field](GiSettings& s, double v) { field(s) = v != 0.0; }};
}

// An enum field (any enum class with values 0 .. names - 1), set and shown by name.
template <typename Field>
Knob enumKnob(const char* name, std::vector<std::string> names, std::optional<Technique> t, const char* help,
              Field field) {
    Knob k{name, help, Knob::Kind::Enum, 0, double(names.size() - 1), t,
           [field, names](const GiSettings& s) { return names.at(size_t(field(const_cast<GiSettings&>(s)))); },
           [field](GiSettings& s, double v) {
               using E = std::remove_reference_t<decltype(field(s))>;
               field(s) = E(uint32_t(v));
           }};
    k.choices = std::move(names);
    return k;
}

std::string joinChoices(const Knob& k) {
    std::string out;
    for (const std::string& c : k.choices)
        out += (out.empty() ? "" : "|") + c;
    return out;
}

std::vector<Knob> makeKnobs() {
    const std::optional<Technique> all;
    const std::optional<Technique> lpv = Technique::Lpv;
    const std::optional<Technique> vpl = Technique::Vpl;
    const std::optional<Technique> vct = Technique::Vct;
    return {
        uintKnob("shadow.size", 16, 4096, all, "shadow-map / RSM texels per side",
                 [](GiSettings& s) -> uint32_t& { return s.shadowMapSize; }),
        uintKnob("shadow.layers", 1, 256, all, "shadow atlas layers (a point light takes 6)",
                 [](GiSettings& s) -> uint32_t& { return s.maxShadowLayers; }),
        uintKnob("shadow.cascades", 0, kMaxShadowCascades, all,
                 "shadow cascades per directional light, fitted to the camera (0 = one whole-scene layer)",
                 [](GiSettings& s) -> uint32_t& { return s.shadowCascades; }),
        uintKnob("shadow.pcf", 0, 4, all, "PCF radius r: (2r+1)^2 filtered compares",
                 [](GiSettings& s) -> uint32_t& { return s.pcfRadius; }),
        floatKnob("shadow.normal_offset", 0, 16, all, "normal-offset bias, in shadow texels",
                  [](GiSettings& s) -> float& { return s.shadowNormalOffset; }),
        floatKnob("shadow.constant_bias", 0, 16, all, "depth bias below the receiver plane, in shadow texels",
                  [](GiSettings& s) -> float& { return s.shadowConstantBias; }),
        uintKnob("lpv.grid", 1, 128, lpv, "LPV cells per axis (memory and time grow as grid^3)",
                 [](GiSettings& s) -> uint32_t& { return s.lpv.gridSize; }),
        uintKnob("lpv.iterations", 0, 4096, lpv, "propagation steps (cells light travels)",
                 [](GiSettings& s) -> uint32_t& { return s.lpv.iterations; }),
        boolKnob("lpv.occlusion", lpv, "geometry-volume occlusion during propagation",
                 [](GiSettings& s) -> bool& { return s.lpv.occlusion; }),
        boolKnob("lpv.bounces", lpv, "reflect at occupied voxels (Gaitatzes et al. multi-bounce)",
                 [](GiSettings& s) -> bool& { return s.lpv.bounces; }),
        floatKnob("lpv.damping", 0, 1, lpv, "light-bleeding damping strength at lookup",
                  [](GiSettings& s) -> float& { return s.lpv.damping; }),
        uintKnob("lpv.cascades", 0, 4, lpv,
                 "nested camera-centred volumes (1 = one grid fitted to the lit region, 0 = automatic)",
                 [](GiSettings& s) -> uint32_t& { return s.lpv.cascades; }),
        floatKnob("lpv.cell", 1e-4, 1e4, lpv, "finest cascade's cell edge, metres",
                  [](GiSettings& s) -> float& { return s.lpv.cellSize; }),
        floatKnob("lpv.fit_cell", 0, 1e4, lpv,
                  "largest cell edge (metres) of the fitted grid: up to 24 cells per axis and "
                  "proportionally more steps where that reaches it (0 = lpv.grid cells)",
                  [](GiSettings& s) -> float& { return s.lpv.fittedCell; }),
        boolKnob("lpv.half", lpv, "RGBA16F SH storage (off = RGBA32F)",
                 [](GiSettings& s) -> bool& { return s.lpv.halfFloat; }),
        uintKnob("lpv.rsm_reduce", 1, 4, lpv,
                 "inject from the RSM reduced by 1, 2 or 4 per axis (flux-weighted surfels)",
                 [](GiSettings& s) -> uint32_t& { return s.lpv.rsmReduce; }),
        uintKnob("vpl.count", 1, kMaxVplsPerLight, vpl, "VPLs per light (Halton points in the spot cone, the sphere or the sun's window)",
                 [](GiSettings& s) -> uint32_t& { return s.vpl.vplCount; }),
        uintKnob("vpl.negative", 0, kMaxNegativeVpls, vpl, "negative VPLs for occlusion (0 = off)",
                 [](GiSettings& s) -> uint32_t& { return s.vpl.negativeVplCount; }),
        uintKnob("vpl.lowres", 1, 4, vpl, "gather at 1/f resolution per axis: 1, 2 or 4, refined at discontinuities",
                 [](GiSettings& s) -> uint32_t& { return s.vpl.lowResFactor; }),
        floatKnob("vpl.threshold", 0, 10, vpl, "discontinuity threshold of the low-res refinement",
                  [](GiSettings& s) -> float& { return s.vpl.refineThreshold; }),
        floatKnob("vpl.clamp", 0.001, 16, vpl, "1/d^2 clamp radius, in VPL footprint radii",
                  [](GiSettings& s) -> float& { return s.vpl.clampDistance; }),
        floatKnob("vpl.focus", 0.01, 1e5, vpl, "radius (m) around the camera a large sun window's VPLs concentrate in",
                  [](GiSettings& s) -> float& { return s.vpl.focusRadius; }),
        uintKnob("vpl.candidates", 0, kMaxVplCandidates, vpl,
                 "large sun window: candidates per VPL, drawn by their contribution to the frame (0 = lattice points)",
                 [](GiSettings& s) -> uint32_t& { return s.vpl.candidates; }),
        uintKnob("vpl.interleave", 1, kMaxVplInterleave, vpl,
                 "interleaved sampling: each pixel of an n x n tile gathers 1/n^2 of the VPLs, filtered back (1 = off)",
                 [](GiSettings& s) -> uint32_t& { return s.vpl.interleave; }),
        floatKnob("vpl.interleave_tolerance", 0.001, 1, vpl,
                  "interleave filter: tangent-plane offset that makes a neighbour another surface, fraction of depth",
                  [](GiSettings& s) -> float& { return s.vpl.interleaveTolerance; }),
        enumKnob("vpl.visibility", {"off", "on", "auto", "maps"}, vpl,
                 "VPL light stopped by a voxel grid's occupancy: on = marched per receiver, maps = per-VPL "
                 "visibility maps (off = none, as in the paper; auto = on with a directional light or emission, "
                 "else maps)",
                 [](GiSettings& s) -> VplVisibilityMode& { return s.vpl.visibility; }),
        uintKnob("vpl.visibility_grid", 16, 256, vpl,
                 "voxels per axis of the visibility (and bounce) grid, a power of two",
                 [](GiSettings& s) -> uint32_t& { return s.vpl.visibilityGrid; }),
        enumKnob("vpl.visibility_placement", {"auto", "fitted", "camera"}, vpl,
                 "where the visibility (and bounce) grid goes: fitted to the scene, centred on the camera (64 m "
                 "per axis), or auto = camera-centred where the fitted voxels would be much coarser",
                 [](GiSettings& s) -> VplGridPlacement& { return s.vpl.visibilityPlacement; }),
        uintKnob("vpl.bounces", 0, kMaxVplBounces, vpl,
                 "indirect bounces: VPL generations, each further one a ray per VPL through the voxel grid "
                 "(0 = automatic: 2 with visibility on, else 1)",
                 [](GiSettings& s) -> uint32_t& { return s.vpl.bounces; }),
        uintKnob("vct.grid", 16, 256, vct, "voxels per axis, a power of two (memory and time grow as grid^3)",
                 [](GiSettings& s) -> uint32_t& { return s.vct.gridResolution; }),
        uintKnob("vct.cones", 1, 32, vct, "diffuse cones per pixel and per voxel (bounce)",
                 [](GiSettings& s) -> uint32_t& { return s.vct.diffuseCones; }),
        floatKnob("vct.aperture", 0.01, kVctMaxDiffuseAperture, vct,
                  "diffuse cone half-angle, radians (the level cap makes every half-angle from atan(1/3) on "
                  "read the same texels, and narrows cones off the normal further)",
                  [](GiSettings& s) -> float& { return s.vct.diffuseAperture; }),
        floatKnob("vct.step", 0.05, 4, vct, "cone step in cone diameters",
                  [](GiSettings& s) -> float& { return s.vct.stepFactor; }),
        uintKnob("vct.bounces", 1, 3, vct,
                 "bounces in the voxels: 1 = direct light, 2 = plus a voxel gather, 3 = plus a second gather",
                 [](GiSettings& s) -> uint32_t& { return s.vct.bounces; }),
        uintKnob("vct.lowres", 1, 4, vct, "cones at 1/f resolution per axis: 1, 2 or 4, refined at discontinuities",
                 [](GiSettings& s) -> uint32_t& { return s.vct.lowResFactor; }),
        uintKnob("vct.filter", 1, kVctMaxFilter, vct,
                 "geometry-aware tent side n over the incoming diffuse light, in pixels (1 = off)",
                 [](GiSettings& s) -> uint32_t& { return s.vct.filter; }),
        floatKnob("vct.threshold", 0, 10, vct, "discontinuity threshold of the low-res refinement",
                  [](GiSettings& s) -> float& { return s.vct.refineThreshold; }),
        boolKnob("vct.glossy", vct, "glossy cone (weighted by metallic)",
                 [](GiSettings& s) -> bool& { return s.vct.glossy; }),
        boolKnob("vct.ao", vct, "cone-traced ambient occlusion (alpha of the indirect image)",
                 [](GiSettings& s) -> bool& { return s.vct.ambientOcclusion; }),
        floatKnob("vct.ao_distance", 0, 1e6, vct, "AO decay distance in metres (0 = 1/8 of the grid)",
                  [](GiSettings& s) -> float& { return s.vct.aoDistance; }),
        boolKnob("vct.soft_shadows", vct, "cone-traced shadows of the punctual lights replace the shadow map's",
                 [](GiSettings& s) -> bool& { return s.vct.softShadows; }),
        floatKnob("vct.shadow_aperture", 0.001, 1, vct, "half-angle of the shadow cones, radians",
                  [](GiSettings& s) -> float& { return s.vct.shadowAperture; }),
        uintKnob("vct.levels", 0, 8, vct,
                 "clipmap levels around the camera (0 = automatic, 1 = one grid fitted to the scene; 2..8: level l has voxels "
                 "of vct.voxel * 2^l)",
                 [](GiSettings& s) -> uint32_t& { return s.vct.levels; }),
        floatKnob("vct.voxel", 0, 1e4, vct, "voxel edge of the finest clipmap level, metres (0 = the finest level spans 16 m)",
                  [](GiSettings& s) -> float& { return s.vct.voxel; }),
        enumKnob("vct.prefilter", {"clipmap", "off", "on"}, vct,
                 "pre-filtered voxel opacity (the share of a voxel's cross-section its surfaces block): in clipmap "
                 "levels only, never, or also in a fitted grid",
                 [](GiSettings& s) -> VctPrefilter& { return s.vct.prefilter; }),
        enumKnob("vct.occlusion", {"hard", "soft", "shadowmap"}, vct,
                 "voxel light visibility: march through the occupancy (hard, soft) or the shadow map",
                 [](GiSettings& s) -> VctOcclusion& { return s.vct.occlusion; }),
    };
}

Result<double> parseValue(const Knob& k, std::string_view text) {
    std::string t(text);
    if (k.kind == Knob::Kind::Bool) {
        if (t == "on" || t == "true" || t == "1")
            return 1.0;
        if (t == "off" || t == "false" || t == "0")
            return 0.0;
        return makeError(k.name + ": '" + t + "' is not on/off/true/false/1/0");
    }
    if (k.kind == Knob::Kind::Enum) {
        for (size_t i = 0; i < k.choices.size(); ++i)
            if (t == k.choices[i])
                return double(i);
        return makeError(k.name + ": '" + t + "' is not one of " + joinChoices(k));
    }
    double v = 0.0;
    if (k.kind == Knob::Kind::Uint) {
        uint64_t u = 0;
        auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), u);
        if (t.empty() || ec != std::errc() || end != t.data() + t.size())
            return makeError(k.name + ": '" + t + "' is not a whole number");
        v = double(u);
    } else {
        char* end = nullptr;
        v = std::strtod(t.c_str(), &end);
        if (t.empty() || end != t.c_str() + t.size())
            return makeError(k.name + ": '" + t + "' is not a number");
        if (!std::isfinite(v))
            return makeError(k.name + ": '" + t + "' is not finite");
    }
    if (v < k.min || v > k.max)
        return makeError(k.name + ": " + t + " is out of range [" + fmt(k.min) + ", " + fmt(k.max) + "]");
    return v;
}

} // namespace

const std::vector<Knob>& knobs() {
    static const std::vector<Knob> table = makeKnobs();
    return table;
}

const Knob* findKnob(std::string_view name) {
    for (const Knob& k : knobs())
        if (k.name == name)
            return &k;
    return nullptr;
}

Result<void> setKnob(GiSettings& settings, std::string_view name, std::string_view value) {
    const Knob* k = findKnob(name);
    if (!k)
        return makeError("unknown setting '" + std::string(name) + "' (see --help for the list)");
    auto v = parseValue(*k, value);
    if (!v)
        return v.error();
    k->set(settings, *v);
    return {};
}

Result<void> applyKnob(GiSettings& settings, std::string_view assignment) {
    size_t eq = assignment.find('=');
    if (eq == std::string_view::npos)
        return makeError("'" + std::string(assignment) + "' is not of the form name=value");
    return setKnob(settings, assignment.substr(0, eq), assignment.substr(eq + 1));
}

std::string describeKnobs(const GiSettings& settings) {
    std::string out;
    for (const Knob& k : knobs()) {
        if (!k.technique || *k.technique != settings.technique)
            continue;
        size_t dot = k.name.find('.');
        out += (out.empty() ? "" : " ") + k.name.substr(dot + 1) + "=" + k.get(settings);
    }
    return out;
}

std::string knobHelp() {
    GiSettings defaults;
    std::string out;
    for (const Knob& k : knobs()) {
        std::string range = k.kind == Knob::Kind::Bool   ? "on|off"
                            : k.kind == Knob::Kind::Enum ? joinChoices(k)
                                                         : "[" + fmt(k.min) + ", " + fmt(k.max) + "]";
        char line[256];
        std::snprintf(line, sizeof line, "  --%-22s %-14s %s (default %s)\n", k.name.c_str(), range.c_str(),
                      k.help.c_str(), k.get(defaults).c_str());
        out += line;
    }
    return out;
}

} // namespace vkgi::gi
