#version 460
#extension GL_GOOGLE_include_directive : require
// Conservative compute voxelization, one invocation or one work group per triangle: every voxel whose interior
// the triangle enters (separating-axis test, so slivers and sub-voxel triangles count too; a
// triangle on a voxel face counts in the voxel behind it only)
// receives the triangle's albedo, its face coverages (max(0, +-n_axis) for the six axis
// directions, which way it faces), emission and, with dims.w = 1 (VCT's pre-filtered opacity),
// its area inside the voxel projected along each axis as fixed-point integer sums. Integer atomics
// make the result independent of the execution order. The contribution that finds a voxel's
// count at 0 sets the voxel's touched bit; voxel_touched_list.comp then lists the set bits in
// the touched list (gi/voxel_passes.h), which the resolve runs over.
#include "engine/scene_types.h"
#include "gi/voxel_passes.h"

// x: the triangles of the draw (one per invocation, or with pc.info.x = 1 one per work group);
// y: slices of each triangle's rows (its voxel columns along the first walked axis),
// gl_NumWorkGroups.y of them: a Cornell wall triangle covers ~2000 voxels at 64^3, and a draw
// of a few such triangles in one work group ran on one CPU thread. With a work group per
// triangle its invocations take turns over the slice's columns: with a triangle per
// invocation, a draw of a few big triangles ran one SIMD lane of eight.
layout(local_size_x = 32) in;
layout(push_constant) uniform Push { VoxelizePush pc; };

layout(set = 1, binding = VOXELIZE_BINDING_VERTICES, std430) readonly buffer Vertices { GpuVertex vertices[]; };
layout(set = 1, binding = VOXELIZE_BINDING_INDICES, std430) readonly buffer Indices { uint indices[]; };
layout(set = 1, binding = VOXELIZE_BINDING_INSTANCES, std430) readonly buffer Instances { GpuInstance instances[]; };
layout(set = 1, binding = VOXELIZE_BINDING_MATERIALS, std430) readonly buffer Materials { GpuMaterial materials[]; };
#define GI_VOXEL_ACC_WORDS
#include "voxel_acc.glsl" // the records (gi/voxel_grid.h)
layout(set = 1, binding = VOXELIZE_BINDING_TOUCHED_BITS, std430) buffer TouchedBits { uint touchedBits[]; }; // bit x + N (y + N z)

// A voxel is set when the triangle enters its interior: the separating-axis tests run on the box
// shrunk by this margin (voxel units), so a triangle that only touches the box's boundary (an
// edge on a voxel face) is separated, whatever the rounding of its coordinates.
const float kSatMargin = 1e-5;
// How far a triangle moves against its normal before the test: see main().
const float kBehindSurface = 1e-3;

// Projection of the three vertices on `axis` against the projected half-extent h of the box.
bool separatedOn(vec3 axis, vec3 v0, vec3 v1, vec3 v2, float h) {
    float p0 = dot(axis, v0), p1 = dot(axis, v1), p2 = dot(axis, v2);
    float r = h * (abs(axis.x) + abs(axis.y) + abs(axis.z));
    return min(p0, min(p1, p2)) > r || max(p0, max(p1, p2)) < -r;
}

// Triangle (vertices relative to the box's centre, voxel units) against the box of half extent
// h: the box axes are the caller's; here the 9 edge cross products and the normal.
bool overlapsBox(vec3 v0, vec3 v1, vec3 v2, vec3 n, float h) {
    // Unrolled: llvmpipe keeps a dynamically indexed array in memory.
    vec3 e0 = v1 - v0, e1 = v2 - v1, e2 = v0 - v2;
    if (separatedOn(vec3(0.0, -e0.z, e0.y), v0, v1, v2, h) || separatedOn(vec3(e0.z, 0.0, -e0.x), v0, v1, v2, h) ||
        separatedOn(vec3(-e0.y, e0.x, 0.0), v0, v1, v2, h) || separatedOn(vec3(0.0, -e1.z, e1.y), v0, v1, v2, h) ||
        separatedOn(vec3(e1.z, 0.0, -e1.x), v0, v1, v2, h) || separatedOn(vec3(-e1.y, e1.x, 0.0), v0, v1, v2, h) ||
        separatedOn(vec3(0.0, -e2.z, e2.y), v0, v1, v2, h) || separatedOn(vec3(e2.z, 0.0, -e2.x), v0, v1, v2, h) ||
        separatedOn(vec3(-e2.y, e2.x, 0.0), v0, v1, v2, h))
        return false;
    float r = h * (abs(n.x) + abs(n.y) + abs(n.z));
    return abs(dot(n, v0)) <= r;
}

