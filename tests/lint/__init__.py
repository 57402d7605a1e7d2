"""Tests of xrdf_tools.lint and the lint command."""
