"""The workflow's configuration against its schema (config/schema.yaml): both profiles are valid,
and a misspelt key or a bad value is refused with a message naming it (a misspelt key would
otherwise be ignored silently and the default used)."""
import copy
from pathlib import Path

import pytest

yaml = pytest.importorskip("yaml")
snakemake_utils = pytest.importorskip("snakemake.utils")

ROOT = Path(__file__).resolve().parents[1]
SCHEMA = str(ROOT / "config" / "schema.yaml")


def load(name):
    return yaml.safe_load((ROOT / "config" / name).read_text())


def merged(base, override):
    out = copy.deepcopy(base)
    for key, value in override.items():
        out[key] = merged(out.get(key, {}), value) if isinstance(value, dict) else value
    return out


def validate(config):
    snakemake_utils.validate(copy.deepcopy(config), SCHEMA)


def test_both_profiles_are_valid():
    quick = load("config.yaml")
    validate(quick)
    validate(merged(quick, load("paper.yaml")))


@pytest.mark.parametrize("section, key, value, named", [
    ("continuum", "ell_study", {"particles": 5}, "ell_study"),        # a key in the wrong section
    ("montecarlo", "sweps", 100, "sweps"),                            # a misspelt key
    ("montecarlo", "method", "magic", "magic"),                       # a value outside the choices
    ("random", "draws", -1, "draws"),                                 # a value out of range
])
def test_bad_keys_and_values_are_refused_naming_them(section, key, value, named):
    config = load("config.yaml")
    config[section][key] = value
    with pytest.raises(Exception, match=named):
        validate(config)
