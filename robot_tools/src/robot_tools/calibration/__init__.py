"""Calibration from a recorded run: the signals read, the fits, the replay check and the overlays written."""
