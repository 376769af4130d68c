"""Transcriptions of optimal control problems into NLPs, one method per module.

`direct_transcription(kind, ocp, n, backend)` is the one-line method swap for any `OCP`:
the NLP is built once per (kind, problem, node count, back end, options) and cached, so a
slider move re-solves the built NLP warm.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from ..context import SolveContext
from ..nlp.cache import built_once
from ..ocp import OCP, OCPResult
from ..solution import WarmStart
from .direct import DirectTranscription
from .hermite_simpson import HermiteSimpson
from .multiple_shooting import MultipleShooting
from .pseudospectral import LGLPseudospectral
from .scvx import SCvxHermiteSimpson


class Transcription(Protocol):
    """What the solve pipeline asks of a method that turns an `OCP` into an answer: its
    facts (kind, convergence order, how its control reads between nodes, whether one build
    takes any mesh) and a solve of the built problem for the mission's parameters `p`, warm
    or cold. A direct transcription builds one NLP and re-solves it; an iterative method
    (successive convexification, `scvx`) solves a sequence of convex problems."""

    kind: str
    order: float
    control_interpolation: str
    variable_mesh: bool
    N: int

    def solve(self, p: np.ndarray, warm: WarmStart | None = None,
              ctx: SolveContext | None = None, dense_per_interval: int = 10,
              tau: np.ndarray | None = None) -> OCPResult:
        """Solve for parameters `p` (see `DirectTranscription.solve`)."""


# The registry, built from the classes: a method's key is its class's `kind`.
TRANSCRIPTIONS: dict[str, type[DirectTranscription]] = {
    cls.kind: cls
    for cls in (HermiteSimpson, MultipleShooting, LGLPseudospectral, SCvxHermiteSimpson)
}


# The order assumed for a mission's own method (a paper's scheme with no transcription):
# the cautious one, second order.
OWN_METHOD_ORDER = 2.0


def convergence_order(kind: str | None) -> float:
    """The convergence order in the node count of method `kind` (a transcription key, or
    None for a mission's own method)."""
    return TRANSCRIPTIONS[kind].order if kind in TRANSCRIPTIONS else OWN_METHOD_ORDER


@built_once
def direct_transcription(
    kind: str, ocp: OCP, n_intervals: int, backend: str = "ipopt", **options: int
) -> Transcription:
    """The cached transcription of `ocp` by method `kind` (a key of TRANSCRIPTIONS)."""
    return TRANSCRIPTIONS[kind](ocp, n_intervals, backend, **options)
