#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "vkgi/gltf_loader.hpp"
#include "support/test_env.hpp"

using namespace vkgi;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// Little-endian byte blob builder for the .bin buffers the tests write.
struct Blob {
    std::vector<uint8_t> bytes;
    size_t addFloats(std::initializer_list<float> v) {
        size_t at = bytes.size();
        for (float f : v) {
            uint8_t b[4];
            std::memcpy(b, &f, 4);
            bytes.insert(bytes.end(), b, b + 4);
        }
        return at;
    }
    size_t addU16(std::initializer_list<uint16_t> v) {
        size_t at = bytes.size();
        for (uint16_t x : v) {
            bytes.push_back(uint8_t(x & 0xff));
            bytes.push_back(uint8_t(x >> 8));
        }
        while (bytes.size() % 4)
            bytes.push_back(0);
        return at;
    }
};

fs::path tempDir(const std::string& name) { return test::freshOutputDir(fs::path("gltf_loader") / name); }

void writeFile(const fs::path& p, const std::string& text) {
    std::ofstream(p, std::ios::binary) << text;
}

void writeBytes(const fs::path& p, const std::vector<uint8_t>& b) {
    std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
}

// One triangle (0,0,0) (1,0,0) (0,1,0), indexed, facing +z; a spot light 2 m above pointing
// down; a camera at z = 3 looking at the origin.
json triangleDoc(Blob& blob) {
    size_t pos = blob.addFloats({0, 0, 0, 1, 0, 0, 0, 1, 0});
    size_t idx = blob.addU16({0, 1, 2});
    json j;
    j["asset"] = {{"version", "2.0"}};
    j["extensionsUsed"] = {"KHR_lights_punctual"};
    j["scene"] = 0;
    j["scenes"] = json::array({{{"nodes", {0, 1, 2}}}});
    const float s = std::sqrt(0.5f); // -90 degrees about x turns -z into -y
    j["nodes"] = json::array({{{"mesh", 0}},
                              {{"translation", {0, 2, 0}},
                               {"rotation", {-s, 0, 0, s}},
                               {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}},
                              {{"translation", {0, 0, 3}}, {"camera", 0}}});
    j["meshes"] = json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}})}}});
    j["accessors"] = json::array({{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}},
                                  {{"bufferView", 1}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}}});
    j["bufferViews"] = json::array({{{"buffer", 0}, {"byteOffset", pos}, {"byteLength", 36}},
                                    {{"buffer", 0}, {"byteOffset", idx}, {"byteLength", 6}}});
    j["buffers"] = json::array({{{"byteLength", blob.bytes.size()}}});
    j["extensions"]["KHR_lights_punctual"]["lights"] = json::array(
        {{{"type", "spot"}, {"color", {1.0, 0.5, 0.25}}, {"intensity", 7.0}, {"range", 12.0},
          {"spot", {{"innerConeAngle", 0.3}, {"outerConeAngle", 0.6}}}}});
    j["cameras"] = json::array({{{"type", "perspective"},
                                 {"perspective", {{"yfov", 0.8}, {"znear", 0.05}, {"zfar", 50.0}}}}});
    return j;
}

fs::path writeGltf(const fs::path& dir, json j, const Blob& blob) {
    j["buffers"][0]["uri"] = "data.bin";
    writeBytes(dir / "data.bin", blob.bytes);
    writeFile(dir / "scene.gltf", j.dump(1));
    return dir / "scene.gltf";
}

fs::path writeGlb(const fs::path& dir, const json& j, const Blob& blob) {
    std::string text = j.dump();
    while (text.size() % 4)
        text += ' ';
    std::vector<uint8_t> bin = blob.bytes;
    while (bin.size() % 4)
        bin.push_back(0);
    std::vector<uint8_t> out;
    auto u32 = [&](uint32_t v) {
        for (int i = 0; i < 4; ++i)
            out.push_back(uint8_t(v >> (8 * i)));
    };
    out.insert(out.end(), {'g', 'l', 'T', 'F'});
    u32(2);
    u32(uint32_t(12 + 8 + text.size() + 8 + bin.size()));
    u32(uint32_t(text.size()));
    out.insert(out.end(), {'J', 'S', 'O', 'N'});
    out.insert(out.end(), text.begin(), text.end());
    u32(uint32_t(bin.size()));
    out.insert(out.end(), {'B', 'I', 'N', 0});
    out.insert(out.end(), bin.begin(), bin.end());
    writeBytes(dir / "scene.glb", out);
    return dir / "scene.glb";
}

