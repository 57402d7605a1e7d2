"""Tests of xrdf_tools.yaml: the YAML reader, its bounds, positions and shapes."""
