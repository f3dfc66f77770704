#include "motion.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <glm/gtc/constants.hpp>
#include <glm/gtx/rotate_vector.hpp>

namespace vkgi::view {

namespace {

constexpr glm::vec3 kUp{0.0f, 1.0f, 0.0f};
// Radians per dragged pixel.
constexpr float kRotateRate = 0.005f;
// Never orbit or look closer than this to straight up/down (keeps forward and up independent).
constexpr float kMaxPitchCos = 0.995f;

// Fraction of the way through a closed loop: exactly 0 at t = 0 and t = 1.
float loopPhase(float t) {
    float f = t - std::floor(t);
    return f * glm::two_pi<float>();
}

glm::vec3 rotatePitch(const glm::vec3& v, const glm::vec3& forward, float angle) {
    glm::vec3 right = glm::cross(forward, kUp);
    if (glm::length(right) < 1e-6f)
        return v;
    glm::vec3 r = glm::rotate(v, angle, glm::normalize(right));
    glm::vec3 dir = glm::normalize(r);
    return std::abs(glm::dot(dir, kUp)) > kMaxPitchCos ? v : r;
}

} // namespace

CameraController::CameraController(const Camera& initial, const Aabb& bounds) : m_initial(initial), m_camera(initial) {
    if (bounds.valid()) {
        m_boundsCentre = bounds.centre();
        m_sceneSize = std::max(glm::length(bounds.extent()), 1e-3f);
    }
    placeTarget();
}

void CameraController::placeTarget() {
    float depth = glm::dot(m_boundsCentre - m_camera.position, m_camera.forward);
    m_target = m_camera.position + m_camera.forward * std::max(depth, 0.05f * m_sceneSize);
}

void CameraController::reset() {
    m_camera = m_initial;
    placeTarget();
}

void CameraController::setCamera(const Camera& camera) {
    m_camera = camera;
    placeTarget();
}

void CameraController::update(const CameraInput& in) {
    Camera& c = m_camera;
    glm::vec3 right = glm::normalize(glm::cross(c.forward, c.up));
    glm::vec3 up = glm::cross(right, c.forward);
    if (m_mode == Mode::Orbit) {
        if (in.dragLeft != glm::vec2(0.0f)) {
            glm::vec3 offset = c.position - m_target;
            offset = glm::rotate(offset, -in.dragLeft.x * kRotateRate, kUp);
            offset = rotatePitch(offset, -offset, -in.dragLeft.y * kRotateRate);
            c.position = m_target + offset;
            c.forward = glm::normalize(-offset);
        }
        if (in.dragRight != glm::vec2(0.0f)) {
            float scale = glm::length(c.position - m_target) * 0.002f;
            glm::vec3 shift = (-in.dragRight.x * right + in.dragRight.y * up) * scale;
            c.position += shift;
            m_target += shift;
        }
        if (in.scroll != 0.0f) {
            float distance = glm::length(c.position - m_target) * std::pow(0.9f, in.scroll);
            c.position = m_target - c.forward * std::max(distance, 1e-3f * m_sceneSize);
        }
        return;
    }
    if (in.dragLeft != glm::vec2(0.0f) || in.dragRight != glm::vec2(0.0f)) {
        glm::vec2 d = in.dragLeft + in.dragRight;
        c.forward = glm::normalize(glm::rotate(c.forward, -d.x * kRotateRate, kUp));
        c.forward = glm::normalize(rotatePitch(c.forward, c.forward, -d.y * kRotateRate));
    }
    float speed = m_sceneSize * 0.25f * (in.fast ? 4.0f : 1.0f) * in.dt;
    right = glm::normalize(glm::cross(c.forward, c.up));
    c.position += (in.move.x * right + in.move.y * kUp + in.move.z * c.forward) * speed;
    if (in.scroll != 0.0f)
        c.position += c.forward * (in.scroll * 0.05f * m_sceneSize);
    placeTarget();
}

Result<CameraScript> CameraScript::load(const std::string& nameOrFile, const Camera& sceneCamera, const Aabb& bounds) {
    CameraScript s;
    s.m_base = sceneCamera;
    if (nameOrFile == "still")
        return s;
    if (nameOrFile == "orbit") {
        s.m_kind = Kind::Orbit;
        // Vertical axis through the point the camera looks at, at the depth of the bounds centre.
        glm::vec3 centre = bounds.valid() ? bounds.centre() : sceneCamera.position + sceneCamera.forward;
        float depth = std::max(glm::dot(centre - sceneCamera.position, sceneCamera.forward), 1e-3f);
        s.m_pivot = sceneCamera.position + sceneCamera.forward * depth;
        return s;
    }
    std::ifstream in(nameOrFile);
    if (!in)
        return makeError("--camera-script: '" + nameOrFile + "' is neither still, orbit nor a readable file");
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        if (size_t hash = line.find('#'); hash != std::string::npos)
            line.resize(hash);
        std::istringstream fields(line);
        std::vector<float> v;
        std::string word;
        while (fields >> word) {
            char* end = nullptr;
            float f = std::strtof(word.c_str(), &end);
            if (*end || !std::isfinite(f))
                return makeError(nameOrFile + ":" + std::to_string(number) + ": '" + word + "' is not a finite number");
            v.push_back(f);
        }
        if (v.empty())
            continue;
        if (v.size() != 6 && v.size() != 7)
            return makeError(nameOrFile + ":" + std::to_string(number) +
                             ": expected 'px py pz tx ty tz [yfov_degrees]', got " + std::to_string(v.size()) +
                             " numbers");
        Camera c = sceneCamera;
        c.position = {v[0], v[1], v[2]};
        glm::vec3 dir = glm::vec3(v[3], v[4], v[5]) - c.position;
        if (glm::length(dir) < 1e-6f)
            return makeError(nameOrFile + ":" + std::to_string(number) + ": the target equals the position");
        c.forward = glm::normalize(dir);
        if (std::abs(glm::dot(c.forward, glm::normalize(c.up))) > 0.9999f)
            return makeError(nameOrFile + ":" + std::to_string(number) + ": looks straight along the up axis");
        if (v.size() == 7) {
            if (!(v[6] > 0.0f && v[6] < 179.0f))
                return makeError(nameOrFile + ":" + std::to_string(number) + ": yfov must be in (0, 179) degrees");
            c.yfov = glm::radians(v[6]);
        }
        s.m_keys.push_back(c);
    }
    if (s.m_keys.empty())
        return makeError(nameOrFile + ": no keyframes");
    s.m_kind = Kind::Keys;
    return s;
}

