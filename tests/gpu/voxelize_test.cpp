// Compute voxelization against an independent CPU reference: the set of voxels a triangle
// touches (by clipping the triangle against each voxel box, not by the separating-axis test
// the shader uses), fixed-point averaging, bit-exact determinism and the static/dynamic split.
#include <algorithm>
#include <bit>
#include <cstdio>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "vkgi/context.hpp"
#include "support/gpu_fixture.hpp"
#include "voxel/voxel_grid.hpp"
#include "vct_test_scene.hpp"

using namespace vkgi;
using namespace vkgi::gi;
using namespace vkgi::test;

namespace {

// --- CPU reference: does the triangle touch the closed box [lo, hi]? Clip the triangle
// polygon against the six box planes (Sutherland-Hodgman); anything left means contact.
bool triangleTouchesBox(const Tri& t, glm::vec3 lo, glm::vec3 hi) {
    std::vector<glm::dvec3> poly = {glm::dvec3(t.a), glm::dvec3(t.b), glm::dvec3(t.c)};
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            double bound = side == 0 ? lo[axis] : hi[axis];
            auto inside = [&](const glm::dvec3& p) { return side == 0 ? p[axis] >= bound : p[axis] <= bound; };
            std::vector<glm::dvec3> out;
            for (size_t i = 0; i < poly.size(); ++i) {
                const glm::dvec3& p = poly[i];
                const glm::dvec3& q = poly[(i + 1) % poly.size()];
                if (inside(p))
                    out.push_back(p);
                if (inside(p) != inside(q)) {
                    double s = (bound - p[axis]) / (q[axis] - p[axis]);
                    glm::dvec3 x = p + s * (q - p);
                    x[axis] = bound;
                    out.push_back(x);
                }
            }
            poly = std::move(out);
            if (poly.empty())
                return false;
        }
    }
    return true;
}

// Zero-area triangles (points, segments) cover nothing, as for the rasteriser and the path
// tracer: the shader skips |e_a x e_b| <= 5e-7 (|e0|^2 + |e1|^2 + |e2|^2); a real sliver is
// orders of magnitude above that.
bool hasNoArea(const Tri& t) {
    glm::dvec3 a(t.a), b(t.b), c(t.c);
    double edges = glm::dot(b - a, b - a) + glm::dot(c - b, c - b) + glm::dot(a - c, a - c);
    return glm::length(glm::cross(b - a, c - a)) <= 5e-7 * edges;
}

// Voxels (unit boxes, grid at the origin) the reference says a triangle must touch (boxes
// shrunk by `eps`) and may touch (grown by `eps`): rounding decides only within eps of contact.
void referenceSets(const std::vector<Tri>& tris, uint32_t n, float eps, std::vector<uint8_t>& must,
                   std::vector<uint8_t>& may) {
    must.assign(size_t(n) * n * n, 0);
    may.assign(size_t(n) * n * n, 0);
    for (uint32_t z = 0; z < n; ++z)
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x) {
                glm::vec3 lo(x, y, z), hi = lo + 1.0f;
                size_t i = (size_t(z) * n + y) * n + x;
                for (const Tri& t : tris) {
                    if (hasNoArea(t))
                        continue;
                    must[i] |= triangleTouchesBox(t, lo + eps, hi - eps);
                    may[i] |= triangleTouchesBox(t, lo - eps, hi + eps);
                }
            }
}

size_t voxelIndex(uint32_t n, glm::uvec3 c) { return (size_t(c.z) * n + c.y) * n + c.x; }

struct Readback {
    std::vector<uint8_t> albedo, normal, emission, accum;
};

class Voxelize : public test::GpuTest {
protected:
    void TearDown() override {
        if (m_grid) {
            for (Buffer* b : {&m_buf.vertices, &m_buf.indices, &m_buf.instances, &m_buf.materials})
                if (*b)
                    destroyBuffer(ctx(), *b);
            m_grid.reset();
            m_pool.reset();
        }
        test::GpuTest::TearDown();
    }

    void makeGrid(const gpu::VoxelGridParams& params) {
        auto g = VoxelGrid::create(ctx(), params);
        ASSERT_TRUE(g) << g.error().message;
        m_grid = std::move(*g);
        m_pool = std::make_unique<rg::TransientPool>(ctx());
    }

    void upload(const TestScene& scene) {
        for (Buffer* b : {&m_buf.vertices, &m_buf.indices, &m_buf.instances, &m_buf.materials})
            if (*b)
                destroyBuffer(ctx(), *b);
        m_buf = uploadTestScene(ctx(), scene);
        m_scene = {m_buf.vertices.buffer, m_buf.indices.buffer, m_buf.instances.buffer, m_buf.materials.buffer,
                   scene.draws};
    }

    // One frame of the voxel passes through the render graph.
    void frame(VoxelUpdate update) {
        runGraph(ctx(), *m_pool, [&](rg::RenderGraph& graph) {
            exportGrid(graph, addVoxelGridPasses(graph, *m_grid, importScene(graph, m_buf, m_scene.draws), update));
        });
    }
    // First frame: static bake + (empty or not) dynamic merge.
    void voxelizeAll() { frame(VoxelUpdate::Full); }
    // One static draw of grey triangles, voxelized.
    void voxelizeGrey(const std::vector<Tri>& tris, float albedo) {
        TestScene scene;
        scene.addDraw(tris, scene.addMaterial(glm::vec3(albedo)));
        upload(scene);
        voxelizeAll();
    }
    void updateDynamic() { frame(VoxelUpdate::Dynamic); }
    // The occupied voxels are exactly those `expected(x, y, z)` names (the first 8 misses reported).
    template <class Expected>
    void expectOccupiedExactly(Expected expected) {
        Readback r = read();
        const uint32_t n = m_grid->resolution();
        uint32_t wrong = 0;
        for (uint32_t z = 0; z < n; ++z)
            for (uint32_t y = 0; y < n; ++y)
                for (uint32_t x = 0; x < n; ++x) {
                    bool set = r.albedo[4 * voxelIndex(n, {x, y, z}) + 3] == 255;
                    if (set != expected(x, y, z) && ++wrong <= 8)
                        ADD_FAILURE() << "voxel " << x << "," << y << "," << z << (set ? " set" : " left empty");
                }
        EXPECT_EQ(wrong, 0u);
    }

