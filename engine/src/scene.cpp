#include "engine/scene.hpp"

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
    return framingCamera(b.min, b.max);
}

} // namespace vkgi
