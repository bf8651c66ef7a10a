"""Run a workflow or figure script as Snakemake would, without Snakemake: the ``snakemake`` object
its rule would give it (inputs, outputs, log, params by name), for tests that drive the real
scripts on small inputs."""
import runpy
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


class Named(list):
    """A Snakemake name list: positional items, some also by name."""

    def __init__(self, items=(), **named):
        super().__init__(list(items) + list(named.values()))
        self.__dict__.update(named)


class Params(dict):
    """Snakemake params or wildcards: by key and by attribute."""

    __getattr__ = dict.__getitem__


class Job:
    """The ``snakemake`` object a rule's script sees."""

    def __init__(self, rule, inputs, outputs, log, params):
        self.rule, self.input, self.output, self.log = rule, inputs, outputs, Named([str(log)])
        self.params, self.wildcards = Params(params), Params()


def run_script(script: str, rule: str, tmp_path: Path, inputs: Named, outputs: Named, params=None):
    """Run ``script`` (relative to the repository) as rule ``rule`` would, its log in ``tmp_path``."""
    job = Job(rule, inputs, outputs, tmp_path / f"{rule}.log", params or {})
    runpy.run_path(str(ROOT / script), init_globals={"snakemake": job}, run_name="__snakemake__")
