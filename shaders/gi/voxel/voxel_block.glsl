// Mean normal of a 2^3 block of the grid (voxel_bounce*.comp). The includer declares the
// normal volume `normalVol` (rgba8 image3D; encoded zero normals decode to ~0).

// Sum of the decoded normals of the occupied voxels of block b, normalized; zero when none
// has a normal or they cancel (|sum| < 1/2, as a voxel's own zero-normal test).
vec3 blockNormal(ivec3 b) {
    vec3 sum = vec3(0.0);
    for (int i = 0; i < 8; ++i) {
        vec4 e = imageLoad(normalVol, 2 * b + ivec3(i & 1, (i >> 1) & 1, i >> 2));
        if (e.a > 0.0)
            sum += voxelNormalDecode(e.xyz);
    }
    return dot(sum, sum) > 0.25 ? normalize(sum) : vec3(0.0);
}
