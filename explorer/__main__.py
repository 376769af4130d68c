"""`python -m explorer [--host 127.0.0.1] [--port 8080] [--mission KEY]`: serve the app."""

from __future__ import annotations

import argparse
import time

from .app import ExplorerApp


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="python -m explorer", description=__doc__)
    parser.add_argument("--host", default="127.0.0.1",
                        help="address to bind (default 127.0.0.1: this machine only)")
    parser.add_argument("--port", type=int, default=8080)
    parser.add_argument("--mission", help="mission key shown first (see `python -m solvers list`)")
    parser.add_argument("--method", help="method key of that mission shown first")
    parser.add_argument("--nodes", type=int, help="node count of that method")
    args = parser.parse_args(argv)
    try:
        app = ExplorerApp(args.host, args.port, args.mission, args.method, args.nodes)
    except ValueError as exc:
        parser.error(str(exc))
    print(f"Trajectory explorer: open {app.url} in a browser (Ctrl-C stops)", flush=True)
    try:
        while True:
            time.sleep(3600)
    except KeyboardInterrupt:
        app.stop()


if __name__ == "__main__":
    main()
