#include "mesh_builder.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

namespace vkgi {

namespace {

glm::vec3 newellNormal(std::span<const glm::vec3> pts) {
    glm::vec3 n(0.0f);
    for (size_t i = 0; i < pts.size(); ++i) {
        const glm::vec3& a = pts[i];
        const glm::vec3& b = pts[(i + 1) % pts.size()];
        n.x += (a.y - b.y) * (a.z + b.z);
        n.y += (a.z - b.z) * (a.x + b.x);
        n.z += (a.x - b.x) * (a.y + b.y);
    }
    float len = glm::length(n);
    return len > 0.0f ? n / len : glm::vec3(0.0f, 1.0f, 0.0f);
}

} // namespace

uint32_t MeshBuilder::addVertex(const glm::vec3& p, const glm::vec3& n) {
    m_mesh.positions.push_back(p);
    m_mesh.normals.push_back(n);
    return uint32_t(m_mesh.positions.size() - 1);
}

void MeshBuilder::addTriangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    std::array<glm::vec3, 3> pts{a, b, c};
    glm::vec3 n = newellNormal(pts);
    for (const glm::vec3& p : pts)
        m_mesh.indices.push_back(addVertex(p, n));
}

void MeshBuilder::addQuad(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d) {
    addGridQuad(a, b, c, d, 1);
}

void MeshBuilder::addGridQuad(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d, uint32_t n) {
    n = std::max(n, 1u);
    std::array<glm::vec3, 4> corners{a, b, c, d};
    glm::vec3 normal = newellNormal(corners);
    uint32_t base = vertexCount();
    for (uint32_t j = 0; j <= n; ++j) {
        float v = float(j) / float(n);
        for (uint32_t i = 0; i <= n; ++i) {
            float u = float(i) / float(n);
            glm::vec3 p = (1 - u) * (1 - v) * a + u * (1 - v) * b + u * v * c + (1 - u) * v * d;
            addVertex(p, normal);
        }
    }
    auto at = [&](uint32_t i, uint32_t j) { return base + j * (n + 1) + i; };
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            uint32_t q[4] = {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
            m_mesh.indices.insert(m_mesh.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
        }
}

void MeshBuilder::addConvexPolygon(std::span<const glm::vec3> points) {
    if (points.size() < 3)
        return;
    glm::vec3 normal = newellNormal(points);
    uint32_t base = vertexCount();
    for (const glm::vec3& p : points)
        addVertex(p, normal);
    for (uint32_t i = 1; i + 1 < points.size(); ++i)
        m_mesh.indices.insert(m_mesh.indices.end(), {base, base + i, base + i + 1});
}

void MeshBuilder::addParallelepiped(const glm::vec3& o, const glm::vec3& ex, const glm::vec3& ey, const glm::vec3& ez,
                                    Facing facing, uint32_t n) {
    std::array<glm::vec3, 8> c;
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i)
                c[size_t(i + 2 * j + 4 * k)] = o + float(i) * ex + float(j) * ey + float(k) * ez;
    addHexahedron(c, facing, n);
}

