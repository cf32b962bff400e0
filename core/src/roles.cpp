// roles: their names and role sets, as scene files and command lines spell them.
#include <core/error.hpp>
#include <core/roles.hpp>

#include <string>

namespace core {

namespace {

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
}

}  // namespace

std::string_view roleName(Role r) {
    switch (r) {
        case Role::Ground: return "ground";
        case Role::Environment: return "environment";
        case Role::Target: return "target";
    }
    return "unknown";
}

Role parseRole(std::string_view name, std::string_view context) {
    if (name == "ground") return Role::Ground;
    if (name == "environment") return Role::Environment;
    if (name == "target") return Role::Target;
    throw Error(std::string(context) + ": role '" + printable(name, 40, true) + "' is not one of " +
                std::string(kRoleList));
}

RoleMask RoleMask::of(std::initializer_list<Role> roles) {
    RoleMask m;
    m.bits = 0;
    for (Role r : roles) m.bits |= std::uint8_t(1u << static_cast<int>(r));
    return m;
}

RoleMask RoleMask::parse(std::string_view list, std::string_view parameter) {
    RoleMask m;
    m.bits = 0;
    std::string_view rest = list;
    while (true) {
        const std::size_t comma = rest.find(',');
        const std::string_view item = trim(rest.substr(0, comma));
        if (item.empty())
            throw Error(std::string(parameter) + ": empty role in '" + std::string(list) +
                        "'; allowed: a comma-separated list of " + std::string(kRoleList));
        m.bits |= std::uint8_t(1u << static_cast<int>(parseRole(item, parameter)));
        if (comma == std::string_view::npos) break;
        rest = rest.substr(comma + 1);
    }
    return m;
}

}  // namespace core