void expectTriangleScene(const Scene& s) {
    ASSERT_EQ(s.meshes.size(), 1u);
    ASSERT_EQ(s.instances.size(), 1u);
    const Mesh& m = s.meshes[0];
    ASSERT_EQ(m.positions.size(), 3u);
    EXPECT_EQ(m.positions[1], glm::vec3(1, 0, 0));
    EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2}));
    ASSERT_EQ(m.normals.size(), 3u); // missing normals are computed: the face faces +z
    for (const glm::vec3& n : m.normals)
        EXPECT_NEAR(glm::length(n - glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
    ASSERT_LT(m.material, s.materials.size()); // no material in the file: a default one
    ASSERT_EQ(s.lights.size(), 1u);
    const Light& l = s.lights[0];
    EXPECT_EQ(l.type, LightType::Spot);
    EXPECT_NEAR(glm::length(l.position - glm::vec3(0, 2, 0)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(l.direction - glm::vec3(0, -1, 0)), 0.0f, 1e-6f);
    EXPECT_EQ(l.color, glm::vec3(1.0f, 0.5f, 0.25f));
    EXPECT_FLOAT_EQ(l.intensity, 7.0f);
    EXPECT_FLOAT_EQ(l.range, 12.0f);
    EXPECT_FLOAT_EQ(l.innerConeAngle, 0.3f);
    EXPECT_FLOAT_EQ(l.outerConeAngle, 0.6f);
    ASSERT_TRUE(s.camera);
    EXPECT_NEAR(glm::length(s.camera->position - glm::vec3(0, 0, 3)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(s.camera->forward - glm::vec3(0, 0, -1)), 0.0f, 1e-6f);
    EXPECT_FLOAT_EQ(s.camera->yfov, 0.8f);
    EXPECT_FLOAT_EQ(s.camera->znear, 0.05f);
    EXPECT_FLOAT_EQ(s.camera->zfar, 50.0f);
    EXPECT_TRUE(validateScene(s).ok());
}

// The committed corpus. sourceDir() comes from VKGI_SOURCE_DIR; when ctest does not pass it on
// (tests/CMakeLists.txt currently forwards only the first ENVIRONMENT entry), fall back to the
// location of this source file.
fs::path badDir() {
    fs::path d = test::sourceDir() / "tests/assets/gltf/bad";
    if (fs::exists(d))
        return d;
    return fs::path(__FILE__).parent_path().parent_path() / "assets/gltf/bad";
}

bool anyContains(const std::vector<std::string>& v, const std::string& s) {
    for (const std::string& x : v)
        if (x.find(s) != std::string::npos)
            return true;
    return false;
}

std::string joined(const std::vector<std::string>& v) {
    std::string out;
    for (const std::string& x : v)
        out += x + " | ";
    return out;
}

} // namespace

TEST(GltfLoader, TriangleWithLightAndCamera) {
    Blob blob;
    json j = triangleDoc(blob);
    fs::path f = writeGltf(tempDir("triangle"), j, blob);
    std::vector<std::string> warnings;
    Result<Scene> r = loadGltf(f, &warnings);
    ASSERT_TRUE(r.ok()) << r.error().message;
    expectTriangleScene(*r);
    EXPECT_EQ(r->name, "scene");
    EXPECT_TRUE(warnings.empty()) << joined(warnings);
}

TEST(GltfLoader, BinaryGlb) {
    Blob blob;
    json j = triangleDoc(blob);
    fs::path f = writeGlb(tempDir("glb"), j, blob);
    std::vector<std::string> warnings;
    Result<Scene> r = loadGltf(f, &warnings);
    ASSERT_TRUE(r.ok()) << r.error().message;
    expectTriangleScene(*r);
    EXPECT_TRUE(warnings.empty()) << joined(warnings);
}

TEST(GltfLoader, TrsHierarchyAndMatrixNodes) {
    Blob blob;
    json j = triangleDoc(blob);
    const float s = std::sqrt(0.5f); // +90 degrees about y: (x, y, z) -> (z, y, -x)
    // parent: T (1,0,0) R 90 deg about y, S 2; child: T (0,0,1) holding the mesh.
    // A child-space point p maps to (1,0,0) + R(2 (p + (0,0,1))).
    j["nodes"][0] = {{"translation", {1, 0, 0}}, {"rotation", {0, s, 0, s}}, {"scale", {2, 2, 2}}, {"children", {3}}};
    j["nodes"].push_back({{"translation", {0, 0, 1}}, {"mesh", 0}});
    // A second instance through a column-major matrix: translate (0, 5, 0), scale x by 3.
    j["nodes"].push_back({{"matrix", {3, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 5, 0, 1}}, {"mesh", 0}});
    j["scenes"][0]["nodes"].push_back(4);
    Result<Scene> r = loadGltf(writeGltf(tempDir("trs"), j, blob));
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->instances.size(), 2u);
    ASSERT_EQ(r->meshes.size(), 1u); // one glTF mesh used twice: loaded once
    auto world = [&](size_t inst, const glm::vec3& p) {
        return glm::vec3(r->instances[inst].transform * glm::vec4(p, 1.0f));
    };
    EXPECT_NEAR(glm::length(world(0, {0, 0, 0}) - glm::vec3(3, 0, 0)), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::length(world(0, {1, 0, 0}) - glm::vec3(3, 0, -2)), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::length(world(0, {0, 1, 0}) - glm::vec3(3, 2, 0)), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::length(world(1, {1, 0, 0}) - glm::vec3(3, 5, 0)), 0.0f, 1e-6f);
}

TEST(GltfLoader, MaterialsEmissiveStrengthAndTexture) {
    Blob blob;
    json j = triangleDoc(blob);
    j["extensionsUsed"].push_back("KHR_materials_emissive_strength");
    j["extensionsUsed"].push_back("KHR_materials_clearcoat");
    j["meshes"][0]["primitives"][0]["material"] = 0;
    j["materials"] = json::array({{{"name", "glow"},
                                   {"pbrMetallicRoughness",
                                    {{"baseColorFactor", {0.5, 0.25, 1.0, 1.0}},
                                     {"metallicFactor", 0.25},
                                     {"roughnessFactor", 0.75},
                                     {"baseColorTexture", {{"index", 0}}}}},
                                   {"normalTexture", {{"index", 0}}},
                                   {"emissiveFactor", {1.0, 0.5, 0.25}},
                                   {"doubleSided", true},
                                   {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}}}}}});
    j["textures"] = json::array({{{"source", 0}}});
    j["images"] = json::array({{{"uri", "tex.ppm"}}});
    fs::path dir = tempDir("material");
    // A 2 x 1 binary PPM: red, then (10, 20, 30).
    std::string ppm = "P6\n2 1\n255\n";
    ppm += std::string("\xff\x00\x00\x0a\x14\x1e", 6);
    writeFile(dir / "tex.ppm", ppm);
    std::vector<std::string> warnings;
    Result<Scene> r = loadGltf(writeGltf(dir, j, blob), &warnings);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Material& m = r->materials[r->meshes[0].material];
    EXPECT_EQ(m.name, "glow");
    EXPECT_EQ(m.baseColor, glm::vec4(0.5f, 0.25f, 1.0f, 1.0f));
    EXPECT_FLOAT_EQ(m.metallic, 0.25f);
    EXPECT_FLOAT_EQ(m.roughness, 0.75f);
    EXPECT_EQ(m.emission, glm::vec3(4.0f, 2.0f, 1.0f)); // emissiveFactor x emissiveStrength
    EXPECT_TRUE(m.doubleSided);
    ASSERT_GE(m.baseColorTexture, 0);
    const Texture& t = r->textures[size_t(m.baseColorTexture)];
    ASSERT_EQ(t.width, 2u);
    ASSERT_EQ(t.height, 1u);
    EXPECT_EQ(t.rgba8, (std::vector<uint8_t>{255, 0, 0, 255, 10, 20, 30, 255}));
    EXPECT_TRUE(anyContains(warnings, "normalTexture")) << joined(warnings);
    EXPECT_TRUE(anyContains(warnings, "KHR_materials_clearcoat")) << joined(warnings);
}

