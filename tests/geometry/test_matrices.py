import numpy as np

from broadtrack_graph.geometry.matrices import cross3, inverses


def test_inverses_match_numpy_and_a_singular_item_spoils_only_its_own():
    rng = np.random.default_rng(0)
    M = rng.normal(size=(5, 3, 3)) + 3.0 * np.eye(3)
    M[2] = np.array([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 1.0, 1.0]])  # two rows on one line: singular
    M[4, 0] = np.nan  # a degenerate hypothesis upstream
    out = inverses(M)
    ok = [0, 1, 3]
    np.testing.assert_allclose(out[ok] @ M[ok], np.broadcast_to(np.eye(3), (3, 3, 3)), atol=1e-12)
    assert np.isnan(out[2]).all() and np.isnan(out[4]).all()


def test_the_singularity_test_does_not_depend_on_the_matrix_scale():
    M = np.diag([1.0, 2.0, 4.0])[None] * np.array([1e-6, 1.0, 1e6])[:, None, None]
    out = inverses(M)
    assert np.isfinite(out).all()
    np.testing.assert_allclose(out @ M, np.broadcast_to(np.eye(3), (3, 3, 3)), atol=1e-9)


def test_cross3_gives_numpys_cross_products_bit_for_bit_over_broadcast_shapes():
    rng = np.random.default_rng(7)
    for shape_a, shape_b in [((3,), (3,)), ((1, 3), (40, 3)), ((40, 3), (3,)), ((5, 4, 3), (4, 3)), ((0, 3), (3,))]:
        a, b = rng.normal(size=shape_a), rng.normal(size=shape_b)
        expected = np.cross(a, b)
        got = cross3(a, b)
        assert got.shape == expected.shape and got.dtype == expected.dtype
        assert np.array_equal(got, expected)
    assert np.array_equal(cross3([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]), [0.0, 0.0, 1.0])  # x cross y is z
