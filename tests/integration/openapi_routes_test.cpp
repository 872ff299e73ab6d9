// schema/openapi.yaml must describe routes the server really has: every documented path and
// method is sent to the real server and must reach a handler (not the "no route" 404).
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "server_process.hpp"
#include "build_paths.hpp"

namespace openapi_routes_test {
namespace {

using locus::testing::ServerProcess;

struct Operation {
    std::string method, path;
};

std::vector<Operation> documented_operations() {
    std::ifstream in(std::string(LOCUS_SOURCE_DIR) + "/schema/openapi.yaml");
    std::vector<Operation> ops;
    std::string line, path;
    bool in_paths = false;
    const std::regex path_line(R"(^  (/[^:]*):\s*$)"), method_line(R"(^    (get|post|patch|delete):)");
    while (std::getline(in, line)) {
        if (line == "paths:") in_paths = true;
        else if (!line.empty() && line[0] != ' ') in_paths = false;
        if (!in_paths) continue;
        std::smatch m;
        if (std::regex_search(line, m, path_line)) path = m[1];
        else if (std::regex_search(line, m, method_line)) ops.push_back({m[1], path});
    }
    return ops;
}

TEST(OpenApi, EveryDocumentedOperationIsServed) {
    const auto ops = documented_operations();
    ASSERT_GE(ops.size(), 30u) << "openapi.yaml could not be read";
    ServerProcess s;
    for (const auto& op : ops) {
        const std::string path = std::regex_replace(op.path, std::regex(R"(\{[^}]+\})"), "424242");
        locus::testing::Response r;
        if (op.method == "get") r = s.get(path);
        else if (op.method == "post") r = s.post(path, nlohmann::json::object());
        else if (op.method == "patch") r = s.patch(path, nlohmann::json::object());
        else r = s.del(path);
        ASSERT_NE(r.status, 0) << op.method << " " << path;
        const std::string message = r.body.is_object() && r.body.contains("error") ? r.body["error"].value("message", "") : "";
        EXPECT_EQ(message.find("no route"), std::string::npos) << op.method << " " << path << " is documented but not served";
        EXPECT_LT(r.status, 500) << op.method << " " << path;
    }
}

}  // namespace
}  // namespace openapi_routes_test
