"""Noise models and iSAM2 parameters, built in one place from the config.

The measurement factors whiten their own residuals (per-point Cauchy inside the
factor) so their GTSAM noise model is ``Unit``; see :mod:`factors.custom`.
"""

from __future__ import annotations

import gtsam
import numpy as np

from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.graph.keys import CAMERA_CHAR, TRIPOD_CHAR


def isam2_params(config: GraphConfig) -> gtsam.ISAM2Params:
    """iSAM2 parameters with per-variable relinearisation thresholds (state order)."""
    s = config.solver
    params = gtsam.ISAM2Params()
    thresholds = np.array([
        s.relinearize_threshold_px, s.relinearize_threshold_k1, s.relinearize_threshold_rad,
        s.relinearize_threshold_rad, s.relinearize_threshold_rad, s.relinearize_threshold_m,
        s.relinearize_threshold_m, s.relinearize_threshold_m,
    ])
    per_kind = gtsam.ISAM2ThresholdMap()  # symbol character -> per-dimension thresholds
    per_kind.insert((CAMERA_CHAR, thresholds))
    per_kind.insert((TRIPOD_CHAR, np.full(4, s.relinearize_threshold_m)))
    params.setRelinearizeThreshold(per_kind)
    params.relinearizeSkip = s.relinearize_skip
    params.cacheLinearizedFactors = s.cache_linearized_factors
    params.findUnusedFactorSlots = True  # reuse the slots of marginalised factors (flat memory)
    return params


def lm_params(config: GraphConfig) -> gtsam.LevenbergMarquardtParams:
    params = gtsam.LevenbergMarquardtParams()
    params.setMaxIterations(config.solver.lm_max_iterations)
    params.setRelativeErrorTol(config.solver.lm_relative_tolerance)
    params.setAbsoluteErrorTol(1e-9)
    return params
