#include "vkgi/gltf_loader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <map>
#include <set>
#include <unordered_map>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
// Debian ships tinygltf as a shared library (README.Debian): include the header only, never
// define TINYGLTF_IMPLEMENTATION here.
#include <tiny_gltf.h>

#include "mesh_builder.hpp"

namespace vkgi {

namespace {

constexpr float kPi = 3.14159265358979f;
// Extensions whose content the loader maps to the Scene.
const std::set<std::string> kSupportedExtensions = {"KHR_lights_punctual", "KHR_materials_emissive_strength"};
// Accessors larger than this are refused before any allocation (2^28 elements = GiBs of floats).
constexpr uint64_t kMaxAccessorCount = uint64_t(1) << 28;
// Node hierarchies deeper than this are treated as malformed (protects the recursion).
constexpr int kMaxNodeDepth = 256;
// A triangle whose |cross| is below this fraction of its longest edge squared is degenerate at
// float precision (its normal is noise).
constexpr float kDegenerateRelArea = 1e-7f;

// Makes tinygltf's multi-line messages fit on one line.
std::string oneLine(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' '))
        s.pop_back();
    std::string out;
    for (char c : s) {
        if (c == '\n')
            out += "; ";
        else if (c != '\r')
            out += c;
    }
    return out;
}

std::string formatNumber(double v) {
    char text[32];
    std::snprintf(text, sizeof(text), "%g", v);
    return text;
}

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Wraps tinygltf's decoder so that a bad image costs only its texture, not the whole file.
bool tolerantImageLoader(tinygltf::Image* image, const int index, std::string* err, std::string* warn, int w, int h,
                         const unsigned char* bytes, int size, void* user) {
    std::string localErr;
    if (tinygltf::LoadImageData(image, index, &localErr, warn, w, h, bytes, size, user))
        return true;
    if (warn)
        *warn += "image " + std::to_string(index) + " could not be decoded (" + oneLine(localErr) + ")\n";
    (void)err;
    image->image.clear();
    image->width = image->height = 0;
    return true;
}

// File access for tinygltf: every file it reads (the scene file, buffers, images) is looked up
// here, so URIs stay inside the scene's folder and no file over the size limit is read.
struct FileGuard {
    std::filesystem::path root; // the scene file's folder, canonical
    GltfLoadOptions options;
    std::vector<std::string> refusals; // one line per refused path
    std::set<std::string> refused;
};

bool insideFolder(const std::filesystem::path& p, const std::filesystem::path& root) {
    auto r = root.begin(), q = p.begin();
    for (; r != root.end(); ++r, ++q)
        if (q == p.end() || *q != *r)
            return false;
    return true;
}

// The canonical path of `path` when the guard lets it be read; empty (with a refusal noted) if not.
std::filesystem::path admit(FileGuard& g, const std::string& path) {
    std::error_code ec;
    std::filesystem::path resolved = std::filesystem::weakly_canonical(std::filesystem::path(path), ec);
    if (ec)
        return {};
    if (!g.options.allowOutsideFolder && !insideFolder(resolved, g.root)) {
        if (g.refused.insert(resolved.string()).second)
            g.refusals.push_back("'" + path + "' resolves outside the scene's folder " + g.root.string() +
                                 "; not read (allow it with allowOutsideFolder / --allow-outside-folder)");
        return {};
    }
    return resolved;
}

bool guardedFileExists(const std::string& path, void* user) {
    std::filesystem::path p = admit(*static_cast<FileGuard*>(user), path);
    std::error_code ec;
    return !p.empty() && std::filesystem::is_regular_file(p, ec);
}

std::string unexpandedPath(const std::string& path, void*) {
    return path; // no ~ or $VARIABLE expansion: a URI names a file, not a shell word
}

bool guardedReadWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    FileGuard& g = *static_cast<FileGuard*>(user);
    std::filesystem::path p = admit(g, path);
    if (p.empty()) {
        *err += "outside the scene's folder";
        return false;
    }
    std::error_code ec;
    const uintmax_t size = std::filesystem::file_size(p, ec);
    if (ec) {
        *err += "cannot read (" + ec.message() + ")";
        return false;
    }
    if (size > g.options.maxFileBytes) {
        *err += p.filename().string() + " is " + std::to_string(size) + " bytes, over the loader's limit of " +
                std::to_string(g.options.maxFileBytes) + " bytes (GltfLoadOptions::maxFileBytes)";
        return false;
    }
    std::ifstream in(p, std::ios::binary);
    out->resize(size_t(size));
    if (!in.read(reinterpret_cast<char*>(out->data()), std::streamsize(size))) {
        *err += "read failed";
        return false;
    }
    return true;
}

bool refuseWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    *err += "the loader writes no files";
    return false;
}

class Loader {
public:
    Loader(const tinygltf::Model& model, std::string file, std::string sceneName) : m_m(model), m_file(std::move(file)) {
        m_scene.name = std::move(sceneName);
    }

    Result<Scene> run();
    std::vector<std::string>& warnings() { return m_warnings; }

private:
    Error error(const std::string& what) const { return makeError(m_file + ": " + what); }
    void warn(const std::string& what) { m_warnings.push_back(m_file + ": " + what); }