    Readback read() {
        const VoxelVolumes& v = m_grid->volumes();
        return {readbackImage(ctx(), v.albedo.image, VK_IMAGE_LAYOUT_GENERAL),
                readbackImage(ctx(), v.normal.image, VK_IMAGE_LAYOUT_GENERAL),
                readbackImage(ctx(), v.emission.image, VK_IMAGE_LAYOUT_GENERAL), {}};
    }

    // Compares the occupied set with the reference; returns the number of occupied voxels.
    uint32_t expectMatchesReference(const std::vector<Tri>& tris) {
        uint32_t n = m_grid->resolution();
        std::vector<uint8_t> must, may;
        referenceSets(tris, n, 1e-3f, must, may);
        Readback r = read();
        uint32_t missing = 0, extra = 0, occupied = 0, ambiguous = 0;
        for (size_t i = 0; i < must.size(); ++i) {
            bool set = r.albedo[4 * i + 3] == 255;
            occupied += set;
            if (must[i] && !set)
                ADD_FAILURE() << "missing voxel " << i % n << "," << i / n % n << "," << i / n / n;
            missing += must[i] && !set;
            extra += set && !may[i];
            ambiguous += may[i] && !must[i];
        }
        EXPECT_EQ(missing, 0u) << "voxels the triangle touches but the GPU left empty";
        EXPECT_EQ(extra, 0u) << "voxels the GPU set that the triangle does not touch";
        // Generic positions: no voxel lies within 1e-3 of contact, so the two sets coincide and
        // the comparison above is exact.
        EXPECT_EQ(ambiguous, 0u);
        return occupied;
    }

    std::unique_ptr<rg::TransientPool> m_pool;
    std::unique_ptr<VoxelGrid> m_grid;
    GpuBuffers m_buf;
    VoxelSceneBuffers m_scene;
};

} // namespace

TEST_F(Voxelize, BigTriangleSetsExactlyTheTouchedVoxels) {
    makeGrid(unitGrid(32));
    std::vector<Tri> tris = {{{1.37f, 2.21f, 3.13f}, {29.71f, 5.33f, 17.29f}, {11.17f, 28.63f, 26.87f}}};
    voxelizeGrey(tris, 0.5f);
    uint32_t occupied = expectMatchesReference(tris);
    // A plane cuts a unit cube in at most sqrt(2) of area, so a triangle of area A needs at
    // least A / sqrt(2) voxels to be covered.
    float area = 0.5f * glm::length(glm::cross(tris[0].b - tris[0].a, tris[0].c - tris[0].a));
    EXPECT_GE(float(occupied), area / std::sqrt(2.0f));
}

