#include <algorithm>
#include <cctype>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "survey_connect.hpp"

#include "command_registry.hpp"

namespace locus::tools {

namespace {
std::map<std::string, Installer>& registry() {
    static std::map<std::string, Installer> r;  // ordered: help lists commands alphabetically
    return r;
}
}  // namespace

CommandRegistration::CommandRegistration(const char* name, Installer install) {
    registry().emplace(name, std::move(install));
}

void install_all(CLI::App& app) {
    for (auto& [name, install] : registry()) install(app);
}

CLI::App& group(CLI::App& app, const std::string& name, const std::string& description) {
    for (auto* sub : app.get_subcommands([](CLI::App*) { return true; }))
        if (sub->get_name() == name) return *sub;
    auto* sub = app.add_subcommand(name, description);
    sub->require_subcommand(1);
    return *sub;
}

namespace {

// Edit distance, for "did you mean".
std::size_t distance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diag = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diag = up;
        }
    }
    return row[b.size()];
}

bool looks_like_option(const std::string& s) {
    return s.size() > 1 && s[0] == '-' && (s[1] == '-' || std::isalpha(static_cast<unsigned char>(s[1])));
}

}  // namespace

// CLI11 leaves an option it does not know among the command's extras, but the words after it
// still fill the positionals first, so "--sever URL FILE" failed on "File does not exist: URL"
// before the extras were checked. Any parse error with an unknown option left over is
// reported as that option instead.
std::optional<std::string> unknown_option(CLI::App& app) {
    std::string path = "locus";
    for (CLI::App* a = &app; a != nullptr;) {
        for (const auto& extra : a->remaining(false)) {
            if (!looks_like_option(extra)) continue;
            const std::string flag = extra.substr(0, extra.find('='));
            std::string message = "unknown option '" + flag + "' for '" + path + "'";
            std::string best;
            std::size_t best_d = 3;  // suggest only close names
            for (const auto* opt : a->get_options())
                for (const auto& name : opt->get_lnames())
                    if (const auto d = distance(flag, "--" + name); d < best_d) best_d = d, best = "--" + name;
            if (!best.empty()) message += "; did you mean '" + best + "'?";
            return message + " (" + path + " --help lists the options)";
        }
        const auto subs = a->get_subcommands();
        a = subs.empty() ? nullptr : subs.front();
        if (a) path += " " + a->get_name();
    }
    return std::nullopt;
}

}  // namespace locus::tools

int main(int argc, char** argv) {
    CLI::App app{"locus: tools for the Locus indoor positioning service"};
    app.set_version_flag("--version", std::string("locus ") + LOCUS_VERSION);
    app.require_subcommand(1);
    locus::tools::install_all(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() != 0)  // not --help
            if (const auto unknown = locus::tools::unknown_option(app)) {
                std::cerr << "locus: " << *unknown << "\n";
                return static_cast<int>(CLI::ExitCodes::ExtrasError);
            }
        return app.exit(e);
    } catch (const locus::tools::CommandError& e) {
        std::cerr << "locus: " << locus::tools::plain_numbers(e.what()) << "\n";
        return e.exit_code;
    } catch (const std::exception& e) {
        std::cerr << "locus: " << locus::tools::plain_numbers(e.what()) << "\n";
        return 1;
    }
    return 0;
}
