// engine/error.hpp: the project's one error type for bad input or configuration.
#pragma once
#include <cstdio>
#include <stdexcept>
#include <string>

namespace engine {

/// Thrown for bad input, configuration or environment. The message is one line that
/// starts with the module ("scene: ", "orbit: ", "pcd: ", ...) and names the offending
/// file, field or parameter and what is allowed. `main` prints it and exits non-zero.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A number as messages show it: "%.10g", so 1e308 reads "1e+308" (not 309 digits),
/// 0.2 reads "0.2" and limits such as 1048576 keep every digit.
inline std::string shownNumber(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.10g", v);
    return buffer;
}

}  // namespace engine