// The half-voxel occupancy (dims.z = 1, gi/voxel_grid.h): bit i + 2 j + 4 k for each half-size
// box (i, j, k) of the voxel that the triangle (relative to the voxel's centre, voxel units)
// enters, by the same separating-axis test as the voxel's, on boxes of half extent 0.25 less the
// margin.
uint halfVoxelBits(vec3 v0, vec3 v1, vec3 v2, vec3 n) {
    uint bits = 0u;
    for (uint b = 0u; b < 8u; ++b) {
        vec3 c = vec3(float(b & 1u), float((b >> 1u) & 1u), float((b >> 2u) & 1u)) * 0.5 - 0.25;
        vec3 a0 = v0 - c, a1 = v1 - c, a2 = v2 - c;
        vec3 lo = min(a0, min(a1, a2)), hi = max(a0, max(a1, a2));
        float r = 0.25 - kSatMargin;
        if (any(greaterThanEqual(lo, vec3(r))) || any(lessThanEqual(hi, vec3(-r))) || !overlapsBox(a0, a1, a2, n, r))
            continue;
        bits |= 1u << b;
    }
    return bits;
}

// The grid's dims.w as a specialization constant (voxel_grid.cpp): grids without the fill compile
// the clipping out instead of branching around it.
layout(constant_id = 1) const bool kVoxelFill = false;

// Area of the triangle (relative to the voxel's centre, voxel units) inside the voxel's closed
// box, projected along x, y and z (dims.w = 1, the fill of gi/voxel_grid.h): the triangle clipped
// to the box's six planes (Sutherland-Hodgman; each plane adds at most one vertex, so 9 hold
// the polygon), whose vector area 1/2 sum v_i x v_i+1 has the projected areas as components.
// The box is closed, as in the separating-axis test; a triangle on a face of it was moved
// behind that face first (main()), so it counts in one of the two voxels, as it occupies one.
vec3 projectedAreaInside(vec3 v0, vec3 v1, vec3 v2) {
    vec3 poly[9], next[9];
    poly[0] = v0;
    poly[1] = v1;
    poly[2] = v2;
    int count = 3;
    // Clipping keeps the polygon inside the triangle's bounds: a plane those bounds lie inside
    // of cuts nothing, and is skipped (a triangle inside the voxel is not clipped at all).
    vec3 lo = min(v0, min(v1, v2)), hi = max(v0, max(v1, v2));
    for (int plane = 0; plane < 6 && count >= 3; ++plane) {
        int axis = plane >> 1;
        float side = (plane & 1) == 0 ? 1.0 : -1.0;
        if ((plane & 1) == 0 ? hi[axis] <= 0.5 : lo[axis] >= -0.5)
            continue;
        int kept = 0;
        for (int i = 0; i < count; ++i) {
            vec3 a = poly[i], b = poly[i + 1 < count ? i + 1 : 0];
            float da = 0.5 - side * a[axis], db = 0.5 - side * b[axis];
            if (da >= 0.0)
                next[kept++] = a;
            if ((da >= 0.0) != (db >= 0.0))
                next[kept++] = a + (b - a) * (da / (da - db));
        }
        for (int i = 0; i < kept; ++i)
            poly[i] = next[i];
        count = kept;
    }
    vec3 area = vec3(0.0);
    for (int i = 1; i + 1 < count; ++i)
        area += cross(poly[i] - poly[0], poly[i + 1] - poly[0]);
    return 0.5 * abs(area);
}

uint toFixed(float v) { return uint(clamp(v, 0.0, 1.0) * GI_VOXEL_FIXED_ONE + 0.5); }

