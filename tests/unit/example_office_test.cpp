// The walkthrough's example office (docs/your-building.md): the hand-drawn plan
// (docs/examples/office-plan.geojson) must agree with the drawing (docs/examples/office.png, 10 px
// a metre, north up): each of the plan's doors stands in a gap of the drawing's walls, so a route
// through the plan's doors is one a person could walk on the drawing. The drawing's rows run
// down and the floor's y up: a door placed by its row, unflipped, lands mirrored in a wall.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "build_paths.hpp"
#include "image_file.hpp"

namespace example_office_test {
namespace {

using nlohmann::json;

constexpr double kPxPerM = 10.0;  // docs/your-building.md draws the office at 10 px/m

TEST(ExampleOffice, EveryDoorOfThePlanStandsInAGapOfTheDrawingsWalls) {
    const std::string examples = std::string(LOCUS_SOURCE_DIR) + "/docs/examples/";
    const auto image = locus::tools::read_grey_image(examples + "office.png");
    const double height_m = image.height / kPxPerM;
    // Ink (a wall's stroke) at floor point (x, y); off the drawing counts as paper.
    const auto ink = [&](double x, double y) {
        const int col = static_cast<int>(std::floor(x * kPxPerM)), row = static_cast<int>(std::floor((height_m - y) * kPxPerM));
        if (col < 0 || row < 0 || col >= image.width || row >= image.height) return false;
        return image.pixels[static_cast<std::size_t>(row * image.width + col)] < 128;
    };
    std::ifstream in(examples + "office-plan.geojson");
    const json plan = json::parse(in);
    int doors = 0;
    for (const json& f : plan.at("features")) {
        if (f.at("properties").value("feature", "") != "door") continue;
        ++doors;
        const double x = f.at("geometry").at("coordinates").at(0), y = f.at("geometry").at("coordinates").at(1);
        const std::string name = f.at("properties").value("name", "a door");
        EXPECT_FALSE(ink(x, y)) << name << " at (" << x << ", " << y << ") is drawn as wall";
        // A metre either way along the wall it passes (a vertical wall, or a horizontal one) is ink.
        const bool in_vertical_wall = ink(x, y - 1.0) && ink(x, y + 1.0);
        const bool in_horizontal_wall = ink(x - 1.0, y) && ink(x + 1.0, y);
        EXPECT_TRUE(in_vertical_wall || in_horizontal_wall) << name << " at (" << x << ", " << y << ") is not in a gap of a drawn wall";
    }
    EXPECT_EQ(doors, 2);
}

}  // namespace
}  // namespace example_office_test
