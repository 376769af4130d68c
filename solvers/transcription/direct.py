"""What every direct transcription of an `OCP` shares: the variable layout (scaled node
states, node controls, final time, initial time, static variables), bounds, guesses, warm
starts and decoding.

A subclass supplies only the dynamics constraints (collocation defects or shooting gaps),
the running-cost quadrature and the dense interpolation that goes with them.
"""

from __future__ import annotations

from abc import ABC, abstractmethod

import casadi as ca
import numpy as np

from ..context import SolveContext
from ..nlp.casadi_nlp import NLP, NLPResult, status_of
from ..nlp.fatrop import Stages
from ..ocp import OCP, BoundaryPoint, OCPResult
from ..optimality import active_state_bounds
from ..solution import Iterate, Series, WarmStart
from .costates import CostatePoints, Endpoints, defect_multipliers, estimate


class DirectTranscription(ABC):
    """Nodes at tau_k in [0, 1] on t = t0 + T tau; states and controls at every node."""

    kind: str = "direct"
    # Convergence order of the terminal miss and of the cost in the node count: where the
    # refinement aims its next count and how the cost error is extrapolated.
    order: float  # every method states its own
    # Symbols of the NLP: SX (fast evaluation, expression graphs expanded) or MX (function
    # calls kept: far less memory for methods with long inner integrations).
    symbolic: type = ca.SX
    # How the control is defined between nodes: "linear" or "polynomial" (through all nodes).
    control_interpolation: str = "linear"
    # Whether the node positions are a parameter of the built NLP, so that one NLP solves on
    # any mesh of N intervals (`solve(..., tau=...)`): a mission can put nodes where its
    # control is not smooth without building again. A method whose defects take each
    # interval's length offers it as an option; a global polynomial (LGL) has its nodes fixed.
    variable_mesh: bool = False

    @staticmethod
    def mesh(n_intervals: int) -> np.ndarray:
        """Node positions tau in [0, 1]: equally spaced unless a method says otherwise."""
        return np.linspace(0.0, 1.0, n_intervals + 1)

    def __init__(self, ocp: OCP, n_intervals: int, backend: str = "ipopt") -> None:
        self.ocp = ocp
        self.N = int(n_intervals)
        self.fn = ocp.functions()
        nx, nu, N = ocp.nx, ocp.nu, self.N
        self.tau = self.mesh(N)  # the mesh a solve uses unless it is given another
        self.free_T = ocp.fixed_final_time is None
        self.free_t0 = ocp.free_initial_time
        sym = self.symbolic
        Xs = sym.sym("X", nx, N + 1)
        Us = sym.sym("U", nu, N + 1)
        p = sym.sym("p", ocp.n_params)
        Ts = sym.sym("T") if self.free_T else sym(0, 1)
        t0s = sym.sym("t0") if self.free_t0 else sym(0, 1)
        ss = sym.sym("s", ocp.ns)
        # Interval lengths over T, a parameter of the NLP with a variable mesh.
        self._steps = sym.sym("steps", 1, N) if self.variable_mesh else sym(0, 1)
        T = Ts * ocp.T_scale if self.free_T else ocp.fixed_final_time(p)
        t0 = t0s * ocp.t0_scale if self.free_t0 else sym(0.0)
        s = ss * ca.DM(ocp.static_scale)
        X = ca.repmat(ca.DM(ocp.offset), 1, N + 1) + ca.repmat(ca.DM(ocp.x_scale), 1, N + 1) * Xs
        U = ca.repmat(ca.DM(ocp.u_scale), 1, N + 1) * Us
        defects, running = self._dynamics(X, U, T, p)
        cost = running
        if ocp.mayer is not None:
            cost = cost + ocp.mayer(X[:, N], T, p)
        g = [defects]
        self.n_terminal = 0
        if ocp.terminal is not None:
            g.append(ocp.terminal(X[:, N], p) / ca.DM(ocp.terminal_scale))
            self.n_terminal = int(np.size(ocp.terminal_scale))
        self.n_boundary = 0
        if ocp.boundary is not None:
            point = BoundaryPoint(X[:, 0], X[:, N], t0, T, s)
            scale = (np.ones(len(ocp.boundary_lb)) if ocp.boundary_scale is None
                     else np.asarray(ocp.boundary_scale, float))
            g.append(ocp.boundary(point, p) / ca.DM(scale))
            self.n_boundary = len(ocp.boundary_lb)
            self._boundary_scale = scale
        self.n_path = self.path_points = 0
        if ocp.path is not None:
            Xp, Up = self._path_points(X, U)
            self.path_points = int(Xp.shape[1])
            self._path_symbols = (Xp, Up, p)  # where an iterative method re-reads the path
            path = ca.horzcat(*[ocp.path(Xp[:, k], Up[:, k], p)
                                for k in range(self.path_points)])
            self.n_path = int(path.size1())
            g.append(ca.vec(path))
        self.n_defects = int(defects.numel())
        z = ca.vertcat(ca.vec(Xs), ca.vec(Us), Ts, t0s, ss)
        nlp_p = ca.vertcat(p, self._steps.T) if self.variable_mesh else p
        self.nlp = NLP(z, cost / ocp.cost_scale, ca.vertcat(*g), nlp_p, backend,
                       name=self.kind.replace("-", "_"), ipopt_options=dict(ocp.nlp_options),
                       stages=self._stages(p) if backend == "fatrop" else None)

    @abstractmethod
    def _dynamics(self, X: ca.SX, U: ca.SX, T: ca.SX, p: ca.SX) -> tuple[ca.SX, ca.SX]:
        """Scaled dynamics constraints (vector) and the running cost in the problem's units."""

    def _stages(self, p: ca.SX) -> Stages | None:
        """The same NLP in stage order for FATROP (`transcription.stages`); None: the method
        has no stage structure (a global polynomial couples every node)."""
        return None

    def _path_points(self, X: ca.SX, U: ca.SX) -> tuple[ca.SX, ca.SX]:
        """The (states, controls) columns where the path constraints are imposed: the
        nodes (a method with interior points of its own may add them)."""
        return X, U

    @abstractmethod
    def costate_points(self, mu: np.ndarray, X: np.ndarray, U: np.ndarray, T: float,
                       p: np.ndarray, ends: Endpoints, tau: np.ndarray) -> CostatePoints:
        """The method's covector mapping: costates from the multipliers `mu` (rows: one per
        dynamics-constraint block, unscaled, `costates.defect_multipliers`); `ends` for the
        methods that need the transversality conditions; `tau` the solve's mesh."""

    @abstractmethod
    def dense(
        self, T: float, X: np.ndarray, U: np.ndarray, p: np.ndarray, per_interval: int,
        tau: np.ndarray,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Dense (t - t0, X, U) as the method defines the trajectory between nodes of the
        mesh `tau`."""

    # ---- variable layout -------------------------------------------------------------
    def _pack(self, X: np.ndarray, U: np.ndarray, T: float, t0: float = 0.0,
              statics: np.ndarray | None = None) -> np.ndarray:
        ocp = self.ocp
        parts = [((X - ocp.offset) / ocp.x_scale).ravel(), (U / ocp.u_scale).ravel()]
        if self.free_T:
            parts.append([T / ocp.T_scale])
        if self.free_t0:
            parts.append([t0 / ocp.t0_scale])
        s = np.zeros(ocp.ns) if statics is None or len(statics) != ocp.ns else statics
        parts.append(np.asarray(s, float) / ocp.static_scale)
        return np.concatenate(parts)

    def _unpack(self, z: np.ndarray, p: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray, float, float, np.ndarray]:
        """(X, U, T, t0, statics) in the problem's units."""
        ocp, N = self.ocp, self.N
        nX, nU = ocp.nx * (N + 1), ocp.nu * (N + 1)
        X = ocp.offset + ocp.x_scale * z[:nX].reshape(N + 1, ocp.nx)
        U = ocp.u_scale * z[nX : nX + nU].reshape(N + 1, ocp.nu)
        i = nX + nU
        if self.free_T:
            T = float(z[i] * ocp.T_scale)
            i += 1
        else:
            T = float(self.fn.fixed_T(p))
        t0 = 0.0
        if self.free_t0:
            t0 = float(z[i] * ocp.t0_scale)
            i += 1
        statics = z[i : i + ocp.ns] * ocp.static_scale
        return X, U, T, t0, statics

    def _box(self, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        ocp, N = self.ocp, self.N
        b = ocp.bounds(p)
        xlb = np.tile((b.x_lb - ocp.offset) / ocp.x_scale, (N + 1, 1))
        xub = np.tile((b.x_ub - ocp.offset) / ocp.x_scale, (N + 1, 1))
        if self.fn.x0 is not None:
            x0 = np.asarray(self.fn.x0(p)).ravel()
            xlb[0] = xub[0] = (x0 - ocp.offset) / ocp.x_scale
        ulb = np.tile(b.u_lb / ocp.u_scale, (N + 1, 1))
        uub = np.tile(b.u_ub / ocp.u_scale, (N + 1, 1))
        lb = [xlb.ravel(), ulb.ravel()]
        ub = [xub.ravel(), uub.ravel()]
        if self.free_T:
            lb.append([b.T_lb / ocp.T_scale])
            ub.append([b.T_ub / ocp.T_scale])
        if self.free_t0:
            lb.append([b.t0_lb / ocp.t0_scale])
            ub.append([b.t0_ub / ocp.t0_scale])
        s_lb = np.full(ocp.ns, -np.inf) if len(b.s_lb) != ocp.ns else np.asarray(b.s_lb, float)
        s_ub = np.full(ocp.ns, np.inf) if len(b.s_ub) != ocp.ns else np.asarray(b.s_ub, float)
        lb.append(s_lb / ocp.static_scale)
        ub.append(s_ub / ocp.static_scale)
        return np.concatenate(lb), np.concatenate(ub)

    def _g_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        n_eq = self.n_defects + self.n_terminal
        lb = [np.zeros(n_eq)]
        ub = [np.zeros(n_eq)]
        if self.n_boundary:
            lb.append(np.asarray(self.ocp.boundary_lb, float) / self._boundary_scale)
            ub.append(np.asarray(self.ocp.boundary_ub, float) / self._boundary_scale)
        if self.n_path:
            reps = self.path_points
            lb.append(np.tile(self.ocp.path_lb, reps))
            ub.append(np.tile(self.ocp.path_ub, reps))
        return np.concatenate(lb), np.concatenate(ub)

    def initial_state(self, p: np.ndarray, fallback: np.ndarray) -> np.ndarray:
        """x(t0) fixed by the problem, or `fallback` when the initial state is free."""
        return np.asarray(self.fn.x0(p)).ravel() if self.fn.x0 is not None else fallback

    def _cold_guess(self, p: np.ndarray, tau: np.ndarray) -> np.ndarray:
        guess = self.ocp.guess(p)
        start = np.asarray(guess.x_initial if guess.x_initial is not None else guess.x_final,
                           float)
        X = guess.states(tau, self.initial_state(p, start))
        U = guess.controls(tau)
        T = guess.T if self.free_T else float(self.fn.fixed_T(p))
        return self._pack(X, U, T, guess.t0, guess.statics)

    def _warm_guess(self, warm: WarmStart, p: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """Re-interpolate another solution onto the mesh `tau` (node count, method or mesh
        changed)."""
        X = _resample(tau, warm.tau, warm.X)
        U = _resample(tau, warm.tau, warm.U)
        X[0] = self.initial_state(p, X[0])
        T = warm.T if self.free_T else float(self.fn.fixed_T(p))
        return self._pack(X, U, T, warm.t0, warm.statics)

    def reuses(self, warm: WarmStart | None) -> bool:
        """Whether `warm` came from this very NLP (its primal and dual values fit as they
        are). On another mesh of a `variable_mesh` NLP too: node k stays node k, so a mesh
        that follows a moving switch keeps the node at the switch there, which
        re-interpolating in tau would not."""
        return (warm is not None and warm.kind == self.kind and warm.n_intervals == self.N
                and warm.has_duals and len(warm.z) == self.nlp.n_x)

    # ---- solve -----------------------------------------------------------------------
    def solve(
        self,
        p: np.ndarray,
        warm: WarmStart | None = None,
        ctx: SolveContext | None = None,
        dense_per_interval: int = 10,
        tau: np.ndarray | None = None,
    ) -> OCPResult:
        """Solve for numeric parameters `p`, warm-started when `warm` fits this mesh,
        re-interpolated from `warm` otherwise, from the problem's guess without `warm`;
        on the mesh `tau` (N+1 increasing positions from 0 to 1) where the method has a
        `variable_mesh`, else on its own."""
        p, tau = np.asarray(p, float), self._checked_mesh(tau)
        lbx, ubx = self._box(p)
        lbg, ubg = self._g_bounds()
        z0, lam_x, lam_g = self._start(warm, p, tau)
        z0 = np.clip(z0, lbx, ubx)
        nlp_p = np.concatenate([p, np.diff(tau)]) if self.variable_mesh else p
        res = self.nlp.solve(z0, nlp_p, lbx, ubx, lbg, ubg, lam_x, lam_g, ctx)
        X, U, T, t0, statics = self._unpack(res.x, p)
        status, message = status_of(res)
        t_dense, X_dense, U_dense = self.dense(T, X, U, p, dense_per_interval, tau)
        bounds = self.ocp.bounds(p)
        lam_X = res.lam_x[:self.ocp.nx * (self.N + 1)].reshape(self.N + 1, self.ocp.nx)
        active = active_state_bounds(
            X, lam_X, bounds.x_lb, bounds.x_ub, self.ocp.x_scale, self.ocp.states,
            lam_scale=float(np.max(np.abs(res.lam_g), initial=0.0)))
        if active and status == "optimal":
            message += (f"; state bound active on {', '.join(active)}: the costates may jump "
                        "there (the maximum principle applies in its state-constrained form)")
        costates, hamiltonian, variation = self._costate_estimate(res, X, U, p, t0, T,
                                                                  statics, tau)
        history = [Iterate(k, tau * Tk, Xk) for k, z in res.history
                   for Xk, _, Tk, _, _ in [self._unpack(z, p)]]
        return OCPResult(
            T=T,
            t_nodes=tau * T,
            X=X,
            U=U,
            t_dense=t_dense,
            X_dense=X_dense,
            U_dense=U_dense,
            cost=res.f * self.ocp.cost_scale,
            status=status,
            message=message,
            iterations=res.iterations,
            n_variables=self.nlp.n_x,
            n_constraints=self.nlp.n_g,
            max_violation=res.max_violation,
            history=history,
            warm=WarmStart(self.kind, self.N, tau, X, U, T, res.x, res.lam_x, res.lam_g,
                           t0=t0, statics=statics),
            control_interpolation=self.control_interpolation,
            t0=t0,
            statics=statics,
            costates=costates,
            hamiltonian=hamiltonian,
            hamiltonian_variation=variation,
            defects=self.defect_points(res.g[:self.n_defects], T, tau),
        )

    def _start(self, warm: WarmStart | None, p: np.ndarray, tau: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
        """The NLP's start and multipliers: `warm` itself where it fits this mesh, else
        re-interpolated from it, else the problem's guess (no multipliers)."""
        if self.reuses(warm):
            return warm.z.copy(), warm.lam_x, warm.lam_g
        if warm is not None:
            return self._warm_guess(warm, p, tau), None, None
        return self._cold_guess(p, tau), None, None

    def _costate_estimate(self, res: NLPResult, X: np.ndarray, U: np.ndarray, p: np.ndarray,
                          t0: float, T: float, statics: np.ndarray, tau: np.ndarray
                          ) -> tuple[Series | None, Series | None, float]:
        """Costates and Hamiltonian from the defects' multipliers (none when the NLP
        returned none), with the Hamiltonian's relative variation."""
        if not (len(res.lam_g) and np.any(res.lam_g[: self.n_defects] != 0)):
            return None, None, float("nan")
        ends = Endpoints(X[0], X[-1], t0, T, statics,
                         res.lam_g[self.n_defects:self.n_defects + self.n_terminal
                                   + self.n_boundary],
                         res.lam_x[:self.ocp.nx],
                         res.lam_x[self.N * self.ocp.nx:(self.N + 1) * self.ocp.nx])
        return self.costates(res.lam_g, X, U, p, ends, tau)

    def _checked_mesh(self, tau: np.ndarray | None) -> np.ndarray:
        """The solve's mesh: `tau` when given (refused unless the method takes a mesh and
        it is N+1 increasing positions from 0 to 1), else the method's own."""
        if tau is None:
            return self.tau
        tau = np.asarray(tau, float)
        if not self.variable_mesh:
            raise ValueError(f"{self.kind} places its own nodes; it takes no mesh")
        if (tau.shape != (self.N + 1,) or tau[0] != 0.0 or tau[-1] != 1.0
                or np.any(np.diff(tau) <= 0.0)):
            raise ValueError(f"a mesh of {self.N} intervals is {self.N + 1} increasing "
                             "positions from 0 to 1")
        return tau

    def defect_points(self, g: np.ndarray, T: float, tau: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray]:
        """The dynamics constraints at the NLP's last point, unscaled (rows: intervals, or
        nodes for LGL, in the states' units), at the interval midpoints (or nodes): where a
        failed answer fails."""
        rows = np.asarray(g, float).reshape(self.N, -1) * np.asarray(self.ocp.x_scale, float)
        return (tau[1:] + tau[:-1]) / 2 * T, rows

    def costates(self, lam_g: np.ndarray, X: np.ndarray, U: np.ndarray, p: np.ndarray,
                 ends: Endpoints, tau: np.ndarray) -> tuple[Series, Series, float]:
        """Costate and Hamiltonian estimates (the OCP's units) from the NLP multipliers."""
        mu = defect_multipliers(lam_g, self.n_defects // self.ocp.nx, self.ocp)
        points = self.costate_points(mu, X, U, ends.T, p, ends, tau)
        return estimate(self.ocp, points, p, X[-1], ends.T)


def _resample(tau: np.ndarray, tau_from: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Linear re-interpolation of node values (rows) onto another normalised mesh."""
    return np.column_stack([np.interp(tau, tau_from, col) for col in values.T])
