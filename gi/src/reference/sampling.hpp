#pragma once
// Random numbers and warps for the reference path tracer. Every (pixel, sample) pair gets
// its own stream derived by hashing, so results do not depend on scheduling.
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

namespace vkgi::gi::ref {

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.31830988618379067154f;

// SplitMix64 finaliser: a bijective 64-bit mix, good enough to decorrelate adjacent seeds.
inline uint64_t mix64(uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

// PCG32 (O'Neill 2014: 64-bit LCG state, xorshift + random-rotation output), seeded per stream.
class Rng {
public:
    Rng(uint64_t seed, uint64_t pixel, uint64_t sample) {
        uint64_t h = mix64(seed ^ mix64(pixel ^ mix64(sample)));
        m_inc = (mix64(h) << 1u) | 1u; // stream selector must be odd
        m_state = 0;
        nextU32();
        m_state += h;
        nextU32();
    }
    uint32_t nextU32() {
        uint64_t old = m_state;
        m_state = old * 6364136223846793005ull + m_inc;
        uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
        uint32_t rot = uint32_t(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
    }
    // Uniform in [0, 1): 24 random mantissa bits, never rounds up to 1.
    float next() { return float(nextU32() >> 8) * 0x1p-24f; }

private:
    uint64_t m_state = 0;
    uint64_t m_inc = 1;
};

// Orthonormal basis around unit n (Duff et al. 2017, branchless).
inline void basis(const glm::vec3& n, glm::vec3& t, glm::vec3& b) {
    float s = std::copysign(1.0f, n.z);
    float a = -1.0f / (s + n.z);
    float c = n.x * n.y * a;
    t = glm::vec3(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
    b = glm::vec3(c, s + n.y * n.y * a, -n.y);
}

// Cosine-weighted direction around unit n; pdf = dot(n, w) / pi.
inline glm::vec3 sampleCosine(const glm::vec3& n, float u1, float u2) {
    float r = std::sqrt(u1);
    float phi = 2.0f * kPi * u2;
    glm::vec3 t, b;
    basis(n, t, b);
    float z = std::sqrt(std::max(0.0f, 1.0f - u1));
    return glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * b + z * n);
}

// Uniform point on a triangle as barycentric weights of (p1, p2) (p0 gets the rest).
inline glm::vec2 sampleTriangle(float u1, float u2) {
    float s = std::sqrt(u1);
    return {s * (1.0f - u2), s * u2};
}

inline float powerHeuristic(float a, float b) {
    float a2 = a * a, b2 = b * b;
    return a2 + b2 > 0.0f ? a2 / (a2 + b2) : 0.0f;
}

inline float maxComponent(const glm::vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

inline float luminance(const glm::vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

} // namespace vkgi::gi::ref
