"""Types that several layers share: frame statuses, track records, shots, player boxes, observations, modes.

They sit low in the import order (they import only :mod:`broadtrack_graph.geometry` and
:mod:`broadtrack_graph.errors`), so that the file formats of :mod:`broadtrack_graph.io`, the
front end, the tracker and the metrics can all speak them without importing each other.
They hold data and its invariants; reading and writing files is :mod:`broadtrack_graph.io`'s.
"""
