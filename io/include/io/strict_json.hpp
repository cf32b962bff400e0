// io/strict_json.hpp: JSON from outside input, parsed stricter than nlohmann is.
//
// Scene files, candidate lists, corpus specs and study plans are written by hand or by
// other tools. nlohmann keeps the last of two equal keys silently and lets a NUL cut a
// file name short; both are refused here, and every parse error becomes one core::Error
// line that names the file and where in it.
#pragma once
#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>
#include <string_view>

namespace io {

/// The deepest nesting of arrays and objects parsed. Every file of the project nests a
/// few levels; the bound keeps every later recursive walk (dump, comparison, messages)
/// far from the stack's end.
inline constexpr std::size_t kMaxJsonDepth = 256;

/// Parses `text`. Throws core::Error("<name>: JSON syntax error: parse error at line L,
/// column C: ..."), "<name>: <where>: duplicate key 'k'; allowed: each key once per
/// object", a NUL in a key or string, a number beyond double range, or nesting deeper
/// than kMaxJsonDepth. Text whose first byte after white space is neither '{' nor '[' is
/// refused as "<name>: not JSON: ..." without quoting any of it.
nlohmann::json parseStrictJson(std::string_view text, const std::string& name);

/// "a string", "an array", "an object", "a number", ... for messages.
std::string jsonTypeName(const nlohmann::json& v);

}  // namespace io
