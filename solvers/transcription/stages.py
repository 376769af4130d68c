"""A direct transcription's NLP in the stage order FATROP needs (`nlp.fatrop.Stages`).

Stage k = 0..N holds y_k = (x_k, u_k, g) in the transcription's scaling, g being the free final
time, free initial time and static variables copied into every stage, and for k < N a stage
control c_k carrying what interval k needs of node k+1:
- explicit (multiple shooting): c_k = u_k+1, the gap is y_k+1 = (phi(x_k, u_k, c_k), c_k, g_k)
  with phi the interval's RK4 map: the original continuity constraint, negated;
- implicit (Hermite–Simpson, whose defect involves x_k+1 and f(x_k+1)): c_k = (x_k+1, u_k+1),
  the defect of interval k is a constraint of stage k on (y_k, c_k) and the gap copies c_k
  into y_k+1.
Path constraints belong to their node's stage (a method's extra points, the Hermite–Simpson
midpoints, to their interval's), the terminal constraints and the Mayer cost to stage N, the
running cost to each interval's stage. Boundary conditions that tie the first node to the
last fit no stage order and are refused.
"""

from __future__ import annotations

from collections.abc import Callable

import casadi as ca
import numpy as np

from ..nlp.fatrop import Stages
from ..ocp import OCP
from .direct import DirectTranscription

Expr = ca.SX | ca.MX
# (x_k, u_k, x_k+1 or None when explicit, u_k+1, T, p), columns k = 0..N-1 in the problem's
# units -> (next states when explicit, else scaled defects; running cost; extra path points
# (states, controls) one per interval, or None).
Interval = Callable[[Expr, Expr, Expr | None, Expr, Expr, Expr],
                    tuple[Expr, Expr, tuple[Expr, Expr] | None]]


def stage_order(tr: DirectTranscription, p: Expr, interval: Interval, explicit: bool) -> Stages:
    """The stage-ordered copy of direct transcription `tr`'s NLP (same parameters `p`, same
    optimum), with the maps between the two layouts."""
    ocp = tr.ocp
    if ocp.boundary is not None:
        raise ValueError("back end 'fatrop' cannot solve this problem: its boundary "
                         "conditions tie the first node to the last, which no stage order "
                         "holds")
    layout = _Layout(ocp, tr.N, int(tr.free_T) + int(tr.free_t0) + ocp.ns, explicit)
    sym, N, nx, nu = tr.symbolic, tr.N, ocp.nx, ocp.nu
    ys = [sym.sym(f"y{k}", layout.ny) for k in range(N + 1)]
    cs = [sym.sym(f"c{k}", layout.nc) for k in range(N)]
    Y, C = ca.horzcat(*ys), ca.horzcat(*cs)
    offset, x_scale = ca.DM(ocp.offset), ca.DM(ocp.x_scale)
    X = ca.repmat(offset, 1, N + 1) + ca.repmat(x_scale, 1, N + 1) * Y[:nx, :]
    U = ca.repmat(ca.DM(ocp.u_scale), 1, N + 1) * Y[nx:nx + nu, :]
    T = Y[nx + nu, :] * ocp.T_scale if tr.free_T else ca.repmat(ocp.fixed_final_time(p), 1, N + 1)
    U1 = ca.repmat(ca.DM(ocp.u_scale), 1, N) * C[layout.nc - nu:, :]
    X1 = None if explicit else ca.repmat(offset, 1, N) + ca.repmat(x_scale, 1, N) * C[:nx, :]
    out, running, extra = interval(X[:, :-1], U[:, :-1], X1, U1, T[:, :-1], p)
    rows = _Rows(tr.n_defects + tr.n_terminal + tr.n_path * tr.path_points)
    stage_g, ng = [], []
    for k in range(N + 1):
        parts: list[Expr] = []
        if k < N:  # the gap to stage k+1, then (implicit) interval k's defect
            x_next = (out[:, k] - offset) / x_scale if explicit else C[:nx, k]
            parts += [Y[:nx, k + 1] - x_next,
                      Y[nx:, k + 1] - ca.vertcat(C[layout.nc - nu:, k], Y[nx + nu:, k])]
            if explicit:
                rows.take(k * nx, nx, -1.0)
                rows.skip(layout.ny - nx)
            else:
                rows.skip(layout.ny)
                parts.append(out[:, k])
                rows.take(k * nx, nx, 1.0)
        parts += _node_constraints(tr, rows, X[:, k], U[:, k], p, k, extra)
        stage_g.append(ca.vertcat(*parts))
        ng.append(int(stage_g[-1].numel()) - (layout.ny if k < N else 0))
    cost = running + (ocp.mayer(X[:, N], T[:, N], p) if ocp.mayer is not None else 0)
    return Stages(
        x=ca.vertcat(*[v for pair in zip(ys, cs, strict=False) for v in pair], ys[N]),
        f=cost / ocp.cost_scale, g=ca.vertcat(*stage_g), nx=(layout.ny,) * (N + 1),
        nu=(layout.nc,) * N + (0,), ng=tuple(ng), source=layout.source, bounded=layout.bounded,
        primary=layout.primary, rows=rows.rows, signs=rows.signs)