// dims.z = 1 (VCT's grids, the camera-centred shared grid of VPL's visibility march): the normal
// volume's alpha holds the half-voxel bits over 255, bit i + 2 j + 4 k for the half-size box
// (i, j, k) a triangle touches, against the clipping reference on the half boxes; without it the
// alpha is the occupancy, 1. With the fill (dims.w = 1) as well, the bits and the fill are the
// ones each flag gives alone (they share the accumulation record: word 0 and words 13..15).
TEST_F(Voxelize, HalfVoxelBitsAreExactlyTheTouchedHalves) {
    gpu::VoxelGridParams params = unitGrid(16);
    params.dims.z = 1;
    makeGrid(params);
    // A generic big triangle and a thin axis-aligned wall (two triangles) 0.3 voxel into the
    // voxels at x = 9 (the lower halves only), whose top edge ends 0.2 voxel into y = 11 (the lower
    // halves only).
    std::vector<Tri> tris = {{{1.37f, 2.21f, 3.13f}, {14.71f, 5.33f, 11.29f}, {5.17f, 13.63f, 12.87f}},
                             {{9.3f, 1.1f, 2.1f}, {9.3f, 11.2f, 2.1f}, {9.3f, 11.2f, 13.9f}},
                             {{9.3f, 1.1f, 2.1f}, {9.3f, 11.2f, 13.9f}, {9.3f, 1.1f, 13.9f}}};
    voxelizeGrey(tris, 0.5f);
    Readback r = read();
    const uint32_t n = 16;
    // Rounding decides only within eps of contact: such halves (the triangle's plane passes within
    // 1e-4 of a half box: 2 of the 32768 here) may go either way.
    const float eps = 1e-4f;
    uint32_t halves = 0, partial = 0, ambiguous = 0;
    for (uint32_t z = 0; z < n; ++z)
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x) {
                const size_t i = voxelIndex(n, {x, y, z});
                const uint32_t bits = r.normal[4 * i + 3];
                EXPECT_EQ(bits != 0, r.albedo[4 * i + 3] == 255) << "bits exactly where the voxel is occupied";
                for (uint32_t b = 0; b < 8; ++b) {
                    const glm::vec3 lo = glm::vec3(x, y, z) + 0.5f * glm::vec3(b & 1, (b >> 1) & 1, (b >> 2) & 1);
                    const glm::vec3 hi = lo + 0.5f;
                    bool must = false, may = false;
                    for (const Tri& t : tris) {
                        must |= triangleTouchesBox(t, lo + eps, hi - eps);
                        may |= triangleTouchesBox(t, lo - eps, hi + eps);
                    }
                    ambiguous += must != may;
                    if (must == may) {
                        EXPECT_EQ(((bits >> b) & 1u) != 0, must) << "voxel " << x << "," << y << "," << z << " half " << b;
                    }
                }
                halves += uint32_t(std::popcount(bits));
                partial += bits != 0 && bits != 255;
            }
    // Where the big triangle does not reach, the wall alone sets the lower-x halves of each voxel
    // it crosses (4 of 8), and at its top edge the lower-x, lower-y ones (2 of 8).
    uint32_t wallOnly = 0;
    for (uint32_t z = 3; z < 13; ++z)
        for (uint32_t y : {5u, 11u}) {
            const glm::vec3 lo(9.0f, float(y), float(z));
            if (triangleTouchesBox(tris[0], lo - eps, lo + 1.0f + eps))
                continue;
            ++wallOnly;
            EXPECT_EQ(uint32_t(r.normal[4 * voxelIndex(n, {9, y, z}) + 3]), y == 5 ? 0x55u : 0x11u)
                << "y " << y << " z " << z;
        }
    EXPECT_GT(wallOnly, 10u);
    EXPECT_LE(ambiguous, 2u);
    EXPECT_GT(partial, 0u);
    std::printf("[voxelize] half-voxel bits: %u halves set, %u voxels partly occupied\n", halves, partial);

    // Without dims.z the alpha is the occupancy, and the emission's alpha stays 0.
    makeGrid(unitGrid(16));
    voxelizeGrey(tris, 0.5f);
    Readback plain = read();
    const auto* pe = reinterpret_cast<const uint16_t*>(plain.emission.data());
    for (size_t i = 0; i < size_t(n) * n * n; ++i) {
        ASSERT_EQ(plain.normal[4 * i + 3], plain.albedo[4 * i + 3]);
        ASSERT_EQ(pe[4 * i + 3], 0u);
    }
    // With the fill too: the same bits, and the fill a grid with the fill alone stores.
    gpu::VoxelGridParams filled = unitGrid(16);
    filled.dims.w = 1;
    makeGrid(filled);
    voxelizeGrey(tris, 0.5f);
    Readback fillOnly = read();
    filled.dims.z = 1;
    makeGrid(filled);
    voxelizeGrey(tris, 0.5f);
    Readback both = read();
    uint32_t filledVoxels = 0;
    for (size_t i = 0; i < size_t(n) * n * n; ++i) {
        ASSERT_EQ(both.normal[4 * i + 3], r.normal[4 * i + 3]) << i;
        ASSERT_EQ(both.emission[8 * i + 6], fillOnly.emission[8 * i + 6]) << i;
        ASSERT_EQ(both.emission[8 * i + 7], fillOnly.emission[8 * i + 7]) << i;
        filledVoxels += fillOnly.emission[8 * i + 6] != 0 || fillOnly.emission[8 * i + 7] != 0;
    }
    EXPECT_GT(filledVoxels, 100u);
}

namespace {

// The two triangles of the quad p, p + u, p + u + v, p + v, facing cross(u, v).
void addQuad(std::vector<Tri>& tris, glm::vec3 p, glm::vec3 u, glm::vec3 v) {
    tris.push_back({p, p + u, p + u + v});
    tris.push_back({p, p + u + v, p + v});
}

// The closed surface of the box [lo, hi], facing outwards.
void addBox(std::vector<Tri>& tris, glm::vec3 lo, glm::vec3 hi) {
    const glm::vec3 d = hi - lo, x(d.x, 0, 0), y(0, d.y, 0), z(0, 0, d.z);
    addQuad(tris, lo, z, y);                          // -x
    addQuad(tris, {hi.x, lo.y, lo.z}, y, z);          // +x
    addQuad(tris, lo, x, z);                          // -y
    addQuad(tris, {lo.x, hi.y, lo.z}, z, x);          // +y
    addQuad(tris, lo, y, x);                          // -z
    addQuad(tris, {lo.x, lo.y, hi.z}, x, y);          // +z
}

} // namespace

