"""The documentation's measured numbers (docs/_ext/measured_values.py): a selector picks exactly
one value from a result file, or fails loudly; checked on files written here with known content
(a JSON object with nested records, a CSV file with the project's provenance comment line)."""
from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "docs" / "_ext"))
from measured_values import formatted, load, select  # noqa: E402


@pytest.fixture
def line_tension(tmp_path):
    rows = [{"ell": 20.0, "cut": 0, "curved": True, "Gamma": {"gamma = g": 1.0012, "gamma = 4g/sqrt3 (supplement)": 2.3122}},
            {"ell": 20.0, "cut": 0, "curved": False, "Gamma": {"gamma = g": 1.0009, "gamma = 4g/sqrt3 (supplement)": 2.3116}},
            {"ell": 5.0, "cut": 1, "curved": False, "Gamma": {"gamma = g": 0.87, "gamma = 4g/sqrt3 (supplement)": 2.0}}]
    path = tmp_path / "line_tension.json"
    path.write_text(json.dumps({"eps": 0.001, "rows": rows}))
    return path


@pytest.fixture
def relax_table(tmp_path):
    path = tmp_path / "relax.csv"
    path.write_text('# provenance: {"git_commit": "abc"}\n'
                    "scene,path,speedup_min\n"
                    "disk R=10,newton cold,6.61\n"
                    "disk R=10,newton cached,31.7\n"
                    "fibre W=30,newton cold,186.1\n")
    return path


def test_json_key_path_with_record_filter_and_quoted_key(line_tension):
    data = load(line_tension)
    assert select(data, ".eps") == 0.001
    # Numbers and booleans compare by value, whatever their spelling in the selector.
    assert select(data, '.rows[ell=20,cut=0,curved=True].Gamma."gamma = g"') == 1.0012
    assert select(data, '.rows[ell=20.0, curved=False].Gamma."gamma = 4g/sqrt3 (supplement)"') == 2.3116


def test_csv_rows_skip_the_provenance_comment(relax_table):
    rows = load(relax_table)
    assert [row["scene"] for row in rows] == ["disk R=10", "disk R=10", "fibre W=30"]
    assert select(rows, "[scene=disk R=10,path=newton cached].speedup_min") == "31.7"
    assert formatted(select(rows, "[scene=fibre W=30,path=newton cold].speedup_min"), ".0f") == "186"


@pytest.mark.parametrize("selector, error", [
    ("[scene=disk R=10].speedup_min", KeyError),          # two rows match: ambiguous
    ("[scene=disk R=99].speedup_min", KeyError),          # none matches
    ("[scene=disk R=10,path=newton cold].missing", KeyError),
    ("speedup_min", ValueError),                           # not a selector
    ("[scene]", ValueError),                               # a condition without a value
])
def test_a_selector_that_does_not_pick_one_value_fails(relax_table, selector, error):
    with pytest.raises(error):
        select(load(relax_table), selector)


def test_other_file_types_are_refused(tmp_path):
    path = tmp_path / "numbers.txt"
    path.write_text("1\n")
    with pytest.raises(ValueError, match="txt"):
        load(path)