TEST(GltfLoader, MissingImageLeavesMaterialUntextured) {
    Blob blob;
    json j = triangleDoc(blob);
    j["meshes"][0]["primitives"][0]["material"] = 0;
    j["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
    j["textures"] = json::array({{{"source", 0}}});
    j["images"] = json::array({{{"uri", "nowhere.png"}}});
    std::vector<std::string> warnings;
    Result<Scene> r = loadGltf(writeGltf(tempDir("missing_image"), j, blob), &warnings);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->materials[r->meshes[0].material].baseColorTexture, -1);
    EXPECT_TRUE(anyContains(warnings, "untextured")) << joined(warnings);
}

TEST(GltfLoader, LoadSceneTakesBuiltinNamesAndPaths) {
    Result<Scene> b = loadScene("furnace");
    ASSERT_TRUE(b.ok());
    EXPECT_EQ(b->name, "furnace");
    Blob blob;
    json j = triangleDoc(blob);
    fs::path f = writeGltf(tempDir("load_scene"), j, blob);
    Result<Scene> g = loadScene(f.string());
    ASSERT_TRUE(g.ok()) << g.error().message;
    EXPECT_EQ(g->triangleCount(), 1u);
    Result<Scene> none = loadScene("no_such_scene");
    ASSERT_FALSE(none.ok());
    EXPECT_NE(none.error().message.find("cornell"), std::string::npos) << none.error().message;
}

