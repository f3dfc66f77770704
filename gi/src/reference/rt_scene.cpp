#include "reference/rt_scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <glm/gtc/matrix_inverse.hpp>

#include "reference/sampling.hpp"

namespace vkgi::gi::ref {

namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool finite(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r]))
                return false;
    return true;
}

float srgbToLinear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

std::string quoted(const std::string& name, size_t index) {
    return name.empty() ? "#" + std::to_string(index) : "'" + name + "'";
}

// Float epsilon (2^-23): the spacing of floats in [1, 2).
constexpr double kFloatEps = 1.0 / 8388608.0;

// How far along the unit normal n a ray origin must sit from the exact point pd of a triangle
// with largest edge component `extent` so that (a) rounding the origin to float cannot move it
// back through the plane (half an ulp per axis, projected on n: 2 ulp taken) and (b) Embree's
// float plane test of a ray leaving the surface cannot place the origin on the wrong side: it
// evaluates n . (v0 - origin), whose rounding error is a few eps of the vertex-origin distance
// (<= the triangle's extent plus the move itself; 8 eps taken).
double spawnDistance(const glm::dvec3& pd, const glm::vec3& n, float extent) {
    const glm::dvec3 an = glm::abs(glm::dvec3(n));
    const double rounding = 2.0 * kFloatEps * glm::dot(an, glm::abs(pd));
    const double planeTest = 8.0 * kFloatEps * double(extent);
    return std::max(rounding + planeTest, 1e-30);
}

// pd moved by `move` along n and rounded to float away from the surface (each component rounded
// towards the side n points to, so rounding only adds to the move).
glm::vec3 spawnPoint(const glm::dvec3& pd, const glm::vec3& n, double move) {
    const glm::dvec3 q = pd + move * glm::dvec3(n);
    glm::vec3 out;
    for (int c = 0; c < 3; ++c) {
        float f = float(q[c]);
        if (n[c] > 0.0f && double(f) < q[c])
            f = std::nextafter(f, std::numeric_limits<float>::infinity());
        else if (n[c] < 0.0f && double(f) > q[c])
            f = std::nextafter(f, -std::numeric_limits<float>::infinity());
        out[c] = f;
    }
    return out;
}

void embreeErrorCallback(void* user, RTCError, const char* message) {
    auto* out = static_cast<std::string*>(user);
    if (out->empty() && message)
        *out = message;
}

} // namespace

glm::vec3 RtTexture::bilinear(glm::vec2 uv) const {
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y))
        uv = glm::vec2(0.0f);
    uv -= glm::floor(uv); // repeat; also keeps huge coordinates from overflowing the int casts
    float x = uv.x * float(width) - 0.5f, y = uv.y * float(height) - 0.5f;
    float fx0 = std::floor(x), fy0 = std::floor(y);
    float fx = x - fx0, fy = y - fy0;
    auto wrap = [](int i, uint32_t n) { return uint32_t(((i % int(n)) + int(n)) % int(n)); };
    uint32_t x0 = wrap(int(fx0), width), x1 = wrap(int(fx0) + 1, width);
    uint32_t y0 = wrap(int(fy0), height), y1 = wrap(int(fy0) + 1, height);
    auto t = [&](uint32_t xi, uint32_t yi) { return texels[size_t(yi) * width + xi]; };
    return (1.0f - fy) * ((1.0f - fx) * t(x0, y0) + fx * t(x1, y0)) + fy * ((1.0f - fx) * t(x0, y1) + fx * t(x1, y1));
}

RtScene::~RtScene() {
    if (m_scene)
        rtcReleaseScene(m_scene);
    if (m_device)
        rtcReleaseDevice(m_device);
}

Result<std::unique_ptr<RtScene>> RtScene::build(const Scene& scene) {
    const std::string sceneName = "scene '" + scene.name + "'";
    std::unique_ptr<RtScene> rt(new RtScene());
    if (auto ok = rt->addMaterials(scene, sceneName); !ok)
        return ok.error();
    if (auto ok = rt->addTextures(scene, sceneName); !ok)
        return ok.error();
    if (auto ok = rt->addInstances(scene, sceneName); !ok)
        return ok.error();
    if (rt->m_geoms.empty())
        return makeError(sceneName + ": no geometry to trace (no instance with triangles)");
    rt->buildLightTable();
    if (auto ok = rt->buildBvh(sceneName); !ok)
        return ok.error();
    return rt;
}

Result<void> RtScene::addMaterials(const Scene& scene, const std::string& sceneName) {
    for (size_t i = 0; i < scene.materials.size(); ++i) {
        const Material& m = scene.materials[i];
        if (!finite(glm::vec3(m.baseColor)) || !finite(m.emission))
            return makeError(sceneName + ": material " + quoted(m.name, i) + " has a non-finite colour or emission");
        if (glm::any(glm::lessThan(m.emission, glm::vec3(0.0f))))
            return makeError(sceneName + ": material " + quoted(m.name, i) + " has negative emission");
        if (m.baseColorTexture >= int(scene.textures.size()))
            return makeError(sceneName + ": material " + quoted(m.name, i) + " references a missing texture");
        RtMaterial rm;
        rm.albedo = glm::clamp(glm::vec3(m.baseColor), 0.0f, 1.0f);
        rm.texture = m.baseColorTexture;
        rm.emission = m.emission;
        rm.doubleSided = m.doubleSided;
        m_materials.push_back(rm);
    }
    return {};
}