void splat(ivec3 c, int n, vec3 albedo, vec3 normal, vec3 emission, bool emissive, uint halves, vec3 area) {
    uint slab = voxelAccSlab(c, uint(n));
    uint rec = GI_VOXEL_ACC_STRIDE * voxelAccRecord(c, uint(n));
    if (halves != 0u)
        voxelAccOr(slab, rec + GI_VOXEL_ACC_COUNT, halves << GI_VOXEL_ACC_COUNT_BITS);
    uint old = voxelAccAdd(slab, rec + GI_VOXEL_ACC_COUNT, 1u) & GI_VOXEL_ACC_COUNT_MASK;
    // The first contribution marks the voxel; voxel_touched_list.comp lists the marks in grid order.
    if (old == 0u) {
        uint i = uint(c.x + n * (c.y + n * c.z));
        atomicOr(touchedBits[i >> 5u], 1u << (i & 31u));
    }
    if (old >= GI_VOXEL_MAX_CONTRIBUTIONS)
        return;
    for (int k = 0; k < 3; ++k) {
        voxelAccAdd(slab, rec + GI_VOXEL_ACC_ALBEDO + k, toFixed(albedo[k]));
        // The face is seen from the side its normal points to: +axis channel for n_k > 0.
        int side = normal[k] > 0.0 ? 0 : 1;
        if (normal[k] != 0.0)
            voxelAccAdd(slab, rec + GI_VOXEL_ACC_FACES + 2 * k + side, toFixed(abs(normal[k])));
        if (emissive)
            voxelAccAdd(slab, rec + GI_VOXEL_ACC_EMISSION + k, toFixed(emission[k]));
        // A clipped triangle's projection lies within the voxel's face: at most 1 each.
        if (area[k] > 0.0)
            voxelAccAdd(slab, rec + GI_VOXEL_ACC_AREA + k, toFixed(area[k]));
    }
}

