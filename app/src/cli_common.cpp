// app/src/cli_common.cpp: the conventions every subcommand shares (cli_common.hpp).
#include "cli_common.hpp"

#include <core/error.hpp>
#include <platform/atomic_file.hpp>
#include <platform/safe_file.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <system_error>

namespace app {
namespace {

namespace fs = std::filesystem;

bool isWholeNumber(const std::string& text, bool allow_minus) {
    std::size_t i = 0;
    if (i < text.size() && (text[i] == '+' || (allow_minus && text[i] == '-'))) ++i;
    if (i == text.size()) return false;
    for (; i < text.size(); ++i)
        if (!std::isdigit(static_cast<unsigned char>(text[i]))) return false;
    return true;
}

std::size_t digitsFrom(std::string_view text, std::size_t i) {
    std::size_t n = 0;
    while (i + n < text.size() && text[i + n] >= '0' && text[i + n] <= '9') ++n;
    return n;
}

// Decimal notation, as parseDecimal documents it. The grammar is checked here rather than
// left to strtod, which also reads hex, inf, nan and leading spaces; strtod then only
// converts (the program never changes the "C" locale, so '.' is the decimal point).
bool isDecimal(std::string_view text) {
    std::size_t i = 0;
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
    const std::size_t whole = digitsFrom(text, i);
    i += whole;
    std::size_t fraction = 0;
    if (i < text.size() && text[i] == '.') {
        fraction = digitsFrom(text, i + 1);
        i += 1 + fraction;
    }
    if (whole == 0 && fraction == 0) return false;
    if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
        ++i;
        if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
        const std::size_t exponent = digitsFrom(text, i);
        if (exponent == 0) return false;
        i += exponent;
    }
    return i == text.size();
}

// What an option of CLI11 type `type` accepts, for messages.
std::string allowedText(const std::string& type) {
    if (type == "INT") return "a whole number";
    if (type == "UINT") return "a whole number >= 0";
    if (type == "FLOAT") return "a number";  // parseDecimal's notation
    return "a non-empty value";
}

// The check run on each value before CLI11 converts it; "" = accepted.
std::string checkValue(const std::string& type, const std::string& text) {
    if (text.empty()) return "the value is empty; allowed: " + allowedText(type);
    if (type == "FLOAT" && isDecimal(text) && !parseDecimal(text))
        return "'" + text + "' is beyond the range of a double; allowed: a finite number";
    const bool ok = type == "INT"     ? isWholeNumber(text, true)
                    : type == "UINT"  ? isWholeNumber(text, false)
                    : type == "FLOAT" ? parseDecimal(text).has_value()
                                      : true;
    if (!ok)
        return "'" + text + "' is not " + allowedText(type) +
               (type == "FLOAT" ? "; allowed: decimal notation such as 16, -2.5 or 1e3" : "");
    return "";
}

// "generate" or "bench generate": the subcommands the parse went into.
const CLI::App* deepestParsed(const CLI::App& cli, std::string& path) {
    const CLI::App* app = &cli;
    while (true) {
        const std::vector<CLI::App*> subs = app->get_subcommands();
        if (subs.empty()) return app;
        app = subs.front();
        path += (path.empty() ? "" : " ") + app->get_name();
    }
}

std::string subcommandNames(const CLI::App& app) {
    std::string names;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
        names += (names.empty() ? "" : ", ") + sub->get_name();
    return names;
}

// A missing or unknown subcommand, found by walking argv the way the parser does: every
// level that requires a subcommand takes no option with a value, so the next word that
// does not start with '-' must name one. "" when the subcommands are fine.
std::string subcommandProblem(const CLI::App& cli, int argc, char** argv, std::string& path) {
    const CLI::App* app = &cli;
    for (int i = 1; app->get_require_subcommand_min() > 0; ++i) {
        if (i >= argc) return "a subcommand is required; allowed: " + subcommandNames(*app);
        const std::string word = argv[i];
        if (!word.empty() && word.front() == '-') {
            // Options before the subcommand: only this level's own (--help, --version).
            const std::string name = word.substr(0, word.find('='));
            return app->get_option_no_throw(name) ? "" : "unknown option: " + word;
        }
        const std::vector<const CLI::App*> named =
            app->get_subcommands([&word](const CLI::App* sub) { return sub->check_name(word); });
        if (named.empty()) return "unknown subcommand '" + word + "'; allowed: " + subcommandNames(*app);
        app = named.front();
        path += (path.empty() ? "" : " ") + app->get_name();
    }
    return "";
}

bool startsWith(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

// CLI11's message, in this project's words where its own are unclear.
std::string describe(const CLI::ParseError& e, const CLI::App& app) {
    std::string what = e.what();
    // "Exactly 1 option from [--a,--b] is required" (and " and N were given"): an either-or.
    if (startsWith(what, "Exactly 1 option from [")) {
        const std::size_t close = what.find(']');
        if (close != std::string::npos) {
            std::string names = what.substr(23, close - 23);
            for (std::size_t at = names.find(','); at != std::string::npos; at = names.find(',', at + 2))
                names.replace(at, 1, ", ");
            return what.find(" were given", close) == std::string::npos
                       ? "one of " + names + " is required"
                       : "more than one of " + names + " given; allowed exactly one of them";
        }
    }
    // "<name> is required" for a positional: name what it takes, from its help text.
    if (what.ends_with(" is required")) {
        const std::string name = what.substr(0, what.size() - 12);
        const CLI::Option* option = app.get_option_no_throw(name);
        if (option != nullptr && option->get_positional() && !option->get_description().empty())
            return "missing " + name + ": " + option->get_description();
    }
    for (const char* prefix :
         {"The following argument was not expected: ", "The following arguments were not expected: "}) {
        if (!startsWith(what, prefix)) continue;
        // CLI11 lists them last first.
        std::vector<std::string> words;
        std::istringstream list(what.substr(std::strlen(prefix)));
        for (std::string word; list >> word;) words.insert(words.begin(), word);
        std::string shown;
        for (const std::string& word : words) shown += (shown.empty() ? "" : " ") + word;
        return (!shown.empty() && shown.front() == '-' ? "unknown option: " : "unexpected argument: ") + shown;
    }
    if (const std::size_t at = what.find(": At Most 1 required but received "); at != std::string::npos)
        return what.substr(0, at) + " is given " + what.substr(at + 34) + " times; allowed once";
    if (const std::size_t at = what.find(": 1 required ");
        at != std::string::npos && what.size() > 8 && what.ends_with(" missing"))
        return what.substr(0, at) + ": the value is missing";
    if (startsWith(what, "Could not convert: ")) {
        std::string rest = what.substr(19);
        const std::size_t eq = rest.find(" = ");
        if (eq != std::string::npos)
            return rest.substr(0, eq) + ": '" + rest.substr(eq + 3) + "' is out of range for this option";
    }
    return what;
}

}  // namespace

std::optional<double> parseDecimal(std::string_view text) {
    if (!isDecimal(text)) return std::nullopt;
    const std::string copy(text);
    const double v = std::strtod(copy.c_str(), nullptr);
    if (!std::isfinite(v)) return std::nullopt;  // overflow (underflow reads as 0 or a denormal)
    return v;
}

glm::dvec3 parseWorldTriple(const std::string& text, std::string_view what) {
    glm::dvec3 v{0.0};
    std::size_t n = 0, start = 0;
    bool ok = true;
    while (ok) {
        const std::size_t comma = text.find(',', start);
        const std::string_view part =
            std::string_view(text).substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        const std::optional<double> value = n < 3 ? parseDecimal(part) : std::nullopt;
        ok = value.has_value();
        if (ok) v[int(n++)] = *value;
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    if (!ok || n != 3)
        throw core::Error(std::string(what) + " '" + core::printable(text, 80) +
                          "': allowed three finite numbers x,y,z (world metres)");
    return v;
}

void applyConventions(CLI::App& app) {
    app.footer(kExitStatusHelp);
    for (CLI::Option* option : app.get_options()) {
        if (option->get_type_size_max() == 0) continue;  // a flag: takes no value
        const std::string type = option->get_type_name();
        option->check(CLI::Validator([type](std::string& text) { return checkValue(type, text); }, ""));
    }
    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) applyConventions(*sub);
}

namespace {

// "<path>: <what> (see 'ladarvr <path> --help')".
std::string withHelpHint(const std::string& path, const std::string& what) {
    const std::string command = path.empty() ? "ladarvr" : "ladarvr " + path;
    return (path.empty() ? "" : path + ": ") + what + " (see '" + command + " --help')";
}

}  // namespace

std::string usageError(const CLI::App& cli, const CLI::ParseError& e, int argc, char** argv) {
    std::string path;
    std::string what = subcommandProblem(cli, argc, argv, path);
    if (what.empty()) {
        path.clear();
        what = describe(e, *deepestParsed(cli, path));
    }
    return withHelpHint(path, what);
}

std::string subcommandError(const CLI::App& cli, int argc, char** argv) {
    std::string path;
    const std::string what = subcommandProblem(cli, argc, argv, path);
    return what.empty() ? "" : withHelpHint(path, what);
}

void warn(const std::string& what) { platform::printMessage("warning", what); }

bool isLasName(const std::string& name) {
    std::string lower = name;
    for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
    return lower.size() > 4 && (lower.ends_with(".las") || lower.ends_with(".laz"));
}

std::vector<std::filesystem::path> lasFilesIn(const std::filesystem::path& folder, std::string_view command,
                                              std::size_t most) {
    const std::string name = core::printable(folder.string(), 400);
    std::vector<std::filesystem::path> files;
    std::error_code ec;
    for (std::filesystem::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
        if (!isLasName(it->path().filename().string()) || !it->is_regular_file()) continue;
        if (files.size() >= most)
            throw core::Error(std::string(command) + ": folder '" + name + "' holds more than " + std::to_string(most) +
                              " LAS/LAZ files; allowed at most that many");
        files.push_back(it->path());
    }
    if (ec) throw core::Error(std::string(command) + ": folder '" + name + "': " + ec.message());
    std::sort(files.begin(), files.end());
    return files;
}

void expandFolderInputs(std::vector<std::string>& inputs, std::string_view command, std::size_t most) {
    std::vector<std::string> files;
    for (const std::string& given : inputs) {
        std::error_code ec;
        if (!std::filesystem::is_directory(given, ec)) {
            files.push_back(given);
            continue;
        }
        const std::vector<std::filesystem::path> tiles = lasFilesIn(given, command, most);
        if (tiles.empty())
            throw core::Error(std::string(command) + ": input '" + core::printable(given, 400) +
                              "' is a folder that holds no .las or .laz file; allowed: cloud files, or folders of "
                              "LAS/LAZ tiles");
        for (const std::filesystem::path& t : tiles) files.push_back(t.string());
    }
    if (files.size() > most)
        throw core::Error(std::string(command) + ": " + std::to_string(files.size()) +
                          " input files; allowed at most " + std::to_string(most));
    inputs = std::move(files);
}

std::vector<std::string> folderInputs(const std::vector<std::string>& inputs) {
    std::vector<std::string> folders;
    for (const std::string& in : inputs) {
        std::error_code ec;
        if (std::filesystem::is_directory(in, ec)) folders.push_back(in);
    }
    return folders;
}

void addTileFolders(platform::InputSet& inputs, const std::vector<std::string>& folders) {
    for (const std::string& folder : folders)
        inputs.addFolder(folder,
                         [](const std::string& name) { return name.find('/') != name.npos || !isLasName(name); });
}

void createParentFolders(const fs::path& file, std::string_view option) {
    platform::checkPathLength(file, option);
    const fs::path parent = file.parent_path();
    if (parent.empty()) return;
    fs::path prefix;
    for (const fs::path& part : parent) {
        prefix /= part;
        std::error_code ec;
        const fs::file_status st = fs::status(prefix, ec);
        if (fs::is_directory(st)) continue;
        if (fs::exists(st))
            throw core::Error(std::string(option) + " '" + file.string() + "': '" + prefix.string() +
                              "' exists and is not a folder; allowed: a path whose folders are folders");
        if (fs::is_symlink(fs::symlink_status(prefix, ec)))  // dangling, or a loop
            throw core::Error(std::string(option) + " '" + core::printable(file.string(), 400) + "': '" +
                              core::printable(prefix.string(), 400) + "' " + platform::regularFileProblem(prefix) +
                              "; allowed: a path whose folders are folders");
        if (!fs::create_directory(prefix, ec) && !fs::is_directory(prefix))
            throw core::Error(std::string(option) + " '" + file.string() + "': cannot create the folder '" +
                              prefix.string() + "': " + (ec ? ec.message() : std::string("unknown reason")));
    }
}

void prepareOutputFile(const fs::path& file, std::string_view option) {
    if (file.empty()) return;
    createParentFolders(file, option);
    platform::checkWritableDestination(file);
}

std::unique_ptr<platform::Watchdog> viewerWatchdog(std::string_view command, double timeout_s) {
    constexpr double kGraceS = 5.0;
    if (!(std::isfinite(timeout_s) && timeout_s > 0.0)) return nullptr;
    char message[160];
    std::snprintf(message, sizeof message, "%.*s: --timeout %g s reached (the run did not end %g s after it)",
                  int(command.size()), command.data(), timeout_s, kGraceS);
    return std::make_unique<platform::Watchdog>(timeout_s + kGraceS, message);
}

}  // namespace app
