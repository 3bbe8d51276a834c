"""Shots: hard cuts and dissolves in the frame stream, and whether a shot shows the tracked camera's view.

The step between frames and detections: :mod:`cuts` finds shot boundaries online,
:mod:`views` says whether a frame looks like the main (tracked) camera or another view
(close-up, crowd, bench, replay), :mod:`segmenter` combines both per frame and keeps
the list of shots, :mod:`stream` annotates the loop's frames as they are decoded.
"""