void MeshBuilder::addHexahedron(const std::array<glm::vec3, 8>& corners, Facing facing, uint32_t n) {
    auto c = [&](int i, int j, int k) { return corners[size_t(i + 2 * j + 4 * k)]; };
    // Outward and counter-clockwise for a right-handed corner layout; flipped otherwise.
    const std::array<std::array<int, 3>, 4> faces[6] = {
        {{{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}}, // i = 0
        {{{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}}, // i = 1
        {{{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}}, // j = 0
        {{{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}}}, // j = 1
        {{{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}}, // k = 0
        {{{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}}, // k = 1
    };
    glm::vec3 ex = c(1, 0, 0) - c(0, 0, 0), ey = c(0, 1, 0) - c(0, 0, 0), ez = c(0, 0, 1) - c(0, 0, 0);
    bool rightHanded = glm::dot(glm::cross(ex, ey), ez) > 0.0f;
    bool flip = rightHanded == (facing == Facing::Inward);
    for (const auto& f : faces) {
        glm::vec3 p[4];
        for (int v = 0; v < 4; ++v)
            p[v] = c(f[size_t(v)][0], f[size_t(v)][1], f[size_t(v)][2]);
        if (flip)
            addGridQuad(p[0], p[3], p[2], p[1], n);
        else
            addGridQuad(p[0], p[1], p[2], p[3], n);
    }
}

void MeshBuilder::addBox(const glm::vec3& min, const glm::vec3& max, Facing facing, uint32_t n) {
    glm::vec3 e = max - min;
    addParallelepiped(min, {e.x, 0, 0}, {0, e.y, 0}, {0, 0, e.z}, facing, n);
}

void MeshBuilder::addPrism(std::span<const glm::vec2> fp, float y0, float y1, bool top, bool bottom) {
    if (fp.size() < 3)
        return;
    // Order the footprint so that the top polygon, seen from +y, is counter-clockwise.
    std::vector<glm::vec2> pts(fp.begin(), fp.end());
    float twiceArea = 0.0f; // x-z shoelace; negative means counter-clockwise seen from +y
    for (size_t i = 0; i < pts.size(); ++i) {
        const glm::vec2& a = pts[i];
        const glm::vec2& b = pts[(i + 1) % pts.size()];
        twiceArea += a.x * b.y - b.x * a.y;
    }
    if (twiceArea > 0.0f)
        std::reverse(pts.begin(), pts.end());
    std::vector<glm::vec3> ring;
    for (size_t i = 0; i < pts.size(); ++i) {
        const glm::vec2& a = pts[i];
        const glm::vec2& b = pts[(i + 1) % pts.size()];
        addQuad({a.x, y0, a.y}, {b.x, y0, b.y}, {b.x, y1, b.y}, {a.x, y1, a.y});
    }
    if (top) {
        for (const glm::vec2& p : pts)
            ring.emplace_back(p.x, y1, p.y);
        addConvexPolygon(ring);
    }
    if (bottom) {
        ring.clear();
        for (auto it = pts.rbegin(); it != pts.rend(); ++it)
            ring.emplace_back(it->x, y0, it->y);
        addConvexPolygon(ring);
    }
}

void MeshBuilder::addCylinder(const glm::vec3& base, float radius, float height, uint32_t sides, bool caps) {
    sides = std::max(sides, 3u);
    std::vector<glm::vec2> fp;
    for (uint32_t i = 0; i < sides; ++i) {
        float a = 2.0f * 3.14159265f * float(i) / float(sides);
        fp.emplace_back(base.x + radius * std::cos(a), base.z + radius * std::sin(a));
    }
    addPrism(fp, base.y, base.y + height, caps, caps);
}

void MeshBuilder::addLathe(const glm::vec3& base, std::span<const glm::vec2> profile, uint32_t segments) {
    segments = std::max(segments, 3u);
    const size_t n = profile.size();
    if (n < 2)
        return;
    // Outward normal of profile segment k in the (radius, height) plane: (dy, -dr) normalised.
    auto segmentNormal = [&](size_t k) {
        glm::vec2 d = profile[k + 1] - profile[k];
        glm::vec2 nrm(d.y, -d.x);
        float len = glm::length(nrm);
        return len > 0.0f ? nrm / len : glm::vec2(1.0f, 0.0f);
    };
    const float cosCorner = 0.5f; // a turn of more than 60 degrees keeps the segments' own normals
    for (size_t k = 0; k + 1 < n; ++k) {
        glm::vec2 nk = segmentNormal(k);
        glm::vec2 n0 = nk, n1 = nk; // normals at the segment's bottom and top
        if (k > 0 && glm::dot(segmentNormal(k - 1), nk) > cosCorner)
            n0 = glm::normalize(segmentNormal(k - 1) + nk);
        if (k + 2 < n && glm::dot(segmentNormal(k + 1), nk) > cosCorner)
            n1 = glm::normalize(segmentNormal(k + 1) + nk);
        const glm::vec2 p0 = profile[k], p1 = profile[k + 1];
        for (uint32_t i = 0; i < segments; ++i) {
            float a0 = 2.0f * 3.14159265f * float(i) / float(segments);
            float a1 = 2.0f * 3.14159265f * float(i + 1) / float(segments);
            glm::vec3 d0(std::cos(a0), 0.0f, -std::sin(a0)), d1(std::cos(a1), 0.0f, -std::sin(a1));
            auto pos = [&](const glm::vec2& p, const glm::vec3& d) { return base + d * p.x + glm::vec3(0, p.y, 0); };
            auto nrm = [&](const glm::vec2& q, const glm::vec3& d) { return glm::normalize(d * q.x + glm::vec3(0, q.y, 0)); };
            // Counter-clockwise seen from outside: bottom a0, bottom a1, top a1, top a0.
            uint32_t v00 = addVertex(pos(p0, d0), nrm(n0, d0)), v01 = addVertex(pos(p0, d1), nrm(n0, d1));
            uint32_t v11 = addVertex(pos(p1, d1), nrm(n1, d1)), v10 = addVertex(pos(p1, d0), nrm(n1, d0));
            if (p0.x > 0.0f)
                m_mesh.indices.insert(m_mesh.indices.end(), {v00, v01, v11});
            if (p1.x > 0.0f)
                m_mesh.indices.insert(m_mesh.indices.end(), {v00, v11, v10});
        }
    }
}

void MeshBuilder::translate(const glm::vec3& offset) {
    for (glm::vec3& p : m_mesh.positions)
        p += offset;
}

Aabb MeshBuilder::bounds() const {
    Aabb b;
    for (const glm::vec3& p : m_mesh.positions)
        b.extend(p);
    return b;
}

void MeshBuilder::addIcosphere(const glm::vec3& centre, uint32_t subdivisions,
                               const std::function<float(const glm::vec3&)>& radiusOf, Facing facing) {
    const float t = (1.0f + std::sqrt(5.0f)) * 0.5f;
    std::vector<glm::vec3> dirs = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                   {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (glm::vec3& d : dirs)
        d = glm::normalize(d);
    std::vector<std::array<uint32_t, 3>> tris = {
        {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (auto& f : tris) // make every base face outward whatever the table's convention
        if (glm::dot(glm::cross(dirs[f[1]] - dirs[f[0]], dirs[f[2]] - dirs[f[0]]), dirs[f[0]]) < 0.0f)
            std::swap(f[1], f[2]);
    for (uint32_t s = 0; s < subdivisions; ++s) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoints;
        auto mid = [&](uint32_t a, uint32_t b) {
            auto key = std::minmax(a, b);
            auto it = midpoints.find(key);
            if (it != midpoints.end())
                return it->second;
            dirs.push_back(glm::normalize(dirs[a] + dirs[b]));
            uint32_t idx = uint32_t(dirs.size() - 1);
            midpoints.emplace(key, idx);
            return idx;
        };
        std::vector<std::array<uint32_t, 3>> next;
        next.reserve(tris.size() * 4);
        for (const auto& f : tris) {
            uint32_t ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
            next.push_back({f[0], ab, ca});
            next.push_back({f[1], bc, ab});
            next.push_back({f[2], ca, bc});
            next.push_back({ab, bc, ca});
        }
        tris = std::move(next);
    }
    uint32_t base = vertexCount();
    for (const glm::vec3& d : dirs)
        addVertex(centre + d * radiusOf(d), glm::vec3(0.0f));
    size_t firstIndex = m_mesh.indices.size();
    for (const auto& f : tris) {
        if (facing == Facing::Inward)
            m_mesh.indices.insert(m_mesh.indices.end(), {base + f[0], base + f[2], base + f[1]});
        else
            m_mesh.indices.insert(m_mesh.indices.end(), {base + f[0], base + f[1], base + f[2]});
    }
    // Smooth normals over just this sphere's vertices (they are referenced by nothing else).
    for (size_t i = firstIndex; i + 2 < m_mesh.indices.size(); i += 3) {
        uint32_t a = m_mesh.indices[i], b = m_mesh.indices[i + 1], c = m_mesh.indices[i + 2];
        glm::vec3 n = glm::cross(m_mesh.positions[b] - m_mesh.positions[a], m_mesh.positions[c] - m_mesh.positions[a]);
        m_mesh.normals[a] += n;
        m_mesh.normals[b] += n;
        m_mesh.normals[c] += n;
    }
    for (uint32_t v = base; v < vertexCount(); ++v)
        m_mesh.normals[v] = glm::normalize(m_mesh.normals[v]);
}

Mesh MeshBuilder::take(std::string name, uint32_t material) {
    Mesh m = std::move(m_mesh);
    m.name = std::move(name);
    m.material = material;
    m_mesh = Mesh{};
    return m;
}

uint32_t addMaterial(Scene& scene, std::string name, const glm::vec3& albedo, const glm::vec3& emission, bool doubleSided) {
    Material m;
    m.name = std::move(name);
    m.baseColor = glm::vec4(albedo, 1.0f);
    m.emission = emission;
    m.doubleSided = doubleSided;
    scene.materials.push_back(std::move(m));
    return uint32_t(scene.materials.size() - 1);
}

void addMeshInstance(Scene& scene, MeshBuilder& builder, std::string name, uint32_t material) {
    scene.meshes.push_back(builder.take(std::move(name), material));
    Instance inst;
    inst.mesh = uint32_t(scene.meshes.size() - 1);
    scene.instances.push_back(inst);
}

void computeSmoothNormals(Mesh& mesh) {
    mesh.normals.assign(mesh.positions.size(), glm::vec3(0.0f));
    for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
        uint32_t a = mesh.indices[i], b = mesh.indices[i + 1], c = mesh.indices[i + 2];
        if (a >= mesh.positions.size() || b >= mesh.positions.size() || c >= mesh.positions.size())
            continue;
        glm::vec3 n = glm::cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
        if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z))
            continue;
        mesh.normals[a] += n; // |n| = twice the area: area weighting for free
        mesh.normals[b] += n;
        mesh.normals[c] += n;
    }
    for (glm::vec3& n : mesh.normals) {
        float len = glm::length(n);
        n = len > 0.0f && std::isfinite(len) ? n / len : glm::vec3(0.0f);
    }
}

} // namespace vkgi
