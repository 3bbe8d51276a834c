"""Measurement models of BroadTrack as GTSAM custom factors.

One module per measurement kind, each a pure numpy function returning stacked
residuals and analytic Jacobians for all its points at once, plus a thin
``make_*_factor`` wrapper (see :mod:`factors.custom`):

* :mod:`broadtrack_graph.geometry.state` - projection of the 8-vector state ``[f, k1, pan, tilt, roll, Cx, Cy, Cz]``;
* :mod:`factors.lines` - line/circle points to the projected marking (Cauchy);
* :mod:`factors.keypoints` - labelled keypoints (Cauchy);
* :mod:`factors.flow` - optical flow through the ground plane between t-1 and t (Cauchy);
* :mod:`factors.tripod` - L_T = delta - |O* - T|;
* :mod:`factors.motion` - random walk and smoothness between consecutive frames;
* :mod:`factors.priors` - physical ranges of f and k1, Gaussian anchor;
* :mod:`factors.robust` - per-point Cauchy IRLS used inside the factors.
"""
