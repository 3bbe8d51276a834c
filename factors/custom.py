"""The one place that turns a numpy residual function into a ``gtsam.CustomFactor``.

Every factor here whitens its own residuals (and applies its per-point Cauchy loss,
see :mod:`factors.robust`), so the GTSAM noise model is always ``Unit(dim)``.
Jacobian shapes are checked before they are handed to GTSAM: a Jacobian of the
wrong shape written into GTSAM's matrices segfaults the process instead of raising.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import NamedTuple

import gtsam
import numpy as np

ResidualFunction = Callable[[list[np.ndarray], bool], tuple[np.ndarray, list[np.ndarray] | None]]
"""``fn(variable_vectors, want_jacobians) -> (residual (dim,), [J_i (dim, size_i)] or None)``."""


class Residuals(NamedTuple):
    """What every ``*_residuals`` function of this package returns, whatever the factor.

    residual: the residuals, in the shape the function states: (N,) for points on lines,
        (N, 2) for keypoints and flow matches, (m,) for a factor on whole states.
    jacobians: one array per variable, in the order of the function's variable arguments,
        each of shape ``residual.shape + (variable size,)``; None when not asked for.
    valid: (N,) bool per point (in front of the camera, near its marking, ...); None for
        factors on whole states, where every residual counts.
    """

    residual: np.ndarray
    jacobians: list[np.ndarray] | None
    valid: np.ndarray | None = None


class FactorShapeError(RuntimeError):
    """A factor produced a residual or Jacobian of the wrong shape (caught before GTSAM sees it)."""


def custom_factor(keys: Sequence[int], sizes: Sequence[int], dim: int, fn: ResidualFunction) -> gtsam.CustomFactor:
    """Wrap a whitened numpy residual function as a CustomFactor with a unit noise model.

    Args:
        keys: GTSAM keys of the vector variables, in the order ``fn`` expects them.
        sizes: dimension of each variable (8 for a camera state, 4 for the tripod).
        dim: residual length (fixed for the factor's life).
        fn: see :data:`ResidualFunction`.
    """
    keys = [int(k) for k in keys]
    sizes = [int(n) for n in sizes]
    if dim <= 0:
        raise ValueError(f"a factor needs at least one residual, got dim={dim}")

    # GTSAM often evaluates a factor again at the values it last saw (iSAM2 relinearising, the smoother
    # marginalising): the last evaluation is kept and handed out again for the same values and the same path
    # (fn is a pure function of the vectors; GTSAM copies what it is given).
    last: list = [None, None, None]  # [(vectors' bytes, Jacobians wanted), residual, Jacobians]

    def error_function(this: gtsam.CustomFactor, values: gtsam.Values, H) -> np.ndarray:
        vectors = [values.atVector(k) for k in keys]
        seen = (b"".join(v.tobytes() for v in vectors), H is not None)
        if seen == last[0]:
            residual, jacobians = last[1], last[2]
        else:
            residual, jacobians = fn(vectors, H is not None)
            residual = np.ascontiguousarray(residual, dtype=float)
            if residual.shape != (dim,):
                raise FactorShapeError(f"residual shape {residual.shape}, expected ({dim},)")
            if H is not None:
                jacobians = [np.ascontiguousarray(J, dtype=float) for J in jacobians]
                for i, J in enumerate(jacobians):
                    if J.shape != (dim, sizes[i]):
                        raise FactorShapeError(f"Jacobian {i} shape {J.shape}, expected ({dim}, {sizes[i]})")
            last[:] = [seen, residual, jacobians]
        if H is not None:
            for i, J in enumerate(jacobians):
                H[i] = J
        return residual

    return gtsam.CustomFactor(gtsam.noiseModel.Unit.Create(dim), keys, error_function)
