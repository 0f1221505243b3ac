"""`synth --front-dir DIR`: every design of a front as a result file (TOML, as `synth --format
toml` writes one), which `analyze` takes as is: `<stem>.front-<k>.toml`, k the row (from 0),
the report of that design alone (the file's sections, without the front)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path


def front_reports(result) -> list[dict]:
    """The report of each row's design of a solved front (empty without a front)."""
    from linkcli.analysis.sections import build
    solution = result.solution
    if solution is None or not solution.alternatives:
        return []
    problem = result.problem
    alone = replace(problem, meta=replace(problem.meta, front=None))
    return [build(alone, design) for design in solution.alternatives]


def write_front(result, folder: Path, stem: str, precision: int) -> list[Path]:
    """Write the front's result files; the paths written (OSError passes through)."""
    from linkcli.io.export import to_toml
    out = []
    reports = front_reports(result)
    width = len(str(max(len(reports) - 1, 0)))
    for k, report in enumerate(reports):
        target = folder / f"{stem}.front-{k:0{width}d}.toml"
        target.write_text(to_toml(report, precision), encoding="utf-8")
        out.append(target)
    return out
