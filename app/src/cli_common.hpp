// app/src/cli_common.hpp: conventions every subcommand shares: exit statuses, the checks
// applied to every option's text, one-line usage errors, warnings, output folders.
#pragma once
#include <CLI/CLI.hpp>

#include <platform/cleanup.hpp>
#include <platform/input_set.hpp>

#include <glm/vec3.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace app {

/// Exit statuses of `ladarvr` (listed in --help's footer and README.md).
enum ExitStatus : int {
    kExitOk = 0,
    kExitError = 1,     // the run failed: bad input file or value, environment, I/O
    kExitUsage = 2,     // the command line does not parse (see usageError)
    kExitInternal = 70  // a bug (sysexits' EX_SOFTWARE): an exception that is no core::Error
};

/// The --help footer: the exit statuses above, in words.
inline constexpr const char* kExitStatusHelp =
    "Exit status: 0 success; 1 the run failed (bad input file or option value, environment, I/O); "
    "2 usage error (unknown subcommand or option, repeated option, missing, empty or malformed value); "
    "70 internal error (a bug).";

/// For `app` and all its subcommands: adds to every option that takes a value a check
/// that refuses an empty value and, for numeric options, text that is not such a number
/// (CLI11 reads '' as 0), and sets the exit-status footer of --help. Call once, after
/// every subcommand and option exists.
void applyConventions(CLI::App& app);

/// A floating-point option's value: a finite number in decimal notation, [+-]digits[.digits]
/// or [+-].digits, then an optional exponent e[+-]digits; nullopt for anything else (hex
/// such as 0x10, inf, nan, spaces, trailing text, a value beyond the double range). The
/// one reading of numbers typed on the command line, so every option agrees with the
/// integer options and the files, which refuse hex too.
std::optional<double> parseDecimal(std::string_view text);

/// "x,y,z": exactly three numbers as parseDecimal reads them. Throws core::Error
/// "<what> '<text>': allowed three finite numbers x,y,z (world metres)" otherwise.
glm::dvec3 parseWorldTriple(const std::string& text, std::string_view what);

/// The one-line message for a parse error of `cli`: "<subcommand>: <what> (see 'ladarvr
/// <subcommand> --help')", with unknown and missing subcommands named from argv.
std::string usageError(const CLI::App& cli, const CLI::ParseError& e, int argc, char** argv);

/// The one-line message for an unknown or missing subcommand in argv, as usageError words
/// it; "" when argv names existing subcommands. For --help and --version, which CLI11
/// answers before it looks at the subcommands: help for a subcommand that does not exist
/// is the same usage error as the command without --help.
std::string subcommandError(const CLI::App& cli, int argc, char** argv);

/// Prints "ladarvr: warning: <what>" on stderr.
void warn(const std::string& what);

/// Creates the folders above `file` that do not exist yet (mkdir -p). Throws
/// core::Error naming `option` when a component exists and is not a folder, or
/// cannot be created.
void createParentFolders(const std::filesystem::path& file, std::string_view option);

/// Whether `name` ends as a LAS, LAZ or COPC file's does (.las, .laz, .copc.laz; any case).
bool isLasName(const std::string& name);

/// The LAS, LAZ and COPC files (isLasName, regular files) directly in `folder`, in name
/// order; empty when it holds none. Throws core::Error("<command>: folder '<folder>' ...")
/// when it cannot be listed or holds more than `most` of them.
std::vector<std::filesystem::path> lasFilesIn(const std::filesystem::path& folder, std::string_view command,
                                              std::size_t most);

/// The inputs of a command with each folder among them replaced by its lasFilesIn() (a
/// survey's tiles, in name order). Throws core::Error("<command>: input '<folder>' is a
/// folder that holds no .las or .laz file; ...") for a folder without them, and when more
/// than `most` files result.
void expandFolderInputs(std::vector<std::string>& inputs, std::string_view command, std::size_t most);
/// The inputs that are folders (of tiles), before expandFolderInputs replaces them.
std::vector<std::string> folderInputs(const std::vector<std::string>& inputs);
/// Adds each folder of tiles to `inputs` so that no output of the run lands among its tiles,
/// where the next run would read it as one: a .las or .laz name directly inside it is
/// refused (InputSet::checkNotAnInput); other names, and names in a subfolder, are not.
void addTileFolders(platform::InputSet& inputs, const std::vector<std::string>& folders);

/// An optional output file of a run (a screenshot, a log): when `file` is not empty,
/// creates its folders and checks the destination (platform::checkWritableDestination), so a
/// bad name fails before the run starts.
void prepareOutputFile(const std::filesystem::path& file, std::string_view option);

/// The viewer's frame loop stops at --timeout by itself and then has up to 3 s to end the
/// OpenXR session and write its log; this watchdog ends whatever still runs 5 s after the
/// deadline (a scene that loads for minutes, a runtime that never answers during start-up)
/// with "<command>: --timeout S s reached ...". None for timeout_s <= 0.
std::unique_ptr<platform::Watchdog> viewerWatchdog(std::string_view command, double timeout_s);

}  // namespace app
