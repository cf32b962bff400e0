// viewer/src/ui/desktop_window.cpp: GLFW window, GL context and ImGui of the desktop mirror.
#include <render/gl.hpp>  // glad first
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <viewer/viewer.hpp>

#include "input/desktop_input.hpp"
#include "ui/desktop_window.hpp"

#include <core/error.hpp>

#include <cstdlib>
#include <string>

namespace viewer {

namespace {
std::string g_glfw_error;
void glfwError(int code, const char* description) {
    g_glfw_error = std::string(description ? description : "?") + " (" + std::to_string(code) + ")";
}
}  // namespace

DesktopWindow::DesktopWindow(const ViewerOptions& options, DesktopInput& input) {
    glfwSetErrorCallback(glfwError);
    // Without a Wayland session GLFW would still probe for one first, and libwayland then
    // prints its own line about XDG_RUNTIME_DIR before the error below: go straight to X11.
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    if (wayland == nullptr || *wayland == '\0') glfwInitHint(GLFW_PLATFORM, GLFW_PLATFORM_X11);
    if (!glfwInit())
        throw core::Error("view: cannot open the desktop window: " + g_glfw_error +
                          "; a display is needed (set DISPLAY, or run under Xvfb)");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_DOUBLEBUFFER, GLFW_TRUE);
    glfwWindowHint(GLFW_VISIBLE, options.hidden_window ? GLFW_FALSE : GLFW_TRUE);
    handle = glfwCreateWindow(options.window_width, options.window_height, "ladarvr view", nullptr, nullptr);
    if (!handle) {
        glfwTerminate();
        throw core::Error("view: cannot create an OpenGL 4.5 core window: " + g_glfw_error);
    }
    glfwMakeContextCurrent(handle);
    render::loadGl(reinterpret_cast<GLADloadfunc>(glfwGetProcAddress));
    input.install(handle);  // before ImGui, which chains to these callbacks
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini next to the user's files
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(handle, true);
    ImGui_ImplOpenGL3_Init("#version 450 core");
}

DesktopWindow::~DesktopWindow() {
    if (handle) {
        glfwMakeContextCurrent(handle);
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
        glfwDestroyWindow(handle);
    }
    glfwTerminate();
}

}  // namespace viewer
