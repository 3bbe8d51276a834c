"""The factor graph solvers: one shared builder, online (iSAM2 fixed-lag), lagged, batch.

Public entry points:

* :func:`broadtrack_graph.graph.single_frame.refine_single_frame` - robust LM on one frame;
* :class:`broadtrack_graph.graph.online.OnlineTracker` - one iSAM2 update per frame;
* :class:`broadtrack_graph.graph.fixed_lag.FixedLagSmoother` - estimates after L frames;
* :mod:`broadtrack_graph.graph.streaming` - one push / finish interface over both, rebuilt on GTSAM errors;
* :class:`broadtrack_graph.graph.batch.BatchRefiner` - LM over a clip with the tripod;
* :func:`broadtrack_graph.graph.tripod_fit.fit_tripod` - T and delta from a track;
* :mod:`broadtrack_graph.graph.estimates` - FrameEstimate / EstimateSequence (camera, std, active factors);
* :mod:`broadtrack_graph.graph.config` - the sigmas and solver settings (frozen dataclasses);
* :mod:`broadtrack_graph.graph.builder` - FrameObservations -> factors (shared by all solvers);
* :mod:`broadtrack_graph.graph.keys` - the GTSAM keys of the camera and tripod variables;
* :mod:`broadtrack_graph.graph.simulate` - synthetic observations for tests and benchmarks.
"""
