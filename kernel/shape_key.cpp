#include "shape_key.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace pyfrustrate {
namespace {

constexpr std::int64_t kBias = std::int64_t(1) << 31;

// Site relative to the canonical origin (i >= 0) as one integer ordered like (i, j, sublattice).
std::int64_t pack(const Site& s) {
    return (static_cast<std::int64_t>(s[0]) << 33) + ((s[1] + kBias) << 1) + s[2];
}
Site unpack(std::int64_t code) {
    return {static_cast<int>(code >> 33), static_cast<int>(((code >> 1) & 0xffffffffLL) - kBias),
            static_cast<int>(code & 1)};
}

}  // namespace

std::vector<int> shape_symmetries(const Tiling& tiling, PointGroup particle) {
    std::vector<Eigen::Matrix2d> own;
    for (const int op : point_group_operations(particle)) own.push_back(point_operation_matrix(op));
    std::vector<int> kept;
    for (int op = 0; op < kPointGroupOrder; ++op) {
        const Eigen::Matrix2d G = point_operation_matrix(op);
        bool symmetry = true;
        for (int s = 0; s < tiling.sublattices && symmetry; ++s) {
            const int image = transform_site(tiling, op, {0, 0, s})[2];
            const Eigen::Matrix2d local = frame_matrix(tiling, image).transpose() * G * frame_matrix(tiling, s);
            symmetry = std::any_of(own.begin(), own.end(), [&](const Eigen::Matrix2d& m) { return (m - local).norm() < 1e-9; });
        }
        if (symmetry) kept.push_back(op);
    }
    return kept;
}

std::size_t ShapeKeyHash::operator()(const ShapeKey& key) const {
    std::uint64_t h = 0x9e3779b97f4a7c15ULL ^ key.size();
    for (const std::int64_t v : key) {
        std::uint64_t z = static_cast<std::uint64_t>(v) + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        h ^= z ^ (z >> 31);
    }
    return static_cast<std::size_t>(h);
}

ShapeKey finite_shape_key(const Tiling& tiling, const std::vector<int>& symmetries, const std::vector<Site>& sites,
                          std::vector<Site>* canonical_sites) {
    const std::size_t n = sites.size();
    ShapeKey best, work(n);
    std::vector<Site> moved(n);
    bool first = true;
    for (const int op : symmetries) {
        Site lo{std::numeric_limits<int>::max(), std::numeric_limits<int>::max(), 0};
        for (std::size_t k = 0; k < n; ++k) {
            moved[k] = op == 0 ? sites[k] : transform_site(tiling, op, sites[k]);
            if (moved[k] < lo) lo = moved[k];
        }
        for (std::size_t k = 0; k < n; ++k) work[k] = pack({moved[k][0] - lo[0], moved[k][1] - lo[1], moved[k][2]});
        std::sort(work.begin(), work.end());
        if (first || work < best) best.swap(work), work.resize(n);
        first = false;
    }
    if (canonical_sites) *canonical_sites = key_sites(best);
    return best;
}

std::vector<Site> key_sites(const ShapeKey& key) {
    std::vector<Site> sites(key.size());
    for (std::size_t k = 0; k < key.size(); ++k) sites[k] = unpack(key[k]);
    return sites;
}

ShapeKey wrapped_shape_key(const Cluster& cl, int L) {
    ShapeKey key{-cl.rank(), L, cl.a, cl.b, cl.c};
    key.insert(key.end(), cl.members.begin(), cl.members.end());
    std::sort(key.begin() + 5, key.end());
    return key;
}

}  // namespace pyfrustrate
