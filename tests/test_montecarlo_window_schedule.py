"""The schedule that dwells in the reshaping window (``annealing.window_schedule``) and the window's
ends read from a heating ladder's stages (``fixed_size.reshaping_window``).

Checked against their definitions: the moves add up to the run, each part gets its fraction, the
window's temperatures span it geometrically, ``anneal`` runs the stages as given; bad input is
refused by name.
"""
import numpy as np
import pytest

from pyfrustrate import Hexagon, anneal, continuum
from pyfrustrate.montecarlo import MonteCarloOptions, window_schedule
from pyfrustrate.montecarlo.fixed_size import reshaping_temperature, reshaping_window


def test_the_stages_spend_their_fractions_in_the_window_and_end_with_a_quench():
    low, high, n, sweeps = 0.1, 0.2, 50, 400
    stages = window_schedule((low, high), n, sweeps=sweeps, T0=1.0, dwell=0.7, quench=0.1, dwell_stages=5,
                             entry_stages=3)
    T = np.array([t for t, _ in stages])
    moves = np.array([m for _, m in stages])
    assert moves.sum() == sweeps * n
    assert np.all(np.diff(T) <= 0) and T[0] == 1.0 and T[-1] == 0.0
    in_window = (T >= low - 1e-12) & (T <= high + 1e-12)
    assert moves[in_window].sum() == pytest.approx(0.7 * sweeps * n, abs=5)
    assert moves[T == 0].sum() == pytest.approx(0.1 * sweeps * n, abs=1)
    # Five temperatures from the top to the bottom of the window, in a constant ratio.
    window = T[in_window]
    assert len(window) == 5 and window[0] == high and window[-1] == pytest.approx(low)
    np.testing.assert_allclose(window[1:] / window[:-1], (low / high) ** 0.25)
    # The entry descends in equal steps from T0 towards the window's top.
    np.testing.assert_allclose(np.diff(T[:4]), (high - 1.0) / 3)


def test_a_run_may_start_in_the_window():
    stages = window_schedule((0.1, 0.3), 10, sweeps=20, T0=0.3, dwell=0.9, quench=0.1, dwell_stages=1)
    assert stages == [(0.3, 180), (0.0, 20)]


def test_reshaping_window_reads_the_ends_of_the_ladder():
    """The ladder of reshaping_temperature's example: holds up to 0.2, reshapes from 0.1."""
    T = [0.05] * 4 + [0.1] * 4 + [0.2] * 4 + [0.3] * 4
    E = [-20] * 4 + [-20, -20, -19.9, -19.9] + [-20, -19.8, -19.7, -19.7] + [-20, -18, -15, -14]
    accepted = [0] * 4 + [1] * 4 + [3] * 4 + [5] * 4
    top, stages = reshaping_temperature(T, E, accepted, n=10, g=1.0, reference_energy=-20.0)
    assert reshaping_window(stages) == (0.1, top) == (0.1, 0.2)


def test_anneal_runs_the_stages_as_given():
    particle = Hexagon.from_continuum(ell=5, nu=0.9, eps=0.01)
    g = float(continuum.particle_parameters(5, 0.9, 0.5, eps=0.01).g)
    n = 12
    stages = window_schedule((0.1 * g, 0.2 * g), n, sweeps=30, T0=g, dwell=0.6, quench=0.2, dwell_stages=3,
                             entry_stages=2)
    options = MonteCarloOptions(method="linear", rotation_moves=0.1, reflection_moves=0.1, shift_moves=0.1)
    r = anneal(particle, g=g, box=10, n=n, seed=3, schedule=stages, options=options, progress=False)
    assert r.steps[-1] == 30 * n  # cumulative attempted moves
    expected = np.concatenate([np.full(-(-m // n), t) for t, m in stages])
    np.testing.assert_allclose(r.temperature, expected)


@pytest.mark.parametrize("kwargs,match", [
    (dict(window=(0.2, 0.1)), "window"),
    (dict(window=(0.0, 0.1)), "window"),
    (dict(window=0.1), "window"),
    (dict(window=(0.1, float("nan"))), "window"),
    (dict(n=0), "n"),
    (dict(sweeps=0), "sweeps"),
    (dict(T0=0.15), "T0"),
    (dict(dwell=0.0), "dwell"),
    (dict(quench=1.5), "quench"),
    (dict(dwell=0.8, quench=0.3), "dwell \\+ quench"),
    (dict(dwell_stages=0), "dwell_stages"),
    (dict(entry_stages=1.5), "entry_stages"),
    (dict(sweeps=1, n=3, dwell_stages=6), "too few"),
])
def test_bad_input_is_refused_by_name(kwargs, match):
    arguments = dict(window=(0.1, 0.2), n=10, sweeps=100, T0=1.0)
    arguments.update(kwargs)
    window, n = arguments.pop("window"), arguments.pop("n")
    with pytest.raises(ValueError, match=match):
        window_schedule(window, n, **arguments)


@pytest.mark.parametrize("stages", [None, [dict(T=0.1)], [dict(T=0.1, holds=False, reshapes=True)]])
def test_reshaping_window_refuses_stages_without_a_window(stages):
    with pytest.raises(ValueError, match="stages"):
        reshaping_window(stages)