Result<void> RtScene::addTextures(const Scene& scene, const std::string& sceneName) {
    float srgbLut[256], linearLut[256];
    for (int i = 0; i < 256; ++i) {
        srgbLut[i] = srgbToLinear(float(i) / 255.0f);
        linearLut[i] = float(i) / 255.0f;
    }
    for (size_t i = 0; i < scene.textures.size(); ++i) {
        const Texture& t = scene.textures[i];
        if (t.width == 0 || t.height == 0 || t.rgba8.size() != size_t(t.width) * t.height * 4)
            return makeError(sceneName + ": texture " + quoted(t.name, i) + " has inconsistent size and data");
        RtTexture texture;
        texture.width = t.width;
        texture.height = t.height;
        texture.texels.resize(size_t(t.width) * t.height);
        const float* lut = t.srgb ? srgbLut : linearLut;
        for (size_t p = 0; p < texture.texels.size(); ++p)
            texture.texels[p] = {lut[t.rgba8[4 * p]], lut[t.rgba8[4 * p + 1]], lut[t.rgba8[4 * p + 2]]};
        m_textures.push_back(std::move(texture));
    }
    return {};
}

// World-space copies of every instance with triangles.
Result<void> RtScene::addInstances(const Scene& scene, const std::string& sceneName) {
    for (size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& inst = scene.instances[i];
        const std::string what = sceneName + ": instance #" + std::to_string(i);
        if (inst.mesh >= scene.meshes.size())
            return makeError(what + " references missing mesh " + std::to_string(inst.mesh));
        const Mesh& mesh = scene.meshes[inst.mesh];
        const std::string meshWhat = sceneName + ": mesh " + quoted(mesh.name, inst.mesh);
        if (mesh.triangleCount() == 0)
            continue;
        if (!finite(inst.transform))
            return makeError(what + " has a non-finite transform");
        if (mesh.indices.size() % 3 != 0)
            return makeError(meshWhat + " index count is not a multiple of 3");
        if (mesh.material >= scene.materials.size())
            return makeError(meshWhat + " references missing material " + std::to_string(mesh.material));
        if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
            return makeError(meshWhat + " has a normal count different from its position count");
        if (!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size())
            return makeError(meshWhat + " has a uv count different from its position count");
        for (uint32_t idx : mesh.indices)
            if (idx >= mesh.positions.size())
                return makeError(meshWhat + " has an index out of range");

        RtGeometry g;
        g.material = mesh.material;
        g.indices = mesh.indices;
        g.uvs = mesh.uvs;
        g.mirrored = glm::determinant(glm::mat3(inst.transform)) < 0.0f;
        g.positions.reserve(mesh.positions.size());
        for (const glm::vec3& p : mesh.positions) {
            glm::vec3 w = glm::vec3(inst.transform * glm::vec4(p, 1.0f));
            if (!finite(w))
                return makeError(meshWhat + " has a non-finite vertex position");
            g.positions.push_back(w);
        }
        if (!mesh.normals.empty()) {
            glm::mat3 nm = glm::inverseTranspose(glm::mat3(inst.transform));
            g.normals.reserve(mesh.normals.size());
            for (const glm::vec3& n : mesh.normals)
                g.normals.push_back(nm * n); // bad ones fall back to the geometric normal per hit
        }
        m_geoms.push_back(std::move(g));
    }
    return {};
}

void RtScene::buildLightTable() {
    // Emissive triangles, chosen by power: area x luminance x sides that emit.
    double total = 0.0;
    std::vector<float> geomLum(m_geoms.size(), 0.0f);
    for (size_t gi = 0; gi < m_geoms.size(); ++gi) {
        const RtGeometry& g = m_geoms[gi];
        const RtMaterial& m = m_materials[g.material];
        float lum = luminance(m.emission) * (m.doubleSided ? 2.0f : 1.0f);
        if (!(lum > 0.0f))
            continue;
        geomLum[gi] = lum;
        for (uint32_t t = 0; t < g.indices.size() / 3; ++t) {
            glm::vec3 p0 = g.positions[g.indices[3 * t]], p1 = g.positions[g.indices[3 * t + 1]],
                      p2 = g.positions[g.indices[3 * t + 2]];
            double area = 0.5 * double(glm::length(glm::cross(p1 - p0, p2 - p0)));
            if (!(area > 0.0))
                continue;
            total += area * double(lum);
            m_lightTris.push_back({uint32_t(gi), t});
            m_lightCdf.push_back(total);
        }
    }
    if (total > 0.0) {
        for (double& c : m_lightCdf)
            c /= total;
        m_lightCdf.back() = 1.0;
        for (size_t gi = 0; gi < m_geoms.size(); ++gi)
            m_geoms[gi].lightPdfPerArea = float(double(geomLum[gi]) / total);
    }
}

