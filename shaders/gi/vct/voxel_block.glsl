// Normal classes of the second bounce (voxel_bounce*.comp, gi/vct_passes.h). The includer
// declares the normal volume `normalVol` (rgba8 image3D).
//
// Everything that decides which gather a voxel takes is integer arithmetic on the stored bytes,
// so the job pass, the gather and the apply (separate shaders) classify a voxel identically.

// The normal's byte triple as integers 2 b - 255 (the decoded normal times 255).
ivec3 voxelNormalInt(vec4 e) {
    return 2 * ivec3(round(e.xyz * 255.0)) - 255;
}

// Class 0..25 of a normal: the face, edge or corner direction of a cube nearest to it, i.e.
// the signs of the components above tan(22.5 degrees) = 0.414 of the largest one. Within an
// axis plane the classes split at 22.5 and 67.5 degrees; a normal is at most 30 degrees from
// its class direction.
uint voxelNormalClass(ivec3 v) {
    ivec3 a = abs(v);
    int m = max(a.x, max(a.y, a.z));
    ivec3 s = sign(v) * ivec3(greaterThanEqual(1000 * a, ivec3(414 * m)));
    uint k = uint(s.x + 1) + 3u * uint(s.y + 1) + 9u * uint(s.z + 1); // 13 = (0, 0, 0): never
    return k > 13u ? k - 1u : k;
}

// Voxel c's unit normal and class; false when it has none: empty, or its faces' normals cancel
// (decoded |n| < 1/2, e.g. both sides of a thin wall): no hemisphere to gather over.
// v: the normal's integers (voxelNormalInt).
bool voxelNormalOf(ivec3 c, out vec3 normal, out uint k, out ivec3 v) {
    vec4 e = imageLoad(normalVol, c);
    v = voxelNormalInt(e);
    normal = vec3(v) / 255.0;
    k = 0u;
    if (e.a == 0.0 || 4 * (v.x * v.x + v.y * v.y + v.z * v.z) < 255 * 255)
        return false;
    normal = normalize(normal);
    k = voxelNormalClass(v);
    return true;
}
bool voxelNormalOf(ivec3 c, out vec3 normal, out uint k) {
    ivec3 v;
    return voxelNormalOf(c, normal, k, v);
}

#ifdef VOXEL_BLOCK_FACES
// The includer also declares the faces volume `facesVol` (r32ui uimage3D).
// The sides of a voxel without a normal: an occupied voxel whose faces' normals cancel (both
// faces of a thin wall or slab in one voxel, a column thinner than a voxel) has no hemisphere of
// its own, but each face direction d with coverage (0..5: +X, -X, +Y, -Y, +Z, -Z) is a side that
// gathers over the axis hemisphere of e_d, as the voxel light lights those faces with e_d
// (voxel_light_body.glsl). Bit d per side, at most four (the stored bounce holds four: a closed
// object smaller than a voxel bounces on its first four); 0 for a voxel with a normal, or empty.
uint voxelSides(ivec3 c) {
    vec4 e = imageLoad(normalVol, c);
    ivec3 v = voxelNormalInt(e);
    if (e.a == 0.0 || 4 * (v.x * v.x + v.y * v.y + v.z * v.z) >= 255 * 255)
        return 0u;
    uint faces = imageLoad(facesVol, c).x, sides = 0u;
    for (uint d = 0u; d < 6u; ++d)
        sides |= ((faces >> (5u * d)) & 31u) != 0u && bitCount(sides) < 4 ? 1u << d : 0u;
    return sides;
}
#endif

// Side d's normal as the integers a stored axis normal decodes to (a flat floor's (1, 255, 1)):
// the same class, and the same bytes as a face voxel's normal (voxelNormalBytes).
ivec3 voxelSideInt(uint d) {
    ivec3 v = ivec3(1);
    v[d >> 1u] = (d & 1u) == 0u ? 255 : -255;
    return v;
}

// The stored normal's bytes as one uint (r | g << 8 | b << 16), and back to voxelNormalOf's
// normal (the same arithmetic: the same bits).
uint voxelNormalBytes(ivec3 v) {
    uvec3 b = uvec3((v + 255) >> 1);
    return b.x | (b.y << 8u) | (b.z << 16u);
}
vec3 voxelNormalFromBytes(uint b) {
    ivec3 v = 2 * ivec3(b & 255u, (b >> 8u) & 255u, b >> 16u) - 255;
    return normalize(vec3(v) / 255.0);
}

// Floats as uints of the same order (for atomicMax), and back.
uint orderedFromFloat(float f) {
    uint u = floatBitsToUint(f);
    return (u & 0x80000000u) != 0u ? ~u : u | 0x80000000u;
}
float floatFromOrdered(uint u) {
    return uintBitsToFloat((u & 0x80000000u) != 0u ? u & 0x7FFFFFFFu : ~u);
}

// Occupied-list helpers (the includer declares that list's words after its header as `entries`
// and defines VOXEL_BLOCK_LIST; gi/vct_passes.h).
#ifdef VOXEL_BLOCK_LIST
// Whether 4^3 block q (in 4^3-block coordinates) holds an occupied voxel.
bool coarseOccupied(ivec3 q, uint n) {
    uint i = uint(q.x) + n / 4u * (uint(q.y) + n / 4u * uint(q.z));
    return (entries[voxelListCoarseBitsOffset(n) + (i >> 5u)] & (1u << (i & 31u))) != 0u;
}

// Occupancy of the row of 4 voxels c .. c + (3, 0, 0) (c.x a multiple of 4): bit i = voxel c.x + i.
uint rowOccupancy(ivec3 c, uint n) {
    uint i = uint(c.x) + n * (uint(c.y) + n * uint(c.z));
    return (entries[voxelListBitsOffset(n) + (i >> 5u)] >> (i & 31u)) & 15u;
}

// The 4^3 blocks of bounce block q (side / 4 per axis, side = bounceBlockSide), i = 0.. their count.
ivec3 bounceSubBlock(ivec3 q, int i, int sub) {
    return sub * q + ivec3(i % sub, (i / sub) % sub, i / (sub * sub));
}
#endif
