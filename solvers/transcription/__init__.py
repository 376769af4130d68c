"""Transcriptions of optimal control problems into NLPs, one method per module.

`direct_transcription(kind, ocp, n, backend)` is the one-line method swap for any `OCP`:
the NLP is built once per (kind, problem, node count, back end, options) and cached, so a
slider move re-solves the built NLP warm.
"""

from __future__ import annotations

from ..nlp.cache import built_once
from ..ocp import OCP
from .direct import DirectTranscription
from .hermite_simpson import HermiteSimpson
from .multiple_shooting import MultipleShooting
from .pseudospectral import LGLPseudospectral
from .scvx import SCvxHermiteSimpson

TRANSCRIPTIONS: dict[str, type[DirectTranscription]] = {
    "hermite-simpson": HermiteSimpson,
    "multiple-shooting": MultipleShooting,
    "lgl": LGLPseudospectral,
    "scvx": SCvxHermiteSimpson,
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
) -> DirectTranscription:
    """The cached transcription of `ocp` by method `kind` (a key of TRANSCRIPTIONS)."""
    return TRANSCRIPTIONS[kind](ocp, n_intervals, backend, **options)
