"""The command line: options, the table per area, the summary, ``--json``.

Exit status: 0 when every check holds or is not applicable, 1 when one differs,
crashed or timed out, 2 on a usage error (no library, an unknown area).
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time

from .checks import AREAS, CRASHED, DIFFERS, HOLDS, NOT_APPLICABLE, TIMED_OUT, VERDICTS, area_checks
from .host import default_library
from .runner import run


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m sf_tch.conformance",
                                description="Checks a library exporting the vendor's CNC module ABI against "
                                            "the vendor's documented behaviour, statement by statement.")
    p.add_argument("--library", metavar="PATH", help="the library to check (default: the one this package ships)")
    p.add_argument("--only", metavar="AREA", action="append", default=[],
                   help=f"run only these areas (repeat or comma-separate): {', '.join(AREAS)}")
    p.add_argument("--json", action="store_true", help="print the results as one JSON document")
    p.add_argument("--timeout", type=float, default=30.0, metavar="S", help="time bound of each check (default 30)")
    p.add_argument("--list", action="store_true", help="list the checks and the statement each checks, run nothing")
    p.add_argument("--markdown", action="store_true", help="with --list: the tables of docs/conformance.md")
    p.add_argument("--verbose", "-v", action="store_true", help="list every check, not only those that do not hold")
    return p


def summary(results: list[dict]) -> dict:
    """How many checks got each verdict."""
    counts = {v: 0 for v in VERDICTS}
    for r in results:
        counts[r["verdict"]] += 1
    return counts


def summary_line(results: list[dict], library: str, seconds: float) -> str:
    """The last line of the report."""
    c = summary(results)
    return (f"conformance: {len(results)} checks: {c[HOLDS]} hold, {c[DIFFERS]} differ, "
            f"{c[NOT_APPLICABLE]} not applicable, {c[CRASHED]} crashed, {c[TIMED_OUT]} timed out "
            f"({library}, {seconds:.1f} s)")


def _detail(r: dict) -> str:
    if r["verdict"] == DIFFERS:
        what = f"{r.get('detail')}: " if r.get("detail") else ""
        return f"{what}expected {r.get('expected')!s}, got {r.get('got')!s}"
    return r.get("detail") or ""


def table(results: list[dict], verbose: bool) -> str:
    """A line per area, and a row per check that does not hold (every check when verbose)."""
    lines = []
    for area in dict.fromkeys(r["area"] for r in results):
        rows = [r for r in results if r["area"] == area]
        c = summary(rows)
        lines.append(f"{area}: {c[HOLDS]}/{len(rows)} hold"
                     + "".join(f", {c[v]} {v}" for v in VERDICTS[1:] if c[v]))
        for r in rows:
            if verbose or r["verdict"] != HOLDS:
                lines.append(f"  {r['verdict']:<14} {r['id']:<46} {r['document']} § {r['section']}")
                if r["verdict"] != HOLDS:
                    lines.append(f"  {'':<14} {r['statement']}")
                    if _detail(r):
                        lines.append(f"  {'':<14} -> {_detail(r)}")
    return "\n".join(lines)


def markdown(areas) -> str:
    """The checks of the areas as the tables of docs/conformance.md ("The checks")."""
    out = []
    for area in areas:
        checks = area_checks(area)
        out += [f"### {area} ({len(checks)})", "", "| check | where | the statement |", "|---|---|---|"]
        out += [f"| `{c.id}` | [{c.document}]({c.document}) § {c.section} | {c.statement.replace('|', '/')} |"
                for c in checks]
        out.append("")
    return "\n".join(out) + "\n"


def main(argv=None) -> int:
    """The command line; its exit status."""
    args = _parser().parse_args(argv)
    areas = [a for item in args.only for a in item.split(",") if a] or list(AREAS)
    unknown = [a for a in areas if a not in AREAS]
    if unknown:
        print(f"conformance: unknown area {unknown[0]!r} (one of {', '.join(AREAS)})", file=sys.stderr)
        return 2
    if args.list and args.markdown:
        print(markdown(areas), end="")
        return 0
    if args.list:
        for area in areas:
            for c in area_checks(area):
                print(f"{c.id:<46} {c.document} § {c.section}: {c.statement}")
        return 0
    try:
        library = os.path.abspath(args.library) if args.library else default_library()
    except Exception as e:  # LibraryNotFoundError
        print(f"conformance: {e}", file=sys.stderr)
        return 2
    if not os.path.isfile(library):
        print(f"conformance: {library}: no such file", file=sys.stderr)
        return 2
    begun = time.monotonic()
    if args.json:
        results = run(library, areas, args.timeout)
        json.dump({"library": library, "seconds": round(time.monotonic() - begun, 2), "summary": summary(results),
                   "checks": results}, sys.stdout, indent=1)
        print()
    else:
        results = []
        for area in areas:                    # each area's table as soon as it ran
            results += run(library, [area], args.timeout)
            print(table([r for r in results if r["area"] == area], args.verbose), flush=True)
        print()
        print(summary_line(results, library, time.monotonic() - begun))
    c = summary(results)
    return 1 if c[DIFFERS] or c[CRASHED] or c[TIMED_OUT] else 0
