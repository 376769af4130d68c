"""Launch-C3 map of the Earth–Kamoʻoalewa transfer (paper 003 fig. 2), and its CLI.

    python -m solvers launch-map --out DIR [--start 2022-01-01 --end 2024-01-01]
                                 [--scheduler tcp://host:8786] [--workers 2] [--elements B]
                                 [--revs 1] [--no-png]

C3 of the prograde Lambert arc (the smallest over 0 and 1 revolutions by default) over a
grid of launch dates (daily) and flight times, computed by `solvers.sweep` (local processes,
or a dask cluster when given a scheduler address). Writes `launch_c3.npz` and
`launch_c3.csv` (always) and `launch_c3.png` (plotly + kaleido if installed, else matplotlib
if installed, else no picture).
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ...dynamics.ephemeris import (
    AU,
    ELEMENT_SETS,
    MJD_2022,
    VU,
    ElementSet,
    asteroid_state,
    earth_state,
    iso_from_mjd,
    mjd_from_iso,
)
from ...dynamics.lambert import lambert
from ...sweep import grid_rows
from .guess import CHOSEN_DATES, DAY_TU

DEFAULT_START = "2022-01-01"
DEFAULT_END = "2024-01-01"
DEFAULT_TOF = (10.0, 700.0, 130)  # days: first, last, count (paper 003 fig. 2 axes)


def launch_c3_rows(
    launch_mjd: np.ndarray, tof_days: np.ndarray, elements: ElementSet, max_revs: int = 1
) -> np.ndarray:
    """Launch C3 [km²/s²] over (launch date, flight time): the smallest over the prograde
    Lambert arcs with 0..`max_revs` revolutions (both branches of the multi-revolution ones).

    One row per launch date; this is the work unit of the launch map (paper 003 fig. 2)
    that `solvers.sweep` distributes over processes or a dask cluster.
    """
    launch_mjd = np.asarray(launch_mjd, float)
    tof_days = np.asarray(tof_days, float)
    rE, vE = earth_state(launch_mjd)
    rA, _ = asteroid_state(launch_mjd[:, None] + tof_days[None, :], elements)
    r1, r2 = rE[:, None, :] / AU, rA / AU
    tof = tof_days[None, :] * DAY_TU
    c3 = np.full(rA.shape[:-1], np.inf)
    for revs in range(max_revs + 1):
        for branch in ("left", "right") if revs else ("left",):
            v1, _, ok = lambert(r1, r2, tof, 1.0, revs, branch)
            vinf = (v1 - vE[:, None, :] / VU) * (VU / 1e3)
            c3 = np.where(ok, np.fmin(c3, np.sum(vinf * vinf, axis=-1)), c3)
    return np.where(np.isfinite(c3), c3, np.nan)


@dataclass
class LaunchMap:
    """C3 [km²/s²] on (launch date MJD TDB) x (flight time, days)."""

    launch_mjd: np.ndarray
    tof_days: np.ndarray
    c3: np.ndarray
    elements: str
    wall_s: float = 0.0

    def best(self) -> tuple[float, float, float]:
        """(launch MJD, flight days, C3) of the grid's lowest C3."""
        i, j = np.unravel_index(np.nanargmin(self.c3), self.c3.shape)
        return float(self.launch_mjd[i]), float(self.tof_days[j]), float(self.c3[i, j])


def compute_launch_map(
    start: str = DEFAULT_START,
    end: str = DEFAULT_END,
    tof: tuple[float, float, int] = DEFAULT_TOF,
    elements: ElementSet = ELEMENT_SETS[0],
    *,
    scheduler: str | None = None,
    workers: int | None = None,
    step_days: float = 1.0,
    max_revs: int = 1,
) -> LaunchMap:
    """The launch-C3 grid, one Lambert batch per chunk of launch dates on the executor."""
    t0 = time.perf_counter()
    launch = np.arange(mjd_from_iso(start), mjd_from_iso(end), step_days)
    tofs = np.linspace(*tof[:2], int(tof[2]))
    c3 = grid_rows(launch_c3_rows, launch, tofs, elements, max_revs, scheduler=scheduler,
                   workers=workers)
    return LaunchMap(launch, tofs, c3, elements.name, time.perf_counter() - t0)


