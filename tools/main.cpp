#include <iostream>
#include <map>

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

}  // namespace locus::tools

int main(int argc, char** argv) {
    CLI::App app{"locus: tools for the Locus indoor positioning service"};
    app.require_subcommand(1);
    locus::tools::install_all(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const locus::tools::CommandError& e) {
        std::cerr << "locus: " << e.what() << "\n";
        return e.exit_code;
    } catch (const std::exception& e) {
        std::cerr << "locus: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
