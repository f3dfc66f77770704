// Reference cache: renders keyed by a hash of everything that changes the image.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

#include <nlohmann/json.hpp>

#include "vkgi/file_util.hpp"
#include "vkgi/image_io.hpp"
#include "vkgi/reference.hpp"

namespace vkgi::gi {

namespace {

namespace fs = std::filesystem;

// Bump whenever the tracer's output for the same input changes, so stale entries are not reused.
constexpr uint64_t kTracerVersion = 2; // 2: ray origins offset by the position's float error

class Fnv1a {
public:
    void bytes(const void* data, size_t n) {
        const auto* p = static_cast<const uint8_t*>(data);
        for (size_t i = 0; i < n; ++i) {
            m_h ^= p[i];
            m_h *= 0x100000001b3ull; // FNV-1a 64 prime
        }
    }
    template <typename T> void pod(const T& v) { bytes(&v, sizeof(T)); }
    template <typename T> void vec(const std::vector<T>& v) {
        pod(uint64_t(v.size())); // sizes keep adjacent arrays from aliasing each other
        bytes(v.data(), v.size() * sizeof(T));
    }
    uint64_t value() const { return m_h; }

private:
    uint64_t m_h = 0xcbf29ce484222325ull; // FNV-1a 64 offset basis
};

fs::path siblingOf(const fs::path& fullFile, const char* suffix) {
    std::string s = fullFile.string();
    const std::string full = ".full.exr";
    return fs::path(s.substr(0, s.size() - full.size()) + suffix);
}

// A complete entry has its .json; anything else (missing, unreadable, wrong size) is a miss.
bool loadEntry(const fs::path& fullFile, uint32_t width, uint32_t height, ReferenceImages& out) {
    std::ifstream meta(siblingOf(fullFile, ".json"));
    if (!meta)
        return false;
    nlohmann::json j = nlohmann::json::parse(meta, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded() || !j.contains("seconds") || !j.contains("rays") || !j["seconds"].is_number() ||
        !j["rays"].is_number_unsigned())
        return false;
    auto full = readExr(fullFile);
    auto direct = readExr(siblingOf(fullFile, ".direct.exr"));
    auto indirect = readExr(siblingOf(fullFile, ".indirect.exr"));
    if (!full || !direct || !indirect)
        return false;
    for (const HdrImage* img : {&full.value(), &direct.value(), &indirect.value()})
        if (img->width != width || img->height != height)
            return false;
    out.full = std::move(full.value());
    out.direct = std::move(direct.value());
    out.indirect = std::move(indirect.value());
    out.seconds = j["seconds"].get<double>();
    out.rays = j["rays"].get<uint64_t>();
    return true;
}

Result<void> storeEntry(const fs::path& fullFile, const ReferenceImages& img) {
    std::error_code ec;
    fs::create_directories(fullFile.parent_path(), ec);
    if (ec)
        return makeError(fullFile.parent_path().string() + ": cannot create cache folder: " + ec.message());
    if (auto r = writeExr(fullFile, img.full); !r)
        return r;
    if (auto r = writeExr(siblingOf(fullFile, ".direct.exr"), img.direct); !r)
        return r;
    if (auto r = writeExr(siblingOf(fullFile, ".indirect.exr"), img.indirect); !r)
        return r;
    nlohmann::json j{{"seconds", img.seconds}, {"rays", img.rays}};
    return writeFileAtomic(siblingOf(fullFile, ".json"), j.dump() + "\n"); // last: marks the entry complete
}

} // namespace

uint64_t referenceHash(const Scene& scene, const Camera& camera, uint32_t width, uint32_t height,
                       const ReferenceSettings& settings) {
    Fnv1a h;
    h.pod(kTracerVersion);
    h.pod(uint64_t(scene.meshes.size()));
    for (const Mesh& m : scene.meshes) {
        h.vec(m.positions);
        h.vec(m.normals);
        h.vec(m.uvs);
        h.vec(m.indices);
        h.pod(m.material);
    }
    h.pod(uint64_t(scene.materials.size()));
    for (const Material& m : scene.materials) {
        h.pod(m.baseColor);
        h.pod(m.baseColorTexture);
        h.pod(m.metallic);
        h.pod(m.roughness);
        h.pod(m.emission);
        h.pod(uint8_t(m.doubleSided));
    }
    h.pod(uint64_t(scene.textures.size()));
    for (const Texture& t : scene.textures) {
        h.pod(t.width);
        h.pod(t.height);
        h.pod(uint8_t(t.srgb));
        h.vec(t.rgba8);
    }
    h.pod(uint64_t(scene.instances.size()));
    for (const Instance& i : scene.instances) {
        h.pod(i.mesh);
        h.pod(i.transform);
    }
    h.pod(uint64_t(scene.lights.size()));
    for (const Light& l : scene.lights) {
        h.pod(uint32_t(l.type));
        h.pod(l.position);
        h.pod(l.direction);
        h.pod(l.color);
        h.pod(l.intensity);
        h.pod(l.range);
        h.pod(l.innerConeAngle);
        h.pod(l.outerConeAngle);
    }
    h.pod(camera.position);
    h.pod(camera.forward);
    h.pod(camera.up);
    h.pod(camera.yfov);
    h.pod(width);
    h.pod(height);
    h.pod(settings.spp);
    h.pod(int64_t(settings.maxBounces));
    h.pod(settings.seed);
    return h.value();
}

fs::path referenceCacheDir() {
    if (const char* env = std::getenv("VKGI_CACHE_DIR"); env && *env)
        return fs::path(env);
    if (const char* home = std::getenv("HOME"); home && *home)
        return fs::path(home) / ".cache" / "vkgi";
    std::error_code ec;
    fs::path tmp = fs::temp_directory_path(ec);
    return (ec ? fs::path("/tmp") : tmp) / "vkgi-cache";
}

fs::path referenceCacheFile(const Scene& scene, const Camera& camera, uint32_t width, uint32_t height,
                            const ReferenceSettings& settings) {
    char name[64];
    std::snprintf(name, sizeof(name), "ref-%016llx.full.exr",
                  static_cast<unsigned long long>(referenceHash(scene, camera, width, height, settings)));
    return referenceCacheDir() / name;
}

Result<ReferenceImages> renderReferenceCached(const Scene& scene, const Camera& camera, uint32_t width,
                                              uint32_t height, const ReferenceSettings& settings, bool* fromCache) {
    if (fromCache)
        *fromCache = false;
    const fs::path file = referenceCacheFile(scene, camera, width, height, settings);
    ReferenceImages images;
    if (loadEntry(file, width, height, images)) {
        if (fromCache)
            *fromCache = true;
        return images;
    }
    auto rendered = renderReference(scene, camera, width, height, settings);
    if (!rendered)
        return rendered;
    if (auto stored = storeEntry(file, rendered.value()); !stored)
        std::fprintf(stderr, "vkgi: warning: reference not cached: %s\n", stored.error().message.c_str());
    return rendered;
}

} // namespace vkgi::gi