// ---- The committed bad-input corpus (tests/assets/gltf/bad; also a fuzzing seed) -----------

struct BadCase {
    const char* file;
    bool loads;            // false: must fail with an error containing `message`
    const char* message;   // expected in the error (or, when it loads, in a warning)
    uint64_t triangles;    // triangles left after repair when it loads
};

class BadGltf : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadGltf, FailsOrRepairsAsDocumented) {
    const BadCase& c = GetParam();
    fs::path f = badDir() / c.file;
    ASSERT_TRUE(fs::exists(f)) << f;
    std::vector<std::string> warnings;
    Result<Scene> r = loadGltf(f, &warnings);
    if (!c.loads) {
        ASSERT_FALSE(r.ok()) << c.file << " loaded";
        const std::string& msg = r.error().message;
        std::cout << "    error: " << msg << "\n"; // the log shows what a user would see
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;               // one line
        EXPECT_NE(msg.find(c.file), std::string::npos) << msg;             // names the file
        EXPECT_NE(msg.find(c.message), std::string::npos) << msg;          // names the problem
        for (const std::string& w : warnings)
            std::cout << "    warning: " << w << "\n";
        return;
    }
    ASSERT_TRUE(r.ok()) << r.error().message;
    for (const std::string& w : warnings)
        std::cout << "    warning: " << w << "\n";
    EXPECT_TRUE(validateScene(*r).ok());
    EXPECT_EQ(r->triangleCount(), c.triangles);
    EXPECT_TRUE(anyContains(warnings, c.message)) << joined(warnings);
    for (const std::string& w : warnings) {
        EXPECT_EQ(w.find('\n'), std::string::npos) << w;
        EXPECT_NE(w.find(c.file), std::string::npos) << w;
    }
}

INSTANTIATE_TEST_SUITE_P(
    Corpus, BadGltf,
    ::testing::Values(
        BadCase{"truncated.gltf", false, "", 0},
        BadCase{"empty.gltf", false, "file is empty", 0},
        BadCase{"truncated.glb", false, "", 0},
        BadCase{"missing_bin.gltf", false, "does_not_exist.bin", 0},
        BadCase{"index_out_of_range.gltf", false, "index 2 = 7 is out of range (3 vertices)", 0},
        BadCase{"accessor_past_end.gltf", false, "accessor 0 (mesh 0 primitive 0 POSITION) reads past the end of buffer view 0", 0},
        BadCase{"buffer_view_past_end.gltf", false, "buffer view 0", 0},
        BadCase{"no_meshes.gltf", false, "no triangle geometry", 0},
        BadCase{"points_only.gltf", false, "no triangle geometry in the scene (1 primitive(s) skipped", 0},
        BadCase{"bad_extension.gltf", false, "requires unsupported extension KHR_draco_mesh_compression", 0},
        BadCase{"node_cycle.gltf", false, "cycle", 0},
        BadCase{"bad_mesh_index.gltf", false, "uses mesh 5, which does not exist", 0},
        BadCase{"nan_position.gltf", true, "dropped 1 triangle(s) with a NaN/Inf vertex position", 1},
        BadCase{"zero_area_triangle.gltf", true, "dropped 1 zero-area triangle(s)", 1},
        BadCase{"zero_length_normal.gltf", true, "replaced 1 zero-length or non-finite normal(s)", 1},
        BadCase{"sparse_accessor.gltf", false, "sparse accessors are not supported", 0},
        BadCase{"bad_material_index.gltf", false, "uses material 3, which does not exist (1 materials)", 0},
        BadCase{"float_indices.gltf", false, "indices must be unsigned byte, short or int", 0},
        BadCase{"nan_normal.gltf", true, "replaced 1 zero-length or non-finite normal(s)", 1},
        BadCase{"negative_light_intensity.gltf", true, "light 0 (node 1) has a non-finite or negative colour/intensity; skipped", 1}),
    [](const ::testing::TestParamInfo<BadCase>& p) {
        std::string n = p.param.file;
        for (char& ch : n)
            if (!std::isalnum(static_cast<unsigned char>(ch)))
                ch = '_';
        return n;
    });