    Result<void> checkExtensions();
    Result<void> loadMaterials();
    int loadTexture(int gltfTexture, const std::string& material);
    Result<std::vector<uint32_t>> meshPrimitives(int gltfMesh);
    Result<bool> loadPrimitive(int meshIndex, int primIndex, Mesh& out);
    std::vector<uint32_t> validTriangles(const std::vector<float>& pos, const std::vector<uint32_t>& idx,
                                         const std::string& where);
    void repairNormalsAndUvs(Mesh& out, const std::string& where);
    Result<std::vector<float>> readFloats(int accessor, int components, const std::string& what);
    Result<std::vector<uint32_t>> readIndices(int accessor, const std::string& what);
    struct ElementRange {
        const unsigned char* base; // first element
        uint64_t stride;           // bytes between elements
    };
    // Where the elements of accessor `a` live, after checking its buffer view, buffer and byte
    // ranges; `acc` names the accessor in errors, `elemSize` is the bytes one element reads.
    Result<ElementRange> elements(const tinygltf::Accessor& a, const std::string& acc, uint64_t elemSize);
    Result<void> visit(int node, const glm::mat4& parent, int depth);
    Result<glm::mat4> localTransform(const tinygltf::Node& n, int index);
    void addLight(int lightIndex, const glm::mat4& world, int node);
    void addCamera(int cameraIndex, const glm::mat4& world, int node);
    uint32_t defaultMaterial();

    const tinygltf::Model& m_m;
    std::string m_file;
    std::vector<std::string> m_warnings;
    Scene m_scene;
    std::map<int, std::vector<uint32_t>> m_meshMap;  // glTF mesh -> Scene meshes (one per primitive)
    std::map<int, int> m_textureMap;                 // glTF image -> Scene texture (-1 = failed)
    std::set<int> m_onStack;                         // nodes on the current path (cycle check)
    std::set<int> m_visited;                         // nodes placed so far (each is placed once)
    int m_defaultMaterial = -1;
    int m_skippedPrimitives = 0;
    bool m_zfarInfinite = false;
    std::set<std::string> m_warnedOnce;
};

Result<void> Loader::checkExtensions() {
    for (const std::string& e : m_m.extensionsRequired)
        if (!kSupportedExtensions.count(e))
            return error("requires unsupported extension " + e);
    std::string ignored;
    for (const std::string& e : m_m.extensionsUsed)
        if (!kSupportedExtensions.count(e))
            ignored += (ignored.empty() ? "" : ", ") + e;
    if (!ignored.empty())
        warn("ignoring unsupported extension(s) " + ignored);
    if (!m_m.skins.empty())
        warn(std::to_string(m_m.skins.size()) + " skin(s) ignored: skinned meshes are loaded in their bind pose");
    if (!m_m.animations.empty())
        warn(std::to_string(m_m.animations.size()) + " animation(s) ignored: the scene is loaded at rest");
    return {};
}

uint32_t Loader::defaultMaterial() {
    if (m_defaultMaterial < 0) {
        m_defaultMaterial = int(addMaterial(m_scene, "default", glm::vec3(0.8f)));
    }
    return uint32_t(m_defaultMaterial);
}

int Loader::loadTexture(int gltfTexture, const std::string& material) {
    if (gltfTexture < 0 || size_t(gltfTexture) >= m_m.textures.size()) {
        warn(material + ": baseColorTexture " + std::to_string(gltfTexture) + " does not exist; untextured");
        return -1;
    }
    int source = m_m.textures[size_t(gltfTexture)].source;
    if (source < 0 || size_t(source) >= m_m.images.size()) {
        warn(material + ": texture " + std::to_string(gltfTexture) + " has no valid image source; untextured");
        return -1;
    }
    if (auto it = m_textureMap.find(source); it != m_textureMap.end())
        return it->second;
    const tinygltf::Image& img = m_m.images[size_t(source)];
    int result = -1;
    const uint64_t w = uint64_t(std::max(img.width, 0)), h = uint64_t(std::max(img.height, 0));
    const uint64_t comps = uint64_t(std::max(img.component, 0));
    const uint64_t bytesPer = img.bits == 16 ? 2 : 1;
    if (w == 0 || h == 0 || comps < 1 || comps > 4 || (img.bits != 8 && img.bits != 16) ||
        img.image.size() < w * h * comps * bytesPer) {
        warn("image " + std::to_string(source) + (img.uri.empty() ? "" : " '" + img.uri + "'") +
             " is missing or undecodable; " + material + " is untextured");
    } else {
        Texture t;
        t.name = img.name.empty() ? img.uri : img.name;
        t.width = uint32_t(w);
        t.height = uint32_t(h);
        t.srgb = true;
        t.rgba8.resize(w * h * 4);
        for (uint64_t p = 0; p < w * h; ++p) {
            uint8_t c[4] = {0, 0, 0, 255};
            for (uint64_t k = 0; k < comps; ++k) {
                uint64_t at = (p * comps + k) * bytesPer;
                c[k] = bytesPer == 2 ? img.image[at + 1] : img.image[at]; // 16-bit little endian: keep the high byte
            }
            if (comps == 1 || comps == 2) { // grey (+ alpha)
                uint8_t a = comps == 2 ? c[1] : 255;
                c[1] = c[2] = c[0];
                c[3] = a;
            }
            std::memcpy(&t.rgba8[p * 4], c, 4);
        }
        m_scene.textures.push_back(std::move(t));
        result = int(m_scene.textures.size() - 1);
    }
    m_textureMap[source] = result;
    return result;
}

