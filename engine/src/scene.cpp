#include "vkgi/scene.hpp"

#include <cmath>
#include <string>

namespace vkgi {

Aabb Scene::bounds() const {
    Aabb box;
    for (const Instance& inst : instances) {
        if (inst.mesh >= meshes.size())
            continue;
        for (const glm::vec3& p : meshes[inst.mesh].positions)
            box.extend(glm::vec3(inst.transform * glm::vec4(p, 1.0f)));
    }
    return box;
}

uint64_t Scene::triangleCount() const {
    uint64_t n = 0;
    for (const Instance& inst : instances)
        if (inst.mesh < meshes.size())
            n += meshes[inst.mesh].triangleCount();
    return n;
}

bool Scene::hasEmission() const {
    for (const Instance& inst : instances) {
        if (inst.mesh >= meshes.size())
            continue;
        uint32_t m = meshes[inst.mesh].material;
        if (m < materials.size() && glm::any(glm::greaterThan(materials[m].emission, glm::vec3(0.0f))))
            return true;
    }
    return false;
}

Camera Scene::cameraOrDefault() const {
    if (camera)
        return *camera;
    Aabb b = bounds();
    if (!b.valid())
        return Camera{};
    if (std::optional<Camera> inside = interiorCamera(*this))
        return *inside;
    return framingCamera(b.min, b.max);
}

namespace {

bool finite(float v) { return std::isfinite(v); }
bool finite(const glm::vec3& v) { return finite(v.x) && finite(v.y) && finite(v.z); }
bool finite(const glm::vec4& v) { return finite(v.x) && finite(v.y) && finite(v.z) && finite(v.w); }
bool nonNegative(const glm::vec3& v) { return finite(v) && v.x >= 0.0f && v.y >= 0.0f && v.z >= 0.0f; }

std::string named(const char* kind, size_t i, const std::string& name) {
    std::string s = std::string(kind) + " " + std::to_string(i);
    if (!name.empty())
        s += " '" + name + "'";
    return s;
}

} // namespace

bool isSingularTransform(const glm::mat4& transform) {
    const glm::mat3 m(transform);
    const float l0 = glm::length(m[0]), l1 = glm::length(m[1]), l2 = glm::length(m[2]);
    // |det| against the product of the axis lengths: 1 for orthogonal axes of any scale, 0 when
    // an axis is zero or the axes are coplanar. NaN counts as singular.
    return !(std::abs(glm::determinant(m)) > kSingularTransformRatio * l0 * l1 * l2);
}

Result<void> validateScene(const Scene& scene) {
    const std::string where = "scene '" + scene.name + "': ";
    auto fail = [&](const std::string& what) { return Result<void>(makeError(where + what)); };

    for (size_t ti = 0; ti < scene.textures.size(); ++ti) {
        const Texture& t = scene.textures[ti];
        if (uint64_t(t.width) * t.height * 4 != t.rgba8.size())
            return fail(named("texture", ti, t.name) + " holds " + std::to_string(t.rgba8.size()) + " bytes, expected " +
                        std::to_string(t.width) + " x " + std::to_string(t.height) + " x 4");
    }
    for (size_t mi = 0; mi < scene.materials.size(); ++mi) {
        const Material& m = scene.materials[mi];
        std::string what = named("material", mi, m.name);
        if (!finite(m.baseColor) || m.baseColor.x < 0.0f || m.baseColor.y < 0.0f || m.baseColor.z < 0.0f)
            return fail(what + " has a non-finite or negative base colour");
        if (!nonNegative(m.emission))
            return fail(what + " has a non-finite or negative emission");
        if (!finite(m.metallic) || !finite(m.roughness))
            return fail(what + " has a non-finite metallic/roughness factor");
        if (m.baseColorTexture >= 0 && size_t(m.baseColorTexture) >= scene.textures.size())
            return fail(what + " uses texture " + std::to_string(m.baseColorTexture) + " of " +
                        std::to_string(scene.textures.size()));
    }
    for (size_t mi = 0; mi < scene.meshes.size(); ++mi) {
        const Mesh& m = scene.meshes[mi];
        std::string what = named("mesh", mi, m.name);
        const size_t nv = m.positions.size();
        if (m.material >= scene.materials.size())
            return fail(what + " uses material " + std::to_string(m.material) + " of " +
                        std::to_string(scene.materials.size()));
        if (m.indices.size() % 3 != 0)
            return fail(what + " has " + std::to_string(m.indices.size()) + " indices, not a multiple of 3");
        if (!m.normals.empty() && m.normals.size() != nv)
            return fail(what + " has " + std::to_string(m.normals.size()) + " normals for " + std::to_string(nv) +
                        " positions");
        if (!m.uvs.empty() && m.uvs.size() != nv)
            return fail(what + " has " + std::to_string(m.uvs.size()) + " uvs for " + std::to_string(nv) + " positions");
        for (size_t i = 0; i < m.indices.size(); ++i)
            if (m.indices[i] >= nv)
                return fail(what + " index " + std::to_string(i) + " = " + std::to_string(m.indices[i]) +
                            " is out of range (" + std::to_string(nv) + " vertices)");
        for (size_t v = 0; v < nv; ++v)
            if (!finite(m.positions[v]))
                return fail(what + " position " + std::to_string(v) + " is not finite");
        for (size_t v = 0; v < m.normals.size(); ++v)
            if (!finite(m.normals[v]) || glm::dot(m.normals[v], m.normals[v]) < 1e-12f)
                return fail(what + " normal " + std::to_string(v) + " is not finite or has zero length");
        for (size_t v = 0; v < m.uvs.size(); ++v)
            if (!std::isfinite(m.uvs[v].x) || !std::isfinite(m.uvs[v].y))
                return fail(what + " uv " + std::to_string(v) + " is not finite");
    }
    for (size_t ii = 0; ii < scene.instances.size(); ++ii) {
        const Instance& inst = scene.instances[ii];
        if (inst.mesh >= scene.meshes.size())
            return fail("instance " + std::to_string(ii) + " uses mesh " + std::to_string(inst.mesh) + " of " +
                        std::to_string(scene.meshes.size()));
        for (int c = 0; c < 4; ++c)
            if (!finite(inst.transform[c]))
                return fail("instance " + std::to_string(ii) + " has a non-finite transform");
        if (isSingularTransform(inst.transform))
            return fail("instance " + std::to_string(ii) +
                        " has a singular transform (a zero scale, or axes collapsed onto a plane or line): its "
                        "triangles have no area and no normal; remove the instance");
        const glm::vec3 t(inst.transform[3]);
        if (glm::any(glm::greaterThan(glm::abs(t), glm::vec3(kMaxCoordinate))))
            return fail("instance " + std::to_string(ii) + " is translated beyond " + std::to_string(kMaxCoordinate) +
                        " m from the origin (float positions there are too coarse to render)");
    }
    for (size_t li = 0; li < scene.lights.size(); ++li) {
        const Light& l = scene.lights[li];
        std::string what = named("light", li, l.name);
        if (uint32_t(l.type) > uint32_t(LightType::Spot))
            return fail(what + " has an unknown type " + std::to_string(uint32_t(l.type)));
        if (!finite(l.position))
            return fail(what + " has a non-finite position");
        if (l.type != LightType::Point &&
            (!finite(l.direction) || std::abs(glm::length(l.direction) - 1.0f) > 1e-3f))
            return fail(what + " direction is not a unit vector");
        if (!nonNegative(l.color))
            return fail(what + " has a non-finite or negative colour");
        if (!finite(l.intensity) || l.intensity < 0.0f)
            return fail(what + " intensity " + std::to_string(l.intensity) + " must be finite and >= 0");
        if (!finite(l.range) || l.range < 0.0f)
            return fail(what + " range " + std::to_string(l.range) + " must be finite and >= 0 (0 = infinite)");
        if (l.type == LightType::Spot &&
            !(l.innerConeAngle >= 0.0f && l.innerConeAngle <= l.outerConeAngle && l.outerConeAngle > 0.0f &&
              l.outerConeAngle <= 1.5707964f))
            return fail(what + " cone angles inner " + std::to_string(l.innerConeAngle) + ", outer " +
                        std::to_string(l.outerConeAngle) + " violate 0 <= inner <= outer <= pi/2, outer > 0");
    }
    if (scene.camera) {
        const Camera& c = *scene.camera;
        if (!finite(c.position) || !finite(c.forward) || !finite(c.up) || glm::length(c.forward) < 1e-6f)
            return fail("camera position/orientation is not finite or forward is zero");
        if (!(c.yfov > 0.0f && c.yfov < 3.14159f))
            return fail("camera yfov " + std::to_string(c.yfov) + " rad is outside (0, pi)");
        if (!(c.znear > 0.0f && std::isfinite(c.zfar) && c.zfar > c.znear))
            return fail("camera clip range znear " + std::to_string(c.znear) + ", zfar " + std::to_string(c.zfar) +
                        " needs 0 < znear < zfar < inf");
    }
    return {};
}

} // namespace vkgi
