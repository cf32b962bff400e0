// viewer/src/input/desktop_input.hpp: the desktop's keyboard and mouse (GLFW callbacks, chained
// by ImGui), turned into OperatorInput. Bindings (docs/viewer.md): space toggles the mode,
// Escape quits, left click designates (a drag looks around), Enter confirms, Backspace
// rejects, N declares no target, the wheel zooms, R resets the zoom, C cycles the
// colours, V toggles the cutting volume and [ ] shrink / grow it, WASD/QE move in free
// mode (Shift: faster), right drag looks around.
#pragma once
#include "input/operator_input.hpp"

struct GLFWwindow;

namespace viewer {

class DesktopInput {
  public:
    /// Installs the callbacks on `window` (its user pointer becomes this object).
    void install(GLFWwindow* window);
    /// The actions gathered since the last call, and this frame's held-key motion.
    OperatorInput take(GLFWwindow* window);

    double lookYawRad() const { return look_yaw_rad_; }
    double lookPitchRad() const { return look_pitch_rad_; }
    double& lookYawRad() { return look_yaw_rad_; }
    double& lookPitchRad() { return look_pitch_rad_; }
    /// The cursor in window coordinates (pixels from the top left), if inside the window
    /// and not over the ImGui panel.
    bool cursor(double& x, double& y) const;

    // Called by the GLFW callbacks.
    void onKey(int key, int action);
    void onButton(GLFWwindow* window, int button, int action);
    void onCursor(double x, double y);
    void onScroll(double dy);

  private:
    OperatorInput pending_;
    double look_yaw_rad_ = 0.0, look_pitch_rad_ = 0.0;
    bool dragging_ = false;
    bool click_pending_ = false;  // left button down, not moved far yet: a click
    double press_x_ = 0.0, press_y_ = 0.0;
    double last_x_ = 0.0, last_y_ = 0.0;
    double cursor_x_ = -1.0, cursor_y_ = -1.0;
    bool cursor_valid_ = false;
};

}  // namespace viewer