Result<void> Loader::loadMaterials() {
    std::map<std::string, int> ignoredTextures;
    for (size_t i = 0; i < m_m.materials.size(); ++i) {
        const tinygltf::Material& g = m_m.materials[i];
        std::string what = "material " + std::to_string(i) + (g.name.empty() ? "" : " '" + g.name + "'");
        Material mat;
        mat.name = g.name;
        const auto& pbr = g.pbrMetallicRoughness;
        if (pbr.baseColorFactor.size() == 4) {
            glm::vec4 c(float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]), float(pbr.baseColorFactor[2]),
                        float(pbr.baseColorFactor[3]));
            if (std::isfinite(c.x + c.y + c.z + c.w))
                mat.baseColor = glm::clamp(c, glm::vec4(0.0f), glm::vec4(1.0f));
            else
                warn(what + ": non-finite baseColorFactor replaced by white");
        }
        auto factor = [&](double v, float fallback, const char* name) {
            float f = float(v);
            if (!std::isfinite(f)) {
                warn(what + ": non-finite " + name + " replaced by " + std::to_string(fallback));
                return fallback;
            }
            return std::clamp(f, 0.0f, 1.0f);
        };
        mat.metallic = factor(pbr.metallicFactor, 0.0f, "metallicFactor");
        mat.roughness = factor(pbr.roughnessFactor, 1.0f, "roughnessFactor");
        if (pbr.baseColorTexture.index >= 0) {
            mat.baseColorTexture = loadTexture(pbr.baseColorTexture.index, what);
            if (pbr.baseColorTexture.texCoord != 0)
                warn(what + ": baseColorTexture uses TEXCOORD_" + std::to_string(pbr.baseColorTexture.texCoord) +
                     ", only TEXCOORD_0 is loaded");
        }
        if (pbr.metallicRoughnessTexture.index >= 0)
            ignoredTextures["metallicRoughnessTexture"]++;
        if (g.normalTexture.index >= 0)
            ignoredTextures["normalTexture"]++;
        if (g.occlusionTexture.index >= 0)
            ignoredTextures["occlusionTexture"]++;
        if (g.emissiveTexture.index >= 0)
            ignoredTextures["emissiveTexture"]++;
        glm::vec3 e(0.0f);
        if (g.emissiveFactor.size() == 3)
            e = glm::vec3(float(g.emissiveFactor[0]), float(g.emissiveFactor[1]), float(g.emissiveFactor[2]));
        float strength = 1.0f;
        if (auto it = g.extensions.find("KHR_materials_emissive_strength"); it != g.extensions.end()) {
            const tinygltf::Value& v = it->second.Get("emissiveStrength");
            if (v.IsNumber())
                strength = float(v.GetNumberAsDouble());
            if (!std::isfinite(strength) || strength < 0.0f) {
                warn(what + ": invalid emissiveStrength ignored (using 1)");
                strength = 1.0f;
            }
        }
        for (const auto& [name, value] : g.extensions)
            if (name != "KHR_materials_emissive_strength" && m_warnedOnce.insert("matext:" + name).second)
                warn("material extension " + name + " ignored");
        e *= strength;
        if (!finite3(e) || e.x < 0.0f || e.y < 0.0f || e.z < 0.0f) {
            warn(what + ": invalid emission replaced by 0");
            e = glm::vec3(0.0f);
        }
        mat.emission = e;
        mat.doubleSided = g.doubleSided;
        if (g.alphaMode != "OPAQUE" && !g.alphaMode.empty() && m_warnedOnce.insert("alpha").second)
            warn("alphaMode " + g.alphaMode + " ignored: materials are treated as opaque");
        m_scene.materials.push_back(std::move(mat));
    }
    for (const auto& [name, count] : ignoredTextures)
        warn(name + " ignored on " + std::to_string(count) + " material(s): only baseColorTexture is supported");
    return {};
}

// Reads a float/normalized-integer attribute as `components` floats per element.
Result<Loader::ElementRange> Loader::elements(const tinygltf::Accessor& a, const std::string& acc,
                                              uint64_t elemSize) {
    if (size_t(a.bufferView) >= m_m.bufferViews.size())
        return error(acc + " uses buffer view " + std::to_string(a.bufferView) + ", which does not exist");
    const tinygltf::BufferView& bv = m_m.bufferViews[size_t(a.bufferView)];
    if (bv.buffer < 0 || size_t(bv.buffer) >= m_m.buffers.size())
        return error("buffer view " + std::to_string(a.bufferView) + " uses buffer " + std::to_string(bv.buffer) +
                     ", which does not exist");
    const std::vector<unsigned char>& data = m_m.buffers[size_t(bv.buffer)].data;
    if (uint64_t(bv.byteOffset) + uint64_t(bv.byteLength) > data.size())
        return error("buffer view " + std::to_string(a.bufferView) + " (bytes " + std::to_string(bv.byteOffset) + "+" +
                     std::to_string(bv.byteLength) + ") lies past the end of buffer " + std::to_string(bv.buffer) +
                     " (" + std::to_string(data.size()) + " bytes)");
    const uint64_t stride = bv.byteStride ? uint64_t(bv.byteStride) : elemSize;
    if (stride < elemSize)
        return error("buffer view " + std::to_string(a.bufferView) + " byteStride " + std::to_string(bv.byteStride) +
                     " is smaller than the " + std::to_string(elemSize) + "-byte elements of " + acc);
    if (a.count > 0 && uint64_t(a.byteOffset) + stride * (uint64_t(a.count) - 1) + elemSize > uint64_t(bv.byteLength))
        return error(acc + " reads past the end of buffer view " + std::to_string(a.bufferView));
    return ElementRange{data.data() + bv.byteOffset + a.byteOffset, stride};
}

