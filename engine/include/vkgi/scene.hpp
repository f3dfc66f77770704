#pragma once
// The CPU scene: one representation shared by the GPU upload, every GI technique and the
// path-traced reference. glTF units and conventions: metres, +Y up, right-handed;
// lights in KHR_lights_punctual units (cd for point/spot, lux for directional);
// material emission in nits (cd/m^2), already multiplied by emissiveStrength.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "vkgi/camera.hpp"
#include "vkgi/result.hpp"

namespace vkgi {

struct Aabb {
    glm::vec3 min{1e30f};
    glm::vec3 max{-1e30f};
    bool valid() const { return min.x <= max.x && min.y <= max.y && min.z <= max.z; }
    void extend(const glm::vec3& p) {
        min = glm::min(min, p);
        max = glm::max(max, p);
    }
    glm::vec3 centre() const { return 0.5f * (min + max); }
    glm::vec3 extent() const { return max - min; }
    // Corner i takes max along x, y, z where bit 0, 1, 2 of i is set.
    std::array<glm::vec3, 8> corners() const {
        std::array<glm::vec3, 8> c;
        for (int i = 0; i < 8; ++i)
            c[i] = glm::vec3((i & 1) ? max.x : min.x, (i & 2) ? max.y : min.y, (i & 4) ? max.z : min.z);
        return c;
    }
    bool operator==(const Aabb&) const = default;
};

// An RGBA8 texture (sRGB-encoded when `srgb`), row 0 at the top as stored in the file.
struct Texture {
    std::string name;
    uint32_t width = 0;
    uint32_t height = 0;
    bool srgb = true;
    std::vector<uint8_t> rgba8; // width*height*4
};

struct Material {
    std::string name;
    glm::vec4 baseColor{1.0f};  // linear RGBA factor
    int baseColorTexture = -1;  // index into Scene::textures, -1 = none
    float metallic = 0.0f;
    float roughness = 1.0f;
    glm::vec3 emission{0.0f};   // nits (emissiveFactor * emissiveStrength)
    bool doubleSided = false;
};

// Indexed triangle mesh in object space. normals/uvs are empty or match positions.
struct Mesh {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<glm::vec2> uvs;
    std::vector<uint32_t> indices; // 3 per triangle
    uint32_t material = 0;         // index into Scene::materials
    uint32_t triangleCount() const { return uint32_t(indices.size() / 3); }
};

// A placed mesh. The glTF node hierarchy is flattened into world transforms at load.
struct Instance {
    uint32_t mesh = 0;
    glm::mat4 transform{1.0f}; // object -> world
    bool dynamic = false;      // moves at run time (re-voxelized every frame)
};

enum class LightType : uint32_t { Directional = 0, Point = 1, Spot = 2 }; // = GI_LIGHT_* in lights.h

struct Light {
    std::string name;
    LightType type = LightType::Point;
    glm::vec3 position{0.0f};
    glm::vec3 direction{0.0f, -1.0f, 0.0f}; // unit; the way the light shines (spot/directional)
    glm::vec3 color{1.0f};                  // linear RGB
    float intensity = 1.0f;                 // cd (point/spot) or lux (directional)
    float range = 0.0f;                     // metres, 0 = infinite
    float innerConeAngle = 0.0f;            // radians (spot)
    float outerConeAngle = 0.7853982f;      // radians (spot)
    bool dynamic = false;
};

struct Scene {
    std::string name;
    std::vector<Mesh> meshes;
    std::vector<Material> materials;
    std::vector<Texture> textures;
    std::vector<Instance> instances;
    std::vector<Light> lights;
    std::optional<Camera> camera; // from the file or the built-in scene; else framingCamera()

    // World-space bounds of all instances (invalid Aabb when the scene has no geometry).
    Aabb bounds() const;
    uint64_t triangleCount() const;
    bool hasEmission() const;
    // The scene camera, or a default: inside an interior (interiorCamera), else framing the bounds.
    Camera cameraOrDefault() const;
};

// For a scene whose surfaces enclose the centre of its bounds (nearly every ray from there that
// is not aimed at the sky meets the front side of a wall): a camera inside, towards one end of the longest horizontal axis and
// looking along it. Nothing for open scenes and closed objects. Costs rays x triangles on the CPU.
std::optional<Camera> interiorCamera(const Scene& scene);

// Largest |translation| of an instance, in metres: beyond it float positions are coarser than
// a millimetre and squared distances approach float overflow in the techniques.
inline constexpr float kMaxCoordinate = 1e9f;
// An instance transform whose |det| is below this fraction of the product of its axis lengths
// collapses space onto a plane, line or point (e.g. a zero scale on one axis).
inline constexpr float kSingularTransformRatio = 1e-6f;
bool isSingularTransform(const glm::mat4& transform);

// Checks the invariants every consumer relies on: indices and material/mesh/texture indices in
// range, attribute arrays sized to match, finite positions/normals/transforms, instance
// transforms that are neither singular nor translated beyond kMaxCoordinate, non-zero normals,
// finite non-negative colours/emission/intensities, sane spot cones (0 <= inner <= outer <= pi/2)
// and a usable camera. The error names the scene and the offending object.
Result<void> validateScene(const Scene& scene);

} // namespace vkgi
