"""Trajectories of Monte Carlo runs as GSD files (HOOMD-blue's format, read by OVITO and freud).

Each frame holds the occupied lattice sites as particles: ``particles.position`` their centres
(the site positions of ``topology.site_positions``, wrapped into the box centred on the origin,
z = 0), ``particles.typeid`` the sublattice (``types``: ``["hexagon"]``, or ``["up", "down"]``
triangles), ``configuration.box`` the periodic box of ``box x box`` cells as HOOMD's triclinic box
``[Lx, Ly, Lz, xy, xz, yz] = [L, L sqrt(3)/2, 1, 1/sqrt(3), 0, 0]`` (``dimensions = 2``),
``configuration.step`` the attempted moves done (an exchange: rounds), and ``log`` the energy
(``pyfrustrate/energy``, in the particle's spring units) and the temperature
(``pyfrustrate/temperature``).
"""
from __future__ import annotations

import math
import os

import numpy as np

from .._checks import integer
from ..io import atomic_path
from ..topology import site_positions, tiling_facts

__all__ = ["Trajectory", "hoomd_box", "TYPES"]

TYPES = {"hexagon": ["hexagon"], "triangle": ["up", "down"]}


def hoomd_box(box: int) -> list[float]:
    """HOOMD's ``[Lx, Ly, Lz, xy, xz, yz]`` of the periodic box of ``box x box`` cells.

    Parameters
    ----------
    box : int
        Box side, in lattice cells.

    Returns
    -------
    list of float
        The box spanned by ``box a1 = (box, 0)`` and ``box a2 = (box/2, box sqrt(3)/2)``, in
        lattice spacings; Lz = 1 for a 2D box.

    Examples
    --------
    >>> from pyfrustrate.montecarlo.trajectory import hoomd_box
    >>> [round(x, 4) for x in hoomd_box(6)]
    [6.0, 5.1962, 1.0, 0.5774, 0.0, 0.0]
    """
    return [float(box), box * math.sqrt(3) / 2, 1.0, 1 / math.sqrt(3), 0.0, 0.0]


class Trajectory:
    """Write the frames of one run to ``path`` every ``every`` record units.

    Parameters
    ----------
    path : str or path-like
        The GSD file.
    every : int
        Record units (an anneal's blocks, an exchange's rounds) between frames, >= 1.
    particle : Hexagon, RandomHexagon or Triangle
        The run's particle (its tiling sets the particle types).
    box : int
        Box side, in lattice cells.

    Raises
    ------
    ValueError
        ``every`` below 1 (named ``trajectory_every``).
    """

    def __init__(self, path, every: int, particle, box: int):
        self.path, self.every, self.box = os.fspath(path), integer("trajectory_every", every, 1), box
        self.tiling = particle.tiling
        self.types = TYPES[self.tiling]
        self.sublattices = tiling_facts(self.tiling)["sublattices"]
        self._file = None

    @classmethod
    def for_run(cls, path, every, particle, box: int, units: int):
        """A writer for a run of ``units`` record units.

        Parameters
        ----------
        path : str, path-like or None
            The GSD file; None: no trajectory.
        every : int or None
            Record units between frames; None: about 100 frames over the run.
        particle : Hexagon, RandomHexagon or Triangle
            The run's particle.
        box : int
            Box side, in lattice cells.
        units : int
            Record units of the run.

        Returns
        -------
        Trajectory or None
            The writer, or None without ``path``.
        """
        if path is None:
            return None
        return cls(path, max(1, units // 100) if every is None else every, particle, box)

    def open(self, resume_step: int) -> None:
        """Start the file, or continue it after ``resume_step``.

        Parameters
        ----------
        resume_step : int
            The step the run resumes from (0: a new file). Frames written later by an
            interrupted run, beyond its checkpoint, are dropped.
        """
        import gsd.hoomd

        if resume_step > 0 and os.path.exists(self.path):
            with gsd.hoomd.open(self.path, "r") as old:
                kept = [frame for frame in old if frame.configuration.step <= resume_step]
            with atomic_path(self.path) as tmp, gsd.hoomd.open(tmp, "w") as f:
                for frame in kept:
                    f.append(frame)
            self._file = gsd.hoomd.open(self.path, "a")
        else:
            self._file = gsd.hoomd.open(self.path, "w")

    def close(self) -> None:
        """Close the file (if open)."""
        if self._file is not None:
            self._file.close()
            self._file = None

    def positions(self, coords) -> np.ndarray:
        """Return the centres of the sites ``coords``, wrapped into the box centred on the origin.

        Parameters
        ----------
        coords : array_like, shape (n, 2) or (n, 3), int
            Lattice coordinates (60-degree axes; the third column the sublattice).

        Returns
        -------
        ndarray, shape (n, 3), float32
            Positions in lattice spacings, z = 0.
        """
        coords = np.asarray(coords)
        xy = site_positions(coords, self.tiling)
        # Fractions of the box vectors (box a1, box a2), wrapped into [-1/2, 1/2).
        basis = self.box * np.array([[1.0, 0.5], [0.0, math.sqrt(3) / 2]])
        fractions = np.linalg.solve(basis, xy.T).T
        fractions -= np.floor(fractions + 0.5)
        out = np.zeros((len(coords), 3), np.float32)
        out[:, :2] = fractions @ basis.T
        return out

    def write(self, step: int, coords, energy: float, temperature: float) -> None:
        """One frame: the occupied sites ``coords`` after ``step``.

        Parameters
        ----------
        step : int
            Attempted moves done (an exchange: rounds).
        coords : array_like, shape (n, 2) or (n, 3), int
            Occupied sites, lattice coordinates.
        energy : float
            The configuration's energy, spring units.
        temperature : float
            The temperature, energy units.

        Raises
        ------
        RuntimeError
            The file was not opened (``open``).
        """
        import gsd.hoomd

        coords = np.asarray(coords)
        frame = gsd.hoomd.Frame()
        frame.configuration.step = int(step)
        frame.configuration.dimensions = 2
        frame.configuration.box = hoomd_box(self.box)
        frame.particles.N = len(coords)
        frame.particles.types = self.types
        frame.particles.position = self.positions(coords)
        frame.particles.typeid = (coords[:, 2] if coords.shape[1] == 3 else np.zeros(len(coords))).astype(np.uint32)
        frame.log["pyfrustrate/energy"] = np.array([energy], np.float64)
        frame.log["pyfrustrate/temperature"] = np.array([temperature], np.float64)
        if self._file is None:
            raise RuntimeError("trajectory: write before open")
        self._file.append(frame)

    def write_blocks(self, site_indices, steps, energies, temperatures, first_block: int) -> None:
        """Write the frames of the blocks whose number + 1 is a multiple of ``every``.

        Parameters
        ----------
        site_indices : sequence of array_like, int
            Per block, the kernel's sorted site indices (``sublattice + S (i + L j)``, ``S``
            sublattices, ``L`` the box side).
        steps : array_like, int
            Attempted moves done at the end of each block.
        energies, temperatures : array_like
            Energy and temperature of each block.
        first_block : int
            Number of the first block given.
        """
        S, L = self.sublattices, self.box
        for k in range(len(steps)):
            if (first_block + k + 1) % self.every:
                continue
            s = np.asarray(site_indices[k])
            cell = s // S
            coords = np.column_stack([cell % L, cell // L] + ([s % S] if S > 1 else []))
            self.write(int(steps[k]), coords, float(energies[k]), float(temperatures[k]))