Result<void> RtScene::buildBvh(const std::string& sceneName) {
    std::string embreeError;
    m_device = rtcNewDevice(nullptr);
    if (!m_device)
        return makeError(sceneName + ": Embree device creation failed (error " +
                         std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    rtcSetDeviceErrorFunction(m_device, embreeErrorCallback, &embreeError);
    m_scene = rtcNewScene(m_device);
    // Robust mode: watertight traversal, so closed boxes (furnace) cannot leak at edges.
    rtcSetSceneFlags(m_scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(m_scene, RTC_BUILD_QUALITY_HIGH);
    for (size_t gi = 0; gi < m_geoms.size(); ++gi) {
        const RtGeometry& g = m_geoms[gi];
        RTCGeometry geom = rtcNewGeometry(m_device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), g.positions.size()));
        auto* ib = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                  3 * sizeof(uint32_t), g.indices.size() / 3));
        if (!vb || !ib) {
            rtcReleaseGeometry(geom);
            return makeError(sceneName + ": Embree buffer allocation failed: " + embreeError);
        }
        for (size_t v = 0; v < g.positions.size(); ++v)
            for (int c = 0; c < 3; ++c)
                vb[3 * v + c] = g.positions[v][c];
        std::copy(g.indices.begin(), g.indices.end(), ib);
        rtcCommitGeometry(geom);
        rtcAttachGeometryByID(m_scene, geom, unsigned(gi));
        rtcReleaseGeometry(geom);
    }
    rtcCommitScene(m_scene);
    if (rtcGetDeviceError(m_device) != RTC_ERROR_NONE || !embreeError.empty())
        return makeError(sceneName + ": Embree BVH build failed: " + embreeError);
    rtcSetDeviceErrorFunction(m_device, nullptr, nullptr); // embreeError goes out of scope
    return {};
}

SurfaceHit RtScene::surface(uint32_t geomId, uint32_t primId, float u, float v) const {
    const RtGeometry& g = m_geoms[geomId];
    const RtMaterial& m = m_materials[g.material];
    const uint32_t i0 = g.indices[3 * primId], i1 = g.indices[3 * primId + 1], i2 = g.indices[3 * primId + 2];
    const float w = 1.0f - u - v;
    SurfaceHit h;
    const glm::vec3 p0 = g.positions[i0], p1 = g.positions[i1], p2 = g.positions[i2];
    // In double the interpolated point lies on the triangle's plane to ~1e-16 relative; only its
    // rounding to float (half an ulp per axis) takes it off the plane.
    const double du = u, dv = v, dw = 1.0 - du - dv;
    const glm::dvec3 pd = dw * glm::dvec3(p0) + du * glm::dvec3(p1) + dv * glm::dvec3(p2);
    h.position = glm::vec3(pd);
    glm::vec3 n = glm::cross(p1 - p0, p2 - p0);
    float len = glm::length(n);
    h.ng = len > 0.0f && std::isfinite(len) ? n / len : glm::vec3(0.0f, 1.0f, 0.0f);
    if (g.mirrored)
        h.ng = -h.ng;
    const float extent = std::max({maxComponent(glm::abs(p1 - p0)), maxComponent(glm::abs(p2 - p0)),
                                   maxComponent(glm::abs(p2 - p1))});
    const double move = spawnDistance(pd, h.ng, extent);
    h.spawnAbove = spawnPoint(pd, h.ng, move);
    h.spawnBelow = spawnPoint(pd, -h.ng, move);
    h.ns = h.ng;
    if (!g.normals.empty()) {
        glm::vec3 s = w * g.normals[i0] + u * g.normals[i1] + v * g.normals[i2];
        float sl = glm::length(s);
        if (sl > 1e-12f && std::isfinite(sl))
            h.ns = s / sl;
    }
    h.albedo = m.albedo;
    if (m.texture >= 0 && !g.uvs.empty()) {
        glm::vec2 uv = w * g.uvs[i0] + u * g.uvs[i1] + v * g.uvs[i2];
        h.albedo *= glm::clamp(m_textures[size_t(m.texture)].bilinear(uv), 0.0f, 1.0f);
    }
    h.emission = m.emission;
    h.doubleSided = m.doubleSided;
    h.lightPdfPerArea = g.lightPdfPerArea;
    return h;
}

LightSample RtScene::sampleAreaLight(float uPick, float u1, float u2) const {
    size_t i = size_t(std::lower_bound(m_lightCdf.begin(), m_lightCdf.end(), double(uPick)) - m_lightCdf.begin());
    i = std::min(i, m_lightCdf.size() - 1);
    const glm::uvec2 tri = m_lightTris[i];
    glm::vec2 b = sampleTriangle(u1, u2);
    SurfaceHit h = surface(tri.x, tri.y, b.x, b.y);
    return {h.position, h.ng, h.emission, h.doubleSided, h.lightPdfPerArea};
}

} // namespace vkgi::gi::ref
