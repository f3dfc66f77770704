#version 460
#extension GL_GOOGLE_include_directive : require
// Second bounce, apply half: each occupied voxel with a normal gets B = albedo * E / pi, with
// E / pi = (1/n) sum L_i from the gather of its block and normal class (voxel_bounce.comp),
// interpolated between neighbouring blocks (below), or, for a misfit voxel, from its own gather
// (voxel_bounce_misfits.comp, which ran before and stored B in the bounce volume). B joins the
// level-0 views that see faces on the normal's side (faces looking towards d with
// d . normal > 0), weighted as the voxel light weights its own radiance there (opacity * shown
// share, voxel_light_body.glsl), so view texel rgb = a s (L + B): the per-pixel gather then sees
// emission + one bounce + two bounces. A third bounce gathers again over that radiance, which
// gives B' = albedo * E(L + B) / pi = B + B3 (the gather is linear in the radiance and its
// opacities did not change), and adds B' - B, B read back from the bounce volume the second
// bounce's apply stored: level 0 then holds a s (L + B + B3). A voxel without a normal (both
// faces of a thin wall or slab in one voxel) takes one B per side (voxelSides) from its side's
// face class, into the view that sees that side's faces, as the voxel light lights them with
// the axis. Reads and writes only its own voxel's texels.
#extension GL_EXT_control_flow_attributes : require
#include "gi/vct_passes.h"

layout(local_size_x = GI_VOXEL_LIST_GROUP) in; // one invocation per occupied voxel (indirect)
layout(push_constant) uniform Push { VoxelApplyPush pc; };
layout(set = 1, binding = VCT_APPLY_BINDING_ALBEDO, rgba8) uniform readonly image3D albedoVol;
layout(set = 1, binding = VCT_APPLY_BINDING_NORMAL, rgba8) uniform readonly image3D normalVol;
layout(set = 1, binding = VCT_APPLY_BINDING_JOBS, std430) readonly buffer Jobs { uint header[GI_BOUNCE_HEADER]; uint words[]; };
layout(set = 1, binding = VCT_APPLY_BINDING_MISFITS, rgba16f) uniform readonly image3D misfitBounce;
layout(set = 1, binding = VCT_APPLY_BINDING_LIST, std430) readonly buffer List { uint listHeader[GI_VOXEL_LIST_HEADER]; uint entries[]; };
layout(set = 1, binding = VCT_APPLY_BINDING_RESULTS, std430) readonly buffer Results { uint results[]; };
layout(set = 1, binding = VCT_APPLY_BINDING_FACES, r32ui) uniform readonly uimage3D facesVol;
layout(set = 1, binding = VCT_APPLY_BINDING_DIRECTIONAL, rgba16f) uniform image2DArray directionalLevel0;
layout(set = 1, binding = VCT_APPLY_BINDING_KEPT, rgba32ui) uniform readonly uimage3D keptBounce;
layout(set = 1, binding = VCT_APPLY_BINDING_BOUNCE, rgba32ui) uniform uimage3D bounceOut;
#define VOXEL_BLOCK_FACES
#include "voxel_block.glsl"

// E / pi of voxel c's class k: the class's gathers at the centres of the nearest blocks, along
// the surface (below).
vec3 classGather(ivec3 c, uint k, uint n, uint side) {
    // Bilinear (linear for an edge class, none for a corner) over the gathers of class k at
    // the centres of the nearest blocks along the axes the class direction lies across, i.e.
    // along the surface, never across it (a floor under a table top takes nothing of the
    // top's gather). Blocks without class k are left out and the weights renormalised; the
    // voxel's own block always weighs at least 5/8 per axis. Fixed order: deterministic.
    uint kk = k < 13u ? k : k + 1u;
    bvec3 along = equal(ivec3(kk % 3u, (kk / 3u) % 3u, kk / 9u), ivec3(1)); // class direction component 0
    vec3 f = (vec3(c) + 0.5) / float(bounceBlockSide(n)) - 0.5;
    ivec3 own = c / int(bounceBlockSide(n));
    ivec3 base = mix(own, ivec3(floor(f)), along);
    vec3 w = mix(vec3(0.0), f - floor(f), along);
    vec3 e = vec3(0.0);
    float weights = 0.0;
    [[unroll]] for (int i = 0; i < 8; ++i) {
        ivec3 corner = ivec3(i & 1, (i >> 1) & 1, i >> 2);
        vec3 cw = mix(1.0 - w, w, vec3(corner));
        float weight = cw.x * cw.y * cw.z;
        ivec3 q = base + corner;
        if (weight == 0.0 || any(lessThan(q, ivec3(0))) || any(greaterThanEqual(q, ivec3(side))))
            continue;
        uint qb = uint(q.x) + side * (uint(q.y) + side * uint(q.z));
        if ((words[qb] & (1u << k)) == 0u)
            continue;
        uint r = 2u * (GI_BOUNCE_CLASSES * qb + k);
        e += weight * vec3(unpackHalf2x16(results[r]), unpackHalf2x16(results[r + 1u]).x);
        weights += weight;
    }
    return weights > 0.0 ? e / weights : vec3(0.0);
}