// dims.w = 1 (VCT's pre-filtered opacity): the emission volume's alpha holds the fill, the share
// of the voxel's cross-section its surfaces block (gi/voxel_grid.h), in closed form: a sheet
// blocks the area it projects onto the voxel's face; a closed column its silhouette once, not
// once per side; a thin closed wall, a wall's face and a floor meeting a wall fill the voxel; a
// surface that only touches a voxel's face leaves it empty.
TEST_F(Voxelize, FillIsTheShareOfTheCrossSectionTheSurfacesBlock) {
    gpu::VoxelGridParams params = unitGrid(16);
    params.dims.w = 1;
    makeGrid(params);
    std::vector<Tri> tris;
    // A: a sheet facing +y at y = 3.4 over x in [3, 6.3], z in [2, 8].
    addQuad(tris, {3.0f, 3.4f, 2.0f}, {0, 0, 6.0f}, {3.3f, 0, 0});
    // B: a closed column 0.4 x 0.4 in the middle of the voxels x = 9, z = 9, y in [2.5, 12.5].
    addBox(tris, {9.3f, 2.5f, 9.3f}, {9.7f, 12.5f, 9.7f});
    // C: a room's floor (facing +y at y = 1.5) meeting its wall (facing +x at x = 1.5).
    addQuad(tris, {1.5f, 1.5f, 1.5f}, {0, 0, 13.0f}, {13.0f, 0, 0});
    addQuad(tris, {1.5f, 1.5f, 1.5f}, {0, 13.0f, 0}, {0, 0, 13.0f});
    // D: a closed wall 0.3 thick inside the voxels x = 12; E: one 1.4 thick across x = 13 and 14.
    addBox(tris, {12.2f, 3.5f, 3.5f}, {12.5f, 12.5f, 12.5f});
    addBox(tris, {13.2f, 3.5f, 3.5f}, {14.6f, 12.5f, 12.5f});
    voxelizeGrey(tris, 0.5f);
    Readback r = read();
    const auto* e = reinterpret_cast<const uint16_t*>(r.emission.data());
    const uint32_t n = 16;
    auto fill = [&](uint32_t x, uint32_t y, uint32_t z) {
        EXPECT_EQ(r.albedo[4 * voxelIndex(n, {x, y, z}) + 3], 255) << x << "," << y << "," << z << " occupied";
        return halfToFloat(e[4 * voxelIndex(n, {x, y, z}) + 3]);
    };
    // Fixed point rounds each triangle's area to 2^-16, the half float the fill to 2^-11.
    const float tol = 1e-3f;
    for (uint32_t z = 2; z < 8; ++z) {
        for (uint32_t x = 3; x < 6; ++x)
            EXPECT_NEAR(fill(x, 3, z), 1.0f, tol) << "A: a sheet across the voxel";
        EXPECT_NEAR(fill(6, 3, z), 0.3f, tol) << "A: a sheet over 0.3 of the voxel";
        EXPECT_EQ(r.albedo[4 * voxelIndex(n, {2, 3, z}) + 3], 0) << "A: the sheet's edge on the voxel's face";
    }
    EXPECT_EQ(r.albedo[4 * voxelIndex(n, {4, 3, 8}) + 3], 0);
    for (uint32_t y = 3; y < 12; ++y)
        EXPECT_NEAR(fill(9, y, 9), 0.4f, tol) << "B: the column's 0.4 silhouette, once";
    for (uint32_t z = 2; z < 14; ++z) {
        EXPECT_NEAR(fill(1, 1, z), 1.0f, tol) << "C: floor and wall over half the voxel each";
        EXPECT_NEAR(fill(5, 1, z), 1.0f, tol) << "C: the floor across the voxel";
    }
    for (uint32_t y = 4; y < 12; ++y)
        for (uint32_t z = 4; z < 12; ++z) {
            EXPECT_NEAR(fill(12, y, z), 1.0f, tol) << "D: both faces of a thin closed wall";
            EXPECT_NEAR(fill(13, y, z), 1.0f, tol) << "E: a thick wall's face";
            EXPECT_NEAR(fill(14, y, z), 1.0f, tol) << "E: its other face";
        }
}

// A surface on the plane between two voxel layers (a floor at y = 0 of a world-aligned
// clipmap level) touches both closed boxes but is voxelized into the one behind it only: a sheet
// facing +y at y = 5 sets the layer y = 4, one facing -y at y = 10 the layer y = 10, and a closed
// box whose y faces lie on the lattice sets its own layers, not one more of free space above and
// below. Edges that lie off the lattice keep the conservative test.
TEST_F(Voxelize, ASurfaceOnAVoxelFaceSetsTheVoxelsBehindIt) {
    makeGrid(unitGrid(16));
    std::vector<Tri> tris;
    addQuad(tris, {2.5f, 5.0f, 2.5f}, {0, 0, 4.0f}, {4.0f, 0, 0});  // facing +y: x, z in [2.5, 6.5]
    addQuad(tris, {2.5f, 10.0f, 2.5f}, {4.0f, 0, 0}, {0, 0, 4.0f}); // facing -y
    addBox(tris, {9.5f, 8.0f, 9.5f}, {12.5f, 12.0f, 12.5f});         // y faces on the lattice
    voxelizeGrey(tris, 0.5f);
    expectOccupiedExactly([](uint32_t x, uint32_t y, uint32_t z) {
        bool inSheets = x >= 2 && x <= 6 && z >= 2 && z <= 6 && (y == 4 || y == 10);
        bool inBox = x >= 9 && x <= 12 && z >= 9 && z <= 12 && y >= 8 && y <= 11 &&
                     (x == 9 || x == 12 || z == 9 || z == 12 || y == 8 || y == 11);
        return inSheets || inBox;
    });
}

// World voxels (a grid placed by setCell, as a clipmap level): voxel k spans [k - 1/2, k + 1/2)
// (worldVoxelCorner), so a sheet on the lattice (y = 0, x and z from -3 to 3) runs through voxel
// centres and sets the one layer k = 0 over x, z in -3..3, and a sheet on a half-integer plane
// lies on a voxel face and sets the voxel behind it. With faces on the lattice the first sheet
// set the layer below it and x, z in -3..2 (docs/vct.md "Voxel centres on the lattice").
TEST_F(Voxelize, WorldVoxelsAreCentredOnTheLattice) {
    makeGrid(unitGrid(16));
    m_grid->setCell(glm::ivec3(-8)); // world voxels -8 .. 7 are grid voxels 0 .. 15
    std::vector<Tri> tris;
    addQuad(tris, {-3.0f, 0.0f, -3.0f}, {0, 0, 6.0f}, {6.0f, 0, 0}); // facing +y, on the lattice
    addQuad(tris, {-3.0f, 2.5f, -3.0f}, {6.0f, 0, 0}, {0, 0, 6.0f}); // facing -y, on a voxel face
    voxelizeGrey(tris, 0.5f);
    // World y = 0 is grid 8; the voxel behind the -y sheet at 2.5 is world 3, grid 11.
    expectOccupiedExactly([](uint32_t x, uint32_t y, uint32_t z) {
        return x >= 5 && x <= 11 && z >= 5 && z <= 11 && (y == 8 || y == 11);
    });
    EXPECT_EQ(m_grid->params().originSize, glm::vec4(-8.5f, -8.5f, -8.5f, 1.0f));
}

