"""Pictures and reports made from camera tracks: overlays, bird's-eye view, plots, run comparison.

Drawing functions take and return images (numpy arrays); the functions that read runs
or write files say so in their names (``write_...``, ``compare_runs``).
"""
