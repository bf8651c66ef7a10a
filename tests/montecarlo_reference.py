"""An independent Monte Carlo chain in Python on the kernel's exact energies, for the tests that
show the exact-enumeration checks can fail (tests/test_montecarlo_rules.py).

The moves are written again from their definitions (``kernel/montecarlo`` and the docstring of
``pyfrustrate.anneal``): a particle to a random empty site; a surface move (a random particle
with an empty neighbour to a random empty site with an occupied neighbour, Hastings ratio
``n_s n_p / (n_s' n_p')``); a linked cluster move (a set grown by following each bond with
probability ``link``, shifted by a random cell vector, Hastings factor ``(1 - link)**(b' - b)``);
a vacancy move (with probability 1/2 a particle with an empty neighbour to a random hole, an empty
site whose neighbours are all occupied, else a particle whose neighbours are all occupied to a
random empty site with an occupied and an empty neighbour; Hastings ratio ``n_s n_h / (n_i' n_p')``
for a fill, ``n_i n_p / (n_s' n_h')`` for a dig); an outline move (grand-canonical, ``kernel/montecarlo/outline_move.hpp``: with probability 1/2 a
particle inserted on a random empty site next to the aggregate, else a random removable particle
deleted, removability found by a search of the rest rather than by articulation points; Hastings
ratio e(C) / d(C') for an insertion, d(C) / e(C') for a deletion, ``mu`` per particle gained). With
outline moves the ``states`` are the connected aggregates, and any other move that leaves them is
refused.
Plain Metropolis-Hastings, hexagon tiling, sites numbered ``i + box j`` as ``enumerate_states``
numbers them. ``wrong`` names one deliberately wrong rule:

``"double_deformation"``  the deformation part of the energy change counted twice;
``"link_p"``              ``link**(b' - b)`` in place of ``(1 - link)**(b' - b)``;
``"no_surface_ratio"``    surface moves accepted without their Hastings ratio;
``"no_vacancy_ratio"``    vacancy moves accepted without their Hastings ratio;
``"outline_counts_dropped"``  outline moves accepted without their Hastings ratio;
``"outline_counts_swapped"``  with its inverse (the reverse move's choices over the forward's).
``"no_isometry_factor"``  isometry moves accepted without ``(1 - link)**(b' - b)``;
``"stale_rest"``          isometry moves count the bonds after the move (b') as if the set's old
                          sites were still occupied, the slip an in-place move invites (a turned or
                          mirrored set always overlaps its image at the seed).

Isometry moves (``kernel/montecarlo/isometry_move.hpp``): a set grown as for the cluster move,
seeded at a random particle, then shifted by one of the six neighbour vectors, turned by +-60
degrees about the seed's site, or mirrored about one of the six axes through it; Hastings factor
``(1 - link)**(b' - b)``. The maps are written here as integer matrices on lattice coordinates.

A chain with the right rules must sample the exact Boltzmann weights; with a wrong one, it must
not, by the same statistic and at the same sample size as the kernel's test.
"""
from __future__ import annotations

import math

import numpy as np

from pyfrustrate import topology as T

NEIGHBOURS = [tuple(int(x) for x in d) for d in T.NEIGHBOURS]
WRONG_RULES = ("double_deformation", "link_p", "no_surface_ratio", "no_vacancy_ratio", "outline_counts_dropped", "outline_counts_swapped",
               "no_isometry_factor", "stale_rest")
TURN = np.array([[0, -1], [1, 1]])  # +60 degrees: (i, j) -> (-j, i + j)
MIRROR = np.array([[-1, -1], [0, 1]])  # about the axis at 90 degrees: (i, j) -> (-i - j, j)
#: The isometries' linear parts: the two turns, and the six mirrors (the mirror turned by k 60 degrees).
TURNS = (TURN, np.linalg.matrix_power(TURN, 5))
MIRRORS = tuple(np.linalg.matrix_power(TURN, k) @ MIRROR for k in range(6))
ISOMETRY_KINDS = ("shift", "rotation", "reflection")