TEST_F(Voxelize, SliversAndSubVoxelTrianglesAreNotLostButZeroAreaOnesSetNothing) {
    makeGrid(unitGrid(16));
    std::vector<Tri> tris = {
        // long sliver, 1e-4 voxels wide, crossing the grid diagonally
        {{0.31f, 0.47f, 0.53f}, {15.61f, 13.37f, 9.91f}, {15.61f, 13.3701f, 9.91f}},
        // zero-area triangle (collinear vertices): a segment
        {{2.2f, 12.3f, 1.4f}, {7.7f, 9.1f, 6.6f}, {4.95f, 10.7f, 4.0f}},
        // sub-voxel triangle in the middle of voxel (11, 3, 7)
        {{11.3f, 3.2f, 7.4f}, {11.6f, 3.3f, 7.45f}, {11.4f, 3.7f, 7.6f}},
        // sub-voxel triangle straddling the corner shared by 8 voxels around (6, 6, 12)
        {{5.9f, 5.95f, 11.93f}, {6.07f, 5.91f, 12.08f}, {6.02f, 6.09f, 11.96f}},
        // a point (all three vertices equal)
        {{13.5f, 1.5f, 14.5f}, {13.5f, 1.5f, 14.5f}, {13.5f, 1.5f, 14.5f}},
    };
    voxelizeGrey(tris, 0.8f);
    uint32_t occupied = expectMatchesReference(tris);
    Readback r = read();
    EXPECT_EQ(r.albedo[4 * voxelIndex(16, {11, 3, 7}) + 3], 255);
    // The point and the segment have no area: their voxels stay empty.
    EXPECT_EQ(r.albedo[4 * voxelIndex(16, {13, 1, 14}) + 3], 0);
    EXPECT_EQ(r.albedo[4 * voxelIndex(16, {2, 12, 1}) + 3], 0);
    EXPECT_EQ(r.albedo[4 * voxelIndex(16, {7, 9, 6}) + 3], 0);
    // The small triangle near the corner (6, 6, 12): its plane passes 0.011 voxels from the
    // corner, so it touches 7 of the 8 voxels around it and misses (5, 6, 12), the one on the far
    // side of the plane (n = (-0.0222, 0.0129, 0.0286) points into it).
    uint32_t around = 0;
    for (uint32_t corner = 0; corner < 8; ++corner) {
        glm::uvec3 c(5 + (corner & 1), 5 + ((corner >> 1) & 1), 11 + (corner >> 2));
        around += r.albedo[4 * voxelIndex(16, c) + 3] == 255;
    }
    EXPECT_EQ(around, 7u);
    EXPECT_EQ(r.albedo[4 * voxelIndex(16, {5, 6, 12}) + 3], 0);
    // The diagonal sliver alone crosses at least max-axis-span voxels (it is a connected path).
    EXPECT_GE(occupied, 16u);
}

TEST_F(Voxelize, TwoRunsAreBitIdentical) {
    makeGrid(unitGrid(16, 0.25f));
    // Many overlapping triangles with different colours and emission, so that the atomics race.
    std::mt19937 rng(1234);
    std::uniform_real_distribution<float> pos(0.0f, 16.0f), off(-2.0f, 2.0f), col(0.0f, 1.0f);
    TestScene scene;
    for (int d = 0; d < 8; ++d) {
        std::vector<Tri> tris;
        for (int i = 0; i < 300; ++i) {
            glm::vec3 a(pos(rng), pos(rng), pos(rng));
            tris.push_back({a, a + glm::vec3(off(rng), off(rng), off(rng)), a + glm::vec3(off(rng), off(rng), off(rng))});
        }
        scene.addDraw(tris, scene.addMaterial(glm::vec3(col(rng), col(rng), col(rng)),
                                              glm::vec3(3.0f * col(rng), 0.0f, col(rng))));
    }
    upload(scene);
    voxelizeAll();
    Readback first = read();
    voxelizeAll();
    Readback second = read();
    EXPECT_TRUE(first.albedo == second.albedo);
    EXPECT_TRUE(first.normal == second.normal);
    EXPECT_TRUE(first.emission == second.emission);
    uint32_t occupied = 0;
    for (size_t i = 3; i < first.albedo.size(); i += 4)
        occupied += first.albedo[i] == 255;
    EXPECT_GT(occupied, 1000u); // the races actually happened: 2400 triangles over 4096 voxels
}

TEST_F(Voxelize, OneVoxelAveragesAlbedoNormalAndEmission) {
    makeGrid(unitGrid(16, 0.5f));
    TestScene scene;
    // Two sub-voxel triangles inside voxel (5, 6, 7): a red one facing +x and an emissive blue
    // one facing +y, plus a third (white, facing +z) counted twice through a second draw.
    glm::vec3 o(5.2f, 6.2f, 7.2f);
    Tri facingX{o, o + glm::vec3(0.0f, 0.5f, 0.0f), o + glm::vec3(0.0f, 0.0f, 0.5f)};
    Tri facingY{o, o + glm::vec3(0.0f, 0.0f, 0.5f), o + glm::vec3(0.5f, 0.0f, 0.0f)};
    scene.addDraw({facingX}, scene.addMaterial(glm::vec3(1.0f, 0.0f, 0.0f)));
    scene.addDraw({facingY}, scene.addMaterial(glm::vec3(0.0f, 0.0f, 1.0f), glm::vec3(1.5f, 0.0f, 0.25f)));
    upload(scene);
    voxelizeAll();
    Readback r = read();
    size_t i = voxelIndex(16, {5, 6, 7});
    // Means of two contributions; RGBA8 quantisation is 1/255, so 0.5 reads as 127 or 128.
    EXPECT_NEAR(r.albedo[4 * i + 0], 127.5, 0.51);
    EXPECT_EQ(r.albedo[4 * i + 1], 0);
    EXPECT_NEAR(r.albedo[4 * i + 2], 127.5, 0.51);
    EXPECT_EQ(r.albedo[4 * i + 3], 255);
    // Normal: normalize(+x + +y) = (0.7071, 0.7071, 0), encoded as n * 0.5 + 0.5.
    EXPECT_NEAR(r.normal[4 * i + 0] / 255.0, 0.5 + 0.5 * std::sqrt(0.5), 1.0 / 255.0);
    EXPECT_NEAR(r.normal[4 * i + 1] / 255.0, 0.5 + 0.5 * std::sqrt(0.5), 1.0 / 255.0);
    EXPECT_NEAR(r.normal[4 * i + 2] / 255.0, 0.5, 1.0 / 255.0);
    // Emission: mean of (0,0,0) and (1.5, 0, 0.25), times radianceScale 0.5 -> (0.375, 0, 0.0625),
    // exact in fixed point and in half float.
    const auto* e = reinterpret_cast<const uint16_t*>(r.emission.data());
    EXPECT_EQ(halfToFloat(e[4 * i + 0]), 0.375f);
    EXPECT_EQ(halfToFloat(e[4 * i + 1]), 0.0f);
    EXPECT_EQ(halfToFloat(e[4 * i + 2]), 0.0625f);
    // Only that voxel is occupied.
    uint32_t occupied = 0;
    for (size_t k = 3; k < r.albedo.size(); k += 4)
        occupied += r.albedo[k] == 255;
    EXPECT_EQ(occupied, 1u);
}