@dataclass(frozen=True)
class LaunchWindow:
    """One connected region of the map below the C3 bound: its span and its best cell."""

    first_mjd: float
    last_mjd: float
    tof_min: float
    tof_max: float
    best_mjd: float
    best_tof: float
    best_c3: float
    cells: int


def windows(m: LaunchMap, c3_max: float = 20.0, min_cells: int = 200) -> list[LaunchWindow]:
    """The launch windows of the map: connected regions with C3 <= c3_max (4-neighbour
    connectivity) of at least `min_cells` grid cells, in order of their first launch date."""
    from scipy import ndimage

    below = np.nan_to_num(m.c3, nan=np.inf) <= c3_max
    labels, n = ndimage.label(below)
    out = []
    for k in range(1, n + 1):
        cells = np.argwhere(labels == k)
        if len(cells) < min_cells:
            continue
        masked = np.where(labels == k, m.c3, np.inf)
        i, j = np.unravel_index(np.argmin(masked), masked.shape)
        out.append(LaunchWindow(
            float(m.launch_mjd[cells[:, 0].min()]), float(m.launch_mjd[cells[:, 0].max()]),
            float(m.tof_days[cells[:, 1].min()]), float(m.tof_days[cells[:, 1].max()]),
            float(m.launch_mjd[i]), float(m.tof_days[j]), float(m.c3[i, j]), len(cells)))
    return sorted(out, key=lambda w: (w.first_mjd, w.tof_min))


def seed_values(launch_mjd: float, tof_days: float) -> dict[str, float]:
    """Mission values that seed the low-thrust solve from one map cell (what a click on the
    map in the explorer sends to `asteroid-rendezvous`)."""
    return {"guess_kind": float(CHOSEN_DATES), "seed_launch": float(launch_mjd - MJD_2022),
            "seed_flight_time": float(tof_days)}


def figure(m: LaunchMap, c3_max: float = 20.0) -> Any:
    """Plotly contour of C3 over launch date and flight time (paper 003 fig. 2)."""
    import plotly.graph_objects as go

    dates = [iso_from_mjd(t) for t in m.launch_mjd]
    fig = go.Figure(go.Contour(
        x=dates, y=m.tof_days, z=np.clip(m.c3.T, 0, 4 * c3_max),
        contours={"start": 0, "end": c3_max, "size": c3_max / 10, "coloring": "heatmap",
                  "showlabels": True},
        colorbar={"title": "C3 [km²/s²]"}, colorscale="Viridis",
        hovertemplate="launch %{x}<br>flight %{y:.0f} d<br>C3 %{z:.2f} km²/s²<extra></extra>",
    ))
    fig.update_layout(title=f"Launch C3, Earth → Kamoʻoalewa (elements {m.elements[:1]})",
                      xaxis_title="launch date", yaxis_title="flight time [d]",
                      width=1100, height=550)
    return fig


def save(m: LaunchMap, out: Path, c3_max: float = 20.0, png: bool = True) -> list[Path]:
    """Write the data (NPZ and CSV) and, if asked and a renderer is installed, the PNG."""
    out.mkdir(exist_ok=True)  # its parent must exist: a mistyped path creates no folders
    written = [out / "launch_c3.npz", out / "launch_c3.csv"]
    np.savez(written[0], launch_mjd=m.launch_mjd, tof_days=m.tof_days, c3_km2_s2=m.c3,
             elements=m.elements)
    header = "launch_date,launch_mjd_tdb," + ",".join(f"tof_{t:.2f}d" for t in m.tof_days)
    with open(written[1], "w", encoding="utf-8") as fh:
        fh.write(f"# launch C3 [km^2/s^2], elements {m.elements}\n{header}\n")
        for t, row in zip(m.launch_mjd, m.c3, strict=True):
            fh.write(f"{iso_from_mjd(t)},{t:.1f}," + ",".join(f"{c:.4f}" for c in row) + "\n")
    path = out / "launch_c3.png"
    if png and _write_png(m, path, c3_max):
        written.append(path)
    return written


