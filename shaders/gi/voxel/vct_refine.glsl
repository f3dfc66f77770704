// Which full-resolution pixels the VCT refine traces (vct_upsample.comp decides and lists them,
// vct_trace_refine.comp traces them). The includer declares push constants `pc` (VctTracePush);
// vctRefines also needs the storage images gPosition (rgba32f) and gNormal (rgba16f) and
// gi/lowres_upsample.h with GI_LOWRES_GBUFFER_FETCH = imageLoad (the upsample).

// Reach of the first cone samples in voxels (lowResFitTaps): a cone starts one voxel off the
// surface and takes its first sample one voxel along itself, a footprint one voxel wide.
// Cornell 256^2, 64^3: 4917 refined pixels against lowResTaps' 7097, 2675 of them traced
// (quad sharing below), relMSE unchanged to 1% (docs/vct.md).
const float kUpsampleReach = 2.0;
// How far (voxels) a refined pixel may be from the pixel whose trace it takes (vctSameSpot).
const float kQuadReach = 0.5;

#ifdef VKGI_GI_LOWRES_UPSAMPLE_H
// Whether pixel px (not background: position.w != 0) needs a full-resolution trace; the
// interpolation taps and weights otherwise.
bool vctRefines(ivec2 px, vec4 position, vec3 n, out ivec2 taps[4], out vec4 w) {
    float depth = distance(position.xyz, pc.eye.xyz);
    return lowResFitTaps(px, position.xyz, n, depth, int(pc.lowRes.x), ivec2(pc.lowRes.yz), ivec2(pc.cones.info.zw),
                         pc.eye.w, pc.grid.originSize.w, kUpsampleReach, taps, w);
}
#endif

// Refined pixels of a 2x2 quad share traces: in quad order, a refined pixel takes the trace of
// the first traced pixel before it that lies on its surface within half a voxel of it (normal
// within the threshold), else it is traced itself. Near a concave corner, where most refined
// pixels are, the gather changes over the 2 voxels its first samples reach; a cone origin moved
// by half a voxel moves the first sample by under half of its footprint. At 256^2 on the
// Cornell box a pixel is 0.3 voxels wide.
bool vctSameSpot(vec4 pa, vec3 na, vec4 pb, vec3 nb) {
    return 1.0 - dot(na, nb) <= pc.eye.w && distance(pa.xyz, pb.xyz) <= kQuadReach * pc.grid.originSize.w;
}

// Refine list entry: quad (x, y < 2^13: frames are at most 16384 pixels a side), the traced
// pixel's index k in the quad (x = k & 1, y = k >> 1) and the mask of the quad's pixels its
// trace writes (bit k included).
uint vctRefineEntry(ivec2 quad, uint k, uint serves) {
    return uint(quad.x) | (uint(quad.y) << 13) | (k << 26) | (serves << 28);
}
ivec2 vctRefineQuad(uint entry) { return ivec2(entry & 0x1fffu, (entry >> 13) & 0x1fffu); }
uint vctRefineIndex(uint entry) { return (entry >> 26) & 3u; }
uint vctRefineServes(uint entry) { return entry >> 28; }