TEST(GltfLoader, ZeroLengthNormalIsReplacedByTheFaceNormal) {
    Result<Scene> r = loadGltf(badDir() / "zero_length_normal.gltf");
    ASSERT_TRUE(r.ok()) << r.error().message;
    for (const glm::vec3& n : r->meshes[0].normals)
        EXPECT_NEAR(glm::length(n - glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
}

TEST(GltfLoader, BadLightIsSkippedAndBadConeClamped) {
    std::vector<std::string> warnings;
    Result<Scene> r = loadGltf(badDir() / "negative_light_intensity.gltf", &warnings);
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->lights.size(), 1u); // the negative point light is gone, the spot stays
    const Light& l = r->lights[0];
    EXPECT_EQ(l.type, LightType::Spot);
    EXPECT_FLOAT_EQ(l.outerConeAngle, 1.0f);
    EXPECT_FLOAT_EQ(l.innerConeAngle, 1.0f); // inner 2.0 > outer 1.0: clamped to outer
    EXPECT_TRUE(anyContains(warnings, "cone angles clamped")) << joined(warnings);
}

TEST(GltfLoader, SkippedPrimitiveIsNamedInAWarning) {
    std::vector<std::string> warnings;
    Result<Scene> r = loadGltf(badDir() / "points_only.gltf", &warnings);
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(anyContains(warnings, "mesh 0 primitive 0 has mode POINTS; only TRIANGLES are loaded")) << joined(warnings);
}

TEST(GltfLoader, MissingFileIsOneLineError) {
    Result<Scene> r = loadGltf("/nonexistent/dir/scene.gltf");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, "/nonexistent/dir/scene.gltf: no such file");
}

// Deterministic mutations of the corpus (truncations, byte flips, digit swaps) must each give a
// scene that validates or a one-line error: never a crash, hang or exception.
TEST(GltfLoader, MutatedCorpusNeverCrashes) {
    fs::path dir = tempDir("mutations");
    uint32_t rng = 12345u;
    auto next = [&]() { // xorshift32: reproducible without <random>'s implementation-defined engines
        rng ^= rng << 13;
        rng ^= rng >> 17;
        rng ^= rng << 5;
        return rng;
    };
    int loaded = 0, failed = 0;
    for (const auto& entry : fs::directory_iterator(badDir())) {
        if (entry.path().extension() != ".gltf" && entry.path().extension() != ".glb")
            continue;
        std::ifstream in(entry.path(), std::ios::binary);
        std::ostringstream buf;
        buf << in.rdbuf();
        std::string original = buf.str();
        if (original.empty())
            continue;
        for (int m = 0; m < 40; ++m) {
            std::string text = original;
            switch (m % 4) {
            case 0: text.resize(next() % text.size()); break;
            case 1: text[next() % text.size()] = char(next() & 0xff); break;
            case 2: { // change a digit: indices, counts, offsets and lengths go out of range
                size_t at = next() % text.size();
                while (at < text.size() && !std::isdigit(static_cast<unsigned char>(text[at])))
                    ++at;
                if (at < text.size())
                    text[at] = char('0' + next() % 10);
                break;
            }
            default: { // grow a number a lot
                size_t at = text.find_first_of("0123456789", next() % text.size());
                if (at != std::string::npos)
                    text.insert(at, "99999");
                break;
            }
            }
            fs::path f = dir / ("m" + std::to_string(m) + entry.path().extension().string());
            writeFile(f, text);
            Result<Scene> r = loadGltf(f);
            if (r.ok()) {
                EXPECT_TRUE(validateScene(*r).ok()) << entry.path().filename() << " mutation " << m;
                ++loaded;
            } else {
                EXPECT_EQ(r.error().message.find('\n'), std::string::npos) << r.error().message;
                ++failed;
            }
        }
    }
    EXPECT_GT(failed, 0); // the mutations do reach the error paths
    std::cout << "    mutations: " << loaded << " loaded, " << failed << " rejected\n";
}

// ---- Hostile input (files outside the scene's folder, sizes, numbers, degenerate nodes) ----

