// Scene analysis and change tracking for pass selection (pass_selection.hpp).
#include "pass_selection.hpp"

#include "direct/direct_passes.hpp"

#include <algorithm>
#include <cstring>

namespace vkgi::gi {

const char* toString(LeftOutReason reason) {
    switch (reason) {
    case LeftOutReason::Culled: return "culled";
    case LeftOutReason::NotNeeded: return "not-needed";
    case LeftOutReason::NotDirty: return "not-dirty";
    }
    return "unknown";
}

SceneFeatures analyzeScene(const Scene& scene) {
    SceneFeatures f;
    for (const Light& l : scene.lights) {
        switch (l.type) {
        case LightType::Directional: ++f.directionalLights; break;
        case LightType::Point: ++f.pointLights; break;
        case LightType::Spot: ++f.spotLights; break;
        }
    }
    for (const Instance& inst : scene.instances) {
        if (inst.mesh >= scene.meshes.size())
            continue;
        const Mesh& mesh = scene.meshes[inst.mesh];
        if (mesh.triangleCount() == 0)
            continue;
        f.geometry = true;
        f.dynamicObjects = f.dynamicObjects || inst.dynamic;
        if (mesh.material >= scene.materials.size())
            continue;
        const Material& m = scene.materials[mesh.material];
        f.emissive = f.emissive || glm::any(glm::greaterThan(m.emission, glm::vec3(0.0f)));
        f.metallic = f.metallic || m.metallic > 0.0f;
    }
    return f;
}

bool SceneChanges::lightChanged(uint32_t light) const {
    return all || std::binary_search(lights.begin(), lights.end(), light);
}

void SceneChanges::merge(const SceneChanges& other) {
    all = all || other.all;
    staticGeometry = staticGeometry || other.staticGeometry;
    dynamicGeometry = dynamicGeometry || other.dynamicGeometry;
    camera = camera || other.camera;
    std::vector<uint32_t> merged;
    std::set_union(lights.begin(), lights.end(), other.lights.begin(), other.lights.end(), std::back_inserter(merged));
    lights = std::move(merged);
}

namespace {

bool sameLight(const Light& a, const Light& b) {
    return a.type == b.type && a.position == b.position && a.direction == b.direction && a.color == b.color &&
           a.intensity == b.intensity && a.range == b.range && a.innerConeAngle == b.innerConeAngle &&
           a.outerConeAngle == b.outerConeAngle;
}

} // namespace

SceneChanges diffScenes(const Scene& before, const Scene& after) {
    SceneChanges c;
    c.all = before.instances.size() != after.instances.size() || before.lights.size() != after.lights.size();
    if (c.all)
        return c;
    for (size_t i = 0; i < after.instances.size(); ++i) {
        const Instance& a = before.instances[i];
        const Instance& b = after.instances[i];
        if (a.mesh != b.mesh || a.dynamic != b.dynamic) {
            c.all = true; // not an edit updateScene accepts; recompute everything
            return c;
        }
        if (a.transform != b.transform)
            (b.dynamic ? c.dynamicGeometry : c.staticGeometry) = true;
    }
    for (uint32_t i = 0; i < after.lights.size(); ++i)
        if (!sameLight(before.lights[i], after.lights[i]))
            c.lights.push_back(i);
    return c;
}

std::string describeChanges(const SceneChanges& c) {
    if (c.all)
        return "everything (new scene)";
    std::string s;
    auto add = [&](const std::string& part) { s += (s.empty() ? "" : ", ") + part; };
    if (c.staticGeometry)
        add("a static object moved");
    if (c.dynamicGeometry)
        add("a dynamic object moved");
    for (uint32_t l : c.lights)
        add("light " + std::to_string(l) + " changed");
    if (c.camera)
        add("camera moved");
    return s.empty() ? "nothing" : s;
}

namespace {
// Whether anything of `last` can still be valid under `now`: not after a geometry change, a
// full invalidation, or a different light count or atlas resolution.
bool layoutsComparable(const ShadowLayout& now, const ShadowLayout& last, const SceneChanges& changes) {
    return !changes.all && !changes.geometry() && last.lights.size() == now.lights.size() &&
           last.resolution == now.resolution;
}
} // namespace

namespace {
// Per light: `same(now's plan, last's plan)` and no change to the light (false for all when the
// layouts are not comparable).
template <class Same>
std::vector<bool> cleanPerLight(const ShadowLayout& now, const ShadowLayout& last, const SceneChanges& changes,
                                Same same) {
    std::vector<bool> clean(now.lights.size(), false);
    if (!layoutsComparable(now, last, changes))
        return clean;
    for (uint32_t i = 0; i < now.lights.size(); ++i)
        clean[i] = same(now.lights[i], last.lights[i]) && !changes.lightChanged(i);
    return clean;
}
} // namespace

std::vector<bool> cleanShadowLights(const ShadowLayout& now, const ShadowLayout& last, const SceneChanges& changes) {
    return cleanPerLight(now, last, changes, [&](const LightShadowPlan& a, const LightShadowPlan& b) {
        bool same = a.kind == b.kind && a.firstLayer == b.firstLayer && a.layerCount == b.layerCount &&
                    a.faceMask == b.faceMask && a.rsmWindowed == b.rsmWindowed;
        if (same && a.layerCount > 0)
            same = std::memcmp(&now.views[a.firstLayer], &last.views[b.firstLayer],
                               a.layerCount * sizeof(gpu::GpuShadowView)) == 0;
        return same;
    });
}

std::vector<bool> cleanRsmWindows(const ShadowLayout& now, const ShadowLayout& last, const SceneChanges& changes) {
    return cleanPerLight(now, last, changes, [](const LightShadowPlan& a, const LightShadowPlan& b) {
        return a.rsmWindowed && b.rsmWindowed && a.firstLayer == b.firstLayer &&
               std::memcmp(&a.rsmView, &b.rsmView, sizeof(gpu::GpuShadowView)) == 0;
    });
}

namespace {
// Per light, bit k set when layer first + k of the range (first, count) of LightShadowPlan is the
// same as in `last` (same range, bitwise same view) and the light did not change.
std::vector<uint32_t> cleanLayerRanges(const ShadowLayout& now, const ShadowLayout& last, const SceneChanges& changes,
                                       uint32_t LightShadowPlan::*first, uint32_t LightShadowPlan::*count) {
    std::vector<uint32_t> clean(now.lights.size(), 0u);
    if (!layoutsComparable(now, last, changes))
        return clean;
    for (uint32_t i = 0; i < now.lights.size(); ++i) {
        const LightShadowPlan& a = now.lights[i];
        const LightShadowPlan& b = last.lights[i];
        if (a.*first != b.*first || a.*count != b.*count || changes.lightChanged(i))
            continue;
        for (uint32_t k = 0; k < a.*count; ++k)
            if (std::memcmp(&now.views[a.*first + k], &last.views[b.*first + k], sizeof(gpu::GpuShadowView)) == 0)
                clean[i] |= 1u << k;
    }
    return clean;
}
} // namespace

std::vector<uint32_t> cleanShadowCascades(const ShadowLayout& now, const ShadowLayout& last,
                                          const SceneChanges& changes) {
    return cleanLayerRanges(now, last, changes, &LightShadowPlan::cascadeFirst, &LightShadowPlan::cascadeCount);
}

std::vector<uint32_t> cleanShadowWindows(const ShadowLayout& now, const ShadowLayout& last,
                                         const SceneChanges& changes) {
    return cleanLayerRanges(now, last, changes, &LightShadowPlan::windowFirst, &LightShadowPlan::windowCount);
}

bool sameView(const Camera& a, uint32_t aw, uint32_t ah, const Camera& b, uint32_t bw, uint32_t bh) {
    return aw == bw && ah == bh && a.position == b.position && a.forward == b.forward && a.up == b.up &&
           a.yfov == b.yfov && a.znear == b.znear && a.zfar == b.zfar;
}

void leaveOutMissingLightKinds(const SceneFeatures& features, PassSelection& selection) {
    if (features.directionalLights == 0)
        selection.leaveOut("gi.light[*].directional", LeftOutReason::NotNeeded, "no directional light in the scene");
    if (features.pointLights == 0)
        selection.leaveOut("gi.light[*].point", LeftOutReason::NotNeeded, "no point light in the scene");
    if (features.spotLights == 0)
        selection.leaveOut("gi.light[*].spot", LeftOutReason::NotNeeded, "no spotlight in the scene");
}

} // namespace vkgi::gi
