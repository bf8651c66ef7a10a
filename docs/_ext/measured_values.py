"""Reading one measured value from a result file (JSON, or CSV with '#' comment lines), for the
documentation's ``measured`` role (docs/_ext/measured.py); free of Sphinx so that the tests can
import it. The selector syntax is described in measured.py."""
from __future__ import annotations

import csv
import io
import json
import re
from pathlib import Path

_TOKEN = re.compile(r'\.(?:"([^"]*)"|([^.\[\]"]+))|\[([^\]]*)\]')


def load(file: Path):
    text = file.read_text()
    if file.suffix == ".json":
        return json.loads(text)
    if file.suffix == ".csv":
        # The first line of the project's CSV files is a '#' comment holding their provenance.
        body = "\n".join(line for line in text.splitlines() if not line.startswith("#"))
        return list(csv.DictReader(io.StringIO(body)))
    raise ValueError(f"measured: cannot read '{file.suffix}' files ({file})")


def _equal(field, wanted: str) -> bool:
    if str(field) == wanted:
        return True
    try:
        return float(field) == float(wanted)
    except (TypeError, ValueError):
        return False


def select(data, selector: str):
    """Walk ``data`` along ``selector`` (see the module's docstring)."""
    position = 0
    for match in _TOKEN.finditer(selector):
        if match.start() != position:
            raise ValueError(f"cannot parse selector '{selector}' at '{selector[position:]}'")
        position = match.end()
        key = match.group(1) if match.group(1) is not None else match.group(2)
        if key is not None:
            if not isinstance(data, dict) or key not in data:
                keys = sorted(data) if isinstance(data, dict) else type(data).__name__
                raise KeyError(f"no key '{key}' (have: {keys})")
            data = data[key]
            continue
        conditions = [part.split("=", 1) for part in match.group(3).split(",")]
        if not isinstance(data, list) or any(len(c) != 2 for c in conditions):
            raise ValueError(f"'[{match.group(3)}]' needs a list of records and k=v conditions")
        found = [r for r in data if all(k.strip() in r and _equal(r[k.strip()], v.strip()) for k, v in conditions)]
        if len(found) != 1:
            raise KeyError(f"[{match.group(3)}] matches {len(found)} records, not one")
        data = found[0]
    if position != len(selector):
        raise ValueError(f"cannot parse selector '{selector}' at '{selector[position:]}'")
    return data


def formatted(value, spec: str) -> str:
    if not spec:
        return str(value)
    try:
        return format(float(value), spec)
    except (TypeError, ValueError):
        return format(value, spec)
