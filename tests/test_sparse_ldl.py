"""The kernel's own sparse LDL^T (kernel/cholesky.cpp), the factorisation of the Monte Carlo's warm
Newton steps: its ordering is AMD's on the quotient graph of nodes (a network's corners, two
coordinates each) without CHOLMOD's analysis, and the two rows of a node are factorised together.
Reference: numpy's dense solve of the same matrix. The matrices are those of networks in miniature:
symmetric positive definite, every pair of nodes either fully coupled (a 2 x 2 block) or not at
all, some nodes with one coordinate only (as a pinned coordinate leaves one)."""
import numpy as np
import pytest

from pyfrustrate import _kernel


def node_matrix(rng, nodes, reach, single_share=0.1, dominance=1.0, links=3):
    """(A, node_of, mask): a symmetric matrix on the nodes' coordinates, each node coupled to
    `links` draws among the next `reach` nodes; dominance >= 1: diagonally dominant, hence
    positive definite."""
    node_of = np.concatenate([[v] * (1 if rng.random() < single_share else 2) for v in range(nodes)]).astype(int)
    linked = np.eye(nodes, dtype=bool)
    for v in range(nodes):
        for w in v + 1 + rng.integers(0, reach, size=links):
            if w < nodes:
                linked[v, w] = linked[w, v] = True
    mask = linked[np.ix_(node_of, node_of)]
    A = np.where(mask, rng.uniform(-1, 1, size=mask.shape), 0.0)
    A = np.triu(A) + np.triu(A, 1).T
    np.fill_diagonal(A, dominance * np.abs(A).sum(axis=1) + 0.1)
    return A, node_of, mask


def upper_csc(A, mask):
    n = len(A)
    column_start, row, values = [0], [], []
    for j in range(n):
        rows = [i for i in range(j + 1) if mask[i, j]]
        row += rows
        values += [A[i, j] for i in rows]
        column_start.append(len(row))
    return column_start, row, values


@pytest.mark.parametrize("seed", range(6))
def test_own_ldl_solves_like_a_dense_solve(seed):
    rng = np.random.default_rng(seed)
    A, node_of, mask = node_matrix(rng, nodes=int(rng.integers(5, 150)), reach=6)
    b = rng.standard_normal(len(A))
    reference = np.linalg.solve(A, b)
    column_start, row, values = upper_csc(A, mask)
    x, own, cholmod, pairs = _kernel._sparse_ldl_solve(len(A), column_start, row, values, list(node_of), b)
    assert own and not cholmod  # the whole analysis without CHOLMOD
    assert pairs >= 0.5 * np.sum(np.bincount(node_of) == 2)  # the paired rows run
    assert np.linalg.norm(x - reference) <= 1e-12 * np.linalg.norm(reference)
    # CHOLMOD's ordering, the same own factorisation (pairs found where its order keeps them adjacent)
    y, own, cholmod, _ = _kernel._sparse_ldl_solve(len(A), column_start, row, values, [], b)
    assert own and cholmod
    assert np.linalg.norm(y - reference) <= 1e-12 * np.linalg.norm(reference)


def test_indefinite_matrices_are_refused():
    """A pivot that is not positive, in a single row or in either row of a pair, refuses the
    factorisation (Newton then damps the Hessian)."""
    rng = np.random.default_rng(11)
    A, node_of, mask = node_matrix(rng, nodes=60, reach=4, single_share=0.2)
    column_start, row, values = upper_csc(A, mask)
    b = np.ones(len(A))
    for k in rng.choice(len(A), size=12, replace=False):
        B = A.copy()
        B[k, k] = -1.0
        assert np.min(np.linalg.eigvalsh(B)) < 0
        _, _, bad = upper_csc(B, mask)
        x, own, _, _ = _kernel._sparse_ldl_solve(len(A), column_start, row, bad, list(node_of), b)
        assert own and x is None
    # Positive definite but not diagonally dominant: still factorised, still exact.
    C, node_of, mask = node_matrix(rng, nodes=60, reach=4, dominance=0.3)
    C += (0.1 - min(0.0, np.min(np.linalg.eigvalsh(C)))) * np.eye(len(C))
    column_start, row, values = upper_csc(C, mask)
    b = np.ones(len(C))
    x, _, _, _ = _kernel._sparse_ldl_solve(len(C), column_start, row, values, list(node_of), b)
    reference = np.linalg.solve(C, b)
    assert np.linalg.norm(x - reference) <= 1e-10 * np.linalg.norm(reference)


def test_dense_factors_go_to_cholmod():
    """Where the factor is dense enough for CHOLMOD's supernodal factorisation (its rule: 40 flops
    per entry of L), CHOLMOD analyses and factorises, and the solution is the same."""
    rng = np.random.default_rng(3)
    A, node_of, mask = node_matrix(rng, nodes=80, reach=80, single_share=0.0, links=40)
    column_start, row, values = upper_csc(A, mask)
    b = rng.standard_normal(len(A))
    x, own, cholmod, _ = _kernel._sparse_ldl_solve(len(A), column_start, row, values, list(node_of), b)
    assert cholmod and not own
    assert np.allclose(x, np.linalg.solve(A, b), rtol=0, atol=1e-12 * np.abs(x).max())


def test_bad_patterns_are_refused():
    A, node_of, mask = node_matrix(np.random.default_rng(0), nodes=10, reach=3)
    column_start, row, values = upper_csc(A, mask)
    n, b = len(A), np.ones(len(A))
    with pytest.raises(ValueError, match="node_of"):
        _kernel._sparse_ldl_solve(n, column_start, row, values, [-1] + list(node_of[1:]), b)
    swapped = list(row)
    swapped[-1], swapped[-2] = swapped[-2], swapped[-1]  # the last column's diagonal not last
    with pytest.raises(ValueError, match="increasing"):
        _kernel._sparse_ldl_solve(n, column_start, swapped, values, list(node_of), b)
    with pytest.raises(ValueError, match="compressed-column"):
        _kernel._sparse_ldl_solve(n, column_start[:-1], row, values, list(node_of), b)
    with pytest.raises(ValueError, match="rhs"):
        _kernel._sparse_ldl_solve(n, column_start, row, values, list(node_of), b[1:])
