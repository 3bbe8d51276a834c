"""Training the learned field model: sample shards, the network, the training loop, the ONNX export.

Outside the package's import graph on purpose: the runtime package never imports torch. Only
:mod:`shards` is free of torch (it writes and reads the training samples with numpy and OpenCV);
:mod:`network`, :mod:`train` and :mod:`export` need the ``train`` extra.
"""
