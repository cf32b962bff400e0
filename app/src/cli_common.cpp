// app/src/cli_common.cpp: the conventions every subcommand shares (cli_common.hpp).
#include "cli_common.hpp"

#include <engine/atomic_file.hpp>
#include <engine/error.hpp>
#include <engine/safe_file.hpp>

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

bool isNumber(const std::string& text) {
    if (text.empty() || std::isspace(static_cast<unsigned char>(text.front()))) return false;
    char* end = nullptr;
    std::strtod(text.c_str(), &end);
    return end == text.c_str() + text.size();
}

// What an option of CLI11 type `type` accepts, for messages.
std::string allowedText(const std::string& type) {
    if (type == "INT") return "a whole number";
    if (type == "UINT") return "a whole number >= 0";
    if (type == "FLOAT") return "a number";
    return "a non-empty value";
}

// The check run on each value before CLI11 converts it; "" = accepted.
std::string checkValue(const std::string& type, const std::string& text) {
    if (text.empty()) return "the value is empty; allowed: " + allowedText(type);
    const bool ok = type == "INT"    ? isWholeNumber(text, true)
                    : type == "UINT" ? isWholeNumber(text, false)
                    : type == "FLOAT" ? isNumber(text)
                                      : true;
    if (!ok) return "'" + text + "' is not " + allowedText(type);
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
        if (i >= argc)
            return "a subcommand is required; allowed: " + subcommandNames(*app);
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
std::string describe(const CLI::ParseError& e) {
    std::string what = e.what();
    for (const char* prefix : {"The following argument was not expected: ",
                               "The following arguments were not expected: "}) {
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
    if (const std::size_t at = what.find(": 1 required "); at != std::string::npos &&
                                                            what.size() > 8 && what.ends_with(" missing"))
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

void applyConventions(CLI::App& app) {
    app.footer(kExitStatusHelp);
    for (CLI::Option* option : app.get_options()) {
        if (option->get_type_size_max() == 0) continue;  // a flag: takes no value
        const std::string type = option->get_type_name();
        option->check(CLI::Validator([type](std::string& text) { return checkValue(type, text); }, ""));
    }
    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) applyConventions(*sub);
}

std::string usageError(const CLI::App& cli, const CLI::ParseError& e, int argc, char** argv) {
    std::string path;
    std::string what = subcommandProblem(cli, argc, argv, path);
    if (what.empty()) {
        path.clear();
        deepestParsed(cli, path);
        what = describe(e);
    }
    const std::string command = path.empty() ? "ladarvr" : "ladarvr " + path;
    return (path.empty() ? "" : path + ": ") + what + " (see '" + command + " --help')";
}

void warn(const std::string& what) { std::fprintf(stderr, "ladarvr: warning: %s\n", what.c_str()); }

void createParentFolders(const fs::path& file, std::string_view option) {
    engine::checkPathLength(file, option);
    const fs::path parent = file.parent_path();
    if (parent.empty()) return;
    fs::path prefix;
    for (const fs::path& part : parent) {
        prefix /= part;
        std::error_code ec;
        const fs::file_status st = fs::status(prefix, ec);
        if (fs::is_directory(st)) continue;
        if (fs::exists(st))
            throw engine::Error(std::string(option) + " '" + file.string() + "': '" + prefix.string() +
                                "' exists and is not a folder; allowed: a path whose folders are folders");
        if (fs::is_symlink(fs::symlink_status(prefix, ec)))  // dangling, or a loop
            throw engine::Error(std::string(option) + " '" + engine::printable(file.string(), 400) + "': '" +
                                engine::printable(prefix.string(), 400) + "' " + engine::regularFileProblem(prefix) +
                                "; allowed: a path whose folders are folders");
        if (!fs::create_directory(prefix, ec) && !fs::is_directory(prefix))
            throw engine::Error(std::string(option) + " '" + file.string() + "': cannot create the folder '" +
                                prefix.string() + "': " + (ec ? ec.message() : std::string("unknown reason")));
    }
}

void prepareOutputFile(const fs::path& file, std::string_view option) {
    if (file.empty()) return;
    createParentFolders(file, option);
    engine::checkWritableDestination(file);
}

std::unique_ptr<engine::Watchdog> viewerWatchdog(std::string_view command, double timeout_s) {
    constexpr double kGraceS = 5.0;
    if (!(std::isfinite(timeout_s) && timeout_s > 0.0)) return nullptr;
    char message[160];
    std::snprintf(message, sizeof message, "%.*s: --timeout %g s reached (the run did not end %g s after it)",
                  int(command.size()), command.data(), timeout_s, kGraceS);
    return std::make_unique<engine::Watchdog>(timeout_s + kGraceS, message);
}

}  // namespace app
