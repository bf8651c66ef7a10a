// The move families of the chain, in the order it tries them: each optional family is taken with
// its probability (one deviate each, drawn only when that probability is positive, so a chain
// without it keeps its random sequence); the last, particle moves, takes the rest.
#pragma once

#include "montecarlo/cluster_move.hpp"
#include "montecarlo/isometry_move.hpp"
#include "montecarlo/outline_move.hpp"
#include "montecarlo/particle_move.hpp"
#include "montecarlo/surface_move.hpp"
#include "montecarlo/vacancy_move.hpp"

#include <tuple>

namespace pyfrustrate {

using MoveFamilies = std::tuple<OutlineMove, ClusterMove, ShiftMove, RotationMove, ReflectionMove, CarryMove, VacancyMove,
                                SurfaceMove, ParticleMove>;

template <class Tuple>
struct CountersOf;
template <class... Moves>
struct CountersOf<std::tuple<Moves...>> {
    using type = std::tuple<typename Moves::Counters...>;
};
using MoveCounters = CountersOf<MoveFamilies>::type;

}  // namespace pyfrustrate
