"""Sources → XRDF: the converter, its source readers and the one-command pipeline."""
