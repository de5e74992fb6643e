"""rtv-study: parameter studies of rt-vehicle on Dask (docs/studies.md).

    rtv-study run STUDY.toml [--out DIR] [--scheduler tcp://HOST:PORT] [--workers N] [--no-progress] [--no-plots]
    rtv-study describe [CASE]      # the cases, their metrics, the statistics, the FMU parameters

RTV_PARSE_ONLY=1 (as for rtv): `run` reads and checks the study file and its arguments, then stops before
running anything (tests/docs checks the documented studies too long to run this way).
"""
import argparse
import json
import os
import sys

from . import native, runner
from .study import StudyError, load


def _positive(text):
    try:
        n = int(text)
    except ValueError:
        n = 0
    if n < 1:
        raise argparse.ArgumentTypeError(f"--workers must be a whole number ≥ 1 (got {text!r})")
    return n


def main(argv=None):
    parser = argparse.ArgumentParser(prog="rtv-study", description="Parameter studies of rt-vehicle on Dask")
    sub = parser.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="run a study (resumes: recorded runs are not run again)")
    r.add_argument("study")
    r.add_argument("--out", help="results folder (default: the study's name beside the study file)")
    r.add_argument("--scheduler", help="a Dask scheduler, tcp://HOST:PORT (default: an embedded LocalCluster)")
    r.add_argument("--workers", type=_positive, help="LocalCluster worker processes (default: one per core)")
    r.add_argument("--no-progress", action="store_true")
    r.add_argument("--no-plots", action="store_true")
    d = sub.add_parser("describe", help="what a study may ask for")
    d.add_argument("case", nargs="?")
    args = parser.parse_args(argv)
    parse_only = os.environ.get("RTV_PARSE_ONLY", "")
    if parse_only not in ("", "0", "1"):
        raise SystemExit(f"rtv-study: RTV_PARSE_ONLY={parse_only!r}: 1 checks the arguments only, 0 or unset runs")
    try:
        if args.command == "describe":
            description = native.describe()
            if args.case:
                print(json.dumps(description["metrics"].get(args.case, f"unknown case {args.case}"), indent=1))
            else:
                print(json.dumps({k: v for k, v in description.items() if k != "metrics"}, indent=1))
            return 0
        study = load(args.study)
        if parse_only == "1":
            print(f"rtv-study: {args.study}: valid, {len(study.all_runs())} runs; not run (RTV_PARSE_ONLY=1)")
            return 0
        try:
            table = runner.run(study, out=args.out, scheduler=args.scheduler, workers=args.workers,
                               progress=not args.no_progress, plots=not args.no_plots)
        except ConnectionError as e:
            where = f"{study.path}:{study.scheduler_line}: " if not args.scheduler and study.scheduler_line else ""
            raise SystemExit(f"rtv-study: {where}{e}")
        out = args.out or study.default_out
        ok = sum(s == "ok" for s in table.column("status").to_pylist())
        print(f"{table.num_rows} runs in {out}/results.parquet: {ok} ok, {table.num_rows - ok} failed")
        return 0
    except StudyError as e:
        print(f"rtv-study: {e}", file=sys.stderr)
        return 2
    except FileNotFoundError as e:
        print(f"rtv-study: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
