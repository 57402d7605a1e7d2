"""Tests of xrdf_tools.diff and the diff command."""
