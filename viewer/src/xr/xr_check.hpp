// viewer/src/xr/xr_check.hpp: OpenXR call checks that name the expression, the result and file:line.
#pragma once
#include <openxr/openxr.h>

#include <string>

namespace viewer {

/// "XR_ERROR_RUNTIME_FAILURE" etc. (through xrResultToString when an instance exists).
std::string xrResultName(XrInstance instance, XrResult result);
/// Throws core::Error("xr: <expr>: <RESULT> at file:line") when XR_FAILED(result).
void xrCheck(XrInstance instance, XrResult result, const char* expression, const char* file, int line);
/// Never throws: prints the same line to stderr and returns false when XR_FAILED(result).
bool xrLog(XrInstance instance, XrResult result, const char* expression, const char* file, int line);

}  // namespace viewer

/// Setup paths: throw on failure. `instance` may be XR_NULL_HANDLE.
#define XR_CHECK(instance, expr) ::viewer::xrCheck((instance), (expr), #expr, __FILE__, __LINE__)
/// Per-frame paths: log and yield false on failure, never throw.
#define XR_LOG(instance, expr) ::viewer::xrLog((instance), (expr), #expr, __FILE__, __LINE__)
