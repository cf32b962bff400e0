// engine/error.hpp: the project's one error type for bad input or configuration.
#pragma once
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

}  // namespace engine
