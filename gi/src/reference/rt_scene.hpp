#pragma once
// The reference tracer's view of a Scene: world-space triangles in an Embree BVH, per-hit
// material and normal lookup, and the emissive-triangle distribution for light sampling.
#include <cstdint>
#include <memory>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/glm.hpp>

#include "vkgi/result.hpp"
#include "vkgi/scene.hpp"

namespace vkgi::gi::ref {

struct RtMaterial {
    glm::vec3 albedo{1.0f}; // baseColor factor, clamped to [0,1]
    int texture = -1;       // index into RtScene::m_textures
    glm::vec3 emission{0.0f};
    bool doubleSided = false;
};

// A texture decoded once to linear float RGB (sRGB curve removed when the source is sRGB).
struct RtTexture {
    uint32_t width = 0, height = 0;
    std::vector<glm::vec3> texels;
    glm::vec3 bilinear(glm::vec2 uv) const; // repeat wrap, texel centres at (i + 0.5) / size
};

// One flattened instance: world-space vertex data and a material.
struct RtGeometry {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals; // empty or one per position, world space, unnormalised
    std::vector<glm::vec2> uvs;     // empty or one per position
    std::vector<uint32_t> indices;
    uint32_t material = 0;
    bool mirrored = false;       // transform has negative determinant: front face is clockwise
    float lightPdfPerArea = 0.0f; // pdf (per m^2) of choosing a point of this geometry by NEE
};

// Everything the integrator needs at a hit point.
struct SurfaceHit {
    glm::vec3 position;
    glm::vec3 ng;        // unit geometric normal of the front face
    glm::vec3 ns;        // unit shading normal (= ng when the mesh has none or it is degenerate)
    glm::vec3 albedo;    // in [0,1]
    glm::vec3 emission;  // nits
    bool doubleSided;
    float lightPdfPerArea;
    // Where rays leaving this hit start: the hit moved off the surface along ng (the front
    // face; spawnBelow on the back) by a bound on the float error of the stored position and of
    // Embree's plane test, rounded to float so that rounding cannot undo the move. The bound
    // scales with the position's own coordinates along ng and with the triangle's size, not
    // with the largest coordinate: a larger move starts rays behind the adjacent face of an
    // acute concave edge (vkgi/reference.hpp).
    glm::vec3 spawnAbove;
    glm::vec3 spawnBelow;
};

struct LightSample {
    glm::vec3 position;
    glm::vec3 ng;       // unit front normal of the emitter at the point
    glm::vec3 emission;
    bool doubleSided;
    float pdfArea;      // per m^2, including the choice of the triangle
};

class RtScene {
public:
    static Result<std::unique_ptr<RtScene>> build(const Scene& scene);
    ~RtScene();
    RtScene(const RtScene&) = delete;
    RtScene& operator=(const RtScene&) = delete;

    RTCScene embree() const { return m_scene; }
    SurfaceHit surface(uint32_t geomId, uint32_t primId, float u, float v) const;
    bool hasAreaLights() const { return !m_lightCdf.empty(); }
    // Picks an emissive triangle by power and a uniform point on it.
    LightSample sampleAreaLight(float uPick, float u1, float u2) const;

private:
    RtScene() = default;
    // The steps of build(); `sceneName` names the scene in errors.
    Result<void> addMaterials(const Scene& scene, const std::string& sceneName);
    Result<void> addTextures(const Scene& scene, const std::string& sceneName);
    Result<void> addInstances(const Scene& scene, const std::string& sceneName);
    void buildLightTable();
    Result<void> buildBvh(const std::string& sceneName);
    RTCDevice m_device = nullptr;
    RTCScene m_scene = nullptr;
    std::vector<RtGeometry> m_geoms;
    std::vector<RtMaterial> m_materials;
    std::vector<RtTexture> m_textures;
    // Emissive triangles: (geometry, primitive) and the running sum of their power.
    std::vector<glm::uvec2> m_lightTris;
    std::vector<double> m_lightCdf;
};

} // namespace vkgi::gi::ref