TEST_F(Voxelize, DynamicObjectLeavesNoStaleVoxelsAndNeverTouchesStatic) {
    makeGrid(unitGrid(16));
    TestScene scene;
    // Static: a white quad-ish triangle in the plane z = 8.5 around (2..6, 2..6).
    std::vector<Tri> floor = {{{2.1f, 2.1f, 8.5f}, {6.9f, 2.1f, 8.5f}, {2.1f, 6.9f, 8.5f}}};
    scene.addDraw(floor, scene.addMaterial(glm::vec3(1.0f)));
    // Dynamic: a small red triangle inside voxel (3, 3, 8) (overlapping static) and beyond.
    std::vector<Tri> mover = {{{0.2f, 0.2f, 0.4f}, {1.7f, 0.3f, 0.5f}, {0.3f, 0.6f, 0.6f}}};
    uint32_t red = scene.addMaterial(glm::vec3(1.0f, 0.0f, 0.0f));
    scene.addDraw(mover, red, true, glm::translate(glm::mat4(1.0f), glm::vec3(3.0f, 3.0f, 8.0f)));
    upload(scene);
    voxelizeAll();
    Readback a = read();
    // The static voxel keeps its static (white) value although the red mover overlaps it.
    size_t shared = voxelIndex(16, {3, 3, 8});
    EXPECT_EQ(a.albedo[4 * shared + 0], 255);
    EXPECT_EQ(a.albedo[4 * shared + 1], 255);
    // Move the mover off the floor's footprint, to voxels (10..11, 10, 3).
    scene.instances[1].model = glm::translate(glm::mat4(1.0f), glm::vec3(10.0f, 10.0f, 3.0f));
    scene.instances[1].normalModel = glm::transpose(glm::inverse(scene.instances[1].model));
    upload(scene);
    updateDynamic();
    Readback b = read();
    size_t moved0 = voxelIndex(16, {10, 10, 3}), moved1 = voxelIndex(16, {11, 10, 3});
    EXPECT_EQ(b.albedo[4 * moved0 + 3], 255);
    EXPECT_EQ(b.albedo[4 * moved1 + 3], 255);
    EXPECT_EQ(b.albedo[4 * moved0 + 0], 255);
    EXPECT_EQ(b.albedo[4 * moved0 + 1], 0);
    // Moved again: the previous position must be empty, the static floor unchanged.
    scene.instances[1].model = glm::translate(glm::mat4(1.0f), glm::vec3(10.0f, 1.0f, 12.0f));
    upload(scene);
    updateDynamic();
    Readback c = read();
    EXPECT_EQ(c.albedo[4 * moved0 + 3], 0);
    EXPECT_EQ(c.albedo[4 * moved1 + 3], 0);
    EXPECT_EQ(c.albedo[4 * voxelIndex(16, {10, 1, 12}) + 3], 255);
    // Everything that is not the mover equals the static bake, voxel for voxel.
    Readback s{readbackImage(ctx(), m_grid->staticVolumes().albedo.image, VK_IMAGE_LAYOUT_GENERAL), {}, {}, {}};
    std::vector<uint8_t> mustMover, mayMover;
    std::vector<Tri> placed = {{mover[0].a + glm::vec3(10, 1, 12), mover[0].b + glm::vec3(10, 1, 12),
                                mover[0].c + glm::vec3(10, 1, 12)}};
    referenceSets(placed, 16, 1e-3f, mustMover, mayMover);
    uint32_t differing = 0;
    for (size_t k = 0; k < mayMover.size(); ++k)
        if (!mayMover[k])
            differing += std::memcmp(&c.albedo[4 * k], &s.albedo[4 * k], 4) != 0;
    EXPECT_EQ(differing, 0u);
}

