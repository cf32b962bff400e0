// viewer/src/ui/desktop_window.hpp: the desktop mirror window: GLFW, its OpenGL 4.5 core
// context (glad loaded) and ImGui, made first and destroyed last.
#pragma once

struct GLFWwindow;

namespace viewer {

struct ViewerOptions;
class DesktopInput;

struct DesktopWindow {
    GLFWwindow* handle = nullptr;
    /// Opens the window (hidden with options.hidden_window), makes its context current,
    /// installs `input`'s callbacks, then ImGui's. Throws core::Error("view: ...") when
    /// no display or no GL 4.5 core context is available.
    DesktopWindow(const ViewerOptions& options, DesktopInput& input);
    ~DesktopWindow();
    DesktopWindow(const DesktopWindow&) = delete;
    DesktopWindow& operator=(const DesktopWindow&) = delete;
};

}  // namespace viewer
