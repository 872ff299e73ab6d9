#include "survey_plan.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace locus::tools::survey_plan {

Plan plan_grid(double width, double height, double cell, const std::vector<Room>& rooms) {
    if (!(width > 0) || !(height > 0) || !(cell > 0) || !std::isfinite(width) || !std::isfinite(height) || !std::isfinite(cell))
        throw std::invalid_argument("floor width, height and cell must be positive");
    const double cols = std::ceil(width / cell), rows = std::ceil(height / cell);
    if (cols * rows > 1e6) throw std::invalid_argument("more than 1e6 grid cells: use a larger cell");
    Plan plan;
    plan.required = static_cast<std::size_t>(std::ceil(width * height / (cell * cell) - 1e-9));
    plan.columns = static_cast<std::size_t>(cols);
    plan.rows = static_cast<std::size_t>(rows);
    const double dx = width / cols, dy = height / rows;
    for (std::size_t r = 0; r < plan.rows; ++r) {
        for (std::size_t c = 0; c < plan.columns; ++c) {
            const Point p{(static_cast<double>(c) + 0.5) * dx, (static_cast<double>(r) + 0.5) * dy};
            bool inside = rooms.empty();
            for (const auto& room : rooms) inside = inside || room.contains(p);
            if (!inside) {
                ++plan.outside_rooms;
                continue;
            }
            char name[48];
            std::snprintf(name, sizeof name, "g%03zu_%03zu", r, c);
            plan.points.push_back({name, p});
        }
    }
    return plan;
}

}  // namespace locus::tools::survey_plan
