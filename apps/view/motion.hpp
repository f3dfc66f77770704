#pragma once
// Everything in vkgi-view that moves: the interactive orbit/fly camera, the scripted camera of
// CI runs (built-in paths or a keyframe file) and the scripted light/object animation. Scripted
// motions are functions of t in [0, 1] that return exactly their start state at t = 0 and 1,
// so the last frame of a CI run sees the same camera and scene as vkgi-render.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "vkgi/camera.hpp"
#include "vkgi/result.hpp"
#include "vkgi/scene.hpp"

namespace vkgi::view {

// Input of one frame, already filtered by the UI (no mouse input while ImGui has the mouse).
struct CameraInput {
    glm::vec2 dragLeft{0.0f};  // pixels moved with the left button held
    glm::vec2 dragRight{0.0f}; // pixels moved with the right button held
    float scroll = 0.0f;       // wheel steps
    glm::vec3 move{0.0f};      // fly: x right, y up, z forward, each -1..1
    bool fast = false;
    float dt = 0.0f; // seconds since the last frame
};

class CameraController {
public:
    enum class Mode { Orbit, Fly };
    // `sceneBounds` sets the speeds and the orbit centre (on the view axis, at the bounds centre depth).
    CameraController(const Camera& initial, const Aabb& sceneBounds);
    void update(const CameraInput& input);
    void reset();
    void setCamera(const Camera& camera); // scripted frames; orbit centre follows
    void toggleMode() { m_mode = m_mode == Mode::Orbit ? Mode::Fly : Mode::Orbit; }
    Mode mode() const { return m_mode; }
    const Camera& camera() const { return m_camera; }

private:
    void placeTarget();
    Camera m_initial;
    Camera m_camera;
    glm::vec3 m_target{0.0f};
    glm::vec3 m_boundsCentre{0.0f};
    float m_sceneSize = 1.0f;
    Mode m_mode = Mode::Orbit;
};

class CameraScript {
public:
    // "still", "orbit", or a keyframe file (see vkgi-view --help); errors name the file and line.
    static Result<CameraScript> load(const std::string& nameOrFile, const Camera& sceneCamera, const Aabb& bounds);
    Camera at(float t) const;

private:
    enum class Kind { Still, Orbit, Keys };
    Kind m_kind = Kind::Still;
    Camera m_base;
    glm::vec3 m_pivot{0.0f};
    std::vector<Camera> m_keys;
};

// The scripted light/object loop (--animate) and the instance the UI moves.
struct SceneAnimation {
    // The instance to move: the first one marked dynamic, else the non-emissive one with the
    // smallest bounds diagonal (cornell: the short block), which then gets marked dynamic.
    static std::optional<uint32_t> pickDynamicInstance(const Scene& scene);
    // `scene` with light 0 and instance `object` displaced along closed loops at phase t.
    static Scene at(const Scene& base, std::optional<uint32_t> object, float t);
};

} // namespace vkgi::view