// The stored bounce of a voxel's side (voxelSides, up to four per voxel, one word each): the
// shared-exponent rgb9e5 of VK_FORMAT_E5B9G9R9_UFLOAT_PACK32 (9-bit mantissas, about 0.2%).
uint packRgb9e5(vec3 c) {
    c = clamp(c, vec3(0.0), vec3(65408.0)); // 511/512 * 2^16, the largest value
    float m = max(c.r, max(c.g, c.b));
    if (m < 1e-20)
        return 0u;
    int e = max(-16, (floatBitsToInt(m) >> 23) - 127) + 16; // floor(log2 m) + 1 + bias 15
    float unit = exp2(float(e - 24));
    if (floor(m / unit + 0.5) >= 512.0) {
        e += 1;
        unit *= 2.0;
    }
    uvec3 q = uvec3(min(floor(c / unit + 0.5), vec3(511.0)));
    return q.r | (q.g << 9u) | (q.b << 18u) | (uint(e) << 27u);
}
vec3 unpackRgb9e5(uint w) {
    return vec3(uvec3(w, w >> 9u, w >> 18u) & 511u) * exp2(float(int(w >> 27u) - 24));
}

// A voxel's bounce as stored: rgb as float bits for a voxel with a normal; for a voxel without
// one, its sides' bounces (rgb9e5) in the order of their directions d.

void main() {
    if (gl_GlobalInvocationID.x >= listHeader[3])
        return;
    uint n = pc.grid.dims.x, side = n / bounceBlockSide(n);
    ivec3 c = ivec3(voxelListUnpack(entries[gl_GlobalInvocationID.x]));
    vec3 normal;
    uint k;
    bool store = (pc.keepHi.w & GI_VCT_APPLY_STORE) != 0, addedOnly = (pc.keepHi.w & GI_VCT_APPLY_ADDED) != 0;
    // A moved clipmap level's kept voxel: its bounce of before the move (docs/vct.md "Clipmap").
    bool kept = all(greaterThanEqual(c, pc.keepLo.xyz)) && all(lessThanEqual(c, pc.keepHi.xyz));
    uint faces = imageLoad(facesVol, c).x;
    if (!voxelNormalOf(c, normal, k)) {
        // No hemisphere of its own: each side gathers with its axis's face class, and its bounce
        // joins the one view that sees that side's faces (voxelSides).
        uint sides = voxelSides(c);
        uvec4 keptWords = kept ? imageLoad(keptBounce, c) : uvec4(0u);
        uvec4 storedWords = addedOnly ? imageLoad(bounceOut, c) : uvec4(0u);
        uvec4 words4 = uvec4(0u);
        vec3 albedo = imageLoad(albedoVol, c).rgb;
        uint slot = 0u;
        [[unroll]] for (uint d = 0u; d < GI_VCT_DIRECTIONS; ++d) {
            if ((sides & (1u << d)) == 0u)
                continue;
            vec3 bd = kept ? unpackRgb9e5(keptWords[slot])
                           : albedo * classGather(c, voxelNormalClass(voxelSideInt(d)), n, side);
            words4[slot] = packRgb9e5(bd);
            bd = unpackRgb9e5(words4[slot]); // what is stored is what level 0 holds
            vec3 added = addedOnly ? bd - unpackRgb9e5(storedWords[slot]) : bd;
            ++slot;
            uint v = d ^ 1u; // the view of a ray travelling towards the side's faces
            float front = voxelFaceCoverage(faces, d);
            float axisCover = voxelFaceCoverage(faces, d & ~1u) + voxelFaceCoverage(faces, d | 1u);
            float shown = min(1.0, 2.0 * front / axisCover);
            ivec3 t = vctDirectionalTexel(c, v, n);
            vec4 texel = imageLoad(directionalLevel0, t);
            texel.rgb = clamp(texel.rgb + added * (texel.a * shown), vec3(0.0), vec3(65000.0));
            imageStore(directionalLevel0, t, texel);
        }
        if (store)
            imageStore(bounceOut, c, words4);
        return;
    }
    vec3 b;
    uvec2 bit = bounceMisfitBit(uvec3(c), n);
    if (kept) {
        b = uintBitsToFloat(imageLoad(keptBounce, c).rgb);
    } else if ((words[bounceMisfitBitsOffset(n) + bit.x] & (1u << bit.y)) != 0u) {
        b = imageLoad(misfitBounce, c).rgb;
    } else {
        b = imageLoad(albedoVol, c).rgb * classGather(c, k, n, side);
    }
    // Level 0 already holds the stored bounce (a third bounce): add what this one adds to it.
    vec3 added = addedOnly ? b - uintBitsToFloat(imageLoad(bounceOut, c).rgb) : b;
    if (store)
        imageStore(bounceOut, c, uvec4(floatBitsToUint(b), 0u));
    if (added == vec3(0.0))
        return;
    [[unroll]] for (uint v = 0u; v < GI_VCT_DIRECTIONS; ++v) {
        uint d = v ^ 1u; // the faces a ray travelling along v sees look towards v ^ 1
        float towards = (d & 1u) == 0u ? normal[d >> 1u] : -normal[d >> 1u];
        float front = voxelFaceCoverage(faces, d);
        if (towards <= 0.0 || front == 0.0)
            continue;
        float axisCover = voxelFaceCoverage(faces, 2u * (v >> 1u)) + voxelFaceCoverage(faces, 2u * (v >> 1u) + 1u);
        float shown = min(1.0, 2.0 * front / axisCover);
        ivec3 t = vctDirectionalTexel(c, v, n);
        vec4 texel = imageLoad(directionalLevel0, t);
        texel.rgb = clamp(texel.rgb + added * (texel.a * shown), vec3(0.0), vec3(65000.0));
        imageStore(directionalLevel0, t, texel);
    }
}