// An image URI that climbs out of the scene's folder is not read (texture dropped, warned);
// allowOutsideFolder reads it. A buffer outside the folder is an error, not a silent read.
TEST(GltfLoader, UrisOutsideTheScenesFolderAreNotRead) {
    Blob blob;
    json j = triangleDoc(blob);
    j["meshes"][0]["primitives"][0]["material"] = 0;
    j["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
    j["textures"] = json::array({{{"source", 0}}});
    j["images"] = json::array({{{"uri", "../outside.ppm"}}});
    fs::path root = tempDir("outside");
    fs::create_directories(root / "scene");
    std::string ppm = "P6\n1 1\n255\n";
    ppm += std::string("\x0a\x14\x1e", 3);
    writeFile(root / "outside.ppm", ppm);
    fs::path f = writeGltf(root / "scene", j, blob);

    std::vector<std::string> warnings;
    Result<Scene> r = loadGltf(f, &warnings);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->materials[r->meshes[0].material].baseColorTexture, -1);
    EXPECT_TRUE(anyContains(warnings, "outside.ppm' resolves outside the scene's folder")) << joined(warnings);

    GltfLoadOptions allow;
    allow.allowOutsideFolder = true;
    warnings.clear();
    r = loadGltf(f, &warnings, allow);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_GE(r->materials[r->meshes[0].material].baseColorTexture, 0) << joined(warnings);

    // The same through a symbolic link inside the folder that points out of it.
    fs::create_symlink(root / "outside.ppm", root / "scene" / "link.ppm");
    j["images"][0]["uri"] = "link.ppm";
    f = writeGltf(root / "scene", j, blob);
    warnings.clear();
    r = loadGltf(f, &warnings);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->materials[r->meshes[0].material].baseColorTexture, -1);
    EXPECT_TRUE(anyContains(warnings, "resolves outside the scene's folder")) << joined(warnings);

    // A buffer outside the folder: an error naming the file.
    json k = triangleDoc(blob);
    writeBytes(root / "data_outside.bin", blob.bytes);
    k["buffers"][0]["uri"] = "../data_outside.bin";
    writeFile(root / "scene" / "buffer.gltf", k.dump());
    warnings.clear();
    r = loadGltf(root / "scene" / "buffer.gltf", &warnings);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("buffer.gltf"), std::string::npos) << r.error().message;
    EXPECT_TRUE(anyContains(warnings, "data_outside.bin' resolves outside")) << joined(warnings);
}

// Sizes are checked before anything is read: the scene file and each buffer against the limit
// (named in the error), and a GLB's stated length against its file size.
TEST(GltfLoader, SizeLimitsAreCheckedBeforeReading) {
    Blob blob;
    json j = triangleDoc(blob);
    fs::path dir = tempDir("limits");
    fs::path f = writeGltf(dir, j, blob);
    GltfLoadOptions small;
    small.maxFileBytes = 100; // the JSON is larger
    Result<Scene> r = loadGltf(f, nullptr, small);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("over the loader's limit of 100 bytes"), std::string::npos) << r.error().message;
    small.maxFileBytes = fs::file_size(f); // the JSON and its 44-byte buffer fit
    EXPECT_TRUE(loadGltf(f, nullptr, small).ok());
    // A buffer over the limit: grown past the JSON's size, it is refused before it is read.
    Blob big = blob;
    big.bytes.resize(blob.bytes.size() + 20000, 0);
    json k = j;
    k["buffers"][0]["byteLength"] = big.bytes.size();
    fs::path h = writeGltf(tempDir("limits_buffer"), k, big);
    small.maxFileBytes = fs::file_size(h);
    r = loadGltf(h, nullptr, small);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("data.bin is 20044 bytes, over the loader's limit"), std::string::npos)
        << r.error().message;
    fs::path g = writeGlb(dir, j, blob);
    // GLB whose header claims more bytes than the file has.
    std::vector<uint8_t> bytes(fs::file_size(g));
    {
        std::ifstream in(g, std::ios::binary);
        in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()));
    }
    bytes[8] = uint8_t(bytes[8] + 4);
    writeBytes(dir / "lying.glb", bytes);
    r = loadGltf(dir / "lying.glb");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("GLB header gives a length of"), std::string::npos) << r.error().message;
}

// Numbers that would overflow an int conversion (undefined behaviour) are checked as doubles.
TEST(GltfLoader, HugeLightIndexIsAWarning) {
    Blob blob;
    json j = triangleDoc(blob);
    j["nodes"][1]["extensions"]["KHR_lights_punctual"]["light"] = 5e68;
    std::vector<std::string> warnings;
    Result<Scene> r = loadGltf(writeGltf(tempDir("huge_light"), j, blob), &warnings);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(r->lights.empty());
    EXPECT_TRUE(anyContains(warnings, "node 1 KHR_lights_punctual light index 5e+68 is not one of the 1 lights"))
        << joined(warnings);
}