def bonds_of(state, box):
    """Bound pairs of sides of a state (a tuple of site numbers) on the torus."""
    occupied = set(state)
    return sum(((k % box + di) % box) + box * ((k // box + dj) % box) in occupied
               for k in state for di, dj in NEIGHBOURS) // 2


class ReferenceChain:
    """Metropolis-Hastings over the enumerated ``states`` with energies ``E`` (``bonds`` per state,
    so that ``E + g bonds`` is the deformation part)."""

    def __init__(self, states, E, g, box, *, surface_moves=0.0, cluster_moves=0.0, link=1.0, outline_moves=0.0, mu=0.0,
                 isometry_moves=None, isometry_link=0.3, vacancy_moves=0.0, wrong=None, seed=0):
        if wrong not in (None,) + WRONG_RULES:
            raise ValueError(f"wrong must be one of {WRONG_RULES} or None, got {wrong!r}")
        self.index = {s: k for k, s in enumerate(states)}
        self.E = np.asarray(E, float)
        self.deformation = self.E + g * np.array([bonds_of(s, box) for s in states])
        self.box, self.g = box, g
        self.surface_moves, self.cluster_moves, self.link, self.wrong = surface_moves, cluster_moves, link, wrong
        self.outline_moves, self.mu = outline_moves, mu
        self.vacancy_moves = vacancy_moves
        self.sizes = np.array([len(s) for s in states])
        # {"shift": probability, ...}: tried in that order before the other moves, as the kernel does
        self.isometry_moves = dict(isometry_moves or {})
        if set(self.isometry_moves) - set(ISOMETRY_KINDS):
            raise ValueError(f"isometry_moves: keys must be among {ISOMETRY_KINDS}, got {sorted(self.isometry_moves)}")
        self.isometry_link = isometry_link
        self.rng = np.random.default_rng(seed)
        self.neighbours = [[((k % box + di) % box) + box * ((k // box + dj) % box) for di, dj in NEIGHBOURS]
                           for k in range(box * box)]

    def _accept(self, old, new, log_hastings, T_):
        delta = self.E[new] - self.E[old] - self.mu * (self.sizes[new] - self.sizes[old])
        if self.wrong == "double_deformation":
            delta += self.deformation[new] - self.deformation[old]
        log_ratio = -delta / T_ + log_hastings
        return log_ratio >= 0 or self.rng.random() < math.exp(log_ratio)

    def _occupied_neighbours(self, site, occupied):
        return sum(u in occupied for u in self.neighbours[site])

    def _particle_proposal(self, occupied):
        a = sorted(occupied)[self.rng.integers(len(occupied))]
        empty = [s for s in range(self.box * self.box) if s not in occupied]
        return a, empty[self.rng.integers(len(empty))], 0.0

    def _exposed(self, occupied):
        D = len(NEIGHBOURS)
        surface = sorted(s for s in occupied if self._occupied_neighbours(s, occupied) < D)
        perimeter = sorted({u for s in occupied for u in self.neighbours[s] if u not in occupied})
        return surface, perimeter

    def _surface_proposal(self, occupied):
        surface, perimeter = self._exposed(occupied)
        a, b = surface[self.rng.integers(len(surface))], perimeter[self.rng.integers(len(perimeter))]
        after = (occupied - {a}) | {b}
        # The reverse move exists iff a keeps an occupied neighbour and b has an empty one.
        if self._occupied_neighbours(a, after) == 0 or self._occupied_neighbours(b, after) == len(NEIGHBOURS):
            return None
        surface_after, perimeter_after = self._exposed(after)
        log_ratio = math.log(len(surface) * len(perimeter) / (len(surface_after) * len(perimeter_after)))
        return a, b, 0.0 if self.wrong == "no_surface_ratio" else log_ratio

    def _vacancy_kinds(self, occupied):
        """(surface, interior, holes, perimeter): particles with and without an empty neighbour,
        empty sites with every neighbour occupied and with some but not all."""
        D = len(NEIGHBOURS)
        count = {s: self._occupied_neighbours(s, occupied) for s in range(self.box * self.box)}
        surface = sorted(s for s in occupied if count[s] < D)
        interior = sorted(s for s in occupied if count[s] == D)
        holes = sorted(s for s in count if s not in occupied and count[s] == D)
        perimeter = sorted(s for s in count if s not in occupied and 0 < count[s] < D)
        return surface, interior, holes, perimeter

    def _vacancy_proposal(self, occupied):
        surface, interior, holes, perimeter = self._vacancy_kinds(occupied)
        fill = self.rng.random() < 0.5
        sources, targets = (surface, holes) if fill else (interior, perimeter)
        if not sources or not targets:
            return None
        a, b = sources[self.rng.integers(len(sources))], targets[self.rng.integers(len(targets))]
        after = (occupied - {a}) | {b}
        surface_after, interior_after, holes_after, perimeter_after = self._vacancy_kinds(after)
        # The reverse draws b from the interior (fill) or the surface (dig), and a among the
        # perimeter (fill) or the holes (dig).
        if fill and (b not in interior_after or a not in perimeter_after):
            return None
        if not fill and (b not in surface_after or a not in holes_after):
            return None
        if fill:
            ratio = len(surface) * len(holes) / (len(interior_after) * len(perimeter_after))
        else:
            ratio = len(interior) * len(perimeter) / (len(surface_after) * len(holes_after))
        return a, b, 0.0 if self.wrong == "no_vacancy_ratio" else math.log(ratio)

    def _grow(self, a, occupied, link):
        grown, queue = {a}, [a]
        for s in queue:  # every bond from the set to the rest tested once
            for u in self.neighbours[s]:
                if u in occupied and u not in grown and self.rng.random() < link:
                    grown.add(u)
                    queue.append(u)
        return grown

    def _moved(self, grown, occupied, image, factor, stale=False):
        """(occupancy after, log Hastings factor) of the set ``grown`` sent to ``image(site)``, or
        None; ``stale``: b' counted against the rest and the set's old sites (wrong)."""
        rest = occupied - grown
        moved = {image(s) for s in grown}
        if moved & rest:
            return None
        before = sum(u in rest for s in grown for u in self.neighbours[s])
        after_rest = (occupied - moved) if stale else rest
        after = sum(u in after_rest for s in moved for u in self.neighbours[s])
        if after != before and factor == 0:
            return None
        return rest | moved, (after - before) * math.log(factor) if after != before else 0.0

    def _site(self, i, j):
        return int(i) % self.box + self.box * (int(j) % self.box)

    def _cluster_proposal(self, occupied):
        a = sorted(occupied)[self.rng.integers(len(occupied))]
        shift = (int(self.rng.integers(self.box)), int(self.rng.integers(self.box)))
        if shift == (0, 0):
            return None
        grown = self._grow(a, occupied, self.link)
        factor = self.link if self.wrong == "link_p" else 1.0 - self.link
        return self._moved(grown, occupied, lambda s: self._site(s % self.box + shift[0], s // self.box + shift[1]),
                           factor)

    def _isometry_proposal(self, occupied, kind):
        a = sorted(occupied)[self.rng.integers(len(occupied))]
        seed = np.array([a % self.box, a // self.box])
        if kind == "shift":
            step = np.array(NEIGHBOURS[self.rng.integers(len(NEIGHBOURS))])
            linear = np.eye(2, dtype=int)
        elif kind == "rotation":
            step = np.zeros(2, int)
            linear = TURNS[self.rng.integers(len(TURNS))]
        else:
            step = np.zeros(2, int)
            linear = MIRRORS[self.rng.integers(len(MIRRORS))]
        grown = self._grow(a, occupied, self.isometry_link)
        factor = 1.0 if self.wrong == "no_isometry_factor" else 1.0 - self.isometry_link

        def image(s):  # seed + linear (x - seed) + step; the box's periods map to periods
            i, j = seed + linear @ (np.array([s % self.box, s // self.box]) - seed) + step
            return self._site(i, j)

        return self._moved(grown, occupied, image, factor, stale=self.wrong == "stale_rest")

    def _connected(self, occupied):
        if not occupied:
            return False
        start = next(iter(occupied))
        seen, queue = {start}, [start]
        for s in queue:
            for u in self.neighbours[s]:
                if u in occupied and u not in seen:
                    seen.add(u)
                    queue.append(u)
        return len(seen) == len(occupied)

    def _removable(self, occupied):
        """Particles whose removal leaves a connected, non-empty aggregate."""
        return sorted(s for s in occupied if len(occupied) > 1 and self._connected(occupied - {s}))

    def _outline_proposal(self, occupied):
        if self.rng.random() < 0.5:
            if len(occupied) + 1 >= self.box * self.box:
                return None
            outline = self._exposed(occupied)[1]
            after = occupied | {outline[self.rng.integers(len(outline))]}
            forward, reverse = len(outline), len(self._removable(after))
        else:
            removable = self._removable(occupied)
            if not removable:
                return None
            after = occupied - {removable[self.rng.integers(len(removable))]}
            forward, reverse = len(removable), len(self._exposed(after)[1])
        ratio = {"outline_counts_dropped": 1.0, "outline_counts_swapped": reverse / forward}.get(self.wrong,
                                                                                                 forward / reverse)
        return after, math.log(ratio)

    def _fixed_size_proposal(self, occupied):
        """(occupancy after, log Hastings ratio) of an isometry, cluster, surface or particle move, or
        (None, 0)."""
        u = self.rng.random()
        # As the kernel: a family that is off draws no deviate.
        kind = next((k for k in ISOMETRY_KINDS
                     if self.isometry_moves.get(k, 0.0) > 0 and self.rng.random() < self.isometry_moves[k]), None)
        if kind is not None:
            proposal = self._isometry_proposal(occupied, kind)
            return proposal if proposal else (None, 0.0)
        if u < self.cluster_moves:
            proposal = self._cluster_proposal(occupied)
            return proposal if proposal else (None, 0.0)
        if self.vacancy_moves and self.rng.random() < self.vacancy_moves:
            proposal = self._vacancy_proposal(occupied)
        else:
            proposal = (self._surface_proposal(occupied) if self.rng.random() < self.surface_moves
                        else self._particle_proposal(occupied))
        if not proposal:
            return None, 0.0
        a, b, log_hastings = proposal
        return (occupied - {a}) | {b}, log_hastings

    def run(self, start, T_, samples):
        """The state index after each of ``samples`` attempted moves at temperature ``T_``."""
        occupied = set(start)
        current = self.index[tuple(sorted(occupied))]
        visited = np.empty(samples, np.int64)
        for step in range(samples):
            # No deviate without outline moves: the other tests keep their random sequences.
            if self.outline_moves and self.rng.random() < self.outline_moves:
                proposal = self._outline_proposal(occupied)
                new_occupied, log_hastings = proposal if proposal else (None, 0.0)
            else:
                new_occupied, log_hastings = self._fixed_size_proposal(occupied)
            key = None if new_occupied is None else tuple(sorted(new_occupied))
            if self.outline_moves and key not in self.index:
                key = None  # a move that disconnects the aggregate: out of the state space
            if key is not None:
                new = self.index[key]
                if self._accept(current, new, log_hastings, T_):
                    occupied, current = new_occupied, new
            visited[step] = current
        return visited