Result<std::vector<float>> Loader::readFloats(int index, int components, const std::string& what) {
    if (index < 0 || size_t(index) >= m_m.accessors.size())
        return error(what + " uses accessor " + std::to_string(index) + ", which does not exist (" +
                     std::to_string(m_m.accessors.size()) + " accessors)");
    const tinygltf::Accessor& a = m_m.accessors[size_t(index)];
    const std::string acc = "accessor " + std::to_string(index) + " (" + what + ")";
    if (a.sparse.isSparse)
        return error(acc + " is sparse; sparse accessors are not supported");
    int nComp = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    if (nComp != components)
        return error(acc + " has " + std::to_string(nComp) + " components per element, expected " +
                     std::to_string(components));
    int compSize = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
    if (compSize <= 0 || a.componentType == TINYGLTF_COMPONENT_TYPE_DOUBLE)
        return error(acc + " has invalid componentType " + std::to_string(a.componentType));
    if (uint64_t(a.count) > kMaxAccessorCount)
        return error(acc + " count " + std::to_string(a.count) + " is implausibly large");
    const uint64_t count = a.count;
    std::vector<float> out(count * uint64_t(components), 0.0f);
    if (a.bufferView < 0) // glTF: no buffer view means all zeros
        return out;
    auto range = elements(a, acc, uint64_t(compSize) * uint64_t(components));
    if (!range)
        return range.error();
    const unsigned char* base = range->base;
    const uint64_t stride = range->stride;
    const bool norm = a.normalized;
    for (uint64_t e = 0; e < count; ++e) {
        const unsigned char* p = base + e * stride;
        for (int c = 0; c < components; ++c) {
            const unsigned char* q = p + c * compSize;
            float v = 0.0f;
            switch (a.componentType) {
            case TINYGLTF_COMPONENT_TYPE_FLOAT: std::memcpy(&v, q, 4); break;
            case TINYGLTF_COMPONENT_TYPE_BYTE: {
                int8_t x;
                std::memcpy(&x, q, 1);
                v = norm ? std::max(float(x) / 127.0f, -1.0f) : float(x);
                break;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = norm ? float(*q) / 255.0f : float(*q); break;
            case TINYGLTF_COMPONENT_TYPE_SHORT: {
                int16_t x;
                std::memcpy(&x, q, 2);
                v = norm ? std::max(float(x) / 32767.0f, -1.0f) : float(x);
                break;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                uint16_t x;
                std::memcpy(&x, q, 2);
                v = norm ? float(x) / 65535.0f : float(x);
                break;
            }
            case TINYGLTF_COMPONENT_TYPE_INT: {
                int32_t x;
                std::memcpy(&x, q, 4);
                v = float(x);
                break;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
                uint32_t x;
                std::memcpy(&x, q, 4);
                v = float(x);
                break;
            }
            default: return error(acc + " has invalid componentType " + std::to_string(a.componentType));
            }
            out[e * uint64_t(components) + uint64_t(c)] = v;
        }
    }
    return out;
}

Result<std::vector<uint32_t>> Loader::readIndices(int index, const std::string& what) {
    if (index < 0 || size_t(index) >= m_m.accessors.size())
        return error(what + " uses accessor " + std::to_string(index) + ", which does not exist (" +
                     std::to_string(m_m.accessors.size()) + " accessors)");
    const tinygltf::Accessor& a = m_m.accessors[size_t(index)];
    const std::string acc = "accessor " + std::to_string(index) + " (" + what + ")";
    if (a.type != TINYGLTF_TYPE_SCALAR)
        return error(acc + " is not SCALAR");
    if (a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        return error(acc + " has componentType " + std::to_string(a.componentType) +
                     "; indices must be unsigned byte, short or int");
    // Read through the float path only for validation would lose precision above 2^24: do it directly.
    if (a.sparse.isSparse)
        return error(acc + " is sparse; sparse accessors are not supported");
    if (uint64_t(a.count) > kMaxAccessorCount)
        return error(acc + " count " + std::to_string(a.count) + " is implausibly large");
    std::vector<uint32_t> out(a.count, 0u);
    if (a.bufferView < 0)
        return out;
    const uint64_t size = uint64_t(tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType)));
    auto range = elements(a, acc, size);
    if (!range)
        return range.error();
    const unsigned char* base = range->base;
    const uint64_t stride = range->stride;
    for (size_t i = 0; i < out.size(); ++i) {
        const unsigned char* q = base + i * stride;
        if (size == 1) {
            out[i] = *q;
        } else if (size == 2) {
            uint16_t x;
            std::memcpy(&x, q, 2);
            out[i] = x;
        } else {
            std::memcpy(&out[i], q, 4);
        }
    }
    return out;
}

// The triangles of `idx` (3 indices each into `pos`, xyz per vertex) whose vertices are finite and
// that have an area; warns about the others.
std::vector<uint32_t> Loader::validTriangles(const std::vector<float>& pos, const std::vector<uint32_t>& idx,
                                             const std::string& where) {
    auto P = [&](uint32_t v) { return glm::vec3(pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]); };
    size_t nonFinite = 0, degenerate = 0;
    std::vector<uint32_t> kept;
    kept.reserve(idx.size());
    for (size_t t = 0; t < idx.size(); t += 3) {
        glm::vec3 a = P(idx[t]), b = P(idx[t + 1]), c = P(idx[t + 2]);
        if (!finite3(a) || !finite3(b) || !finite3(c)) {
            ++nonFinite;
            continue;
        }
        float longest = std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
        float area2 = glm::length(glm::cross(b - a, c - a));
        if (!(area2 > kDegenerateRelArea * longest) || !std::isfinite(area2)) {
            ++degenerate;
            continue;
        }
        kept.insert(kept.end(), {idx[t], idx[t + 1], idx[t + 2]});
    }
    if (nonFinite)
        warn(where + ": dropped " + std::to_string(nonFinite) + " triangle(s) with a NaN/Inf vertex position");
    if (degenerate)
        warn(where + ": dropped " + std::to_string(degenerate) + " zero-area triangle(s)");
    return kept;
}