def _node_constraints(tr: DirectTranscription, rows: _Rows, x: Expr, u: Expr, p: Expr, k: int,
                      extra: tuple[Expr, Expr] | None) -> list[Expr]:
    """Stage k's path constraints (at node k, and at interval k's extra point) and, at the
    last node, the terminal constraints; their original rows recorded in `rows`."""
    ocp, N, n_path = tr.ocp, tr.N, tr.n_path
    first_path = tr.n_defects + tr.n_terminal
    parts = []
    if n_path:
        parts.append(ocp.path(x, u, p))
        rows.take(first_path + k * n_path, n_path, 1.0)
        if extra is not None and k < N:
            parts.append(ocp.path(extra[0][:, k], extra[1][:, k], p))
            rows.take(first_path + (N + 1 + k) * n_path, n_path, 1.0)
    if k == N and ocp.terminal is not None:
        parts.append(ocp.terminal(x, p) / ca.DM(ocp.terminal_scale))
        rows.take(tr.n_defects, tr.n_terminal, 1.0)
    return parts


class _Rows:
    """Where each original constraint lands among the staged ones, filled in staged order."""

    def __init__(self, n_original: int) -> None:
        self.rows = np.full(n_original, -1)
        self.signs = np.ones(n_original)
        self.at = 0  # the next staged row

    def skip(self, n: int) -> None:
        """`n` staged rows with no original counterpart (the copies' gaps)."""
        self.at += n

    def take(self, first: int, n: int, sign: float) -> None:
        """The next `n` staged rows are original rows `first`.. times `sign`."""
        self.rows[first:first + n] = np.arange(self.at, self.at + n)
        self.signs[first:first + n] = sign
        self.at += n


class _Layout:
    """Index maps between the transcription's variables [X (node-major), U, globals] and the
    staged ones [y_0, c_0, ..., y_N]."""

    def __init__(self, ocp: OCP, N: int, n_globals: int, explicit: bool) -> None:
        nx, nu = ocp.nx, ocp.nu
        self.ny, self.nc = nx + nu + n_globals, nu if explicit else nx + nu
        n_X, n_U = nx * (N + 1), nu * (N + 1)
        xs = lambda k: list(range(k * nx, (k + 1) * nx))  # noqa: E731
        us = lambda k: list(range(n_X + k * nu, n_X + (k + 1) * nu))  # noqa: E731
        glob = list(range(n_X + n_U, n_X + n_U + n_globals))
        source, bounded = [], []
        for k in range(N + 1):
            source += xs(k) + us(k) + glob
            bounded += [True] * (nx + nu) + [k == 0] * n_globals
            if k < N:
                nxt = us(k + 1) if explicit else xs(k + 1) + us(k + 1)
                source += nxt
                bounded += [False] * len(nxt)
        self.source, self.bounded = np.array(source), np.array(bounded)
        stride = self.ny + self.nc
        primary = np.empty(n_X + n_U + n_globals, int)
        for k in range(N + 1):
            primary[xs(k)] = k * stride + np.arange(nx)
            primary[us(k)] = k * stride + nx + np.arange(nu)
        primary[glob] = nx + nu + np.arange(n_globals)
        self.primary = primary
