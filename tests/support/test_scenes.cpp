#include "support/test_scenes.hpp"

namespace vkgi::test {

Scene plane(float albedo, float halfSize) {
    Scene s;
    s.name = "plane";
    Mesh m;
    const float h = halfSize;
    m.positions = {{-h, 0, -h}, {h, 0, -h}, {h, 0, h}, {-h, 0, h}};
    m.normals.assign(4, glm::vec3(0, 1, 0));
    m.indices = {0, 2, 1, 0, 3, 2};
    s.meshes.push_back(m);
    Material mat;
    mat.baseColor = glm::vec4(glm::vec3(albedo), 1.0f);
    s.materials.push_back(mat);
    s.instances.push_back({});
    return s;
}

Scene planeScene(float albedo, const Light& light) {
    Scene s = plane(albedo, 10.0f);
    s.lights.push_back(light);
    Camera c;
    c.position = {0.0f, 3.0f, 0.0f};
    c.forward = {0.0f, -1.0f, 0.0f};
    c.up = {0.0f, 0.0f, -1.0f};
    c.yfov = 1.0471976f; // 60 degrees
    c.znear = 0.01f;
    c.zfar = 10.0f;
    s.camera = c;
    return s;
}

} // namespace vkgi::test
