#include "tiling.hpp"

#include <cmath>
#include <stdexcept>

namespace pyfrustrate {
namespace {

int positive_mod(int a, int b) { return ((a % b) + b) % b; }

}  // namespace

const Tiling& tiling_named(const std::string& name) {
    if (name == kHexagonTiling.name) return kHexagonTiling;
    if (name == kTriangleTiling.name) return kTriangleTiling;
    throw std::invalid_argument("tiling must be 'hexagon' or 'triangle', got '" + name + "'");
}

Site site_at(const Tiling& t, const LatticeVector& v3) {
    for (int s = 0; s < t.sublattices; ++s) {
        const int a = v3[0] - t.site_offset3[s][0], b = v3[1] - t.site_offset3[s][1];
        if (positive_mod(a, 3) == 0 && positive_mod(b, 3) == 0) return {a / 3, b / 3, s};
    }
    throw std::invalid_argument(std::string("no site of the ") + t.name + " tiling at that point");
}

LatticeVector point_operation(int op, const LatticeVector& v) {
    if (op < 0 || op >= kPointGroupOrder) throw std::invalid_argument("op must lie in [0, 12)");
    LatticeVector w = op >= 6 ? LatticeVector{-v[0] - v[1], v[1]} : v;
    for (int k = 0; k < op % 6; ++k) w = {-w[1], w[0] + w[1]};
    return w;
}

Eigen::Matrix2d point_operation_matrix(int op) {
    if (op < 0 || op >= kPointGroupOrder) throw std::invalid_argument("op must lie in [0, 12)");
    const double angle = (op % 6) * M_PI / 3;
    Eigen::Matrix2d r;
    r << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
    if (op >= 6) r.col(0) = -r.col(0);  // the mirror x -> -x first
    return r;
}

std::vector<int> point_group_operations(PointGroup group) {
    // Rotations by 0, 120, 240 degrees are ops 0, 2, 4; ops 6, 8, 10 mirror x -> -x (axis at 90
    // degrees) and then rotate by 0, 120, 240 degrees, which turns the axis to 90, 150, 210 (=30).
    if (group == PointGroup::C3) return {0, 2, 4};
    return {0, 2, 4, 6, 8, 10};
}

}  // namespace pyfrustrate
