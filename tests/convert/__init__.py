"""Tests of xrdf_tools.convert and the convert command (sources, targets, the one command)."""
