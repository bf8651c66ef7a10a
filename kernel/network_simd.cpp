// The finite-network energy of the hexagon compiled for AVX-512 (x86-64-v4: eight doubles per
// instruction) and chosen at run time: the extension itself is built for the baseline x86-64,
// so that it runs on every node of a cluster. Measured at R = 25 on the development machine:
// 30 ns per particle instead of 111 for the scalar loop (16 or 32 lanes: no faster; the spring
// loop waits on its divisions and square roots). AVX2 (four lanes) was slower than the scalar
// loop there, so only AVX-512 is used. This file is compiled with -ffp-contract=off
// (CMakeLists.txt): no fused multiply-add, the same bits as the scalar loop.
#include "hexagon.hpp"
#include "network.hpp"

namespace pyfrustrate {

#if defined(__x86_64__) && defined(__GNUC__) && !defined(PYFRUSTRATE_NO_SIMD)

namespace {

__attribute__((target("arch=x86-64-v4"), flatten)) double hexagon_finite_energy_avx512(const HexagonModel& model,
                                                                                         const Topology& topology,
                                                                                         const double* u, double* g) {
    return finite_energy_lanes<HexagonModel, 8>(model, topology, u, g);
}

bool has_avx512() {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
           __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl");
}

// Without AVX-512 (or below eight particles) the same lanes, four at a time, for the baseline
// x86-64 (SSE2): measured 100 instead of 111 ns per particle for the scalar loop at R = 25.
__attribute__((flatten)) double hexagon_finite_energy_baseline(const HexagonModel& model, const Topology& topology,
                                                               const double* u, double* g) {
    return finite_energy_lanes<HexagonModel, 4>(model, topology, u, g);
}

}  // namespace

bool vectorised_evaluation_available() {
    static const bool available = has_avx512();
    return available;
}


bool vectorised_finite_energy(const HexagonModel& model, const Topology& topology, const double* u, double* gradient,
                              double& total) {
    if (topology.n_particles() < 4) return false;
    total = vectorised_evaluation_available() && topology.n_particles() >= 8
                ? hexagon_finite_energy_avx512(model, topology, u, gradient)
                : hexagon_finite_energy_baseline(model, topology, u, gradient);
    return true;
}

#else

bool vectorised_evaluation_available() { return false; }

bool vectorised_finite_energy(const HexagonModel&, const Topology&, const double*, double*, double&) { return false; }

#endif

}  // namespace pyfrustrate
