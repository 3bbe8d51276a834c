import numpy as np

from broadtrack_graph.metrics.players import (
    AnalyticsConfig,
    error_stats,
    jitter_m,
    smooth_track,
    track_analytics,
    tracks,
)


def test_constant_velocity_is_unchanged_by_smoothing():
    frames = np.arange(20)
    xy = np.column_stack([0.3 * frames, 1.0 + 0 * frames])
    np.testing.assert_allclose(smooth_track(frames, xy, 5), xy, atol=1e-12)


def test_noise_inflates_raw_distance_and_smoothing_removes_most_of_it():
    rng = np.random.default_rng(0)
    frames = np.arange(250)
    truth = np.column_stack([0.2 * frames, np.zeros(250)])  # 5 m/s, 49.8 m
    noisy = truth + rng.normal(0, 0.05, truth.shape)
    result = track_analytics(frames, np.zeros(250, int), noisy, AnalyticsConfig(fps=25.0, smooth_frames=5))[0]
    assert result["raw_distance_m"] > 1.03 * 49.8
    assert abs(result["distance_m"] / 49.8 - 1) < 0.03
    assert abs(result["top_speed_m_s"] - 5.0) < 0.5
    assert 0.15 < result["jitter_rms_m"] < 0.2  # sqrt(2 * 6) * 0.05 = 0.17 (two axes)


def test_gaps_and_unknown_ids():
    frames = np.array([0, 1, 2, 10, 11, 0])
    ids = np.array([4, 4, 4, 4, 4, -1])
    xy = np.array([[0, 0], [1, 0], [2, 0], [3, 0], [4, 0], [9, 9]], float)
    grouped = tracks(frames, ids, xy)
    assert list(grouped) == [4]
    result = track_analytics(frames, ids, xy, AnalyticsConfig(smooth_frames=1, max_gap_frames=5))[4]
    assert result["distance_m"] == 3.0  # the 8-frame gap is not bridged
    assert len(jitter_m(*grouped[4])) == 1


def test_error_stats():
    stats = error_stats(np.array([0.1, 0.2, np.nan, 0.3]))
    assert stats["count"] == 3 and stats["median_m"] == 0.2
    assert error_stats(np.array([np.nan]))["median_m"] is None