// Normals: computed when missing; bad ones repaired from the surrounding faces. Non-finite
// texture coordinates become 0.
void Loader::repairNormalsAndUvs(Mesh& out, const std::string& where) {
    Mesh computed = out;
    computeSmoothNormals(computed);
    for (glm::vec3& n : computed.normals) // area-weighted normals can cancel (e.g. a two-sided sheet)
        if (glm::dot(n, n) == 0.0f)
            n = glm::vec3(NAN);
    for (size_t t = 0; t < out.indices.size(); t += 3) { // fall back to a face normal of the vertex
        glm::vec3 a = out.positions[out.indices[t]], b = out.positions[out.indices[t + 1]],
                  c = out.positions[out.indices[t + 2]];
        glm::vec3 fn = glm::normalize(glm::cross(b - a, c - a));
        for (int k = 0; k < 3; ++k)
            if (!finite3(computed.normals[out.indices[t + size_t(k)]]))
                computed.normals[out.indices[t + size_t(k)]] = fn;
    }
    if (out.normals.empty()) {
        out.normals = std::move(computed.normals);
    } else {
        size_t repaired = 0;
        for (size_t v = 0; v < out.normals.size(); ++v) {
            glm::vec3& n = out.normals[v];
            float len = glm::length(n);
            if (!std::isfinite(len) || len < 1e-12f) {
                n = computed.normals[v];
                ++repaired;
            } else {
                n /= len;
            }
        }
        if (repaired)
            warn(where + ": replaced " + std::to_string(repaired) +
                 " zero-length or non-finite normal(s) by the face normal");
    }
    size_t badUv = 0;
    for (glm::vec2& t : out.uvs)
        if (!std::isfinite(t.x) || !std::isfinite(t.y)) {
            t = glm::vec2(0.0f);
            ++badUv;
        }
    if (badUv)
        warn(where + ": replaced " + std::to_string(badUv) + " non-finite texture coordinate(s) by 0");
}

// Returns false (with a warning) when the primitive is skipped, an error when the file is bad.
Result<bool> Loader::loadPrimitive(int meshIndex, int primIndex, Mesh& out) {
    const tinygltf::Mesh& gm = m_m.meshes[size_t(meshIndex)];
    const tinygltf::Primitive& prim = gm.primitives[size_t(primIndex)];
    const std::string where = "mesh " + std::to_string(meshIndex) + (gm.name.empty() ? "" : " '" + gm.name + "'") +
                              " primitive " + std::to_string(primIndex);
    if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) {
        static const char* kModes[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP", "TRIANGLES", "TRIANGLE_STRIP",
                                       "TRIANGLE_FAN"};
        std::string mode = prim.mode >= 0 && prim.mode <= 6 ? kModes[prim.mode] : std::to_string(prim.mode);
        warn(where + " has mode " + mode + "; only TRIANGLES are loaded, primitive skipped");
        ++m_skippedPrimitives;
        return false;
    }
    if (!prim.targets.empty())
        warn(where + ": " + std::to_string(prim.targets.size()) + " morph target(s) ignored");
    auto posIt = prim.attributes.find("POSITION");
    if (posIt == prim.attributes.end()) {
        warn(where + " has no POSITION attribute; primitive skipped");
        ++m_skippedPrimitives;
        return false;
    }
    Result<std::vector<float>> pos = readFloats(posIt->second, 3, where + " POSITION");
    if (!pos)
        return pos.error();
    const size_t nv = pos->size() / 3;
    std::vector<float> nrm, uv;
    if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
        Result<std::vector<float>> r = readFloats(it->second, 3, where + " NORMAL");
        if (!r)
            return r.error();
        nrm = std::move(r).value();
        if (nrm.size() / 3 != nv)
            return error(where + " has " + std::to_string(nrm.size() / 3) + " normals for " + std::to_string(nv) +
                         " positions");
    }
    if (auto it = prim.attributes.find("TEXCOORD_0"); it != prim.attributes.end()) {
        Result<std::vector<float>> r = readFloats(it->second, 2, where + " TEXCOORD_0");
        if (!r)
            return r.error();
        uv = std::move(r).value();
        if (uv.size() / 2 != nv)
            return error(where + " has " + std::to_string(uv.size() / 2) + " texture coordinates for " +
                         std::to_string(nv) + " positions");
    }
    std::vector<uint32_t> idx;
    if (prim.indices >= 0) {
        Result<std::vector<uint32_t>> r = readIndices(prim.indices, where + " indices");
        if (!r)
            return r.error();
        idx = std::move(r).value();
        for (size_t i = 0; i < idx.size(); ++i)
            if (idx[i] >= nv)
                return error(where + ": index " + std::to_string(i) + " = " + std::to_string(idx[i]) +
                             " is out of range (" + std::to_string(nv) + " vertices)");
    } else {
        idx.resize(nv);
        for (size_t i = 0; i < nv; ++i)
            idx[i] = uint32_t(i);
    }
    if (idx.size() % 3 != 0) {
        warn(where + ": " + std::to_string(idx.size() % 3) + " trailing index(es) that form no triangle dropped");
        idx.resize(idx.size() - idx.size() % 3);
    }
    auto P = [&](uint32_t v) { return glm::vec3(pos.value()[3 * v], pos.value()[3 * v + 1], pos.value()[3 * v + 2]); };

    // Drop triangles with non-finite vertices or no area, then keep only referenced vertices.
    std::vector<uint32_t> kept = validTriangles(*pos, idx, where);
    if (kept.empty()) {
        warn(where + " has no valid triangles; primitive skipped");
        ++m_skippedPrimitives;
        return false;
    }
    std::unordered_map<uint32_t, uint32_t> remap;
    out = Mesh{};
    out.name = gm.name.empty() ? "mesh" + std::to_string(meshIndex) : gm.name;
    if (gm.primitives.size() > 1)
        out.name += "/" + std::to_string(primIndex);
    for (uint32_t v : kept) {
        auto [it, inserted] = remap.emplace(v, uint32_t(out.positions.size()));
        if (inserted) {
            out.positions.push_back(P(v));
            if (!nrm.empty())
                out.normals.emplace_back(nrm[3 * v], nrm[3 * v + 1], nrm[3 * v + 2]);
            if (!uv.empty())
                out.uvs.emplace_back(uv[2 * v], uv[2 * v + 1]);
        }
        out.indices.push_back(it->second);
    }
    repairNormalsAndUvs(out, where);

    if (prim.material >= 0) {
        if (size_t(prim.material) >= m_m.materials.size())
            return error(where + " uses material " + std::to_string(prim.material) + ", which does not exist (" +
                         std::to_string(m_m.materials.size()) + " materials)");
        out.material = uint32_t(prim.material);
    } else {
        out.material = defaultMaterial();
    }
    return true;
}

