// Which full-resolution pixels the VCT refine traces (vct_upsample.comp decides and lists them,
// vct_trace_refine.comp repeats the decision for the pixels a listed one serves). The includer
// declares the storage images gPosition (rgba32f) and gNormal (rgba16f), push constants `pc`
// (VctTracePush) and includes gi/lowres_upsample.h with GI_LOWRES_GBUFFER_FETCH = imageLoad.

// Reach of the first cone samples in voxels (lowResFitTaps): a cone starts one voxel off the
// surface and takes its first sample one voxel along itself, a footprint one voxel wide.
// Cornell 256^2, 64^3: 4917 refined pixels against lowResTaps' 7097, 2675 of them traced
// (vctQuadLeader), relMSE unchanged to 1% (docs/vct.md).
const float kUpsampleReach = 2.0;
// How far (voxels) a refined pixel may be from the pixel whose trace it takes (vctQuadLeader).
const float kQuadReach = 0.5;

// Whether pixel px (not background: position.w != 0) needs a full-resolution trace; the
// interpolation taps and weights otherwise.
bool vctRefines(ivec2 px, vec4 position, vec3 n, out ivec2 taps[4], out vec4 w) {
    float depth = distance(position.xyz, pc.eye.xyz);
    return lowResFitTaps(px, position.xyz, n, depth, int(pc.lowRes.x), ivec2(pc.lowRes.yz), ivec2(pc.cones.info.zw),
                         pc.eye.w, pc.grid.originSize.w, kUpsampleReach, taps, w);
}

// Refined pixels of a 2x2 quad share traces: in quad order, a refined pixel takes the trace of
// the first listed pixel before it that lies on its surface within half a voxel of it (normal
// within the threshold), else it is listed itself. Near a concave corner, where most refined
// pixels are, the gather changes over the 2 voxels its first samples reach; a cone origin moved
// by half a voxel moves the first sample by under half of its footprint. At 256^2 on the
// Cornell box a pixel is 0.3 voxels wide.
bool vctSameSpot(vec4 pa, vec3 na, vec4 pb, vec3 nb) {
    return 1.0 - dot(na, nb) <= pc.eye.w && distance(pa.xyz, pb.xyz) <= kQuadReach * pc.grid.originSize.w;
}

// The pixel whose trace refined pixel q (position pq, normal nq) takes: q itself when q is
// listed.
ivec2 vctQuadLeader(ivec2 q, vec4 pq, vec3 nq) {
    ivec2 base = q & ~1;
    int kq = (q.x & 1) | ((q.y & 1) << 1);
    bool listed[3] = bool[3](false, false, false);
    vec4 pm[3];
    vec3 nm[3];
    for (int k = 0; k < kq; ++k) {
        ivec2 m = base + ivec2(k & 1, k >> 1);
        pm[k] = vec4(0.0);
        nm[k] = vec3(0.0, 0.0, 1.0);
        if (any(greaterThanEqual(m, ivec2(pc.cones.info.zw))))
            continue; // outside the image (odd sizes): not refined, never loaded
        pm[k] = imageLoad(gPosition, m);
        nm[k] = normalize(imageLoad(gNormal, m).xyz);
        ivec2 taps[4];
        vec4 w;
        if (pm[k].w == 0.0 || !vctRefines(m, pm[k], nm[k], taps, w))
            continue;
        bool served = false;
        for (int j = 0; j < k; ++j)
            served = served || (listed[j] && vctSameSpot(pm[k], nm[k], pm[j], nm[j]));
        listed[k] = !served;
    }
    for (int k = 0; k < kq; ++k)
        if (listed[k] && vctSameSpot(pq, nq, pm[k], nm[k]))
            return base + ivec2(k & 1, k >> 1);
    return q;
}
