#pragma once
// Each commands/*.cpp registers its subcommands with a static LOCUS_COMMAND(...) object;
// main() installs them all into one CLI11 app. A command file puts everything, its
// LOCUS_COMMANDs too, in a namespace named for the file (locus_cli_<file>): the CLI is a unity
// build (CMakeLists.txt), and eight files' `Args`, `run` and using-directives would otherwise
// meet in one unit.
#include <CLI/CLI.hpp>
#include <functional>
#include <stdexcept>
#include <string>

namespace locus::tools {

using Installer = std::function<void(CLI::App&)>;

struct CommandRegistration {
    CommandRegistration(const char* name, Installer install);
};

void install_all(CLI::App& app);

// Subcommand groups such as `import` are shared by several files: get it or create it.
CLI::App& group(CLI::App& app, const std::string& name, const std::string& description);

// Thrown by a command to end with a message on stderr and a non-zero exit status.
struct CommandError : std::runtime_error {
    int exit_code;
    explicit CommandError(const std::string& message, int code = 1) : std::runtime_error(message), exit_code(code) {}
};

}  // namespace locus::tools

#define LOCUS_COMMAND_CAT2(a, b) a##b
#define LOCUS_COMMAND_CAT(a, b) LOCUS_COMMAND_CAT2(a, b)
#define LOCUS_COMMAND(name, fn) \
    static const ::locus::tools::CommandRegistration LOCUS_COMMAND_CAT(locus_command_, __LINE__){name, fn}