Result<std::vector<uint32_t>> Loader::meshPrimitives(int gltfMesh) {
    if (auto it = m_meshMap.find(gltfMesh); it != m_meshMap.end())
        return it->second;
    std::vector<uint32_t> ids;
    const tinygltf::Mesh& gm = m_m.meshes[size_t(gltfMesh)];
    for (size_t p = 0; p < gm.primitives.size(); ++p) {
        Mesh mesh;
        Result<bool> r = loadPrimitive(gltfMesh, int(p), mesh);
        if (!r)
            return r.error();
        if (!r.value())
            continue;
        m_scene.meshes.push_back(std::move(mesh));
        ids.push_back(uint32_t(m_scene.meshes.size() - 1));
    }
    m_meshMap[gltfMesh] = ids;
    return ids;
}

Result<glm::mat4> Loader::localTransform(const tinygltf::Node& n, int index) {
    const std::string what = "node " + std::to_string(index);
    glm::mat4 m(1.0f);
    if (!n.matrix.empty()) {
        if (n.matrix.size() != 16)
            return error(what + " matrix has " + std::to_string(n.matrix.size()) + " elements, expected 16");
        for (int i = 0; i < 16; ++i)
            glm::value_ptr(m)[i] = float(n.matrix[size_t(i)]); // glTF and glm are both column-major
    } else {
        glm::vec3 t(0.0f), s(1.0f);
        glm::quat r(1.0f, 0.0f, 0.0f, 0.0f);
        if (!n.translation.empty()) {
            if (n.translation.size() != 3)
                return error(what + " translation has " + std::to_string(n.translation.size()) + " elements, expected 3");
            t = glm::vec3(float(n.translation[0]), float(n.translation[1]), float(n.translation[2]));
        }
        if (!n.rotation.empty()) {
            if (n.rotation.size() != 4)
                return error(what + " rotation has " + std::to_string(n.rotation.size()) + " elements, expected 4");
            // glTF stores x, y, z, w; glm::quat's constructor takes w first.
            r = glm::quat(float(n.rotation[3]), float(n.rotation[0]), float(n.rotation[1]), float(n.rotation[2]));
            float len = glm::length(r);
            if (!(len > 0.0f) || !std::isfinite(len))
                return error(what + " rotation quaternion is zero or not finite");
            r = r / len;
        }
        if (!n.scale.empty()) {
            if (n.scale.size() != 3)
                return error(what + " scale has " + std::to_string(n.scale.size()) + " elements, expected 3");
            s = glm::vec3(float(n.scale[0]), float(n.scale[1]), float(n.scale[2]));
        }
        m = glm::translate(glm::mat4(1.0f), t) * glm::mat4_cast(r) * glm::scale(glm::mat4(1.0f), s);
    }
    for (int i = 0; i < 16; ++i)
        if (!std::isfinite(glm::value_ptr(m)[i]))
            return error(what + " transform is not finite");
    return m;
}

void Loader::addLight(int li, const glm::mat4& world, int node) {
    const std::string what = "light " + std::to_string(li) + " (node " + std::to_string(node) + ")";
    if (li < 0 || size_t(li) >= m_m.lights.size()) {
        warn(what + " does not exist; skipped");
        return;
    }
    const tinygltf::Light& g = m_m.lights[size_t(li)];
    Light l;
    l.name = g.name;
    if (g.type == "point") {
        l.type = LightType::Point;
    } else if (g.type == "spot") {
        l.type = LightType::Spot;
    } else if (g.type == "directional") {
        l.type = LightType::Directional;
    } else {
        warn(what + " has unknown type '" + g.type + "'; skipped");
        return;
    }
    if (g.color.size() == 3)
        l.color = glm::vec3(float(g.color[0]), float(g.color[1]), float(g.color[2]));
    l.intensity = float(g.intensity);
    if (!finite3(l.color) || l.color.x < 0.0f || l.color.y < 0.0f || l.color.z < 0.0f || !std::isfinite(l.intensity) ||
        l.intensity < 0.0f) {
        warn(what + " has a non-finite or negative colour/intensity; skipped");
        return;
    }
    l.range = float(g.range);
    if (!std::isfinite(l.range) || l.range < 0.0f) {
        warn(what + " has an invalid range; treated as infinite");
        l.range = 0.0f;
    }
    if (l.type == LightType::Spot) {
        float inner = float(g.spot.innerConeAngle), outer = float(g.spot.outerConeAngle);
        float ci = std::isfinite(inner) ? std::clamp(inner, 0.0f, kPi / 2) : 0.0f;
        float co = std::isfinite(outer) ? std::clamp(outer, 1e-4f, kPi / 2) : kPi / 4;
        ci = std::min(ci, co);
        if (ci != inner || co != outer)
            warn(what + " cone angles clamped to 0 <= inner <= outer <= pi/2");
        l.innerConeAngle = ci;
        l.outerConeAngle = co;
    }
    l.position = glm::vec3(world * glm::vec4(0, 0, 0, 1));
    glm::vec3 dir = glm::vec3(world * glm::vec4(0, 0, -1, 0));
    float len = glm::length(dir);
    if (!(len > 0.0f) || !std::isfinite(len)) {
        warn(what + " node transform collapses its direction; skipped");
        return;
    }
    l.direction = dir / len;
    m_scene.lights.push_back(std::move(l));
}