Camera CameraScript::at(float t) const {
    switch (m_kind) {
    case Kind::Still:
        return m_base;
    case Kind::Orbit: {
        float angle = loopPhase(t);
        if (angle == 0.0f)
            return m_base;
        Camera c = m_base;
        c.position = m_pivot + glm::rotate(m_base.position - m_pivot, angle, kUp);
        c.forward = glm::rotate(m_base.forward, angle, kUp);
        return c;
    }
    case Kind::Keys:
        break;
    }
    if (m_keys.size() == 1 || t <= 0.0f)
        return m_keys.front();
    if (t >= 1.0f)
        return m_keys.back();
    float x = t * float(m_keys.size() - 1);
    size_t i = size_t(x);
    float f = x - float(i);
    const Camera& a = m_keys[i];
    const Camera& b = m_keys[std::min(i + 1, m_keys.size() - 1)];
    Camera c = a;
    c.position = glm::mix(a.position, b.position, f);
    c.forward = glm::normalize(glm::mix(a.forward, b.forward, f));
    c.yfov = glm::mix(a.yfov, b.yfov, f);
    return c;
}

std::optional<uint32_t> SceneAnimation::pickDynamicInstance(const Scene& scene) {
    std::optional<uint32_t> best;
    float bestSize = 0.0f;
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& inst = scene.instances[i];
        if (inst.dynamic)
            return i;
        const Mesh& mesh = scene.meshes[inst.mesh];
        if (scene.materials[mesh.material].emission != glm::vec3(0.0f))
            continue; // moving an emitter is moving a light: the light controls do that
        Aabb box;
        for (const glm::vec3& p : mesh.positions)
            box.extend(glm::vec3(inst.transform * glm::vec4(p, 1.0f)));
        float size = glm::length(box.extent());
        if (box.valid() && size > 0.0f && (!best || size < bestSize)) {
            best = i;
            bestSize = size;
        }
    }
    return best;
}

Scene SceneAnimation::at(const Scene& base, std::optional<uint32_t> object, float t) {
    Scene s = base;
    float angle = loopPhase(t);
    if (angle == 0.0f)
        return s;
    Aabb bounds = base.bounds();
    float size = bounds.valid() ? glm::length(bounds.extent()) : 1.0f;
    glm::vec3 loop(std::sin(angle), 0.0f, 1.0f - std::cos(angle));
    if (!s.lights.empty() && s.lights[0].type != LightType::Directional)
        s.lights[0].position += loop * (0.08f * size);
    if (object) {
        glm::mat4& m = s.instances[*object].transform;
        m[3] += glm::vec4(loop * (0.05f * size), 0.0f);
    }
    return s;
}

} // namespace vkgi::view
