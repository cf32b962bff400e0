// viewer/src/input/desktop_input.cpp: GLFW keyboard and mouse callbacks into OperatorInput.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <imgui.h>

#include "input/desktop_input.hpp"

#include <algorithm>
#include <cmath>

namespace viewer {

namespace {
DesktopInput* of(GLFWwindow* window) { return static_cast<DesktopInput*>(glfwGetWindowUserPointer(window)); }
bool imguiWantsKeys() { return ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureKeyboard; }
bool imguiWantsMouse() { return ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureMouse; }
constexpr double kClickSlopPx = 4.0;  // a press that moves less than this is a click
}  // namespace

void DesktopInput::install(GLFWwindow* window) {
    glfwSetWindowUserPointer(window, this);
    glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int) { of(w)->onKey(key, action); });
    glfwSetMouseButtonCallback(window,
                               [](GLFWwindow* w, int button, int action, int) { of(w)->onButton(w, button, action); });
    glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) { of(w)->onCursor(x, y); });
    glfwSetScrollCallback(window, [](GLFWwindow* w, double, double dy) { of(w)->onScroll(dy); });
}

void DesktopInput::onKey(int key, int action) {
    if (action != GLFW_PRESS || imguiWantsKeys()) return;
    switch (key) {
        case GLFW_KEY_SPACE: pending_.toggle_mode = true; break;
        case GLFW_KEY_ESCAPE: pending_.quit = true; break;
        case GLFW_KEY_ENTER:
        case GLFW_KEY_KP_ENTER:
            // Enter also dismisses the ready screen (the loop ignores confirm there).
            pending_.confirm = true;
            pending_.next = true;
            break;
        case GLFW_KEY_BACKSPACE: pending_.reject = true; break;
        case GLFW_KEY_N: pending_.no_target = true; break;
        case GLFW_KEY_R: pending_.reset_zoom = true; break;
        case GLFW_KEY_C: pending_.cycle_colour = true; break;
        case GLFW_KEY_V: pending_.toggle_cut = true; break;
        case GLFW_KEY_LEFT_BRACKET: pending_.cut_radius_step -= 1.0; break;
        case GLFW_KEY_RIGHT_BRACKET: pending_.cut_radius_step += 1.0; break;
        default: break;
    }
}

void DesktopInput::onButton(GLFWwindow* window, int button, int action) {
    if (button != GLFW_MOUSE_BUTTON_LEFT && button != GLFW_MOUSE_BUTTON_RIGHT) return;
    if (action == GLFW_PRESS && !imguiWantsMouse()) {
        dragging_ = true;
        glfwGetCursorPos(window, &last_x_, &last_y_);
        press_x_ = last_x_;
        press_y_ = last_y_;
        click_pending_ = button == GLFW_MOUSE_BUTTON_LEFT;
    } else if (action == GLFW_RELEASE) {
        dragging_ = false;
        if (click_pending_ && button == GLFW_MOUSE_BUTTON_LEFT) pending_.designate = true;
        click_pending_ = false;
    }
}

void DesktopInput::onCursor(double x, double y) {
    cursor_x_ = x;
    cursor_y_ = y;
    cursor_valid_ = true;
    if (!dragging_) return;
    if (click_pending_ && std::hypot(x - press_x_, y - press_y_) < kClickSlopPx) return;
    click_pending_ = false;  // moved: a drag that looks around, not a click
    look_yaw_rad_ -= (x - last_x_) * 0.004;
    look_pitch_rad_ = std::clamp(look_pitch_rad_ - (y - last_y_) * 0.004, -1.5, 1.5);
    last_x_ = x;
    last_y_ = y;
}

void DesktopInput::onScroll(double dy) {
    if (!imguiWantsMouse()) pending_.wheel += dy;
}

bool DesktopInput::cursor(double& x, double& y) const {
    if (!cursor_valid_ || imguiWantsMouse()) return false;
    x = cursor_x_;
    y = cursor_y_;
    return true;
}

OperatorInput DesktopInput::take(GLFWwindow* window) {
    OperatorInput in = pending_;
    pending_ = OperatorInput{};
    if (!imguiWantsKeys()) {
        auto key = [&](int k) { return glfwGetKey(window, k) == GLFW_PRESS ? 1.0 : 0.0; };
        const double boost = key(GLFW_KEY_LEFT_SHIFT) > 0 ? 4.0 : 1.0;
        in.motion.forward = (key(GLFW_KEY_W) - key(GLFW_KEY_S)) * boost;
        in.motion.right = (key(GLFW_KEY_D) - key(GLFW_KEY_A)) * boost;
        in.motion.up = (key(GLFW_KEY_E) - key(GLFW_KEY_Q)) * boost;
    }
    return in;
}

}  // namespace viewer