def _write_png(m: LaunchMap, path: Path, c3_max: float) -> bool:
    try:
        figure(m, c3_max).write_image(str(path))
        return True
    except Exception:  # noqa: BLE001 - kaleido missing or no browser: try matplotlib
        pass
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return False
    fig, ax = plt.subplots(figsize=(11, 5.5))
    cs = ax.contourf(m.launch_mjd - MJD_2022, m.tof_days, np.clip(m.c3.T, 0, 4 * c3_max),
                     levels=np.linspace(0, c3_max, 11), extend="max")
    fig.colorbar(cs, label="C3 [km²/s²]")
    ax.set_xlabel("launch [days since 2022-01-01]")
    ax.set_ylabel("flight time [d]")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line and exit 2, as the rest of the CLI
        self.exit(2, f"error: {message}\n")


def _bad_out(out: Path) -> str | None:
    """Why --out cannot be the output folder (None: it can); checked before any work."""
    if out.exists() and not out.is_dir():
        return f"--out {out}: that is a file, not a folder"
    if not out.exists() and not out.resolve().parent.is_dir():
        return f"--out {out}: the folder {out.parent} does not exist"
    return None


def main(argv: Sequence[str] | None = None) -> int:
    parser = _Parser(prog="python -m solvers launch-map", description=__doc__,
                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", required=True, type=Path, help="output directory")
    parser.add_argument("--start", default=DEFAULT_START, help="first launch date (ISO)")
    parser.add_argument("--end", default=DEFAULT_END, help="last launch date (ISO, excluded)")
    parser.add_argument("--tof", type=float, nargs=3, default=DEFAULT_TOF,
                        metavar=("FIRST", "LAST", "COUNT"), help="flight times [d]")
    parser.add_argument("--elements", choices=("B", "A"), default="B",
                        help="asteroid element set (reference/asteroid.md)")
    parser.add_argument("--scheduler", help="dask.distributed scheduler address")
    parser.add_argument("--workers", type=int, help="local worker processes (default: cores)")
    parser.add_argument("--revs", type=int, default=1, help="most Lambert revolutions")
    parser.add_argument("--c3-max", type=float, default=20.0, help="contour top [km²/s²]")
    parser.add_argument("--no-png", action="store_true", help="write the data files only")
    args = parser.parse_args(argv)
    bad = _bad_out(args.out)
    if bad is None and args.workers is not None and args.workers < 1:
        bad = f"--workers must be at least 1, not {args.workers}"
    if bad is not None:
        print(f"error: {bad}", file=sys.stderr)
        return 2
    try:
        elements = ELEMENT_SETS[("B", "A").index(args.elements)]
        m = compute_launch_map(args.start, args.end, (*args.tof[:2], int(args.tof[2])),
                               elements, scheduler=args.scheduler, workers=args.workers,
                               max_revs=args.revs)
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    for path in save(m, args.out, args.c3_max, png=not args.no_png):
        print(path)
    print(f"{m.c3.shape[0]} x {m.c3.shape[1]} grid in {m.wall_s:.2f} s; windows with C3 <= "
          f"{args.c3_max:g} km²/s²:")
    for w in windows(m, args.c3_max):
        print(f"  launch {iso_from_mjd(w.first_mjd)} .. {iso_from_mjd(w.last_mjd)}, flight "
              f"{w.tof_min:.0f}-{w.tof_max:.0f} d; best {iso_from_mjd(w.best_mjd)}, "
              f"{w.best_tof:.0f} d, C3 {w.best_c3:.2f}")
    return 0