void Loader::addCamera(int ci, const glm::mat4& world, int node) {
    if (m_scene.camera)
        return; // the first camera wins
    const std::string what = "camera " + std::to_string(ci) + " (node " + std::to_string(node) + ")";
    if (ci < 0 || size_t(ci) >= m_m.cameras.size()) {
        warn(what + " does not exist; ignored");
        return;
    }
    const tinygltf::Camera& g = m_m.cameras[size_t(ci)];
    if (g.type != "perspective") {
        if (m_warnedOnce.insert("camtype").second)
            warn(what + " is " + g.type + "; only perspective cameras are used");
        return;
    }
    Camera c;
    c.yfov = float(g.perspective.yfov);
    c.znear = float(g.perspective.znear);
    c.zfar = float(g.perspective.zfar);
    if (!(c.yfov > 0.0f && c.yfov < kPi) || !(c.znear > 0.0f) || !std::isfinite(c.znear)) {
        warn(what + " has invalid yfov/znear; ignored");
        return;
    }
    m_zfarInfinite = !(c.zfar > c.znear) || !std::isfinite(c.zfar);
    c.position = glm::vec3(world * glm::vec4(0, 0, 0, 1));
    glm::vec3 f = glm::vec3(world * glm::vec4(0, 0, -1, 0));
    glm::vec3 u = glm::vec3(world * glm::vec4(0, 1, 0, 0));
    if (!(glm::length(f) > 0.0f) || !finite3(f) || !finite3(u) || !finite3(c.position)) {
        warn(what + " node transform is degenerate; ignored");
        return;
    }
    c.forward = glm::normalize(f);
    c.up = glm::length(u) > 0.0f ? glm::normalize(u) : glm::vec3(0, 1, 0);
    m_scene.camera = c;
}

Result<void> Loader::visit(int node, const glm::mat4& parent, int depth) {
    if (node < 0 || size_t(node) >= m_m.nodes.size())
        return error("node " + std::to_string(node) + " does not exist (" + std::to_string(m_m.nodes.size()) + " nodes)");
    if (depth > kMaxNodeDepth)
        return error("node hierarchy deeper than " + std::to_string(kMaxNodeDepth) + " levels at node " +
                     std::to_string(node));
    if (!m_onStack.insert(node).second)
        return error("node hierarchy has a cycle through node " + std::to_string(node));
    if (!m_visited.insert(node).second) {
        // glTF nodes form a forest: a node listed under two parents (or twice) is malformed.
        warn("node " + std::to_string(node) + " is listed more than once in the hierarchy (a glTF node has one "
             "parent); drawn at its first place only");
        m_onStack.erase(node);
        return {};
    }
    const tinygltf::Node& n = m_m.nodes[size_t(node)];
    Result<glm::mat4> local = localTransform(n, node);
    if (!local)
        return local.error();
    glm::mat4 world = parent * local.value();
    if (n.mesh >= 0) {
        if (size_t(n.mesh) >= m_m.meshes.size())
            return error("node " + std::to_string(node) + " uses mesh " + std::to_string(n.mesh) +
                         ", which does not exist (" + std::to_string(m_m.meshes.size()) + " meshes)");
        Result<std::vector<uint32_t>> ids = meshPrimitives(n.mesh);
        if (!ids)
            return ids.error();
        const glm::vec3 t(world[3]);
        if (isSingularTransform(world)) {
            warn("node " + std::to_string(node) + ": singular transform (a zero scale, or axes collapsed onto a "
                 "plane or line); mesh " + std::to_string(n.mesh) + " is not drawn");
            ids = std::vector<uint32_t>{};
        } else if (glm::any(glm::greaterThan(glm::abs(t), glm::vec3(kMaxCoordinate)))) {
            warn("node " + std::to_string(node) + ": placed beyond " + std::to_string(kMaxCoordinate) +
                 " m from the origin; mesh " + std::to_string(n.mesh) + " is not drawn");
            ids = std::vector<uint32_t>{};
        }
        for (uint32_t id : ids.value()) {
            Instance inst;
            inst.mesh = id;
            inst.transform = world;
            m_scene.instances.push_back(inst);
        }
    }
    if (n.camera >= 0)
        addCamera(n.camera, world, node);
    if (auto it = n.extensions.find("KHR_lights_punctual"); it != n.extensions.end()) {
        const tinygltf::Value& v = it->second.Get("light");
        // Checked as a double first: converting an out-of-range number to int is undefined.
        const double index = v.IsNumber() ? v.GetNumberAsDouble() : -1.0;
        if (v.IsNumber() && index >= 0.0 && index < double(m_m.lights.size()) && index == std::floor(index))
            addLight(int(index), world, node);
        else if (v.IsNumber())
            warn("node " + std::to_string(node) + " KHR_lights_punctual light index " + formatNumber(index) +
                 " is not one of the " + std::to_string(m_m.lights.size()) + " lights; ignored");
        else
            warn("node " + std::to_string(node) + " KHR_lights_punctual has no light index; ignored");
    }
    for (int child : n.children) {
        Result<void> r = visit(child, world, depth + 1);
        if (!r)
            return r;
    }
    m_onStack.erase(node);
    return {};
}