void main() {
    bool perGroup = pc.info.x != 0u;
    uint tri = perGroup ? gl_WorkGroupID.x : gl_GlobalInvocationID.x;
    int lane = perGroup ? int(gl_LocalInvocationID.x) : 0, lanes = perGroup ? int(gl_WorkGroupSize.x) : 1;
    if (tri >= pc.draw.z)
        return;
    GpuInstance inst = instances[pc.draw.x];
    uint base = pc.draw.y + 3u * tri;
    vec3 p[3];
    vec3 shadingSum = vec3(0.0);
    // World-voxel positions (clipmap levels) subtract no origin but half a voxel: see VoxelizePush.
    vec3 origin = pc.info.y != 0u ? vec3(-0.5 * pc.grid.originSize.w) : pc.grid.originSize.xyz;
    for (int i = 0; i < 3; ++i) {
        GpuVertex v = vertices[indices[base + uint(i)] + pc.draw.w];
        p[i] = ((inst.model * vec4(v.positionU.xyz, 1.0)).xyz - origin) * pc.grid.scales.x;
        shadingSum += v.normalV.xyz;
    }
    GpuMaterial mat = materials[inst.info.x];
    vec3 albedo = mat.baseColor.rgb;
    vec3 emission = mat.emission.rgb * (pc.grid.scales.y / GI_VOXEL_RADIANCE_TARGET);
    bool emissive = any(greaterThan(emission, vec3(0.0)));

    // Face normal, oriented like the authored vertex normals (which carry the facing of
    // double-sided or mirrored geometry). Cross the shortest edge with the next one: for slivers
    // this keeps the normal accurate to a few ulps (crossing the two long edges would cancel
    // catastrophically).
    vec3 e0 = p[1] - p[0], e1 = p[2] - p[1], e2 = p[0] - p[2];
    float l0 = dot(e0, e0), l1 = dot(e1, e1), l2 = dot(e2, e2);
    vec3 n = (l0 <= l1 && l0 <= l2) ? cross(e0, e1) : (l1 <= l2 ? cross(e1, e2) : cross(e2, e0));
    vec3 shading = mat3(inst.normalModel) * shadingSum;
    float len = length(n);
    // Zero-area triangles (points, segments, and slivers thinner than float rounding of their
    // edges: |e_a x e_b| <= 5e-7 (|e0|^2 + |e1|^2 + |e2|^2)) cover nothing for the rasteriser and
    // the path tracer, so they set no voxel either.
    if (!(len > 5e-7 * (l0 + l1 + l2)))
        return;
    vec3 faceNormal = n / len;
    if (dot(faceNormal, shading) < 0.0)
        faceNormal = -faceNormal;
    // A surface lying on a plane between two voxel layers (a floor at y = 0 in world voxels)
    // touches both closed boxes; it belongs to the one behind it. Moved back by 1e-3 voxels (far
    // above the test's margin), it sets one layer, and a closed solid whose faces lie on the lattice sets
    // its own voxels only, not one more layer of free space on each side, which the cones would
    // read as occupied at the surface (docs/vct.md "Voxelization").
    for (int i = 0; i < 3; ++i)
        p[i] -= faceNormal * kBehindSurface;

    int res = int(pc.grid.dims.x);
    // Voxel coordinates below are those of p (world voxels with info.y = 1); the box is the part
    // of the grid voxelized, in the same coordinates.
    ivec3 boxLo = pc.cell.xyz + pc.boxLo.xyz, boxHi = pc.cell.xyz + pc.boxHi.xyz;
    vec3 lo = min(p[0], min(p[1], p[2])), hi = max(p[0], max(p[1], p[2]));
    if (any(isnan(lo + hi)))
        return;
    ivec3 vlo = ivec3(floor(lo + kSatMargin)), vhi = ivec3(ceil(hi - kSatMargin)) - 1;
    // World voxels: a triangle is skipped exactly when none of the voxels it may enter lies in
    // the box, so a voxel on a box face gets the same triangles whichever box held it. A fitted
    // grid keeps its original test (its images are the goldens').
    bool outside = pc.info.y != 0u ? any(greaterThan(vlo, boxHi)) || any(lessThan(vhi, boxLo))
                                   : any(greaterThan(lo, vec3(boxHi + 1))) || any(lessThan(hi, vec3(boxLo)));
    if (outside)
        return;
    vlo = clamp(vlo, boxLo, boxHi);
    vhi = clamp(vhi, boxLo, boxHi);

    // Walk the two axes in which the triangle is widest; along the third (the dominant normal
    // axis) only the voxels between the plane's heights at the column corners can overlap.
    vec3 an = abs(n);
    int k = (an.x >= an.y && an.x >= an.z) ? 0 : (an.y >= an.z ? 1 : 2);
    int u = (k + 1) % 3, w = (k + 2) % 3;
    int rows = (vhi[u] - vlo[u]) / int(gl_NumWorkGroups.y) + 1;
    int cuFirst = vlo[u] + int(gl_GlobalInvocationID.y) * rows;
    int cuLast = min(vhi[u], cuFirst + rows - 1);
    float planeD = dot(n, p[0]);
    // The slice's columns (cu, cw) in order, `lanes` apart, starting at the lane's own.
    int cols = vhi[w] - vlo[w] + 1;
    int count = (cuLast - cuFirst + 1) * cols;
    int cu = cuFirst + lane / cols, cw = vlo[w] + lane % cols;
    int du = lanes / cols, dw = lanes % cols;
    for (int i = lane; i < count; i += lanes) {
        // Plane height along k at the four column corners: k = (d - n_u*u - n_w*w) / n_k.
        float h00 = (planeD - n[u] * float(cu) - n[w] * float(cw)) / n[k];
        float du_ = -n[u] / n[k], dw_ = -n[w] / n[k];
        float hmin = h00 + min(du_, 0.0) + min(dw_, 0.0);
        float hmax = h00 + max(du_, 0.0) + max(dw_, 0.0);
        int k0 = max(vlo[k], int(floor(hmin - 1e-3)));
        int k1 = min(vhi[k], int(floor(hmax + 1e-3)));
        for (int ck = k0; ck <= k1; ++ck) {
            ivec3 c;
            c[k] = ck;
            c[u] = cu;
            c[w] = cw;
            vec3 centre = vec3(c) + 0.5;
            if (overlapsBox(p[0] - centre, p[1] - centre, p[2] - centre, n, 0.5 - kSatMargin))
                splat(c - pc.cell.xyz, res, albedo, faceNormal, emission, emissive,
                      pc.grid.dims.z != 0u ? halfVoxelBits(p[0] - centre, p[1] - centre, p[2] - centre, n) : 0u,
                      kVoxelFill ? projectedAreaInside(p[0] - centre, p[1] - centre, p[2] - centre) : vec3(0.0));
        }
        cw += dw;
        cu += du;
        if (cw > vhi[w]) {
            cw -= cols;
            ++cu;
        }
    }
}