// A node whose world transform is singular or astronomically far is not drawn, with a warning
// naming it; the rest of the scene loads. Mirrored scales are fine.
TEST(GltfLoader, DegenerateNodeTransformsAreDroppedWithAWarning) {
    struct Case {
        json node;
        bool drawn;
        const char* warning;
    } cases[] = {
        {{{"mesh", 0}, {"scale", {1, 0, 1}}}, false, "node 3: singular transform"},
        {{{"mesh", 0}, {"scale", {0, 1, 1}}}, false, "node 3: singular transform"},
        {{{"mesh", 0}, {"matrix", {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1}}}, false, "node 3: singular transform"},
        {{{"mesh", 0}, {"matrix", {1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1}}}, false, "node 3: singular transform"},
        {{{"mesh", 0}, {"translation", {1e30, 0, 0}}}, false, "node 3: placed beyond"},
        {{{"mesh", 0}, {"scale", {-1, 1, 1}}}, true, nullptr},
    };
    for (const Case& c : cases) {
        Blob blob;
        json j = triangleDoc(blob);
        j["nodes"].push_back(c.node);
        j["scenes"][0]["nodes"].push_back(3);
        std::vector<std::string> warnings;
        Result<Scene> r = loadGltf(writeGltf(tempDir("degenerate"), j, blob), &warnings);
        ASSERT_TRUE(r.ok()) << c.node.dump() << ": " << r.error().message;
        EXPECT_EQ(r->instances.size(), c.drawn ? 2u : 1u) << c.node.dump();
        if (c.warning) {
            EXPECT_TRUE(anyContains(warnings, c.warning)) << c.node.dump() << ": " << joined(warnings);
        }
        EXPECT_TRUE(validateScene(*r).ok());
    }
}

// The Scene API refuses what the loader drops: a clean error naming the instance.
TEST(SceneValidation, SingularAndFarInstancesAreErrors) {
    Result<Scene> s = loadScene("cornell");
    ASSERT_TRUE(s.ok());
    glm::mat4 coplanar(1.0f); // the third axis lies in the plane of the first two
    coplanar[2] = glm::vec4(1.0f, 1.0f, 0.0f, 0.0f);
    for (glm::mat4 m : {glm::scale(glm::mat4(1.0f), glm::vec3(1, 0, 1)), glm::mat4(0.0f), coplanar}) {
        Scene bad = *s;
        bad.instances[0].transform = m;
        Result<void> v = validateScene(bad);
        ASSERT_FALSE(v.ok());
        EXPECT_NE(v.error().message.find("instance 0 has a singular transform"), std::string::npos) << v.error().message;
    }
    Scene far = *s;
    far.instances[0].transform[3] = glm::vec4(1e30f, 0.0f, 0.0f, 1.0f);
    Result<void> v = validateScene(far);
    ASSERT_FALSE(v.ok());
    EXPECT_NE(v.error().message.find("instance 0 is translated beyond"), std::string::npos) << v.error().message;
    Scene mirrored = *s;
    mirrored.instances[0].transform = glm::scale(glm::mat4(1.0f), glm::vec3(-1, 1, 1)) * mirrored.instances[0].transform;
    EXPECT_TRUE(validateScene(mirrored).ok());
    Scene tiny = *s; // uniformly small is not singular: a millimetre scene
    tiny.instances[0].transform = glm::scale(glm::mat4(1.0f), glm::vec3(1e-6f)) * tiny.instances[0].transform;
    EXPECT_TRUE(validateScene(tiny).ok());
}