Result<Scene> Loader::run() {
    if (Result<void> r = checkExtensions(); !r)
        return r.error();
    if (Result<void> r = loadMaterials(); !r)
        return r.error();

    std::vector<int> roots;
    if (!m_m.scenes.empty()) {
        int s = m_m.defaultScene;
        if (s < 0 || size_t(s) >= m_m.scenes.size()) {
            if (s >= 0)
                warn("default scene " + std::to_string(s) + " does not exist; using scene 0");
            s = 0;
        }
        roots = m_m.scenes[size_t(s)].nodes;
    } else { // no scenes: every node that is nobody's child is a root
        std::vector<bool> isChild(m_m.nodes.size(), false);
        for (const tinygltf::Node& n : m_m.nodes)
            for (int c : n.children)
                if (c >= 0 && size_t(c) < isChild.size())
                    isChild[size_t(c)] = true;
        for (size_t i = 0; i < m_m.nodes.size(); ++i)
            if (!isChild[i])
                roots.push_back(int(i));
    }
    for (int root : roots)
        if (Result<void> r = visit(root, glm::mat4(1.0f), 0); !r)
            return r.error();

    if (m_scene.instances.empty())
        return error(m_skippedPrimitives ? "no triangle geometry in the scene (" + std::to_string(m_skippedPrimitives) +
                                               " primitive(s) skipped: points/lines or no valid triangles)"
                                         : "no triangle geometry in the scene");
    if (m_scene.lights.empty())
        warn(m_scene.hasEmission() ? "no punctual lights; the scene is lit by emissive materials only"
                                   : "no punctual lights and no emissive materials; the scene will render black");
    if (m_scene.camera && m_zfarInfinite) { // infinite glTF projection: reach well past the scene
        Aabb b = m_scene.bounds();
        float reach = glm::length(b.extent()) + glm::length(b.centre() - m_scene.camera->position);
        m_scene.camera->zfar = std::max(4.0f * reach, 1000.0f * m_scene.camera->znear);
    }
    if (Result<void> v = validateScene(m_scene); !v)
        return error("loaded scene is invalid: " + v.error().message);
    return std::move(m_scene);
}

bool isBinaryGltf(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    char magic[4] = {};
    in.read(magic, 4);
    return in.gcount() == 4 && std::memcmp(magic, "glTF", 4) == 0;
}

} // namespace

// A GLB states its total length in its 12-byte header: checked against the file before reading.
Result<void> checkGlbHeader(const std::filesystem::path& file, uint64_t fileSize) {
    std::ifstream in(file, std::ios::binary);
    uint32_t header[3] = {};
    in.read(reinterpret_cast<char*>(header), sizeof(header));
    if (in.gcount() != sizeof(header))
        return makeError(file.string() + ": GLB header is truncated");
    if (header[2] != fileSize)
        return makeError(file.string() + ": GLB header gives a length of " + std::to_string(header[2]) +
                         " bytes, the file has " + std::to_string(fileSize));
    return {};
}

Result<Scene> loadGltf(const std::filesystem::path& file, std::vector<std::string>* warnings,
                       const GltfLoadOptions& options) {
    const std::string name = file.string();
    try {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(file, ec))
            return makeError(name + ": no such file");
        const uintmax_t size = std::filesystem::file_size(file, ec);
        if (ec || size == 0)
            return makeError(name + ": file is empty");
        if (size > options.maxFileBytes)
            return makeError(name + ": file is " + std::to_string(size) + " bytes, over the loader's limit of " +
                             std::to_string(options.maxFileBytes) + " bytes (GltfLoadOptions::maxFileBytes)");
        const bool binary = isBinaryGltf(file);
        if (binary)
            if (Result<void> ok = checkGlbHeader(file, size); !ok)
                return ok.error();
        FileGuard guard;
        guard.root = std::filesystem::weakly_canonical(std::filesystem::absolute(file, ec), ec).parent_path();
        guard.options = options;
        tinygltf::TinyGLTF ctx;
        ctx.SetImageLoader(tolerantImageLoader, nullptr);
        tinygltf::FsCallbacks callbacks;
        callbacks.FileExists = guardedFileExists;
        callbacks.ExpandFilePath = unexpandedPath;
        callbacks.ReadWholeFile = guardedReadWholeFile;
        callbacks.WriteWholeFile = refuseWrite;
        callbacks.user_data = &guard;
        ctx.SetFsCallbacks(callbacks);
        tinygltf::Model model;
        std::string err, warn;
        bool ok = binary ? ctx.LoadBinaryFromFile(&model, &err, &warn, name)
                         : ctx.LoadASCIIFromFile(&model, &err, &warn, name);
        Loader loader(model, name, file.stem().string());
        for (const std::string& refusal : guard.refusals)
            loader.warnings().push_back(name + ": " + refusal);
        if (!ok) {
            if (warnings)
                warnings->insert(warnings->end(), loader.warnings().begin(), loader.warnings().end());
            return makeError(name + ": " + (err.empty() ? "not a valid glTF file" : oneLine(err)));
        }
        if (!warn.empty())
            loader.warnings().push_back(name + ": " + oneLine(warn));
        Result<Scene> scene = loader.run();
        if (warnings)
            warnings->insert(warnings->end(), loader.warnings().begin(), loader.warnings().end());
        return scene;
    } catch (const std::exception& e) {
        return makeError(name + ": " + oneLine(e.what()));
    } catch (...) {
        return makeError(name + ": unknown failure while parsing");
    }
}

Result<Scene> loadScene(std::string_view nameOrPath, const BuiltinSceneParams& p, std::vector<std::string>* warnings,
                        const GltfLoadOptions& options) {
    if (isBuiltinScene(nameOrPath))
        return makeBuiltinScene(nameOrPath, p);
    std::filesystem::path path{std::string(nameOrPath)};
    std::error_code ec;
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (std::filesystem::exists(path, ec) || ext == ".gltf" || ext == ".glb")
        return loadGltf(path, warnings, options);
    std::string names;
    for (const std::string& n : builtinSceneNames())
        names += (names.empty() ? "" : ", ") + n;
    return makeError("'" + std::string(nameOrPath) + "' is neither a built-in scene (" + names +
                     ") nor a .gltf/.glb file");
}

} // namespace vkgi
