"""The front end: field-marking detection, optical flow, confidence, re-initialisation, calibration.

Submodules: detector (interface and Detections), weightfree (default, no weights),
onnx_detector (learned models through onnxruntime), meanshift, flow, confidence,
reinit, linefit (hypothesis refinement), template_image (the projected template as dense image
samples and masks), calibrate (single-frame calibration).
"""
