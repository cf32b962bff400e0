// viewer/src/xr/xr_check.cpp: OpenXR call checks that name the expression, the result and file:line.
#include <openxr/openxr.h>
#include <openxr/openxr_reflection.h>

#include "xr/xr_check.hpp"

#include <core/error.hpp>

#include <cstdio>
#include <string>

namespace viewer {

std::string xrResultName(XrInstance instance, XrResult result) {
    char buffer[XR_MAX_RESULT_STRING_SIZE] = {};
    if (instance != XR_NULL_HANDLE && XR_SUCCEEDED(xrResultToString(instance, result, buffer))) return buffer;
    switch (result) {  // no instance (yet): the names from the spec's reflection header
#define LADARVR_XR_RESULT_CASE(name, value) \
    case name: return #name;
        XR_LIST_ENUM_XrResult(LADARVR_XR_RESULT_CASE)
#undef LADARVR_XR_RESULT_CASE
            default : break;
    }
    return "XrResult(" + std::to_string(static_cast<int>(result)) + ")";
}

void xrCheck(XrInstance instance, XrResult result, const char* expression, const char* file, int line) {
    if (XR_FAILED(result))
        throw core::Error("xr: " + std::string(expression) + ": " + xrResultName(instance, result) + " at " + file +
                          ":" + std::to_string(line));
}

bool xrLog(XrInstance instance, XrResult result, const char* expression, const char* file, int line) {
    if (XR_SUCCEEDED(result)) return true;
    std::fprintf(stderr, "ladarvr: xr: %s: %s at %s:%d\n", expression, xrResultName(instance, result).c_str(), file,
                 line);
    return false;
}

}  // namespace viewer
