"""A study's results as a text table: one line per case, its swept values, energies and status."""

from __future__ import annotations

from scalf_opt.studies.runner import StudyRun


def _cell(value: object) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value)


def _energy(value: float | None) -> str:
    """An energy [J] to the millijoule, as the other commands' tables print them."""
    return "" if value is None else f"{value:.3f}"


def results_table(name: str, result: StudyRun) -> str:
    """The results as a text table, and the files written."""
    swept = result.columns[1 : result.columns.index("status")]
    header = ["case", *(s.split(".")[-1] for s in swept), "reference J", "optimized J", "saving"]
    lines = [f"study {name}: {len(result.rows)} cases ({result.cached} from the cache)"]
    lines.append("  ".join(f"{h:>12s}" for h in header) + "  status")
    for row in result.rows:
        cells = [str(row["case"]), *(_cell(row[s]) for s in swept)]
        cells += [_energy(row["reference_energy_j"]), _energy(row["optimized_energy_j"])]
        cells.append(f"{row['saving_pct']:.2f} %" if row["saving_pct"] is not None else "")
        status = row["status"] + (f": {row['error']}" if row["error"] else "")
        lines.append("  ".join(f"{c:>12s}" for c in cells) + f"  {status}")
    lines.append(f"wrote {result.results_path} and {result.figure_path}")
    return "\n".join(lines)