namespace {

// The touched list of `set` (gi/voxel_passes.h) as voxel indices, checking its header.
std::vector<size_t> touchedVoxels(Context& ctx, const VoxelGrid& grid, VoxelDrawSet set) {
    std::vector<uint8_t> bytes = readbackBuffer(ctx, grid.touched(set));
    std::vector<uint32_t> words(bytes.size() / 4);
    std::memcpy(words.data(), bytes.data(), words.size() * 4);
    uint32_t count = words[3];
    EXPECT_EQ(words[0], (count + GI_VOXEL_LIST_GROUP - 1) / GI_VOXEL_LIST_GROUP) << "dispatch x";
    EXPECT_EQ(words[1], 1u);
    EXPECT_EQ(words[2], 1u);
    std::vector<size_t> out;
    for (uint32_t i = 0; i < count; ++i) {
        uint32_t v = words[GI_VOXEL_TOUCHED_HEADER + i];
        out.push_back(voxelIndex(grid.resolution(), glm::uvec3(v & 1023u, (v >> 10) & 1023u, v >> 20)));
    }
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<size_t> occupiedVoxels(const std::vector<uint8_t>& albedo) {
    std::vector<size_t> out;
    for (size_t i = 0; 4 * i + 3 < albedo.size(); ++i)
        if (albedo[4 * i + 3] == 255)
            out.push_back(i);
    return out;
}

} // namespace

// The resolve and the VCT list run over the touched list instead of N^3: it must hold every
// occupied voxel exactly once, and nothing else.
TEST_F(Voxelize, TouchedListHoldsEachOccupiedVoxelOnce) {
    makeGrid(unitGrid(16));
    std::mt19937 rng(77);
    std::uniform_real_distribution<float> pos(0.0f, 16.0f), off(-3.0f, 3.0f);
    TestScene scene;
    std::vector<Tri> tris;
    for (int i = 0; i < 200; ++i) { // overlapping: many voxels get several first-touch candidates
        glm::vec3 a(pos(rng), pos(rng), pos(rng));
        tris.push_back({a, a + glm::vec3(off(rng), off(rng), off(rng)), a + glm::vec3(off(rng), off(rng), off(rng))});
    }
    scene.addDraw(tris, scene.addMaterial(glm::vec3(0.5f)));
    scene.addDraw(tris, scene.addMaterial(glm::vec3(0.25f))); // the same voxels again, another dispatch
    upload(scene);
    voxelizeAll();
    std::vector<size_t> listed = touchedVoxels(ctx(), *m_grid, VoxelDrawSet::All);
    std::vector<size_t> occupied = occupiedVoxels(read().albedo);
    EXPECT_GT(occupied.size(), 500u);
    EXPECT_TRUE(std::adjacent_find(listed.begin(), listed.end()) == listed.end()) << "a voxel listed twice";
    EXPECT_TRUE(listed == occupied) << listed.size() << " listed, " << occupied.size() << " occupied";
}

// A mover voxelized over many frames, across and off the static voxels, leaves exactly what a
// fresh voxelization of its last placement gives (all four volumes, bit for bit): the grid
// starts each frame as a copy of the static volumes and only the mover's voxels are written.
TEST_F(Voxelize, ManyFramesOfAMovingObjectEqualAFreshVoxelization) {
    TestScene scene;
    std::vector<Tri> floor = {{{1.1f, 1.1f, 8.5f}, {14.9f, 1.1f, 8.5f}, {1.1f, 14.9f, 8.5f}},
                              {{14.9f, 1.1f, 8.5f}, {14.9f, 14.9f, 8.5f}, {1.1f, 14.9f, 8.5f}}};
    scene.addDraw(floor, scene.addMaterial(glm::vec3(0.9f, 0.8f, 0.7f)));
    // A tilted emissive triangle about two voxels wide.
    std::vector<Tri> mover = {{{0.1f, 0.2f, 0.3f}, {2.3f, 0.4f, 1.1f}, {0.6f, 2.2f, 1.7f}}};
    uint32_t material = scene.addMaterial(glm::vec3(0.2f, 0.6f, 0.3f), glm::vec3(0.5f, 0.25f, 0.0f));
    scene.addDraw(mover, material, true, glm::mat4(1.0f));
    auto place = [&](glm::vec3 t) {
        scene.instances[1].model = glm::translate(glm::mat4(1.0f), t);
        scene.instances[1].normalModel = glm::transpose(glm::inverse(scene.instances[1].model));
        upload(scene);
    };
    auto readAll = [&] {
        Readback r = read();
        r.accum = readbackImage(ctx(), m_grid->volumes().faces.image, VK_IMAGE_LAYOUT_GENERAL);
        return r;
    };
    makeGrid(unitGrid(16, 0.5f));
    place(glm::vec3(3.0f, 3.0f, 7.6f));
    voxelizeAll();
    // Through the floor, beside it, over the grid's edge, and back into the floor.
    const glm::vec3 path[] = {{4.0f, 3.5f, 7.9f}, {6.0f, 5.0f, 8.2f}, {9.5f, 9.0f, 4.0f}, {13.2f, 13.5f, 14.0f},
                              {14.5f, 2.0f, 8.0f}, {2.0f, 12.0f, 0.1f}, {7.3f, 7.7f, 7.7f}, {7.4f, 7.6f, 8.1f}};
    for (glm::vec3 t : path) {
        place(t);
        updateDynamic();
    }
    Readback moved = readAll();
    std::vector<size_t> dynamicListed = touchedVoxels(ctx(), *m_grid, VoxelDrawSet::Dynamic);
    makeGrid(unitGrid(16, 0.5f));
    voxelizeAll(); // the mover still at the last placement
    Readback fresh = readAll();
    EXPECT_TRUE(moved.albedo == fresh.albedo);
    EXPECT_TRUE(moved.normal == fresh.normal);
    EXPECT_TRUE(moved.emission == fresh.emission);
    EXPECT_TRUE(moved.accum == fresh.accum) << "faces";
    // The last placement overlaps the floor: it has voxels of its own and voxels the floor keeps.
    std::vector<size_t> mine = occupiedVoxels(moved.albedo);
    Readback floorOnly{readbackImage(ctx(), m_grid->staticVolumes().albedo.image, VK_IMAGE_LAYOUT_GENERAL), {}, {}, {}};
    size_t outside = 0, inside = 0;
    for (size_t i : dynamicListed)
        (floorOnly.albedo[4 * i + 3] == 255 ? inside : outside)++;
    EXPECT_GT(outside, 0u);
    EXPECT_GT(inside, 0u);
    EXPECT_EQ(mine.size(), occupiedVoxels(floorOnly.albedo).size() + outside);
}

// Re-voxelizing into volumes that hold an earlier voxelization clears only the earlier touched
// voxels the new one leaves out (the accumulation is zeroed by the resolve, not by a clear):
// after static objects and a mover went through several placements, with static re-bakes
// (Full) between dynamic updates, the grid and the static volumes equal a fresh voxelization
// bit for bit, in a scene without dynamic draws and in one with.
TEST_F(Voxelize, RevoxelizingEqualsAFreshVoxelization) {
    std::vector<Tri> floor = {{{1.1f, 1.1f, 8.5f}, {14.9f, 1.1f, 8.5f}, {1.1f, 14.9f, 8.5f}},
                              {{14.9f, 1.1f, 8.5f}, {14.9f, 14.9f, 8.5f}, {1.1f, 14.9f, 8.5f}}};
    std::vector<Tri> mover = {{{0.1f, 0.2f, 0.3f}, {2.3f, 0.4f, 1.1f}, {0.6f, 2.2f, 1.7f}}};
    const glm::vec3 path[] = {{4.0f, 3.5f, 7.9f}, {6.0f, 5.0f, 8.2f}, {9.5f, 9.0f, 4.0f}, {13.2f, 13.5f, 14.0f},
                              {14.5f, 2.0f, 8.0f}, {2.0f, 12.0f, 0.1f}, {7.3f, 7.7f, 7.7f}, {7.4f, 7.6f, 8.1f}};
    auto readAll = [&](const VoxelVolumes& v) { // each image in the layout the last graph left it in
        auto one = [&](const rg::PersistentImage& i) { return readbackImage(ctx(), i.image, i.state[0].layout); };
        return Readback{one(v.albedo), one(v.normal), one(v.emission), one(v.faces)};
    };
    auto expectEqual = [](const Readback& a, const Readback& b, const char* what) {
        EXPECT_TRUE(a.albedo == b.albedo) << what << " albedo";
        EXPECT_TRUE(a.normal == b.normal) << what << " normal";
        EXPECT_TRUE(a.emission == b.emission) << what << " emission";
        EXPECT_TRUE(a.accum == b.accum) << what << " faces";
    };
    for (bool dynamicMover : {false, true}) {
        SCOPED_TRACE(dynamicMover ? "dynamic mover" : "static scene");
        TestScene scene;
        scene.addDraw(floor, scene.addMaterial(glm::vec3(0.9f, 0.8f, 0.7f)));
        scene.addDraw(mover, scene.addMaterial(glm::vec3(0.2f, 0.6f, 0.3f), glm::vec3(0.5f, 0.25f, 0.0f)),
                      dynamicMover);
        auto place = [&](uint32_t instance, glm::vec3 t) {
            scene.instances[instance].model = glm::translate(glm::mat4(1.0f), t);
            scene.instances[instance].normalModel = glm::transpose(glm::inverse(scene.instances[instance].model));
            upload(scene);
        };
        makeGrid(unitGrid(16, 0.5f));
        place(1, glm::vec3(3.0f, 3.0f, 7.6f));
        voxelizeAll();
        for (int i = 0; i < 8; ++i) {
            place(1, path[i]);
            if (!dynamicMover || i % 3 == 1) {
                // The floor moves too (a static change: the static volumes are re-baked).
                place(0, glm::vec3(0.0f, 0.0f, 0.37f * float(i % 4) - 0.6f));
                voxelizeAll();
            } else {
                updateDynamic();
            }
        }
        Readback grid = readAll(m_grid->volumes()), statics;
        if (dynamicMover)
            statics = readAll(m_grid->staticVolumes());
        std::vector<size_t> listed = touchedVoxels(ctx(), *m_grid, VoxelDrawSet::All);
        makeGrid(unitGrid(16, 0.5f));
        voxelizeAll(); // the last placements
        expectEqual(grid, readAll(m_grid->volumes()), "grid");
        if (dynamicMover)
            expectEqual(statics, readAll(m_grid->staticVolumes()), "static volumes");
        EXPECT_TRUE(listed == touchedVoxels(ctx(), *m_grid, VoxelDrawSet::All));
        EXPECT_GT(occupiedVoxels(grid.albedo).size(), 200u); // the floor (14^2) and the mover
    }
}

// A frame graph that is built but never run (a failed compile) leaves the grid's bookkeeping
// as it was: the next voxelization still clears what the last executed one wrote.
TEST_F(Voxelize, AGraphThatNeverRunsChangesNothing) {
    std::vector<Tri> a = {{{1.3f, 1.2f, 3.5f}, {14.6f, 2.1f, 3.5f}, {2.2f, 13.9f, 3.5f}}};
    std::vector<Tri> b = {{{1.3f, 1.2f, 11.5f}, {14.6f, 2.1f, 11.5f}, {2.2f, 13.9f, 11.5f}}};
    std::vector<Tri> c = {{{1.3f, 7.2f, 7.5f}, {4.6f, 7.1f, 7.5f}, {2.2f, 9.9f, 7.5f}}};
    TestScene sceneA, sceneB, sceneC;
    sceneA.addDraw(a, sceneA.addMaterial(glm::vec3(0.9f, 0.8f, 0.7f)));
    sceneB.addDraw(b, sceneB.addMaterial(glm::vec3(0.9f, 0.8f, 0.7f)));
    sceneC.addDraw(c, sceneC.addMaterial(glm::vec3(0.9f, 0.8f, 0.7f)));
    makeGrid(unitGrid(16));
    upload(sceneC);
    voxelizeAll();
    upload(sceneA);
    voxelizeAll(); // the touched lists (used in turn) hold C's and A's voxels
    upload(sceneB);
    {   // built, never compiled or run
        rg::RenderGraph unused;
        addVoxelGridPasses(unused, *m_grid, importScene(unused, m_buf, m_scene.draws), VoxelUpdate::Full);
    }
    voxelizeAll();
    std::vector<uint8_t> moved = read().albedo;
    makeGrid(unitGrid(16));
    voxelizeAll();
    EXPECT_TRUE(moved == read().albedo) << "voxels of the first placement left in the grid";
}