// Every repair the loader makes silently elsewhere is a warning naming the element: each edit of
// the triangle document below must load and produce the quoted warning.
TEST(GltfLoader, EveryRepairIsAWarningNamingTheElement) {
    struct Case {
        const char* what;
        void (*edit)(json&);
        const char* warning;
    } cases[] = {
        {"camera yfov 0", [](json& j) { j["cameras"][0]["perspective"]["yfov"] = 0.0; },
         "camera 0 (node 2) has invalid yfov/znear; ignored"},
        {"camera yfov 3.2", [](json& j) { j["cameras"][0]["perspective"]["yfov"] = 3.2; },
         "camera 0 (node 2) has invalid yfov/znear; ignored"},
        {"camera yfov -1", [](json& j) { j["cameras"][0]["perspective"]["yfov"] = -1.0; },
         "camera 0 (node 2) has invalid yfov/znear; ignored"},
        {"orthographic camera",
         [](json& j) {
             j["cameras"][0] = {{"type", "orthographic"},
                                {"orthographic", {{"xmag", 1.0}, {"ymag", 1.0}, {"znear", 0.1}, {"zfar", 10.0}}}};
         },
         "camera 0 (node 2) is orthographic; only perspective cameras are used"},
        {"spot inner > outer",
         [](json& j) { j["extensions"]["KHR_lights_punctual"]["lights"][0]["spot"]["innerConeAngle"] = 0.9; },
         "light 0 (node 1) cone angles clamped"},
        {"negative colour",
         [](json& j) { j["extensions"]["KHR_lights_punctual"]["lights"][0]["color"] = {1.0, -1.0, 0.0}; },
         "light 0 (node 1) has a non-finite or negative colour/intensity; skipped"},
        {"unknown light type", [](json& j) { j["extensions"]["KHR_lights_punctual"]["lights"][0]["type"] = "area"; },
         "light 0 (node 1) has unknown type 'area'; skipped"},
        {"no lights", [](json& j) { j["nodes"][1].erase("extensions"); }, "no punctual lights and no emissive"},
        {"node listed twice", [](json& j) { j["scenes"][0]["nodes"].push_back(0); },
         "node 0 is listed more than once in the hierarchy"},
        {"all-zero matrix (a second instance)",
         [](json& j) {
             j["nodes"].push_back({{"mesh", 0}, {"matrix", {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1}}});
             j["scenes"][0]["nodes"].push_back(3);
         },
         "node 3: singular transform"},
        {"animation",
         [](json& j) {
             j["animations"] = json::array({{{"channels", json::array()}, {"samplers", json::array()}}});
         },
         "1 animation(s) ignored"},
        {"alpha mode", [](json& j) {
             j["meshes"][0]["primitives"][0]["material"] = 0;
             j["materials"] = json::array({{{"alphaMode", "BLEND"}}});
         },
         "alphaMode BLEND ignored"},
        {"undecodable image (a PNG header claiming 60000 x 60000)",
         [](json& j) {
             j["meshes"][0]["primitives"][0]["material"] = 0;
             j["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
             j["textures"] = json::array({{{"source", 0}}});
             j["images"] = json::array({{{"uri", "huge.png"}}});
         },
         "untextured"},
    };
    for (const Case& c : cases) {
        Blob blob;
        json j = triangleDoc(blob);
        c.edit(j);
        fs::path dir = tempDir("repairs");
        // 8-byte PNG signature and an IHDR chunk for 60000 x 60000 RGB, then nothing.
        const uint8_t png[] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a, 0, 0, 0, 13, 'I', 'H', 'D', 'R',
                               0, 0, 0xea, 0x60, 0, 0, 0xea, 0x60, 8, 2, 0, 0, 0, 0, 0, 0, 0};
        writeBytes(dir / "huge.png", std::vector<uint8_t>(std::begin(png), std::end(png)));
        std::vector<std::string> warnings;
        Result<Scene> r = loadGltf(writeGltf(dir, j, blob), &warnings);
        ASSERT_TRUE(r.ok()) << c.what << ": " << r.error().message;
        EXPECT_TRUE(anyContains(warnings, c.warning)) << c.what << ": " << joined(warnings);
        for (const std::string& w : warnings)
            EXPECT_EQ(w.find('\n'), std::string::npos) << w;
    }
}

// The fuzzer-grown corpus (tests/assets/gltf/fuzz) replayed: each file loads into a scene that
// passes validateScene, or fails with one line naming the file, as the fuzz harness demands.
TEST(GltfLoader, FuzzCorpusLoadsOrFailsInOneLine) {
    const fs::path dir = badDir().parent_path() / "fuzz";
    ASSERT_TRUE(fs::is_directory(dir)) << dir;
    int files = 0, loaded = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (entry.path().extension() != ".gltf" && entry.path().extension() != ".glb")
            continue;
        ++files;
        std::vector<std::string> warnings;
        Result<Scene> r = loadGltf(entry.path(), &warnings);
        if (r) {
            ++loaded;
            EXPECT_TRUE(validateScene(*r).ok()) << entry.path();
        } else {
            const std::string& m = r.error().message;
            EXPECT_EQ(m.find('\n'), std::string::npos) << entry.path() << ": " << m;
            EXPECT_NE(m.find(entry.path().filename().string()), std::string::npos) << m;
        }
        for (const std::string& w : warnings)
            EXPECT_EQ(w.find('\n'), std::string::npos) << w;
    }
    EXPECT_GE(files, 100);
    std::printf("fuzz corpus: %d files, %d load\n", files, loaded);
}
