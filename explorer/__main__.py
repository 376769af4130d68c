"""`python -m explorer [--host 127.0.0.1] [--port 8080] [--mission KEY] [--shared | --classroom]`:
serve the app. Each browser tab has its own session unless `--shared` (one session mirrored to
every tab: any tab drives) or `--classroom` (the presenter mode: the tab opened with the
teacher's link drives, the students follow it and may explore on their own)."""

from __future__ import annotations

import argparse
import math
import time

from .app import ExplorerApp
from .session import DEFAULT_TIME_LIMIT


def _parser() -> argparse.ArgumentParser:
    """The command line: where to serve, what to show first, which mode, where to solve."""
    parser = argparse.ArgumentParser(prog="python -m explorer", description=__doc__)
    parser.add_argument("--host", default="127.0.0.1",
                        help="address to bind (default 127.0.0.1: this machine only; "
                             "0.0.0.0 lets a classroom's laptops connect)")
    parser.add_argument("--port", type=int, default=8080)
    parser.add_argument("--mission", help="mission key shown first (see `python -m solvers list`)")
    parser.add_argument("--method", help="method key of that mission shown first")
    parser.add_argument("--nodes", type=int, help="node count of that method")
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--shared", action="store_true",
                      help="one session shared by every tab instead of one per tab")
    mode.add_argument("--classroom", action="store_true",
                      help="presenter mode: prints a teacher link (drives) and a students' "
                           "link (follow, explore, rejoin)")
    parser.add_argument("--teacher-secret", metavar="KEY",
                        help="the teacher link's key with --classroom (default: a random one "
                             "made at start-up)")
    parser.add_argument("--time-limit", type=float, default=DEFAULT_TIME_LIMIT,
                        help=f"seconds before a solve is stopped (default {DEFAULT_TIME_LIMIT:g}; "
                             "0: no limit; also settable in the GUI)")
    parser.add_argument("--mission-file", action="append", default=[], metavar="F",
                        help="a mission file of your own (a folder: its *.py files); "
                             "repeatable; saving it reloads it in the running explorer")
    parser.add_argument("--workers", type=int,
                        help="solve processes (default: one per core); every solve runs in one")
    parser.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                        help="solve on this dask.distributed cluster instead (a lecture hall "
                             "beyond one machine; needs dask[distributed] here and on the "
                             "workers, with this package installed)")
    return parser


def main(argv: list[str] | None = None) -> None:
    """Start the explorer and serve until Ctrl-C."""
    parser = _parser()
    args = parser.parse_args(argv)
    if args.workers is not None and args.workers < 1:
        parser.error("--workers must be at least 1")
    if args.workers is not None and args.scheduler:
        parser.error("--workers and --scheduler: the cluster's workers solve; choose one")
    if args.teacher_secret is not None and not args.classroom:
        parser.error("--teacher-secret needs --classroom")
    if args.teacher_secret is not None and not _url_safe(args.teacher_secret):
        parser.error("--teacher-secret must be 8 to 200 letters, digits, '-' or '_'")
    if not math.isfinite(args.time_limit) or args.time_limit < 0:
        parser.error(f"--time-limit must be a number of seconds >= 0, not {args.time_limit}")
    try:
        app = ExplorerApp(args.host, args.port, args.mission, args.method, args.nodes,
                          shared=args.shared, time_limit=args.time_limit or None,
                          workers=args.workers, mission_files=tuple(args.mission_file),
                          classroom=args.classroom, teacher_secret=args.teacher_secret,
                          scheduler=args.scheduler)
    except (ValueError, RuntimeError) as exc:
        parser.error(str(exc))
    if args.classroom:
        print(f"Trajectory explorer (classroom; Ctrl-C stops)\n"
              f"teacher: {app.teacher_url}\nstudents: {app.url}/", flush=True)
    else:
        mode = "one shared session" if args.shared else "one session per tab"
        print(f"Trajectory explorer ({mode}): open {app.url} in a browser (Ctrl-C stops)",
              flush=True)
    try:
        while True:
            time.sleep(3600)
    except KeyboardInterrupt:
        app.stop()


def _url_safe(key: str) -> bool:
    """A key that travels in a link unchanged (the alphabet of `secrets.token_urlsafe`)."""
    return 8 <= len(key) <= 200 and all(c.isascii() and (c.isalnum() or c in "-_")
                                        for c in key)


if __name__ == "__main__":
    main()
