// core/roles.hpp: the role of each mesh, and of each point that hits it: ground,
// environment or target (the ground truth every cloud carries as its label).
#pragma once
#include <cstdint>
#include <initializer_list>
#include <string_view>

namespace core {

enum class Role : std::uint8_t { Ground = 0, Environment = 1, Target = 2 };
inline constexpr int kRoleCount = 3;
/// The role names as messages list what is allowed.
inline constexpr std::string_view kRoleList = "ground, environment, target";

/// "ground", "environment" or "target".
std::string_view roleName(Role r);
/// Parses a role name; throws Error("<context>: role 'x' is not one of ground, environment, target").
Role parseRole(std::string_view name, std::string_view context);

/// A set of roles as a bit mask (bit i = Role i).
struct RoleMask {
    std::uint8_t bits = 0b111;
    bool has(Role r) const { return (bits >> static_cast<int>(r)) & 1u; }
    static RoleMask all() { return {}; }
    static RoleMask of(std::initializer_list<Role> roles);
    /// Parses "target,environment"; throws Error naming `parameter` on an unknown or empty list.
    static RoleMask parse(std::string_view list, std::string_view parameter);
};

}  // namespace core
