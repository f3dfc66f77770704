#pragma once
// The one set of geometry builders used by every built-in scene (private to the engine; the unit
// tests include it through engine/src). Convention for every builder: a face's front side is the
// side its normal points to, and its vertices are counter-clockwise seen from that side.
#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <string>

#include <glm/glm.hpp>

#include "vkgi/scene.hpp"

namespace vkgi {

enum class Facing { Outward, Inward };

class MeshBuilder {
public:
    // A triangle, flat-shaded, counter-clockwise seen from its front.
    void addTriangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c);
    // A quad a-b-c-d counter-clockwise seen from its front, split along a-c. Slightly non-planar
    // quads (the published Cornell walls are off by ~3 mm) keep one Newell normal for all 4 vertices.
    void addQuad(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d);
    // A quad subdivided into n x n cells (the same split everywhere so boxes stay watertight).
    void addGridQuad(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d, uint32_t n);
    // A convex polygon (fan-triangulated), counter-clockwise seen from its front.
    void addConvexPolygon(std::span<const glm::vec3> points);
    // A parallelepiped with corner `origin` and edge vectors ex, ey, ez: 6 faces, each split into
    // n x n cells, facing out of (or into) the solid. The edge vectors may be left-handed.
    void addParallelepiped(const glm::vec3& origin, const glm::vec3& ex, const glm::vec3& ey, const glm::vec3& ez,
                           Facing facing = Facing::Outward, uint32_t n = 1);
    // A hexahedron from 8 corners c[i + 2j + 4k] laid out like the parallelepiped's
    // origin + i ex + j ey + k ez (faces may be slightly non-planar, e.g. arch segments).
    void addHexahedron(const std::array<glm::vec3, 8>& c, Facing facing = Facing::Outward, uint32_t n = 1);
    // Axis-aligned box.
    void addBox(const glm::vec3& min, const glm::vec3& max, Facing facing = Facing::Outward, uint32_t n = 1);
    // A vertical prism over a convex footprint given in (x, z), from y0 to y1: the side faces and
    // the top (and the bottom if asked), all facing outward whatever the footprint's winding.
    void addPrism(std::span<const glm::vec2> footprintXZ, float y0, float y1, bool top = true, bool bottom = false);
    // A vertical n-sided cylinder (flat-shaded prism) of the given radius standing on `base`.
    void addCylinder(const glm::vec3& base, float radius, float height, uint32_t sides, bool caps = true);
    // A welded icosphere (closed: every edge shared by exactly two triangles) with smooth normals.
    // `radiusOf(unitDir)` sets the radius per direction, so a positive function displaces the
    // surface radially without self-intersection.
    void addIcosphere(const glm::vec3& centre, uint32_t subdivisions, const std::function<float(const glm::vec3&)>& radiusOf,
                      Facing facing = Facing::Outward);

    // A surface of revolution about the vertical axis through `base`: `profile` holds (radius,
    // height) points from bottom to top; `segments` around; smooth normals from the profile's
    // tangents (a corner of the profile, where the tangent turns by more than 60 degrees, gets
    // split normals). A radius of 0 at the ends closes the surface.
    void addLathe(const glm::vec3& base, std::span<const glm::vec2> profile, uint32_t segments);

    // Moves everything built so far.
    void translate(const glm::vec3& offset);
    Aabb bounds() const;
    uint32_t vertexCount() const { return uint32_t(m_mesh.positions.size()); }
    // Moves the geometry out as a mesh with the given name and material.
    Mesh take(std::string name, uint32_t material);

private:
    uint32_t addVertex(const glm::vec3& p, const glm::vec3& n);
    Mesh m_mesh;
};

// Adds a material and returns its index.
uint32_t addMaterial(Scene& scene, std::string name, const glm::vec3& albedo, const glm::vec3& emission = glm::vec3(0.0f),
                     bool doubleSided = false);
// Adds a mesh from a builder plus an identity-transform instance of it.
void addMeshInstance(Scene& scene, MeshBuilder& builder, std::string name, uint32_t material);
// Area-weighted smooth vertex normals from the triangles (zero-area triangles add nothing; a
// vertex only touched by degenerate triangles keeps a zero normal for the caller to repair).
void computeSmoothNormals(Mesh& mesh);

} // namespace vkgi
